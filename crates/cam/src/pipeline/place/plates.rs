//! The PZT plates' snappable layout of score lines, planned by [`crate::layout::layout_plates`]
//! and checked by the verifier before the score lines are drawn ([`crate::pipeline::score_lines`]).
//! The remnants a batch names (`[[stock]]` with `sheet = "pzt"`) are laid out first, each from its
//! own straight edges; whatever is left goes on whole sheets. Every sheet's own remnant, the
//! rectangle one edge-to-edge line frees, is kept for the report.

use super::refusal::sheet_too_small;
use super::{promised, sheet_of, ROUNDING_MM};
use crate::layout::{
    layout_plates, layout_plates_on_remnant, pzt_remnant, verify_break_order, verify_offcuts,
    verify_snappable, LayoutError, PlateSpec,
};
use crate::pipeline::jobs::{format_violations, Job, Names};
use crate::pipeline::BuildError;
use crate::process::template::SheetSpec;
use cam_geometry::{Bounds, Point};
use cam_nest::{
    verify_copies, verify_sheet, verify_stock, Clearance, NestBin, NestItem, NestedBin,
};

/// The PZT sheets of a group: first those laid out on the drawn remnants, then whole sheets.
pub(crate) struct PlacedPlates {
    /// Every sheet's layout, in the sheet's frame (a remnant's in the frame of the sheet it was
    /// cut from, as its drawing is).
    pub bins: Vec<NestedBin>,
    /// The drawn sheet ([`SheetSpec::drawn`]) each of the first `drawn.len()` layouts is on.
    pub drawn: Vec<usize>,
    /// The rectangle of each sheet that is left to keep (`[min, max]`), if one is.
    pub remnants: Vec<Option<[Point; 2]>>,
}

/// The verifier's checks of one laid-out PZT sheet, and the smallest rest worth keeping of it.
struct SheetCheck<'a> {
    items: Vec<NestItem>,
    clearance: Clearance,
    min_strip_mm: f64,
    keep_mm: f64,
    names: &'a Names,
}

impl SheetCheck<'_> {
    fn fail(&self, what: String) -> BuildError {
        self.names.error(format!("pzt (verifier) layout: {what}"))
    }

    /// `bin` on the sheet (or remnant) `on`, in its frame: each plate its nominal trapezoid placed, the
    /// kerf between plates and the margin to the edge, the score lines snappable, in break order and
    /// leaving no sliver. Its own remnant, if one is worth keeping.
    fn verified(&self, bin: &NestedBin, on: &NestBin) -> Result<Option<[Point; 2]>, BuildError> {
        verify_sheet(
            &self.items,
            on,
            self.clearance,
            bin.index,
            &bin.parts,
            ROUNDING_MM,
        )
        .map_err(|v| self.fail(v.to_string()))?;
        let snap = |v: Vec<crate::layout::Violation>| self.fail(format_violations(&v));
        verify_snappable(bin, on).map_err(snap)?;
        verify_break_order(bin, on).map_err(snap)?;
        verify_offcuts(bin, on, self.min_strip_mm).map_err(snap)?;
        Ok(pzt_remnant(bin, on, self.keep_mm))
    }
}

/// Lay out two plates per actuator of every job, on `spec`'s drawn remnants first and then on its
/// sheets (at most `stock`), as snappable layouts, and verify them: every copy once, the score lines
/// snappable and listed in break order, each plate its nominal trapezoid placed, the kerf between
/// plates and the margin to the sheet's (or the remnant's) edge.
pub(crate) fn place_plates(
    jobs: &[Job<'_>],
    spec: &SheetSpec,
    stock: Option<usize>,
    names: &Names,
) -> Result<PlacedPlates, BuildError> {
    let plates: Vec<PlateSpec> = jobs
        .iter()
        .map(|j| PlateSpec {
            length_mm: j.geometry.plate_length_mm(),
            base_width_mm: j.geometry.plate_base_width_mm(),
            tip_width_mm: j.geometry.plate_tip_width_mm(),
            count: 2 * j.quantity,
        })
        .collect();
    let copies: usize = plates.iter().map(|p| p.count).sum();
    let sheet = sheet_of(spec, stock.unwrap_or(copies.max(1)));
    // The narrowest snappable strip scales with the plate thickness (docs/cam.md §4).
    let thickness_mm = jobs
        .iter()
        .map(|j| j.design.pzt_thickness * 1e3)
        .fold(0.0, f64::max);
    let min_strip_mm = spec.min_snap_strip_thicknesses * thickness_mm;
    let check = SheetCheck {
        // PZT is in-plane isotropic: strips may run either way, so any quarter turn is allowed.
        items: jobs
            .iter()
            .zip(&plates)
            .map(|(j, p)| NestItem {
                outline: j.geometry.pzt_outline(),
                demand: p.count,
                rotations_deg: vec![0.0, 90.0, 180.0, 270.0],
            })
            .collect(),
        // Scored plates keep the kerf between each other but only the margin to the sheet edge.
        clearance: Clearance {
            between_parts_mm: promised(spec.kerf_mm),
            to_edge_mm: promised(spec.edge_margin_mm),
        },
        min_strip_mm,
        // The smallest rest worth keeping: room for the trim lines of both edges and a strip between.
        keep_mm: 2.0 * spec.edge_margin_mm + min_strip_mm,
        names,
    };
    let mut placed = on_remnants(&plates, spec, &check)?;
    let plates = still_to_place(&plates, &placed.bins);
    let layout = layout_plates(
        &plates,
        &sheet,
        spec.kerf_mm,
        spec.edge_margin_mm,
        min_strip_mm,
    )
    .map_err(|e| refused(e, &plates, spec, min_strip_mm, names))?;
    verify_stock(&layout.bins, sheet.stock).map_err(|v| check.fail(v.to_string()))?;
    for mut bin in layout.bins {
        let remnant = check.verified(&bin, &sheet)?;
        bin.index = placed.bins.len();
        placed.remnants.push(remnant);
        placed.bins.push(bin);
    }
    // Copies numbered across all the group's sheets, remnants first, then checked once each.
    let mut next = vec![0usize; plates.len()];
    for bin in &mut placed.bins {
        for part in &mut bin.parts {
            part.copy = next[part.item];
            next[part.item] += 1;
        }
    }
    verify_copies(&check.items, &placed.bins).map_err(|v| check.fail(v.to_string()))?;
    Ok(placed)
}

/// The plates laid out on `spec`'s drawn remnants, one after the other, each as much as fits of what
/// the ones before left, planned and verified in the remnant's own frame and then moved to where the
/// remnant lies on its sheet.
fn on_remnants(
    plates: &[PlateSpec],
    spec: &SheetSpec,
    check: &SheetCheck<'_>,
) -> Result<PlacedPlates, BuildError> {
    let mut placed = PlacedPlates {
        bins: Vec::new(),
        drawn: Vec::new(),
        remnants: Vec::new(),
    };
    for (k, d) in spec.drawn.iter().enumerate() {
        let these = still_to_place(plates, &placed.bins);
        if these.iter().all(|p| p.count == 0) {
            break;
        }
        let b = Bounds::of(&d.shape.outline);
        let on = NestBin {
            width_mm: b.width(),
            height_mm: b.height(),
            stock: 1,
        };
        let laid = layout_plates_on_remnant(
            &these,
            &on,
            spec.kerf_mm,
            spec.edge_margin_mm,
            check.min_strip_mm,
        )
        .map_err(|e| check.names.error(format!("pzt layout on {}: {e}", d.file)))?;
        let Some(mut bin) = laid else { continue };
        bin.index = placed.bins.len();
        let remnant = check.verified(&bin, &on)?;
        shift_bin(&mut bin, b.min);
        placed
            .remnants
            .push(remnant.map(|[lo, hi]| [add(lo, b.min), add(hi, b.min)]));
        placed.bins.push(bin);
        placed.drawn.push(k);
    }
    Ok(placed)
}

/// The refusal of a layout on whole sheets: a plate too large for the sheet is named with the sheet
/// size that would take it (the planner's own answer for the plate alone).
fn refused(
    e: LayoutError,
    plates: &[PlateSpec],
    spec: &SheetSpec,
    min_strip_mm: f64,
    names: &Names,
) -> BuildError {
    let LayoutError::TooLarge {
        item,
        width_mm,
        height_mm,
        sheet_width_mm,
        sheet_height_mm,
        usable_width_mm,
        usable_height_mm,
    } = e
    else {
        return names.error(format!("pzt layout: {e}"));
    };
    let alone = [PlateSpec {
        count: 1,
        ..plates[item]
    }];
    let takes = |width_mm: f64, height_mm: f64| {
        let sheet = NestBin {
            width_mm,
            height_mm,
            stock: 1,
        };
        layout_plates(
            &alone,
            &sheet,
            spec.kerf_mm,
            spec.edge_margin_mm,
            min_strip_mm,
        )
        .is_ok()
    };
    sheet_too_small(
        spec,
        &format!("a {width_mm:.2} x {height_mm:.2} mm PZT plate"),
        [width_mm, height_mm],
        [
            sheet_width_mm - usable_width_mm,
            sheet_height_mm - usable_height_mm,
        ],
        true,
        Some(&takes),
    )
}

/// `plates` with their counts less the copies `bins` already hold.
fn still_to_place(plates: &[PlateSpec], bins: &[NestedBin]) -> Vec<PlateSpec> {
    let mut left: Vec<PlateSpec> = plates.to_vec();
    for part in bins.iter().flat_map(|b| &b.parts) {
        left[part.item].count -= 1;
    }
    left
}

fn add(a: Point, b: Point) -> Point {
    [a[0] + b[0], a[1] + b[1]]
}

/// A layout planned in a remnant's own frame moved to where the remnant lies on its sheet.
fn shift_bin(bin: &mut NestedBin, by: Point) {
    for part in &mut bin.parts {
        part.translation = add(part.translation, by);
        for q in &mut part.outline {
            *q = add(*q, by);
        }
    }
    for line in &mut bin.score_lines {
        *line = [add(line[0], by), add(line[1], by)];
    }
}
