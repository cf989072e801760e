//! Snappable layout of PZT plates (isosceles trapezoids) on a sheet.
//!
//! PZT is scored with the laser and snapped by hand, so a layout must be a guillotine layout:
//! a sequence of straight breaks, each running edge to edge of the piece it splits
//! (docs/cam.md §4). Trapezoids tile into strips when every other plate is turned 180°:
//!
//! ```text
//!  ___________________________________   <- strip top boundary (score line)
//!   \ tip /\ base  /\     /\     /
//!    \   /  \     /  \   /  \   /        slanted score lines, one per pair of neighbours,
//!     \_/    \___/    \_/    \_/         each from the strip bottom to the strip top
//!  ___________________________________   <- strip bottom boundary
//! ```
//!
//! Every score line sits in the middle of a kerf-wide gap, so each plate keeps its full nominal
//! outline. Between two neighbours the gap is the kerf measured perpendicular to the slanted
//! edge, which is `kerf / cos θ` along the strip, with `tan θ = (base - tip) / (2 l_p)`.
//!
//! The sheet is split recursively into rectangular regions (a guillotine tree): a strip of one
//! item across the region (as tall as `l_p`, plates side by side), the leftover at the end of the
//! strip (filled with other items when they fit), and the rest of the region beyond the strip.
//! Strips may run either way; at each region both directions are tried (within a node budget)
//! and the one that places more plate area is kept.

mod planner;
#[cfg(test)]
mod tests;

use super::error::{check_length, check_sheet, LayoutError};
use cam_geometry::{area, Point};
use cam_nest::{NestBin, NestSolution, NestedBin, PlacedPart};
use planner::{Planner, Region, Shape, Side, SEARCH_BUDGET};
use serde::{Deserialize, Serialize};

/// One plate design: an isosceles trapezoid, `count` copies wanted.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PlateSpec {
    /// Plate length `l_p` along the actuator axis, mm.
    pub length_mm: f64,
    /// Width at the base (clamped end), mm.
    pub base_width_mm: f64,
    /// Width at the tip (free end), mm.
    pub tip_width_mm: f64,
    /// How many plates.
    pub count: usize,
}

/// The nominal plate ring: base centred on the x axis, tip at `y = length_mm`, CCW.
///
/// A [`PlacedPart`] of a plate is this ring rotated by `rotation_deg` and translated by `translation`.
pub fn plate_outline(spec: &PlateSpec) -> Vec<Point> {
    let (b, t, l) = (spec.base_width_mm, spec.tip_width_mm, spec.length_mm);
    vec![[-b / 2.0, 0.0], [b / 2.0, 0.0], [t / 2.0, l], [-t / 2.0, l]]
}

/// Lays out plates on as many sheets as needed, each sheet a snappable (guillotine) layout.
///
/// `kerf_mm` is the width the score removes (the gap between neighbouring outlines);
/// `margin_mm` keeps plates away from the chipped sheet edge (a trim score line separates the
/// margin when it is wider than half the kerf). `min_strip_mm` is the narrowest offcut a score
/// line may leave, between it and the sheet edge or another score line (docs/cam.md §4,
/// "Snappable strips"): the trim margin grows to half a kerf plus it, runs start and end so that
/// their end offcuts are at least that wide, and no strip leaves a narrower rest; 0 allows any.
/// Items are filled in order; leftovers of strips and of the sheet take later items when they fit.
/// Errors when an item does not fit an empty sheet, or when more sheets than `sheet.stock` are
/// needed (saying how many).
pub fn layout_plates(
    items: &[PlateSpec],
    sheet: &NestBin,
    kerf_mm: f64,
    margin_mm: f64,
    min_strip_mm: f64,
) -> Result<NestSolution, LayoutError> {
    let shapes = shapes_of(items, sheet, kerf_mm, margin_mm, min_strip_mm)?;
    let planner = planner(&shapes, kerf_mm, margin_mm, min_strip_mm);
    let whole = whole_sheet(sheet);
    for (i, spec) in items.iter().enumerate() {
        if spec.count > 0 && !(planner.fits(&whole, i, 0) || planner.fits(&whole, i, 1)) {
            let usable = |axis: usize| {
                let (a, b) = planner.inner(&whole, axis);
                b - a
            };
            return Err(LayoutError::TooLarge {
                item: i,
                width_mm: shapes[i].width,
                height_mm: shapes[i].length,
                sheet_width_mm: sheet.width_mm,
                sheet_height_mm: sheet.height_mm,
                usable_width_mm: usable(0),
                usable_height_mm: usable(1),
            });
        }
    }

    let mut remaining: Vec<usize> = items.iter().map(|s| s.count).collect();
    let mut next_copy = vec![0usize; items.len()];
    let mut sheets = Vec::new();
    while remaining.iter().any(|&n| n > 0) {
        let bin = plan_sheet(
            &planner,
            &whole,
            &mut remaining,
            &mut next_copy,
            sheets.len(),
        );
        // Every remaining item fits an empty sheet, so a sheet always takes at least one plate.
        assert!(!bin.parts.is_empty(), "empty sheet plan");
        sheets.push(bin);
    }
    if sheets.len() > sheet.stock {
        return Err(LayoutError::TooManySheets {
            needed: sheets.len(),
            stock: sheet.stock,
        });
    }
    Ok(NestSolution { bins: sheets })
}

/// The plates' shapes, once the sheet and the lengths are checked.
fn shapes_of(
    items: &[PlateSpec],
    sheet: &NestBin,
    kerf_mm: f64,
    margin_mm: f64,
    min_strip_mm: f64,
) -> Result<Vec<Shape>, LayoutError> {
    check_sheet(sheet)?;
    check_length("kerf_mm", kerf_mm)?;
    check_length("margin_mm", margin_mm)?;
    check_length("min_strip_mm", min_strip_mm)?;
    items
        .iter()
        .enumerate()
        .map(|(i, spec)| Shape::new(i, spec, kerf_mm))
        .collect()
}

fn planner(shapes: &[Shape], kerf_mm: f64, margin_mm: f64, min_strip_mm: f64) -> Planner<'_> {
    Planner {
        shapes,
        half_kerf: kerf_mm / 2.0,
        margin: margin_mm,
        min_strip: min_strip_mm,
        budget: std::cell::Cell::new(0),
    }
}

/// The whole sheet as the guillotine tree's root: every side the sheet's (chipped) edge.
fn whole_sheet(sheet: &NestBin) -> Region {
    Region {
        lo: [0.0, 0.0],
        hi: [sheet.width_mm, sheet.height_mm],
        lo_side: [Side::Edge; 2],
        hi_side: [Side::Edge; 2],
    }
}

/// One sheet planned from what is `remaining` (taken from it): its plates numbered on from
/// `next_copy`, its score lines in break order.
fn plan_sheet(
    planner: &Planner<'_>,
    whole: &Region,
    remaining: &mut [usize],
    next_copy: &mut [usize],
    index: usize,
) -> NestedBin {
    planner.budget.set(SEARCH_BUDGET);
    let mut plan = planner.fill(whole, remaining, 0);
    plan.lines.sort_by_key(|&(depth, _)| depth);
    let parts: Vec<PlacedPart> = plan
        .plates
        .iter()
        .map(|p| {
            let copy = next_copy[p.item];
            next_copy[p.item] += 1;
            PlacedPart::at(
                p.item,
                copy,
                &planner.shapes[p.item].nominal,
                p.rotation_deg,
                p.bbox_min,
            )
        })
        .collect();
    let part_area: f64 = parts.iter().map(|p| area(&p.outline)).sum();
    let sheet_area = (whole.hi[0] - whole.lo[0]) * (whole.hi[1] - whole.lo[1]);
    NestedBin {
        index,
        parts,
        utilization: part_area / sheet_area,
        score_lines: plan.lines.into_iter().map(|(_, l)| l).collect(),
    }
}

/// One snappable layout on a remnant `sheet` (a rectangle of PZT with straight edges, in its own
/// frame): as many of the plates as fit, planned from its edges as from a whole sheet's; the
/// plates no sheet of this size can take wait for the next. `None` when none fits. Copies are
/// numbered from 0 per item; the caller numbers them among its other sheets.
pub fn layout_plates_on_remnant(
    items: &[PlateSpec],
    sheet: &NestBin,
    kerf_mm: f64,
    margin_mm: f64,
    min_strip_mm: f64,
) -> Result<Option<NestedBin>, LayoutError> {
    let shapes = shapes_of(items, sheet, kerf_mm, margin_mm, min_strip_mm)?;
    let planner = planner(&shapes, kerf_mm, margin_mm, min_strip_mm);
    let whole = whole_sheet(sheet);
    let mut remaining: Vec<usize> = items
        .iter()
        .enumerate()
        .map(|(i, s)| {
            let fits = planner.fits(&whole, i, 0) || planner.fits(&whole, i, 1);
            if fits {
                s.count
            } else {
                0
            }
        })
        .collect();
    let mut next_copy = vec![0usize; items.len()];
    let bin = plan_sheet(&planner, &whole, &mut remaining, &mut next_copy, 0);
    Ok((!bin.parts.is_empty()).then_some(bin))
}
