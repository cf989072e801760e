//! The guillotine planner behind [`super::layout_plates`]: a sheet split recursively into regions, a
//! strip of one item across each (plates turned alternately by 180°), the leftover at the end of the
//! strip and the rest of the region filled in turn, with the slanted score lines between neighbours.
//!
//! The score lines are planned here and drawn in `crate::pipeline::score_lines` (the PZT sheets'
//! layer files), after `crate::pipeline::place` has checked the plan with the verifier.

use super::{plate_outline, PlateSpec};
use crate::layout::LayoutError;
use cam_geometry::Point;

/// Tolerance for comparing positions, mm.
pub(super) const EPS: f64 = 1e-9;

/// How many two-way choices (strip direction) a sheet may explore before it settles each
/// further choice by a one-item estimate. A count, not a time, so the result is reproducible.
pub(super) const SEARCH_BUDGET: usize = 2048;

/// Plate geometry derived once per item.
pub(super) struct Shape {
    pub(super) nominal: Vec<Point>,
    pub(super) length: f64,
    base: f64,
    tip: f64,
    /// Bounding width, max(base, tip).
    pub(super) width: f64,
    /// Distance along the strip from a slanted plate edge to its score line:
    /// `(kerf / 2) / cos θ`, `tan θ = (base - tip) / (2 l_p)`.
    edge_to_line: f64,
    /// `1 / cos θ` of the slanted edges.
    sec: f64,
    /// Distance along the strip between the centres of neighbouring plates:
    /// `(base + tip) / 2 + kerf / cos θ`.
    pitch: f64,
    area: f64,
}

impl Shape {
    pub(super) fn new(item: usize, spec: &PlateSpec, kerf: f64) -> Result<Shape, LayoutError> {
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
            sec,
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
pub(super) enum Side {
    /// The sheet edge: plates keep `margin` from it.
    Edge,
    /// A score line: plates keep half the kerf from it.
    Line,
}

/// An axis-aligned rectangle of the guillotine tree. Index 0 is x, 1 is y. Every side lies on
/// the sheet edge or within one score line over its whole length.
#[derive(Debug, Clone, Copy)]
pub(super) struct Region {
    pub(super) lo: [f64; 2],
    pub(super) hi: [f64; 2],
    pub(super) lo_side: [Side; 2],
    pub(super) hi_side: [Side; 2],
}

/// A plate placed by the planner, before copy numbers are assigned.
pub(super) struct PlatePos {
    pub(super) item: usize,
    pub(super) rotation_deg: f64,
    pub(super) bbox_min: Point,
}

/// The plates and score lines of one region. Each line carries its depth in the guillotine tree:
/// its ends rest on the sheet edge or on lines of smaller depth, so sorting by depth gives a
/// break order that starts with the lines across the whole sheet.
#[derive(Default)]
pub(super) struct Plan {
    pub(super) plates: Vec<PlatePos>,
    pub(super) lines: Vec<(usize, [Point; 2])>,
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
pub(super) fn point(u_axis: usize, u: f64, v: f64) -> Point {
    let mut p = [0.0; 2];
    p[u_axis] = u;
    p[1 - u_axis] = v;
    p
}

/// Plate rotation for a strip running along `u_axis`, with the base at the low (`base_low`) or
/// high side across the strip. The nominal plate points +y from its base.
pub(super) fn rotation_for(u_axis: usize, base_low: bool) -> f64 {
    match (u_axis, base_low) {
        (0, true) => 0.0,
        (0, false) => 180.0,
        (_, true) => 270.0, // base at low x: the plate points +x
        (_, false) => 90.0,
    }
}

pub(super) struct Planner<'a> {
    pub(super) shapes: &'a [Shape],
    pub(super) half_kerf: f64,
    pub(super) margin: f64,
    /// Narrowest offcut a score line may leave, mm (docs/cam.md §4, "Snappable strips"); 0: any.
    pub(super) min_strip: f64,
    pub(super) budget: std::cell::Cell<usize>,
}

/// How a run of plates along a strip ends: how many plates, where the first one's bounding box
/// starts, and the cross cut its far end needs (if any) so that no offcut is a sliver.
struct Run {
    n: usize,
    u_start: f64,
    end_cut: Option<f64>,
}

impl Planner<'_> {
    fn clearance(&self, side: Side) -> f64 {
        match side {
            Side::Edge => self.edge_clearance(),
            Side::Line => self.half_kerf,
        }
    }

    /// Distance from the sheet edge to the plates. A margin within half a kerf needs no trim line:
    /// the plates' edge is the sheet edge. A wider one is trimmed off by a score line half a kerf
    /// off the plates, and the strip it leaves must be wide enough to snap (docs/cam.md §4), so the
    /// margin grows to half a kerf plus the narrowest snappable strip when that is more.
    pub(super) fn edge_clearance(&self) -> f64 {
        if self.margin <= self.half_kerf {
            self.margin
        } else {
            self.margin.max(self.half_kerf + self.min_strip)
        }
    }

    /// The offcut between the outer slanted score line of a run's end plate and the region side
    /// `c` mm from the plate's bounding box, for a strip reaching `d0` below and `d1` above the
    /// plates: the gap along the strip between line and side at the strip's two boundaries is
    /// `c + a0` and `c + a1`. The same two numbers hold at the start and at the far end of a run
    /// (the far plate mirrored); `base_low` is whether the end plate has its base on the low side.
    fn offcut_offsets(&self, shape: &Shape, base_low: bool, d0: f64, d1: f64) -> (f64, f64) {
        let (w, b, t, l) = (shape.width, shape.base, shape.tip, shape.length);
        let m = (b - t) / (2.0 * l);
        let e = shape.edge_to_line;
        if base_low {
            ((w - b) / 2.0 - e - d0 * m, (w - b) / 2.0 - e + (l + d1) * m)
        } else {
            ((w - t) / 2.0 - e + d0 * m, (w - t) / 2.0 - e - (l + d1) * m)
        }
    }

    /// Whether the offcut at a run end `c` mm from the side can be snapped: there is none (the
    /// score line lies on the side or outside), or it is at least `min_strip` wide square to the
    /// score line at both its ends (docs/cam.md §4).
    fn offcut_ok(&self, shape: &Shape, c: f64, base_low: bool, d0: f64, d1: f64) -> bool {
        let (a0, a1) = self.offcut_offsets(shape, base_low, d0, d1);
        let (g0, g1) = (c + a0, c + a1);
        self.min_strip <= 0.0 || g0.max(g1) <= EPS || g0.min(g1) / shape.sec >= self.min_strip - EPS
    }

    /// The least distance `c >= base` from a run end to the region side that leaves a snappable
    /// offcut (any larger distance leaves one too, unless `base` itself leaves none).
    fn offcut_clearance(&self, shape: &Shape, base: f64, base_low: bool, d0: f64, d1: f64) -> f64 {
        if self.offcut_ok(shape, base, base_low, d0, d1) {
            return base;
        }
        let (a0, a1) = self.offcut_offsets(shape, base_low, d0, d1);
        (self.min_strip * shape.sec - a0.min(a1)).max(base)
    }

    /// The run of at most `max_n` plates of `shape` along `ua` across `region`, for a strip reaching
    /// `d0` below and `d1` above the plates: the first plate as close to the low side as a snappable
    /// offcut allows, as many as fit, and at the far end either a snappable offcut up to the side
    /// or a cross cut that leaves one on each side of it. `n` is 0 when none fits.
    fn run(
        &self,
        region: &Region,
        ua: usize,
        shape: &Shape,
        d0: f64,
        d1: f64,
        max_n: usize,
    ) -> Run {
        let (lo, hi) = (region.lo[ua], region.hi[ua]);
        let c_lo = self.offcut_clearance(shape, self.clearance(region.lo_side[ua]), true, d0, d1);
        let u_start = lo + c_lo;
        let base_hi = self.clearance(region.hi_side[ua]);
        let c_hi = [true, false]
            .map(|base_low| self.offcut_clearance(shape, base_hi, base_low, d0, d1))
            .into_iter()
            .fold(base_hi, f64::max);
        let capacity = shape.run_capacity(hi - c_hi - u_start).min(max_n);
        for n in (1..=capacity).rev() {
            let run_end = u_start + shape.width + (n - 1) as f64 * shape.pitch;
            let base_low = (n - 1).is_multiple_of(2);
            if self.offcut_ok(shape, hi - run_end, base_low, d0, d1) {
                return Run {
                    n,
                    u_start,
                    end_cut: None,
                };
            }
            let cut = run_end + self.offcut_clearance(shape, self.half_kerf, base_low, d0, d1);
            if hi - cut >= self.min_strip - EPS {
                return Run {
                    n,
                    u_start,
                    end_cut: Some(cut),
                };
            }
        }
        Run {
            n: 0,
            u_start,
            end_cut: None,
        }
    }

    /// How far a strip whose plates start at `plate_v0` reaches below and above them: half a kerf to
    /// its boundary score lines, or less where the region side is closer (no line is drawn there).
    fn strip_reach(&self, region: &Region, va: usize, plate_v0: f64, length: f64) -> (f64, f64) {
        (
            self.half_kerf.min(plate_v0 - region.lo[va]).max(0.0),
            self.half_kerf
                .min(region.hi[va] - plate_v0 - length)
                .max(0.0),
        )
    }

    /// Whether a strip whose top score line lies at `top` leaves a snappable offcut above it: the
    /// line is on the region side (no offcut), or the rest is at least `min_strip` wide.
    fn top_ok(&self, region: &Region, va: usize, top: f64) -> bool {
        let rest = region.hi[va] - top;
        rest <= EPS || rest >= self.min_strip - EPS
    }

    /// The range on `axis` that plate outlines may occupy inside `region`.
    pub(super) fn inner(&self, region: &Region, axis: usize) -> (f64, f64) {
        (
            region.lo[axis] + self.clearance(region.lo_side[axis]),
            region.hi[axis] - self.clearance(region.hi_side[axis]),
        )
    }

    /// (plates per strip, strips) of item `i` in `region` with strips along `u_axis`.
    fn grid(&self, region: &Region, i: usize, u_axis: usize) -> (usize, usize) {
        let shape = &self.shapes[i];
        let va = 1 - u_axis;
        let (v0, v1) = self.inner(region, va);
        let (d0, d1) = self.strip_reach(region, va, v0, shape.length);
        let per_strip = self.run(region, u_axis, shape, d0, d1, usize::MAX).n;
        let pitch = shape.length + 2.0 * self.half_kerf;
        let fitting = if v1 - v0 + EPS < shape.length {
            0
        } else {
            ((v1 - v0 - shape.length) / pitch + EPS).floor() as usize + 1
        };
        // Strips are laid from the low side and stop at the first that would leave a sliver.
        let strips = (0..fitting)
            .take_while(|&k| {
                let top = v0 + k as f64 * pitch + shape.length + self.half_kerf;
                self.top_ok(region, va, top)
            })
            .count();
        (per_strip, strips)
    }

    pub(super) fn fits(&self, region: &Region, i: usize, u_axis: usize) -> bool {
        let (per_strip, strips) = self.grid(region, i, u_axis);
        per_strip > 0 && strips > 0
    }

    /// Fills `region` with the remaining plates, taking them from `remaining`.
    pub(super) fn fill(&self, region: &Region, remaining: &mut [usize], depth: usize) -> Plan {
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
            let (v_in0, v_in1) = self.inner(&region, va);
            if v_in0 + shape.length > v_in1 + EPS {
                break;
            }
            // Strip boundaries half a kerf off the plates, unless the region side is already there
            // (a score line) or the line would fall outside the sheet (margin below half a kerf).
            // A strip whose top line would leave a sliver of the region above it is not laid.
            let plate_v0 = v_in0;
            let plate_v1 = v_in0 + shape.length;
            let (bottom, top) = (plate_v0 - self.half_kerf, plate_v1 + self.half_kerf);
            if !self.top_ok(&region, va, top) {
                break;
            }
            let (d0, d1) = self.strip_reach(&region, va, plate_v0, shape.length);
            let run = self.run(&region, ua, shape, d0, d1, remaining[i]);
            if run.n == 0 {
                break;
            }
            let n = run.n;
            remaining[i] -= n;

            let mut strip = region;
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
            let centre0 = run.u_start + shape.width / 2.0;
            let run_end = run.u_start + shape.width + (n - 1) as f64 * shape.pitch;
            for k in 0..n {
                let centre = centre0 + k as f64 * shape.pitch;
                plan.plates.push(PlatePos {
                    item: i,
                    rotation_deg: rotation_for(ua, k % 2 == 0),
                    bbox_min: point(ua, centre - shape.width / 2.0, plate_v0),
                });
            }
            plan.area += n as f64 * shape.area;

            // The leftover at the end of the strip, split off by a cross cut if anything fits there
            // or if the offcut up to the region side would be a sliver (then both offcuts of the
            // cut are snappable, `run` made sure).
            let mut run_region = strip;
            let mut slanted_depth = depth + 1;
            let last_base_low = (n - 1).is_multiple_of(2);
            let (cut, forced) = match run.end_cut {
                Some(cut) => (cut, true),
                None => (
                    run_end + self.offcut_clearance(shape, self.half_kerf, last_base_low, d0, d1),
                    false,
                ),
            };
            if cut < strip.hi[ua] - EPS {
                let mut leftover = strip;
                leftover.lo[ua] = cut;
                leftover.lo_side[ua] = Side::Line;
                let sub = self.fill(&leftover, remaining, depth + 2);
                if forced || !sub.plates.is_empty() {
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
        if plan.plates.is_empty() {
            // Nothing of this item fits after all (a run that would leave slivers): leave the region
            // to the caller rather than filling it again with the same choice.
            return plan;
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
