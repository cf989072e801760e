//! Input and output types of the nesting engine, their validation, and an independent check of a
//! finished layout.
//!
//! Coordinates are millimetres with y up. Rings are closed implicitly (no repeated closing point).
//! A placed part is `R(rotation_deg) * p + translation` for every vertex `p` of the item outline:
//! rotation about the outline's own origin, then translation into sheet coordinates, where the
//! sheet spans `[0, width_mm] x [0, height_mm]`.
//!
//! Two measures of a nest:
//! * **utilisation** ([`NestSolution::utilization`]): part area / area of the sheets used. What
//!   the report prints per sheet; it jumps when the parts spill onto one more sheet and cannot
//!   tell apart two nests on the same number of sheets.
//! * **used-length utilisation** ([`NestSolution::used_length_utilization`]): part area /
//!   (sheet width x used length), used length = all sheets but one counted whole + the used
//!   height of the sheet with the lowest top (top of its highest part + separation). The rest of
//!   that sheet is a reusable remnant (the nester packs toward `y = 0`). On one long sheet it is
//!   the density of strip packing (fixed width, length minimised), the usual benchmark of
//!   irregular nesting; it is the measure to compare nesters with.

use geo::{Distance, Euclidean};
use serde::{Deserialize, Serialize};
use thiserror::Error;

/// A 2D point or vector in millimetres, `[x, y]`.
pub type Point = [f64; 2];

/// One part design to cut, with how many copies are wanted.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct NestItem {
    /// Outer outline (holes are not nested into), counterclockwise, without repeated closing point.
    pub outline: Vec<Point>,
    /// Number of copies to place; 0 skips the item.
    pub demand: usize,
    /// Rotations the part may be cut at, in degrees counterclockwise, e.g. `[0, 180]` to keep the
    /// fibre direction of a prepreg ply.
    pub rotations_deg: Vec<f64>,
}

/// The sheet parts are cut from.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct NestBin {
    pub width_mm: f64,
    pub height_mm: f64,
    /// Number of sheets available.
    pub stock: usize,
}

/// Copies from which a job gets the whole iteration budget (the bench's 60-actuator batches).
const FULL_BUDGET_COPIES: usize = 60;
/// Fewest iterations a smaller job gets (unless the budget is smaller).
const MIN_BUDGET: usize = 100;

/// Knobs of a nesting run. The same settings and input give the same layout on any machine.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct NestSettings {
    /// Minimum gap between two parts and between a part and the sheet edge (kerf plus web).
    pub separation_mm: f64,
    /// Seed of every random choice.
    pub seed: u64,
    /// Optimiser budget: number of improvement moves (ruin-and-recreate steps) over all workers
    /// for a job of 60 copies or more; smaller jobs get a proportional share
    /// ([`Job::iteration_budget`]). Not wall-clock time, so runs are reproducible; 0 keeps the
    /// greedy fill.
    pub iterations: usize,
    /// Number of parallel workers; fixed, so the result does not depend on the machine.
    pub workers: usize,
}

impl Default for NestSettings {
    fn default() -> Self {
        Self {
            separation_mm: 0.3,
            seed: 0,
            iterations: 1000,
            workers: 2,
        }
    }
}

/// One copy of an item placed on a sheet.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PlacedPart {
    /// Index into the `items` slice given to the nester.
    pub item: usize,
    /// Which copy of the item (0..demand).
    pub copy: usize,
    /// Rotation, one of the item's `rotations_deg` (the value as given).
    pub rotation_deg: f64,
    /// Translation applied after the rotation.
    pub translation: Point,
    /// The placed ring in sheet coordinates: `R(rotation_deg) * p + translation`.
    pub outline: Vec<Point>,
}

/// One sheet of the solution.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct NestedBin {
    /// Position of the sheet in the solution (0-based), fullest sheet first.
    pub index: usize,
    pub parts: Vec<PlacedPart>,
    /// Part area / sheet area.
    pub utilization: f64,
}

/// A finished nest: the sheets used, fullest first.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct NestSolution {
    pub bins: Vec<NestedBin>,
}

impl NestSolution {
    /// Number of sheets used.
    #[must_use]
    pub fn bins_used(&self) -> usize {
        self.bins.len()
    }

    /// Total part area over total area of the sheets used (0 when nothing is placed).
    #[must_use]
    pub fn utilization(&self) -> f64 {
        if self.bins.is_empty() {
            return 0.0;
        }
        self.bins.iter().map(|b| b.utilization).sum::<f64>() / self.bins.len() as f64
    }

    /// Number of parts placed on all sheets.
    #[must_use]
    pub fn parts_placed(&self) -> usize {
        self.bins.iter().map(|b| b.parts.len()).sum()
    }

    /// Total area of the placed parts, mm².
    #[must_use]
    pub fn part_area_mm2(&self) -> f64 {
        self.bins.iter().map(NestedBin::part_area_mm2).sum()
    }

    /// Used length: all sheets but one counted whole (`height_mm` each), plus the used height
    /// of the sheet with the lowest top ([`NestedBin::used_height_mm`]), whose rest is a
    /// reusable remnant. This is the strip length of strip packing, measured on sheets.
    #[must_use]
    pub fn used_length_mm(&self, bin: &NestBin, separation_mm: f64) -> f64 {
        let remnant = self
            .bins
            .iter()
            .map(|b| b.used_height_mm(bin, separation_mm))
            .fold(f64::INFINITY, f64::min);
        if self.bins.is_empty() {
            return 0.0;
        }
        (self.bins.len() - 1) as f64 * bin.height_mm + remnant
    }

    /// Used-length utilisation: part area / (sheet width x [`Self::used_length_mm`]). Unlike
    /// [`Self::utilization`] it does not jump when the parts spill onto one more sheet, so it
    /// compares nesters on the same parts; on a single long sheet it is the density of strip
    /// packing. 0 when nothing is placed.
    #[must_use]
    pub fn used_length_utilization(&self, bin: &NestBin, separation_mm: f64) -> f64 {
        let length = self.used_length_mm(bin, separation_mm);
        if length <= 0.0 {
            return 0.0;
        }
        self.part_area_mm2() / (bin.width_mm * length)
    }
}

impl NestedBin {
    /// Total area of the parts on this sheet, mm².
    #[must_use]
    pub fn part_area_mm2(&self) -> f64 {
        self.parts
            .iter()
            .map(|p| signed_area(&p.outline).abs())
            .sum()
    }

    /// Height of the strip `[0, used]` of the sheet the parts need: the top of the highest part
    /// plus the separation a cut along it must keep, at most the sheet height; 0 when empty.
    /// The rest of the sheet above is a remnant, whole if the nester packed toward `y = 0`.
    #[must_use]
    pub fn used_height_mm(&self, bin: &NestBin, separation_mm: f64) -> f64 {
        let top = self
            .parts
            .iter()
            .flat_map(|p| p.outline.iter().map(|q| q[1]))
            .fold(f64::NEG_INFINITY, f64::max);
        if top.is_finite() {
            (top + separation_mm).min(bin.height_mm)
        } else {
            0.0
        }
    }
}

/// Why a nest could not be made.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum NestError {
    #[error(
        "item {item}: part is {part_width_mm:.3} x {part_height_mm:.3} mm at its best allowed rotation, \
         which with {separation_mm} mm edge separation does not fit the {bin_width_mm} x {bin_height_mm} mm sheet"
    )]
    PartLargerThanBin {
        item: usize,
        part_width_mm: f64,
        part_height_mm: f64,
        bin_width_mm: f64,
        bin_height_mm: f64,
        separation_mm: f64,
    },
    #[error("stock too small: the parts need {needed} sheets but only {stock} are in stock")]
    StockTooSmall { needed: usize, stock: usize },
    #[error("item {item}: outline is empty or degenerate: {reason}")]
    DegenerateOutline { item: usize, reason: String },
    #[error("item {item}: rotations_deg must hold at least one finite angle, got {rotations:?}")]
    BadRotations { item: usize, rotations: Vec<f64> },
    #[error("bad settings: {0}")]
    BadSettings(String),
}

/// A placement that breaks a rule, found by [`verify`].
#[derive(Debug, Clone, PartialEq, Error)]
pub enum NestViolation {
    #[error("sheet {bin}: part {part} comes {distance_mm:.4} mm from the sheet edge (needs {required_mm} mm)")]
    TooCloseToEdge {
        bin: usize,
        part: usize,
        distance_mm: f64,
        required_mm: f64,
    },
    #[error(
        "sheet {bin}: parts {a} and {b} are {distance_mm:.4} mm apart (needs {required_mm} mm)"
    )]
    TooClose {
        bin: usize,
        a: usize,
        b: usize,
        distance_mm: f64,
        required_mm: f64,
    },
    #[error("sheet {bin}: part {part} has rotation {rotation_deg} not allowed for item {item}")]
    RotationNotAllowed {
        bin: usize,
        part: usize,
        item: usize,
        rotation_deg: f64,
    },
    #[error("sheet {bin}: part {part} outline differs from item outline + rotation + translation")]
    OutlineMismatch { bin: usize, part: usize },
    #[error("item {item} copy {copy}: placed {count} times (must be exactly once)")]
    CopyCount {
        item: usize,
        copy: usize,
        count: usize,
    },
    #[error("part references item {item}, copy {copy}, which was not demanded")]
    UnknownCopy { item: usize, copy: usize },
    #[error("{used} sheets used but only {stock} in stock")]
    StockExceeded { used: usize, stock: usize },
}

/// Rotates `p` counterclockwise by `deg` about the origin. Multiples of 90° are exact, so a part
/// turned by 180° has exactly the coordinates a caller computes by hand.
#[must_use]
pub fn rotate(p: Point, deg: f64) -> Point {
    let (sin, cos) = sin_cos_deg(deg);
    [cos * p[0] - sin * p[1], sin * p[0] + cos * p[1]]
}

/// `(sin, cos)` of an angle in degrees, exact at multiples of 90°.
fn sin_cos_deg(deg: f64) -> (f64, f64) {
    let normalized = deg.rem_euclid(360.0);
    if normalized == 0.0 {
        (0.0, 1.0)
    } else if normalized == 90.0 {
        (1.0, 0.0)
    } else if normalized == 180.0 {
        (0.0, -1.0)
    } else if normalized == 270.0 {
        (-1.0, 0.0)
    } else {
        normalized.to_radians().sin_cos()
    }
}

/// The outline of an item placed with `rotation_deg` and `translation`.
#[must_use]
pub fn place_outline(outline: &[Point], rotation_deg: f64, translation: Point) -> Vec<Point> {
    outline
        .iter()
        .map(|&p| {
            let r = rotate(p, rotation_deg);
            [r[0] + translation[0], r[1] + translation[1]]
        })
        .collect()
}

/// Shoelace area of a ring (positive for counterclockwise).
#[must_use]
pub fn signed_area(ring: &[Point]) -> f64 {
    let n = ring.len();
    (0..n)
        .map(|i| {
            let a = ring[i];
            let b = ring[(i + 1) % n];
            a[0] * b[1] - b[0] * a[1]
        })
        .sum::<f64>()
        / 2.0
}

/// Axis-aligned bounds `[x_min, y_min, x_max, y_max]` of a ring.
#[must_use]
pub fn bounds(ring: &[Point]) -> [f64; 4] {
    ring.iter().fold(
        [
            f64::INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NEG_INFINITY,
        ],
        |b, p| {
            [
                b[0].min(p[0]),
                b[1].min(p[1]),
                b[2].max(p[0]),
                b[3].max(p[1]),
            ]
        },
    )
}

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
        let b = bounds(&place_outline(&self.outline, rotation_deg, [0.0, 0.0]));
        [b[2] - b[0], b[3] - b[1]]
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
        let job = Self {
            parts,
            bin: *bin,
            settings: *settings,
        };
        job.check_sizes()?;
        Ok(job)
    }

    /// Gap the jagua-rs model keeps: the requested separation plus a margin that covers its f32
    /// coordinates and the chords of its round offset joins (<= 0.125 % of the offset).
    pub fn model_separation(&self) -> f64 {
        self.settings.separation_mm * 1.01 + 2e-3
    }

    /// Every part must fit an empty sheet at some allowed rotation.
    fn check_sizes(&self) -> Result<(), NestError> {
        // The engine also keeps 1 µm start clearances; 0.01 mm covers them.
        let gap = 2.0 * self.model_separation() + 0.01;
        for part in &self.parts {
            let fits =
                |s: &[f64; 2]| s[0] + gap < self.bin.width_mm && s[1] + gap < self.bin.height_mm;
            let sizes: Vec<[f64; 2]> = part
                .rotations_deg
                .iter()
                .map(|&r| part.bbox_size(r))
                .collect();
            if !sizes.iter().any(fits) {
                let best = sizes
                    .iter()
                    .copied()
                    .min_by(|a, b| {
                        let over = |s: &[f64; 2]| {
                            (s[0] - self.bin.width_mm).max(s[1] - self.bin.height_mm)
                        };
                        over(a).total_cmp(&over(b))
                    })
                    .unwrap_or([0.0, 0.0]);
                return Err(NestError::PartLargerThanBin {
                    item: part.item,
                    part_width_mm: best[0],
                    part_height_mm: best[1],
                    bin_width_mm: self.bin.width_mm,
                    bin_height_mm: self.bin.height_mm,
                    separation_mm: self.settings.separation_mm,
                });
            }
        }
        Ok(())
    }

    /// Total number of copies to place.
    pub fn copies(&self) -> usize {
        self.parts.iter().map(|p| p.demand).sum()
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
                            outline: place_outline(&part.outline, rotation_deg, translation),
                        }
                    })
                    .collect(),
            })
            .collect();
        Ok(NestSolution { bins })
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
    let b = bounds(&outline);
    let area = signed_area(&outline).abs();
    if area <= 1e-9 * ((b[2] - b[0]) * (b[3] - b[1])).max(1e-12) || area < 1e-9 {
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

/// Checks a solution against the rules without trusting the nester (plain `geo` geometry, no
/// jagua-rs): every part inside its sheet with at least the separation to each edge, pairwise
/// distance at least the separation, rotations from the allowed list, outlines equal to the item
/// outline ([`clean_ring`]) + rotation + translation, every demanded copy placed exactly once,
/// stock respected.
/// `tolerance_mm` absorbs rounding in the check itself (1e-9 is plenty).
pub fn verify(
    items: &[NestItem],
    bin: &NestBin,
    settings: &NestSettings,
    solution: &NestSolution,
    tolerance_mm: f64,
) -> Result<(), NestViolation> {
    let sep = settings.separation_mm;
    let mut counts: Vec<Vec<usize>> = items.iter().map(|i| vec![0; i.demand]).collect();
    if solution.bins.len() > bin.stock {
        return Err(NestViolation::StockExceeded {
            used: solution.bins.len(),
            stock: bin.stock,
        });
    }
    for (b, sheet) in solution.bins.iter().enumerate() {
        let mut polygons = Vec::with_capacity(sheet.parts.len());
        for (k, part) in sheet.parts.iter().enumerate() {
            let Some(slot) = counts.get_mut(part.item).and_then(|c| c.get_mut(part.copy)) else {
                return Err(NestViolation::UnknownCopy {
                    item: part.item,
                    copy: part.copy,
                });
            };
            *slot += 1;
            let item = &items[part.item];
            if !item.rotations_deg.contains(&part.rotation_deg) {
                return Err(NestViolation::RotationNotAllowed {
                    bin: b,
                    part: k,
                    item: part.item,
                    rotation_deg: part.rotation_deg,
                });
            }
            let expected = place_outline(
                &clean_ring(&item.outline),
                part.rotation_deg,
                part.translation,
            );
            let matches = expected.len() == part.outline.len()
                && expected.iter().zip(&part.outline).all(|(e, o)| {
                    (e[0] - o[0]).abs() <= tolerance_mm && (e[1] - o[1]).abs() <= tolerance_mm
                });
            if !matches {
                return Err(NestViolation::OutlineMismatch { bin: b, part: k });
            }
            let edge = part
                .outline
                .iter()
                .map(|p| {
                    p[0].min(p[1])
                        .min(bin.width_mm - p[0])
                        .min(bin.height_mm - p[1])
                })
                .fold(f64::INFINITY, f64::min);
            if edge < sep - tolerance_mm {
                return Err(NestViolation::TooCloseToEdge {
                    bin: b,
                    part: k,
                    distance_mm: edge,
                    required_mm: sep,
                });
            }
            let ring: Vec<geo::Coord> = part
                .outline
                .iter()
                .map(|p| geo::Coord { x: p[0], y: p[1] })
                .collect();
            polygons.push((
                bounds(&part.outline),
                geo::Polygon::new(geo::LineString::new(ring), vec![]),
            ));
        }
        for a in 0..polygons.len() {
            for c in a + 1..polygons.len() {
                let (ba, pa) = &polygons[a];
                let (bc, pc) = &polygons[c];
                let gap_x = (bc[0] - ba[2]).max(ba[0] - bc[2]);
                let gap_y = (bc[1] - ba[3]).max(ba[1] - bc[3]);
                if gap_x.max(gap_y) >= sep {
                    continue;
                }
                let distance = Euclidean.distance(pa, pc);
                if distance < sep - tolerance_mm {
                    return Err(NestViolation::TooClose {
                        bin: b,
                        a,
                        b: c,
                        distance_mm: distance,
                        required_mm: sep,
                    });
                }
            }
        }
    }
    for (item, copies) in counts.iter().enumerate() {
        if let Some((copy, &count)) = copies.iter().enumerate().find(|(_, &c)| c != 1) {
            return Err(NestViolation::CopyCount { item, copy, count });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(side: f64) -> Vec<Point> {
        vec![[0.0, 0.0], [side, 0.0], [side, side], [0.0, side]]
    }

    /// `demand` 10 mm squares and a 100 mm sheet with `stock`.
    fn squares_job(demand: usize, stock: usize) -> (Vec<NestItem>, NestBin) {
        let items = vec![NestItem {
            outline: square(10.0),
            demand,
            rotations_deg: vec![0.0],
        }];
        let bin = NestBin {
            width_mm: 100.0,
            height_mm: 100.0,
            stock,
        };
        (items, bin)
    }

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
    fn rotation_by_180_is_exact() {
        assert_eq!(rotate([3.5, -2.25], 180.0), [-3.5, 2.25]);
        assert_eq!(rotate([3.5, -2.25], -180.0), [-3.5, 2.25]);
        assert_eq!(rotate([1.0, 0.0], 90.0), [0.0, 1.0]);
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

    #[test]
    fn verify_catches_parts_too_close() {
        let (items, bin) = squares_job(2, 1);
        let settings = NestSettings {
            separation_mm: 0.5,
            ..NestSettings::default()
        };
        let part = |copy, x: f64| PlacedPart {
            item: 0,
            copy,
            rotation_deg: 0.0,
            translation: [x, 1.0],
            outline: place_outline(&square(10.0), 0.0, [x, 1.0]),
        };
        let mut solution = NestSolution {
            bins: vec![NestedBin {
                index: 0,
                parts: vec![part(0, 1.0), part(1, 11.4)],
                utilization: 0.02,
            }],
        };
        assert!(matches!(
            verify(&items, &bin, &settings, &solution, 1e-9),
            Err(NestViolation::TooClose { .. })
        ));
        solution.bins[0].parts[1] = part(1, 11.5);
        assert_eq!(verify(&items, &bin, &settings, &solution, 1e-9), Ok(()));
        solution.bins[0].parts[1] = part(1, 0.2);
        assert!(verify(&items, &bin, &settings, &solution, 1e-9).is_err());
    }
}
