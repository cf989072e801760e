//! A validated nesting job: what both nesters work from, and how their placements become a
//! [`NestSolution`].

use cam_geometry::{area, place_ring, Bounds, Point};

use crate::problem::{
    NestBin, NestError, NestItem, NestSettings, NestSolution, NestedBin, PlacedPart, SheetShape,
};

/// Copies from which a job gets the whole iteration budget (the bench's 60-actuator batches).
const FULL_BUDGET_COPIES: usize = 60;
/// Fewest iterations a smaller job gets (unless the budget is smaller).
const MIN_BUDGET: usize = 100;

/// An item after validation: what both nesters work from.
#[derive(Debug, Clone)]
pub(crate) struct Part {
    /// Index into the caller's `items`.
    pub item: usize,
    pub outline: Vec<Point>,
    pub area: f64,
    pub demand: usize,
    /// Allowed rotations, deduplicated modulo 360°, values as the caller gave them.
    pub rotations_deg: Vec<f64>,
}

impl Part {
    /// Width and height of the axis-aligned bounding box at a rotation.
    pub fn bbox_size(&self, rotation_deg: f64) -> [f64; 2] {
        box_size(&self.outline, rotation_deg)
    }
}

/// One part copy as a nester placed it: part index, rotation index, translation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Placed {
    pub part: usize,
    pub rot: usize,
    pub translation: Point,
}

/// A validated job: parts with positive demand, a sheet, settings.
#[derive(Debug, Clone)]
pub(crate) struct Job {
    pub parts: Vec<Part>,
    pub bin: NestBin,
    pub settings: NestSettings,
    /// The sheet's outline and keep-outs, if it is not the whole rectangle of `bin`.
    pub shape: SheetShape,
    /// Largest coordinate a placement can reach, mm: the sheet's longer side, or for an endless
    /// sheet (the strip's probe) the parts laid end to end.
    extent_mm: f64,
}

impl Job {
    /// Checks the caller's input; everything downstream trusts it.
    pub fn new(
        items: &[NestItem],
        bin: &NestBin,
        settings: &NestSettings,
    ) -> Result<Self, NestError> {
        let bad = |msg: String| Err(NestError::BadSettings(msg));
        if !(bin.width_mm.is_finite() && bin.width_mm > 0.0) {
            return bad(format!("sheet width_mm must be > 0, got {}", bin.width_mm));
        }
        if !(bin.height_mm.is_finite() && bin.height_mm > 0.0) {
            return bad(format!(
                "sheet height_mm must be > 0, got {}",
                bin.height_mm
            ));
        }
        if !(settings.separation_mm.is_finite() && settings.separation_mm >= 0.0) {
            return bad(format!(
                "separation_mm must be finite and >= 0, got {}",
                settings.separation_mm
            ));
        }
        if settings.workers == 0 {
            return bad("workers must be at least 1".into());
        }
        let mut parts = Vec::new();
        for (index, item) in items.iter().enumerate() {
            let part = validate_item(index, item)?;
            if part.demand > 0 {
                parts.push(part);
            }
        }
        // Every copy laid end to end: no layout on the sheet reaches further.
        let end_to_end: f64 = parts
            .iter()
            .map(|p| p.demand as f64 * reach(&p.outline, settings.separation_mm))
            .sum();
        let job = Self {
            parts,
            bin: *bin,
            settings: *settings,
            shape: SheetShape::default(),
            extent_mm: bin.width_mm.max(bin.height_mm.min(end_to_end)),
        };
        job.check_sizes()?;
        Ok(job)
    }

    /// The job on a sheet of `shape` ([`SheetShape`]): each ring of at least three finite points.
    pub fn with_shape(mut self, shape: &SheetShape) -> Result<Self, NestError> {
        let rings = std::iter::once(&shape.outline)
            .filter(|o| !o.is_empty())
            .chain(&shape.keep_outs);
        for ring in rings {
            let ring = clean_ring(ring);
            if ring.len() < 3 || ring.iter().flatten().any(|v| !v.is_finite()) {
                return Err(NestError::BadSettings(
                    "a sheet outline or keep-out needs at least three finite points".into(),
                ));
            }
        }
        self.shape = shape.clone();
        Ok(self)
    }

    /// Gap the jagua-rs model keeps: the requested separation plus a margin that covers its f32
    /// coordinates and the chords of its round offset joins (<= 0.125 % of the offset).
    pub fn model_separation(&self) -> f64 {
        model_separation(self.settings.separation_mm, self.model_margin())
    }

    /// The part of [`Job::model_separation`] that covers the model's f32 coordinates, mm.
    pub fn model_margin(&self) -> f64 {
        f32_margin(self.extent_mm)
    }

    /// Gap a part needs to each edge of an empty sheet, mm: what the size check
    /// ([`fits_empty_sheet`]) adds on either side of a part's box.
    pub fn edge_gap_mm(&self) -> f64 {
        edge_gap(self.settings.separation_mm, self.model_margin())
    }

    /// Every part must fit an empty sheet at some allowed rotation.
    fn check_sizes(&self) -> Result<(), NestError> {
        for part in &self.parts {
            let fit = fits_with_gap(
                &part.outline,
                &part.rotations_deg,
                self.bin.width_mm,
                self.bin.height_mm,
                self.settings.separation_mm,
                self.model_margin(),
            );
            if !fit.fits {
                return Err(NestError::PartLargerThanBin {
                    item: part.item,
                    part_width_mm: fit.size_mm[0],
                    part_height_mm: fit.size_mm[1],
                    bin_width_mm: self.bin.width_mm,
                    bin_height_mm: self.bin.height_mm,
                    separation_mm: self.settings.separation_mm,
                    edge_gap_mm: fit.edge_gap_mm,
                });
            }
        }
        Ok(())
    }

    /// Total area of the copies to place, mm².
    pub fn part_area(&self) -> f64 {
        self.parts.iter().map(|p| p.area * p.demand as f64).sum()
    }

    /// Total number of copies to place.
    pub fn copies(&self) -> usize {
        self.parts.iter().map(|p| p.demand).sum()
    }

    /// The error for part `p` when no sheet takes it: its box at its first allowed rotation
    /// against the sheet.
    pub fn too_large(&self, p: usize) -> NestError {
        let part = &self.parts[p];
        let size = part.bbox_size(part.rotations_deg[0]);
        NestError::PartLargerThanBin {
            item: part.item,
            part_width_mm: size[0],
            part_height_mm: size[1],
            bin_width_mm: self.bin.width_mm,
            bin_height_mm: self.bin.height_mm,
            separation_mm: self.settings.separation_mm,
            edge_gap_mm: edge_gap(self.settings.separation_mm, self.model_margin()),
        }
    }

    /// The optimiser's iterations for this job: the whole budget from `FULL_BUDGET_COPIES` copies
    /// up, a proportional share below (at least `MIN_BUDGET`, never more than the budget). A move
    /// costs about as much on 16 parts as on 300 (it reinserts up to 16), so a fixed budget made
    /// a small batch on a mostly empty sheet take seconds for nothing: the example batch's layout
    /// is the same after 100 iterations as after 1000. Counted in iterations, never in time.
    pub fn iteration_budget(&self) -> usize {
        let full = self.settings.iterations;
        let share = full.saturating_mul(self.copies()) / FULL_BUDGET_COPIES;
        share.clamp(full.min(MIN_BUDGET), full)
    }

    /// Builds the solution from placed copies sheet by sheet, ordering sheets fullest first and
    /// numbering copies in that order; fails if stock is exceeded.
    pub fn solution(&self, sheets: Vec<Vec<Placed>>) -> Result<NestSolution, NestError> {
        if sheets.len() > self.bin.stock {
            return Err(NestError::StockTooSmall {
                needed: sheets.len(),
                stock: self.bin.stock,
            });
        }
        let sheet_area = self.bin.width_mm * self.bin.height_mm;
        let mut filled: Vec<(f64, Vec<Placed>)> = sheets
            .into_iter()
            .map(|s| (s.iter().map(|p| self.parts[p.part].area).sum::<f64>(), s))
            .collect();
        // Stable: equal fills keep their construction order.
        filled.sort_by(|a, b| b.0.total_cmp(&a.0));
        let mut next_copy = vec![0usize; self.parts.len()];
        let bins = filled
            .into_iter()
            .enumerate()
            .map(|(index, (area, placements))| NestedBin {
                index,
                utilization: area / sheet_area,
                parts: placements
                    .into_iter()
                    .map(|placed| {
                        let Placed {
                            part: p,
                            rot,
                            translation,
                        } = placed;
                        let part = &self.parts[p];
                        let rotation_deg = part.rotations_deg[rot];
                        let copy = next_copy[p];
                        next_copy[p] += 1;
                        PlacedPart {
                            item: part.item,
                            copy,
                            rotation_deg,
                            translation,
                            outline: place_ring(&part.outline, rotation_deg, translation),
                        }
                    })
                    .collect(),
                score_lines: Vec::new(),
            })
            .collect();
        Ok(NestSolution { bins })
    }
}

/// Width and height of the axis-aligned bounding box of `outline` turned by `rotation_deg`.
fn box_size(outline: &[Point], rotation_deg: f64) -> [f64; 2] {
    let b = Bounds::of(&place_ring(outline, rotation_deg, [0.0, 0.0]));
    [b.width(), b.height()]
}

/// Fewest f32 steps of the largest coordinate that the model's margin spans: jagua-rs's
/// collision test and the verifier's f64 one disagree by about a step where shapes touch.
const MARGIN_F32_STEPS: f64 = 4.0;
/// Least margin, mm, however small the coordinates: a dozen f32 steps of a 150 mm sheet.
const MIN_MARGIN_MM: f64 = 2e-4;

/// See [`Job::model_separation`]. The margin is paid at every contact and at both edges, so it
/// is kept to a few f32 steps of `extent_mm` rather than a fixed length: on a strip of
/// whole-number parts a few micrometres wider than a row (ESICUP's 40.004 for rows of 40) a fixed
/// 2 µm used up the slack, while on coordinates of 10,000 (albano) 0.2 µm is less than one step.
fn model_separation(separation_mm: f64, margin_mm: f64) -> f64 {
    separation_mm * 1.01 + margin_mm
}

/// See [`Job::model_margin`].
fn f32_margin(extent_mm: f64) -> f64 {
    (MARGIN_F32_STEPS * f64::from(f32::EPSILON) * extent_mm).max(MIN_MARGIN_MM)
}

/// Length one copy of `outline` can take along a sheet, mm: its box's diagonal (no side of its
/// box at any rotation is longer) plus more than its two gaps.
fn reach(outline: &[Point], separation_mm: f64) -> f64 {
    let [w, h] = box_size(outline, 0.0);
    w.hypot(h) + 3.0 * separation_mm + 1.0
}

/// Whether a part fits an empty sheet, as the nesters decide it ([`fits_empty_sheet`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EmptySheetFit {
    /// Fits at some allowed rotation.
    pub fits: bool,
    /// Its bounding box (width, height) at the allowed rotation that comes closest to fitting, mm.
    pub size_mm: [f64; 2],
    /// Gap it needs to each edge, mm: the separation plus the nester's working margin.
    pub edge_gap_mm: f64,
}

/// The size check every nest starts with ([`crate::nest`] and [`crate::nest_strip`] refuse an
/// item with [`NestError::PartLargerThanBin`] when it fails), for a caller that wants to refuse a
/// part in its own terms before nesting: whether `outline` fits an empty `width_mm` x
/// `height_mm` sheet (`height_mm` infinite for a strip) at one of `rotations_deg`, with
/// `separation_mm` to every edge plus the margin the nester's model works with.
///
/// On a sheet, what passes here passes the nester. On a strip the nester's margin grows with the
/// whole job's length (a few f32 steps of it: about 0.01 mm for 20 m of parts), which a check of
/// one part cannot know: a part within that of the strip's width passes here and is refused by the
/// nester, whose [`NestError::PartLargerThanBin`] gives the edge gap it needed.
#[must_use]
pub fn fits_empty_sheet(
    outline: &[Point],
    rotations_deg: &[f64],
    width_mm: f64,
    height_mm: f64,
    separation_mm: f64,
) -> EmptySheetFit {
    // The coordinates of one part on the sheet, which is all the check places.
    let extent_mm = width_mm.max(height_mm.min(reach(outline, separation_mm)));
    fits_with_gap(
        outline,
        rotations_deg,
        width_mm,
        height_mm,
        separation_mm,
        f32_margin(extent_mm),
    )
}

/// Gap a part needs to each edge of an empty sheet, mm: the model's separation, and the half margin
/// the engine keeps each start clear of the edge; 0.005 mm more covers the f32 rounding of the
/// part's box.
fn edge_gap(separation_mm: f64, margin_mm: f64) -> f64 {
    model_separation(separation_mm, margin_mm) + margin_mm / 2.0 + 0.005
}

/// [`fits_empty_sheet`] with the model's f32 margin ([`Job::model_margin`]) given.
fn fits_with_gap(
    outline: &[Point],
    rotations_deg: &[f64],
    width_mm: f64,
    height_mm: f64,
    separation_mm: f64,
    margin_mm: f64,
) -> EmptySheetFit {
    let edge_gap_mm = edge_gap(separation_mm, margin_mm);
    let gap = 2.0 * edge_gap_mm;
    let overshoot = |s: &[f64; 2]| (s[0] + gap - width_mm).max(s[1] + gap - height_mm);
    let size_mm = rotations_deg
        .iter()
        .map(|&r| box_size(outline, r))
        .min_by(|a, b| overshoot(a).total_cmp(&overshoot(b)))
        .unwrap_or([0.0, 0.0]);
    EmptySheetFit {
        fits: !rotations_deg.is_empty() && overshoot(&size_mm) < 0.0,
        size_mm,
        edge_gap_mm,
    }
}

/// The ring without a repeated closing point and without repeated consecutive points: what the
/// nesters place and what placed outlines are made of.
#[must_use]
pub fn clean_ring(outline: &[Point]) -> Vec<Point> {
    let mut ring: Vec<Point> = Vec::with_capacity(outline.len());
    for &p in outline {
        if ring.last() != Some(&p) {
            ring.push(p);
        }
    }
    while ring.len() > 1 && ring.first() == ring.last() {
        ring.pop();
    }
    ring
}

fn validate_item(index: usize, item: &NestItem) -> Result<Part, NestError> {
    let degenerate = |reason: &str| {
        Err(NestError::DegenerateOutline {
            item: index,
            reason: reason.to_string(),
        })
    };
    let outline = clean_ring(&item.outline);
    if outline.len() < 3 {
        return degenerate(&format!("{} points, needs at least 3", outline.len()));
    }
    if outline.iter().flatten().any(|c| !c.is_finite()) {
        return degenerate("non-finite coordinate");
    }
    let b = Bounds::of(&outline);
    let area = area(&outline);
    if area <= 1e-9 * (b.width() * b.height()).max(1e-12) || area < 1e-9 {
        return degenerate("zero area");
    }
    if let Some((i, j)) = self_intersection(&outline) {
        return degenerate(&format!("edges {i} and {j} cross"));
    }
    let mut rotations_deg: Vec<f64> = Vec::new();
    for &r in &item.rotations_deg {
        if !r.is_finite() {
            return Err(NestError::BadRotations {
                item: index,
                rotations: item.rotations_deg.clone(),
            });
        }
        let same = |q: &f64| {
            let d = (q - r).rem_euclid(360.0);
            !(1e-9..=360.0 - 1e-9).contains(&d)
        };
        if !rotations_deg.iter().any(same) {
            rotations_deg.push(r);
        }
    }
    if rotations_deg.is_empty() {
        return Err(NestError::BadRotations {
            item: index,
            rotations: item.rotations_deg.clone(),
        });
    }
    Ok(Part {
        item: index,
        outline,
        area,
        demand: item.demand,
        rotations_deg,
    })
}

/// First pair of non-adjacent edges that touch or cross, if any (O(n²), outlines are small).
fn self_intersection(ring: &[Point]) -> Option<(usize, usize)> {
    let n = ring.len();
    let edge = |i: usize| (ring[i], ring[(i + 1) % n]);
    for i in 0..n {
        for j in i + 1..n {
            if j == i + 1 || (i == 0 && j == n - 1) {
                continue;
            }
            let (a, b) = edge(i);
            let (c, d) = edge(j);
            if segments_touch(a, b, c, d) {
                return Some((i, j));
            }
        }
    }
    None
}

fn segments_touch(a: Point, b: Point, c: Point, d: Point) -> bool {
    let orient = |p: Point, q: Point, r: Point| {
        let v = (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0]);
        if v > 0.0 {
            1
        } else if v < 0.0 {
            -1
        } else {
            0
        }
    };
    let on_segment = |p: Point, q: Point, r: Point| {
        r[0] >= p[0].min(q[0])
            && r[0] <= p[0].max(q[0])
            && r[1] >= p[1].min(q[1])
            && r[1] <= p[1].max(q[1])
    };
    let (o1, o2, o3, o4) = (
        orient(a, b, c),
        orient(a, b, d),
        orient(c, d, a),
        orient(c, d, b),
    );
    (o1 != o2 && o3 != o4)
        || (o1 == 0 && on_segment(a, b, c))
        || (o2 == 0 && on_segment(a, b, d))
        || (o3 == 0 && on_segment(c, d, a))
        || (o4 == 0 && on_segment(c, d, b))
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::test_support::squares_job;

    #[test]
    fn small_jobs_get_a_proportional_share_of_the_iterations() {
        let budget = |copies: usize, iterations: usize| {
            let (items, bin) = squares_job(copies, 10);
            let settings = NestSettings {
                iterations,
                ..NestSettings::default()
            };
            Job::new(&items, &bin, &settings)
                .unwrap()
                .iteration_budget()
        };
        // 60 copies and up: the whole budget (the bench's batches keep their figures).
        assert_eq!(budget(60, 1000), 1000);
        assert_eq!(budget(300, 1000), 1000);
        // Below: in proportion, 16 of 60 copies -> 266 of 1000, but never under 100 ...
        assert_eq!(budget(16, 1000), 266);
        assert_eq!(budget(2, 1000), 100);
        // ... unless the budget itself is smaller; 0 keeps the greedy fill.
        assert_eq!(budget(2, 40), 40);
        assert_eq!(budget(16, 0), 0);
    }

    #[test]
    fn the_model_margin_spans_a_few_f32_steps_of_the_largest_coordinate() {
        let margin = |demand: usize, width_mm: f64, height_mm: f64| {
            let (items, _) = squares_job(demand, 1);
            let bin = NestBin {
                width_mm,
                height_mm,
                stock: 1,
            };
            let job = Job::new(&items, &bin, &NestSettings::default()).unwrap();
            job.model_margin()
        };
        // A lab sheet takes the least margin.
        assert_eq!(margin(20, 150.0, 150.0), MIN_MARGIN_MM);
        // Coordinates of 20,000 (albano's strip) take at least four f32 steps of 20,000 ...
        let far = 20_000.0_f32;
        let step = f32::from_bits(far.to_bits() + 1) - far;
        let wide = margin(2000, 4900.0, 20_000.0) as f32;
        assert!(far + wide - far >= MARGIN_F32_STEPS as f32 * step, "{wide}");
        // ... when the parts can reach them: 20 squares on the same sheet reach 4,900 at most.
        assert!(margin(20, 4900.0, 20_000.0) < f64::from(wide) / 3.0);
        // The strip's endless probe is bounded by the parts laid end to end: 2,000 squares of 10
        // mm (14.1 on the diagonal) with their gaps reach no further than 2,000 x 20 mm, and no
        // less than the 20,000 mm they fill in a single file, so the probe's gaps are never
        // narrower than the nest's.
        let probe = margin(2000, 40.0, f64::MAX / 4.0);
        assert!(probe >= margin(2000, 40.0, 20_000.0), "{probe}");
        assert!(probe <= margin(2000, 40.0, 2000.0 * 20.0), "{probe}");
    }

    #[test]
    fn self_crossing_outline_is_degenerate() {
        let bow_tie = NestItem {
            outline: vec![[0.0, 0.0], [1.0, 1.0], [1.0, 0.0], [0.0, 1.0]],
            demand: 1,
            rotations_deg: vec![0.0],
        };
        assert!(matches!(
            validate_item(0, &bow_tie),
            Err(NestError::DegenerateOutline { .. })
        ));
    }
}
