//! Snappable layout of PZT plates (isosceles trapezoids) on a sheet.
//!
//! PZT is scored with the laser and snapped by hand, so a layout must be a guillotine layout:
//! a sequence of straight breaks, each running edge to edge of the piece it splits
//! (CAM-NOTES §4). Trapezoids tile into strips when every other plate is turned 180°:
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

use super::placement::{check_length, place_at, LayoutError, Sheet, SheetLayout};
use cam_geometry::Point;
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
/// A [`Placement`](super::Placement) of a plate is this ring rotated by `rotation_deg` and translated by `offset`.
pub fn plate_outline(spec: &PlateSpec) -> Vec<Point> {
    let (b, t, l) = (spec.base_width_mm, spec.tip_width_mm, spec.length_mm);
    vec![[-b / 2.0, 0.0], [b / 2.0, 0.0], [t / 2.0, l], [-t / 2.0, l]]
}

/// Lays out plates on as many sheets as needed, each sheet a snappable (guillotine) layout.
///
/// `kerf_mm` is the width the score removes (the gap between neighbouring outlines);
/// `margin_mm` keeps plates away from the chipped sheet edge (a trim score line separates the
/// margin when it is wider than half the kerf). Items are filled in order; leftovers of strips
/// and of the sheet take later items when they fit. Errors when an item does not fit an empty
/// sheet, or when more than `max_sheets` sheets are needed (saying how many).
pub fn layout_plates(
    items: &[PlateSpec],
    sheet: &Sheet,
    kerf_mm: f64,
    margin_mm: f64,
    max_sheets: Option<usize>,
) -> Result<Vec<SheetLayout>, LayoutError> {
    sheet.validate()?;
    check_length("kerf_mm", kerf_mm)?;
    check_length("margin_mm", margin_mm)?;
    let shapes = items
        .iter()
        .enumerate()
        .map(|(i, spec)| Shape::new(i, spec, kerf_mm))
        .collect::<Result<Vec<_>, _>>()?;
    let planner = Planner {
        shapes: &shapes,
        half_kerf: kerf_mm / 2.0,
        margin: margin_mm,
        budget: std::cell::Cell::new(0),
    };
    let whole = Region {
        lo: [0.0, 0.0],
        hi: [sheet.width_mm, sheet.height_mm],
        lo_side: [Side::Edge; 2],
        hi_side: [Side::Edge; 2],
    };
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
        planner.budget.set(SEARCH_BUDGET);
        let mut plan = planner.fill(&whole, &mut remaining, 0);
        plan.lines.sort_by_key(|&(depth, _)| depth);
        // Every remaining item fits an empty sheet, so a sheet always takes at least one plate.
        assert!(!plan.plates.is_empty(), "empty sheet plan");
        let placements = plan
            .plates
            .iter()
            .map(|p| {
                let copy = next_copy[p.item];
                next_copy[p.item] += 1;
                place_at(
                    p.item,
                    copy,
                    &shapes[p.item].nominal,
                    p.rotation_deg,
                    p.bbox_min,
                )
            })
            .collect();
        sheets.push(SheetLayout {
            sheet_index: sheets.len(),
            placements,
            score_lines: plan.lines.into_iter().map(|(_, l)| l).collect(),
        });
    }
    match max_sheets {
        Some(stock) if sheets.len() > stock => Err(LayoutError::TooManySheets {
            needed: sheets.len(),
            stock,
        }),
        _ => Ok(sheets),
    }
}

/// Tolerance for comparing positions, mm.
const EPS: f64 = 1e-9;

/// How many two-way choices (strip direction) a sheet may explore before it settles each
/// further choice by a one-item estimate. A count, not a time, so the result is reproducible.
const SEARCH_BUDGET: usize = 2048;

/// Plate geometry derived once per item.
struct Shape {
    nominal: Vec<Point>,
    length: f64,
    base: f64,
    tip: f64,
    /// Bounding width, max(base, tip).
    width: f64,
    /// Distance along the strip from a slanted plate edge to its score line:
    /// `(kerf / 2) / cos θ`, `tan θ = (base - tip) / (2 l_p)`.
    edge_to_line: f64,
    /// Distance along the strip between the centres of neighbouring plates:
    /// `(base + tip) / 2 + kerf / cos θ`.
    pitch: f64,
    area: f64,
}

impl Shape {
    fn new(item: usize, spec: &PlateSpec, kerf: f64) -> Result<Shape, LayoutError> {
        let (l, b, t) = (spec.length_mm, spec.base_width_mm, spec.tip_width_mm);
        for (name, v) in [("length_mm", l), ("base_width_mm", b), ("tip_width_mm", t)] {
            if !(v.is_finite() && v > 0.0) {
                return Err(LayoutError::InvalidItem {
                    item,
                    reason: format!("{name} must be finite and > 0, got {v}"),
                });
            }
        }
        let slant = (b - t) / 2.0;
        let sec = (l * l + slant * slant).sqrt() / l;
        let edge_to_line = kerf / 2.0 * sec;
        Ok(Shape {
            nominal: plate_outline(spec),
            length: l,
            base: b,
            tip: t,
            width: b.max(t),
            edge_to_line,
            pitch: (b + t) / 2.0 + 2.0 * edge_to_line,
            area: (b + t) / 2.0 * l,
        })
    }

    /// How many plates fit side by side in a run of length `room`.
    fn run_capacity(&self, room: f64) -> usize {
        if room + EPS < self.width {
            0
        } else {
            ((room - self.width) / self.pitch + EPS).floor() as usize + 1
        }
    }
}

/// What bounds a region on one side.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Side {
    /// The sheet edge: plates keep `margin` from it.
    Edge,
    /// A score line: plates keep half the kerf from it.
    Line,
}

/// An axis-aligned rectangle of the guillotine tree. Index 0 is x, 1 is y. Every side lies on
/// the sheet edge or within one score line over its whole length.
#[derive(Debug, Clone, Copy)]
struct Region {
    lo: [f64; 2],
    hi: [f64; 2],
    lo_side: [Side; 2],
    hi_side: [Side; 2],
}

/// A plate placed by the planner, before copy numbers are assigned.
struct PlatePos {
    item: usize,
    rotation_deg: f64,
    bbox_min: Point,
}

/// The plates and score lines of one region. Each line carries its depth in the guillotine tree:
/// its ends rest on the sheet edge or on lines of smaller depth, so sorting by depth gives a
/// break order that starts with the lines across the whole sheet.
#[derive(Default)]
struct Plan {
    plates: Vec<PlatePos>,
    lines: Vec<(usize, [Point; 2])>,
    area: f64,
}

impl Plan {
    fn append(&mut self, other: Plan) {
        self.plates.extend(other.plates);
        self.lines.extend(other.lines);
        self.area += other.area;
    }
}

/// Builds a point from coordinates along the strip (`u`, on axis `u_axis`) and across it (`v`).
fn point(u_axis: usize, u: f64, v: f64) -> Point {
    let mut p = [0.0; 2];
    p[u_axis] = u;
    p[1 - u_axis] = v;
    p
}

/// Plate rotation for a strip running along `u_axis`, with the base at the low (`base_low`) or
/// high side across the strip. The nominal plate points +y from its base.
fn rotation_for(u_axis: usize, base_low: bool) -> f64 {
    match (u_axis, base_low) {
        (0, true) => 0.0,
        (0, false) => 180.0,
        (_, true) => 270.0, // base at low x: the plate points +x
        (_, false) => 90.0,
    }
}

struct Planner<'a> {
    shapes: &'a [Shape],
    half_kerf: f64,
    margin: f64,
    budget: std::cell::Cell<usize>,
}

impl Planner<'_> {
    fn clearance(&self, side: Side) -> f64 {
        match side {
            Side::Edge => self.margin,
            Side::Line => self.half_kerf,
        }
    }

    /// The range on `axis` that plate outlines may occupy inside `region`.
    fn inner(&self, region: &Region, axis: usize) -> (f64, f64) {
        (
            region.lo[axis] + self.clearance(region.lo_side[axis]),
            region.hi[axis] - self.clearance(region.hi_side[axis]),
        )
    }

    /// (plates per strip, strips) of item `i` in `region` with strips along `u_axis`.
    fn grid(&self, region: &Region, i: usize, u_axis: usize) -> (usize, usize) {
        let shape = &self.shapes[i];
        let (u0, u1) = self.inner(region, u_axis);
        let (v0, v1) = self.inner(region, 1 - u_axis);
        let per_strip = shape.run_capacity(u1 - u0);
        let strips = if v1 - v0 + EPS < shape.length {
            0
        } else {
            ((v1 - v0 - shape.length) / (shape.length + 2.0 * self.half_kerf) + EPS).floor()
                as usize
                + 1
        };
        (per_strip, strips)
    }

    fn fits(&self, region: &Region, i: usize, u_axis: usize) -> bool {
        let (per_strip, strips) = self.grid(region, i, u_axis);
        per_strip > 0 && strips > 0
    }

    /// Fills `region` with the remaining plates, taking them from `remaining`.
    fn fill(&self, region: &Region, remaining: &mut [usize], depth: usize) -> Plan {
        let Some(i) = (0..self.shapes.len())
            .find(|&i| remaining[i] > 0 && (self.fits(region, i, 0) || self.fits(region, i, 1)))
        else {
            return Plan::default();
        };
        let axes: Vec<usize> = (0..2).filter(|&a| self.fits(region, i, a)).collect();
        if axes.len() == 2 && self.budget.get() > 0 {
            self.budget.set(self.budget.get() - 1);
            let mut best: Option<(Plan, Vec<usize>)> = None;
            for &axis in &axes {
                let mut left = remaining.to_vec();
                let plan = self.fill_strips(region, i, axis, &mut left, depth);
                if best.as_ref().is_none_or(|(b, _)| plan.area > b.area + EPS) {
                    best = Some((plan, left));
                }
            }
            let (plan, left) = best.expect("two candidates");
            remaining.copy_from_slice(&left);
            plan
        } else {
            // One item alone decides: the direction that holds more of what is left.
            let holds = |axis: usize| {
                let (per_strip, strips) = self.grid(region, i, axis);
                (per_strip * strips).min(remaining[i])
            };
            let axis = axes.iter().copied().max_by_key(|&a| (holds(a), 1 - a));
            self.fill_strips(region, i, axis.expect("item fits"), remaining, depth)
        }
    }

    /// Fills `region` with strips of item `i` running along `u_axis` from the low side across,
    /// then the strip leftovers and the rest of the region with whatever fits.
    fn fill_strips(
        &self,
        region: &Region,
        i: usize,
        u_axis: usize,
        remaining: &mut [usize],
        depth: usize,
    ) -> Plan {
        let (ua, va) = (u_axis, 1 - u_axis);
        let shape = &self.shapes[i];
        let mut plan = Plan::default();
        let mut rest = Some(*region);
        while let Some(region) = rest {
            if remaining[i] == 0 {
                break;
            }
            let (u_in0, u_in1) = self.inner(&region, ua);
            let (v_in0, v_in1) = self.inner(&region, va);
            let capacity = shape.run_capacity(u_in1 - u_in0);
            if capacity == 0 || v_in0 + shape.length > v_in1 + EPS {
                break;
            }
            let n = capacity.min(remaining[i]);
            remaining[i] -= n;

            // Strip boundaries half a kerf off the plates, unless the region side is already there
            // (a score line) or the line would fall outside the sheet (margin below half a kerf).
            let plate_v0 = v_in0;
            let plate_v1 = v_in0 + shape.length;
            let mut strip = region;
            let (bottom, top) = (plate_v0 - self.half_kerf, plate_v1 + self.half_kerf);
            if bottom > region.lo[va] + EPS {
                plan.lines.push((
                    depth,
                    [
                        point(ua, region.lo[ua], bottom),
                        point(ua, region.hi[ua], bottom),
                    ],
                ));
                strip.lo[va] = bottom;
                strip.lo_side[va] = Side::Line;
            }
            rest = None;
            if top < region.hi[va] - EPS {
                plan.lines.push((
                    depth,
                    [point(ua, region.lo[ua], top), point(ua, region.hi[ua], top)],
                ));
                strip.hi[va] = top;
                strip.hi_side[va] = Side::Line;
                let mut beyond = region;
                beyond.lo[va] = top;
                beyond.lo_side[va] = Side::Line;
                rest = Some(beyond);
            }

            // The run: plate k centred at centre0 + k * pitch, every other one turned 180°.
            let centre0 = u_in0 + shape.width / 2.0;
            let run_end = u_in0 + shape.width + (n - 1) as f64 * shape.pitch;
            for k in 0..n {
                let centre = centre0 + k as f64 * shape.pitch;
                plan.plates.push(PlatePos {
                    item: i,
                    rotation_deg: rotation_for(ua, k % 2 == 0),
                    bbox_min: point(ua, centre - shape.width / 2.0, plate_v0),
                });
            }
            plan.area += n as f64 * shape.area;

            // The leftover at the end of the strip, split off by a cross cut if anything fits.
            let mut run_region = strip;
            let mut slanted_depth = depth + 1;
            let cut = run_end + self.half_kerf;
            if cut < strip.hi[ua] - EPS {
                let mut leftover = strip;
                leftover.lo[ua] = cut;
                leftover.lo_side[ua] = Side::Line;
                let sub = self.fill(&leftover, remaining, depth + 2);
                if !sub.plates.is_empty() {
                    plan.lines.push((
                        depth + 1,
                        [point(ua, cut, strip.lo[va]), point(ua, cut, strip.hi[va])],
                    ));
                    slanted_depth = depth + 2;
                    run_region.hi[ua] = cut;
                    run_region.hi_side[ua] = Side::Line;
                    plan.append(sub);
                }
            }
            let slanted = self.slanted_lines(shape, &run_region, ua, centre0, plate_v0, n);
            plan.lines
                .extend(slanted.into_iter().map(|l| (slanted_depth, l)));
        }
        if let Some(region) = rest {
            let more = self.fill(&region, remaining, depth + 1);
            plan.append(more);
        }
        plan
    }

    /// Score lines of a run of `n` plates: one before the first plate, one after each plate,
    /// each clipped to `run_region` so that it ends on the region's sides.
    fn slanted_lines(
        &self,
        shape: &Shape,
        run_region: &Region,
        ua: usize,
        centre0: f64,
        plate_v0: f64,
        n: usize,
    ) -> Vec<[Point; 2]> {
        let va = 1 - ua;
        let (b, t, l) = (shape.base, shape.tip, shape.length);
        // A line is u(v) = u_at_plate_v0 + (v - plate_v0) * slope.
        let mut lines = vec![(centre0 - b / 2.0 - shape.edge_to_line, (b - t) / (2.0 * l))];
        for k in 0..n {
            let centre = centre0 + k as f64 * shape.pitch;
            lines.push(if k % 2 == 0 {
                (centre + b / 2.0 + shape.edge_to_line, (t - b) / (2.0 * l))
            } else {
                (centre + t / 2.0 + shape.edge_to_line, (b - t) / (2.0 * l))
            });
        }
        let (u_lo, u_hi) = (run_region.lo[ua], run_region.hi[ua]);
        let (v_lo, v_hi) = (run_region.lo[va], run_region.hi[va]);
        let mut out = Vec::new();
        for (u_at, slope) in lines {
            let u_of = |v: f64| u_at + (v - plate_v0) * slope;
            if slope.abs() < 1e-15 {
                if u_at > u_lo + EPS && u_at < u_hi - EPS {
                    out.push([point(ua, u_at, v_lo), point(ua, u_at, v_hi)]);
                }
                continue;
            }
            // The v at which the line meets each u side; the part between them lies inside.
            let v_at_lo = plate_v0 + (u_lo - u_at) / slope;
            let v_at_hi = plate_v0 + (u_hi - u_at) / slope;
            let (v_a, u_a_side, v_b, u_b_side) = if v_at_lo < v_at_hi {
                (v_at_lo, u_lo, v_at_hi, u_hi)
            } else {
                (v_at_hi, u_hi, v_at_lo, u_lo)
            };
            let start = if v_a > v_lo {
                point(ua, u_a_side, v_a)
            } else {
                point(ua, u_of(v_lo), v_lo)
            };
            let end = if v_b < v_hi {
                point(ua, u_b_side, v_b)
            } else {
                point(ua, u_of(v_hi), v_hi)
            };
            if v_b.min(v_hi) - v_a.max(v_lo) > EPS {
                out.push([start, end]);
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::layout::verify::{
        verify_break_order, verify_copies, verify_outlines, verify_sheet_edges, verify_snappable,
        Violation,
    };
    use cam_geometry::signed_area;
    use proptest::prelude::*;

    fn plate(length_mm: f64, base_width_mm: f64, tip_width_mm: f64, count: usize) -> PlateSpec {
        PlateSpec {
            length_mm,
            base_width_mm,
            tip_width_mm,
            count,
        }
    }

    /// Thesis design C: l_p = 42.2 mm / 1.833, base 5.0 mm, tip 1.0 mm.
    fn design_c(count: usize) -> PlateSpec {
        PlateSpec {
            length_mm: 42.2 / 1.833,
            base_width_mm: 5.0,
            tip_width_mm: 1.0,
            count,
        }
    }

    const PZT_SHEET: Sheet = Sheet {
        width_mm: 72.4,
        height_mm: 72.4,
    };

    /// Runs every verifier on a plate layout and checks the copies add up.
    fn check_layout(
        items: &[PlateSpec],
        sheet: &Sheet,
        kerf: f64,
        margin: f64,
        sheets: &[SheetLayout],
    ) {
        let any_rotation = |_: usize| vec![0.0, 90.0, 180.0, 270.0];
        let nominal = |i: usize| plate_outline(&items[i]);
        for layout in sheets {
            verify_snappable(layout, sheet)
                .unwrap_or_else(|v| panic!("sheet {} not snappable: {v:?}", layout.sheet_index));
            verify_break_order(layout, sheet)
                .unwrap_or_else(|v| panic!("sheet {} break order: {v:?}", layout.sheet_index));
            verify_sheet_edges(layout, sheet, kerf - 1e-9, margin - 1e-9, &any_rotation)
                .unwrap_or_else(|v| panic!("sheet {} invalid: {v:?}", layout.sheet_index));
            verify_outlines(layout, &nominal, 1e-9)
                .unwrap_or_else(|v| panic!("sheet {} outlines: {v:?}", layout.sheet_index));
        }
        let counts: Vec<usize> = items.iter().map(|s| s.count).collect();
        verify_copies(sheets, &counts).unwrap();
    }

    #[test]
    fn design_c_fills_a_pzt_sheet() {
        for (margin, expected) in [(0.5, 66), (0.0, 69)] {
            let items = [design_c(200)];
            let sheets = layout_plates(&items, &PZT_SHEET, 0.03, margin, None).unwrap();
            check_layout(&items, &PZT_SHEET, 0.03, margin, &sheets);
            let first = &sheets[0];
            let count = first.placements.len();
            assert!(count >= 66, "margin {margin}: {count} plates");
            assert_eq!(count, expected, "margin {margin}");
            let nominal_area = 3.0 * 42.2 / 1.833;
            for p in &first.placements {
                assert!((signed_area(&p.outline) - nominal_area).abs() < 1e-9);
            }
            let fill = count as f64 * nominal_area / (72.4 * 72.4);
            assert!(fill > 0.869, "margin {margin}: fill {fill}");
        }
    }

    #[test]
    fn design_c_stock_limit() {
        let ok = layout_plates(&[design_c(66)], &PZT_SHEET, 0.03, 0.5, Some(1)).unwrap();
        assert_eq!(ok.len(), 1);
        let err = layout_plates(&[design_c(133)], &PZT_SHEET, 0.03, 0.5, Some(2)).unwrap_err();
        assert_eq!(err.to_string(), "needs 3 sheets but the stock is 2");
    }

    #[test]
    fn design_c_score_lines_are_the_strip_pattern() {
        let sheets = layout_plates(&[design_c(66)], &PZT_SHEET, 0.03, 0.5, Some(1)).unwrap();
        let lines = &sheets[0].score_lines;
        let horizontal = lines.iter().filter(|l| l[0][1] == l[1][1]).count();
        // Bottom trim, two strip boundaries, top trim first; then 23 slanted lines in each of
        // 3 strips.
        assert_eq!(horizontal, 4);
        assert!(lines[..4].iter().all(|l| l[0][1] == l[1][1]));
        assert_eq!(lines.len(), 4 + 3 * 23);
        for l in lines.iter().filter(|l| l[0][1] == l[1][1]) {
            assert_eq!(
                (l[0][0], l[1][0]),
                (0.0, 72.4),
                "strip boundaries run edge to edge"
            );
        }
    }

    #[test]
    fn verifier_catches_a_tampered_design_c_sheet() {
        let layout = &layout_plates(&[design_c(66)], &PZT_SHEET, 0.03, 0.5, Some(1)).unwrap()[0];
        let any = |_: usize| vec![0.0, 90.0, 180.0, 270.0];
        // Drop a slanted line between two neighbours: they now share a cell.
        let mut missing = layout.clone();
        let slanted = missing
            .score_lines
            .iter()
            .rposition(|l| l[0][0] != l[1][0] && l[0][1] != l[1][1])
            .unwrap();
        missing.score_lines.remove(slanted - 1);
        let v = verify_snappable(&missing, &PZT_SHEET).unwrap_err();
        assert!(matches!(&v[..], [Violation::SharedCell { .. }]), "{v:?}");
        // Push one plate 0.02 mm towards its neighbour: below the kerf, and across a score line.
        let mut pushed = layout.clone();
        for p in &mut pushed.placements[1].outline {
            p[0] -= 0.02;
        }
        let v = verify_sheet_edges(&pushed, &PZT_SHEET, 0.03 - 1e-9, 0.5 - 1e-9, &any).unwrap_err();
        assert!(
            matches!(&v[..], [Violation::Gap { a, b, .. }] if a.index == 0 && b.index == 1),
            "{v:?}"
        );
        let v = verify_snappable(&pushed, &PZT_SHEET).unwrap_err();
        assert!(
            v.iter().any(
                |x| matches!(x, Violation::ScoreLineCrossesPlate { part, .. } if part.index == 1)
            ),
            "{v:?}"
        );
    }

    #[test]
    fn rectangular_plates() {
        let items = [plate(50.0, 10.0, 10.0, 20)];
        let sheets = layout_plates(&items, &PZT_SHEET, 0.03, 0.5, None).unwrap();
        check_layout(&items, &PZT_SHEET, 0.03, 0.5, &sheets);
        // 7 upright in one 50 mm strip, 2 lying in the 21.4 mm left above it.
        assert_eq!(sheets[0].placements.len(), 9);
        assert_eq!(sheets.len(), 3);
        let lines = &sheets[0].score_lines;
        assert!(lines
            .iter()
            .all(|l| l[0][0] == l[1][0] || l[0][1] == l[1][1]));
    }

    #[test]
    fn mixed_items_share_a_sheet() {
        let items = [design_c(40), plate(15.0, 4.0, 2.0, 30)];
        let sheets = layout_plates(&items, &PZT_SHEET, 0.03, 0.5, None).unwrap();
        check_layout(&items, &PZT_SHEET, 0.03, 0.5, &sheets);
        assert_eq!(sheets.len(), 1, "40 C plates leave room for 30 small ones");
        // Same input, same output.
        assert_eq!(
            sheets,
            layout_plates(&items, &PZT_SHEET, 0.03, 0.5, None).unwrap()
        );
    }

    #[test]
    fn too_large_plate_is_reported() {
        let items = [plate(80.0, 10.0, 10.0, 1)];
        let err = layout_plates(&items, &PZT_SHEET, 0.03, 0.5, None).unwrap_err();
        assert!(matches!(err, LayoutError::TooLarge { item: 0, .. }));
        assert!(err.to_string().starts_with(
            "item 0 is larger than the sheet: 10.0 x 80.0 mm on a 72.4 x 72.4 mm sheet"
        ));
    }

    #[test]
    fn invalid_input_is_reported() {
        let mut bad = design_c(1);
        bad.tip_width_mm = 0.0;
        assert!(matches!(
            layout_plates(&[bad], &PZT_SHEET, 0.03, 0.5, None),
            Err(LayoutError::InvalidItem { item: 0, .. })
        ));
        assert!(matches!(
            layout_plates(&[design_c(1)], &PZT_SHEET, -0.1, 0.5, None),
            Err(LayoutError::InvalidParameter {
                name: "kerf_mm",
                ..
            })
        ));
    }

    #[test]
    fn kerf_zero_plates_share_edges() {
        let items = [design_c(30)];
        let sheets = layout_plates(&items, &PZT_SHEET, 0.0, 0.0, None).unwrap();
        check_layout(&items, &PZT_SHEET, 0.0, 0.0, &sheets);
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]
        #[test]
        fn random_trapezoids_verify(
            length in 5.0..60.0f64,
            base in 1.0..25.0f64,
            tip in 0.3..25.0f64,
            count in 1usize..40,
            kerf in 0.0..0.05f64,
            margin in 0.0..1.0f64,
            side in 20.0..100.0f64,
            second in proptest::option::of((5.0..30.0f64, 1.0..10.0f64, 0.3..10.0f64, 1usize..20)),
        ) {
            let sheet = Sheet { width_mm: side, height_mm: side * 0.8 };
            let mut items = vec![PlateSpec { length_mm: length, base_width_mm: base, tip_width_mm: tip, count }];
            if let Some((l, b, t, n)) = second {
                items.push(PlateSpec { length_mm: l, base_width_mm: b, tip_width_mm: t, count: n });
            }
            match layout_plates(&items, &sheet, kerf, margin, None) {
                Ok(sheets) => check_layout(&items, &sheet, kerf, margin, &sheets),
                Err(LayoutError::TooLarge { item, .. }) => {
                    let s = &items[item];
                    let room = |a: f64, b: f64| a <= side - 2.0 * margin + 1e-9 && b <= side * 0.8 - 2.0 * margin + 1e-9;
                    let w = s.base_width_mm.max(s.tip_width_mm);
                    prop_assert!(!room(w, s.length_mm) && !room(s.length_mm, w));
                }
                Err(e) => prop_assert!(false, "unexpected error {e}"),
            }
        }
    }
}
