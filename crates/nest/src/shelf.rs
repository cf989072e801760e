//! The shelf packer: a fast, deterministic strategy for cut-through parts, the one `cut-sheet` uses for
//! a single design (where the irregular nester's search buys little on a handful of parts).
//!
//! Parts go into rows (shelves) left to right, each part slid left until it is `gap_mm` from the
//! parts already in the row. A design may alternate with a copy turned 180° when that packs
//! tighter (a trapezoid with an extension interlocks with its turned copy like the PZT plates do).
//! Items go tallest row first; a part takes the first row on the sheet that has room, else a new
//! row, else a new sheet. Input and output are the crate's vocabulary ([`NestItem`], [`NestBin`],
//! [`NestSolution`]), so [`verify()`](crate::verify()) checks a shelf layout as it checks a nest.

use crate::problem::{NestBin, NestError, NestItem, NestSolution, NestedBin, PlacedPart};
use cam_geometry::{area, normalize_deg, rotate, signed_area, Bounds, Point};
use std::collections::BTreeMap;

/// Lays out `items` in shelves on at most `bin.stock` sheets, `gap_mm` between parts and to the
/// sheet edge, rotations only from each item's list. Errors when a part fits an empty sheet in none
/// of its rotations, or when more sheets than the stock are needed (saying how many).
pub fn nest_shelves(
    items: &[NestItem],
    bin: &NestBin,
    gap_mm: f64,
) -> Result<NestSolution, NestError> {
    let positive = |v: f64| v.is_finite() && v > 0.0;
    if !positive(bin.width_mm) || !positive(bin.height_mm) {
        return Err(NestError::BadSettings(format!(
            "sheet {} x {} mm: both sides must be finite and > 0",
            bin.width_mm, bin.height_mm
        )));
    }
    if !(gap_mm.is_finite() && gap_mm >= 0.0) {
        return Err(NestError::BadSettings(format!(
            "gap {gap_mm} mm: must be finite and >= 0"
        )));
    }
    let usable = [bin.width_mm - 2.0 * gap_mm, bin.height_mm - 2.0 * gap_mm];
    let mut shapes = Vec::with_capacity(items.len());
    for (i, item) in items.iter().enumerate() {
        shapes.push(Oriented::all(i, item)?);
    }
    let mut packer = Packer {
        shapes: &shapes,
        gap: gap_mm,
        rel_cache: BTreeMap::new(),
    };
    let mut patterns = Vec::with_capacity(items.len());
    for (i, item) in items.iter().enumerate() {
        let fitting: Vec<usize> = (0..shapes[i].len())
            .filter(|&o| {
                let s = &shapes[i][o];
                s.size[0] <= usable[0] + EPS && s.size[1] <= usable[1] + EPS
            })
            .collect();
        if item.demand > 0 && fitting.is_empty() {
            let first = &shapes[i][0];
            return Err(NestError::PartLargerThanBin {
                item: i,
                part_width_mm: first.size[0],
                part_height_mm: first.size[1],
                bin_width_mm: bin.width_mm,
                bin_height_mm: bin.height_mm,
                separation_mm: gap_mm,
                edge_gap_mm: gap_mm,
            });
        }
        patterns.push(if item.demand > 0 {
            packer.pattern(i, &fitting)
        } else {
            Vec::new()
        });
    }

    // Tallest rows first, so that later, lower parts fill rows already open.
    let mut order: Vec<usize> = (0..items.len()).filter(|&i| items[i].demand > 0).collect();
    let height = |i: usize| {
        patterns[i]
            .iter()
            .map(|&o: &usize| shapes[i][o].size[1])
            .fold(0.0, f64::max)
    };
    order.sort_by(|&a, &b| height(b).total_cmp(&height(a)).then(a.cmp(&b)));

    let mut sheets: Vec<Vec<Shelf>> = vec![Vec::new()];
    for &i in &order {
        for copy in 0..items[i].demand {
            packer.place(i, copy, &patterns[i], &mut sheets, bin);
        }
    }
    if sheets.len() > bin.stock {
        return Err(NestError::StockTooSmall {
            needed: sheets.len(),
            stock: bin.stock,
        });
    }
    let sheet_area = bin.width_mm * bin.height_mm;
    let bins = sheets
        .into_iter()
        .enumerate()
        .map(|(index, shelves)| {
            let mut parts: Vec<_> = shelves
                .iter()
                .flat_map(|shelf| {
                    shelf.parts.iter().map(|part| {
                        let o = &shapes[part.item][part.orientation];
                        PlacedPart::at(
                            part.item,
                            part.copy,
                            &items[part.item].outline,
                            o.rotation_deg,
                            [part.x, shelf.y],
                        )
                    })
                })
                .collect();
            parts.sort_by_key(|p| (p.item, p.copy));
            let part_area: f64 = parts.iter().map(|p| area(&p.outline)).sum();
            NestedBin {
                index,
                parts,
                utilization: part_area / sheet_area,
                score_lines: Vec::new(),
            }
        })
        .collect();
    Ok(NestSolution { bins })
}

/// Tolerance for comparing positions, mm.
const EPS: f64 = 1e-9;

/// An item's outline in one allowed rotation, moved so that its bounding box starts at (0, 0).
struct Oriented {
    rotation_deg: f64,
    ring: Vec<Point>,
    size: [f64; 2],
}

impl Oriented {
    fn all(item: usize, spec: &NestItem) -> Result<Vec<Oriented>, NestError> {
        let invalid = |reason: String| NestError::DegenerateOutline { item, reason };
        if spec.outline.len() < 3 {
            return Err(invalid("outline has fewer than 3 points".into()));
        }
        if spec.outline.iter().flatten().any(|v| !v.is_finite()) {
            return Err(invalid(
                "outline has a coordinate that is not finite".into(),
            ));
        }
        let area = signed_area(&spec.outline);
        if area <= 0.0 {
            return Err(invalid(format!(
                "outline must be a counter-clockwise ring with area > 0 (signed area {area} mm²)"
            )));
        }
        let mut rotations: Vec<f64> = Vec::new();
        for &r in &spec.rotations_deg {
            if !r.is_finite() {
                return Err(NestError::BadRotations {
                    item,
                    rotations: spec.rotations_deg.clone(),
                });
            }
            if !rotations.iter().any(|&q| q == normalize_deg(r)) {
                rotations.push(normalize_deg(r));
            }
        }
        if rotations.is_empty() {
            return Err(NestError::BadRotations {
                item,
                rotations: spec.rotations_deg.clone(),
            });
        }
        Ok(rotations
            .into_iter()
            .map(|rotation_deg| {
                let rotated: Vec<Point> = spec
                    .outline
                    .iter()
                    .map(|p| rotate(*p, rotation_deg))
                    .collect();
                let Bounds { min: lo, max: hi } = Bounds::of(&rotated);
                Oriented {
                    rotation_deg,
                    ring: rotated
                        .iter()
                        .map(|p| [p[0] - lo[0], p[1] - lo[1]])
                        .collect(),
                    size: [hi[0] - lo[0], hi[1] - lo[1]],
                }
            })
            .collect())
    }
}

/// A part in a shelf: bounding box from (x, shelf.y).
struct ShelfPart {
    item: usize,
    copy: usize,
    orientation: usize,
    x: f64,
}

struct Shelf {
    y: f64,
    height: f64,
    parts: Vec<ShelfPart>,
}

struct Packer<'a> {
    shapes: &'a [Vec<Oriented>],
    gap: f64,
    /// Relative slide distances, keyed by (item, orientation) of the left and the right part.
    rel_cache: BTreeMap<(usize, usize, usize, usize), f64>,
}

impl Packer<'_> {
    /// The orientation sequence an item repeats along a row: one orientation, or two that
    /// alternate (an orientation and its 180° turn), whichever needs the least area per part.
    fn pattern(&mut self, item: usize, fitting: &[usize]) -> Vec<usize> {
        let shapes = &self.shapes[item];
        let mut best: Option<(f64, Vec<usize>)> = None;
        for &o in fitting {
            let turned = fitting
                .iter()
                .copied()
                .find(|&q| normalize_deg(shapes[q].rotation_deg - shapes[o].rotation_deg) == 180.0);
            let mut candidates = vec![vec![o]];
            if let Some(q) = turned {
                candidates.push(vec![o, q]);
            }
            for cand in candidates {
                let pitch = cand
                    .iter()
                    .enumerate()
                    .map(|(k, &a)| {
                        let b = cand[(k + 1) % cand.len()];
                        self.rel(item, a, item, b)
                    })
                    .sum::<f64>()
                    / cand.len() as f64;
                let height = cand.iter().map(|&a| shapes[a].size[1]).fold(0.0, f64::max);
                let cost = pitch * (height + self.gap);
                if best.as_ref().is_none_or(|(c, _)| cost < c - EPS) {
                    best = Some((cost, cand));
                }
            }
        }
        best.map(|(_, p)| p).unwrap_or_default()
    }

    /// Places one part: first shelf on the current sheet with room, else a new shelf, else a
    /// new sheet.
    fn place(
        &mut self,
        item: usize,
        copy: usize,
        pattern: &[usize],
        sheets: &mut Vec<Vec<Shelf>>,
        sheet: &NestBin,
    ) {
        let right = sheet.width_mm - self.gap;
        let shelves = sheets.last_mut().expect("at least one sheet");
        for shelf in shelves.iter_mut() {
            // Continue the alternation when the row ends with this item.
            let orientation = match shelf.parts.last() {
                Some(last) if last.item == item => {
                    let k = pattern.iter().position(|&o| o == last.orientation);
                    pattern[k.map_or(0, |k| (k + 1) % pattern.len())]
                }
                _ => pattern[0],
            };
            let size = self.shapes[item][orientation].size;
            if size[1] > shelf.height + EPS {
                continue;
            }
            let x = self.slide_x(shelf, item, orientation);
            if x + size[0] <= right + EPS {
                shelf.parts.push(ShelfPart {
                    item,
                    copy,
                    orientation,
                    x,
                });
                return;
            }
        }
        let orientation = pattern[0];
        let size = self.shapes[item][orientation].size;
        let y = shelves
            .last()
            .map_or(self.gap, |s| s.y + s.height + self.gap);
        let shelf = Shelf {
            y,
            height: size[1],
            parts: vec![ShelfPart {
                item,
                copy,
                orientation,
                x: self.gap,
            }],
        };
        if y + size[1] <= sheet.height_mm - self.gap + EPS {
            shelves.push(Shelf { y, ..shelf });
        } else {
            sheets.push(vec![Shelf {
                y: self.gap,
                ..shelf
            }]);
        }
    }

    /// Leftmost x for a new part in a shelf, sliding in from the right against every part there.
    fn slide_x(&mut self, shelf: &Shelf, item: usize, orientation: usize) -> f64 {
        let mut x = self.gap;
        for part in &shelf.parts {
            let rel = self.rel(part.item, part.orientation, item, orientation);
            x = x.max(part.x + rel);
        }
        x
    }

    /// How far right of part A's bounding box start part B's must start (bottoms aligned) so
    /// that B, slid in from the right, stays at least `gap` from A.
    ///
    /// For each pair of edges the distance is a convex function of the shift, so the shifts that
    /// bring them within the gap form an interval; the answer is the largest upper end.
    fn rel(&mut self, item_a: usize, o_a: usize, item_b: usize, o_b: usize) -> f64 {
        let key = (item_a, o_a, item_b, o_b);
        if let Some(&v) = self.rel_cache.get(&key) {
            return v;
        }
        let a = &self.shapes[item_a][o_a].ring;
        let b = &self.shapes[item_b][o_b].ring;
        let gap = self.gap;
        let mut shift = f64::NEG_INFINITY;
        for ka in 0..a.len() {
            let (a0, a1) = (a[ka], a[(ka + 1) % a.len()]);
            for kb in 0..b.len() {
                let (b0, b1) = (b[kb], b[(kb + 1) % b.len()]);
                if a0[1].min(a1[1]) - b0[1].max(b1[1]) > gap
                    || b0[1].min(b1[1]) - a0[1].max(a1[1]) > gap
                {
                    continue;
                }
                let dist =
                    |dx: f64| segment_distance(a0, a1, [b0[0] + dx, b0[1]], [b1[0] + dx, b1[1]]);
                let lo = a0[0].min(a1[0]) - b0[0].max(b1[0]) - gap - 1.0;
                let hi = a0[0].max(a1[0]) - b0[0].min(b1[0]) + gap + 1.0;
                if let Some(last) = last_shift_within(dist, lo, hi, gap) {
                    shift = shift.max(last);
                }
            }
        }
        // The bisection ends on the far side of the limit, so the gap holds at `shift` itself.
        let v = if shift.is_finite() { shift } else { 0.0 };
        self.rel_cache.insert(key, v);
        v
    }
}

/// For a convex `f` with `f(lo) > limit` and `f(hi) > limit`, the largest x in [lo, hi] with
/// `f(x) <= limit` (to rounding, from above), or `None` if there is none.
fn last_shift_within(f: impl Fn(f64) -> f64, lo: f64, hi: f64, limit: f64) -> Option<f64> {
    // Ternary search for a minimiser.
    let (mut l, mut h) = (lo, hi);
    for _ in 0..100 {
        let m1 = l + (h - l) / 3.0;
        let m2 = h - (h - l) / 3.0;
        if f(m1) <= f(m2) {
            h = m2;
        } else {
            l = m1;
        }
    }
    let min_at = (l + h) / 2.0;
    if f(min_at) > limit {
        return None;
    }
    // f is non-decreasing right of the minimiser: bisect for where it passes the limit.
    let (mut inside, mut outside) = (min_at, hi);
    for _ in 0..100 {
        let mid = (inside + outside) / 2.0;
        if f(mid) <= limit {
            inside = mid;
        } else {
            outside = mid;
        }
    }
    Some(outside)
}

fn cross(o: Point, a: Point, b: Point) -> f64 {
    (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
}

fn point_segment_distance(p: Point, a: Point, b: Point) -> f64 {
    let ab = [b[0] - a[0], b[1] - a[1]];
    let len2 = ab[0] * ab[0] + ab[1] * ab[1];
    let t = if len2 > 0.0 {
        (((p[0] - a[0]) * ab[0] + (p[1] - a[1]) * ab[1]) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let q = [a[0] + t * ab[0], a[1] + t * ab[1]];
    ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2)).sqrt()
}

/// Distance between segments a0-a1 and b0-b1 (0 when they cross).
fn segment_distance(a0: Point, a1: Point, b0: Point, b1: Point) -> f64 {
    let (d1, d2) = (cross(a0, a1, b0), cross(a0, a1, b1));
    let (d3, d4) = (cross(b0, b1, a0), cross(b0, b1, a1));
    if d1 * d2 < 0.0 && d3 * d4 < 0.0 {
        return 0.0;
    }
    point_segment_distance(a0, b0, b1)
        .min(point_segment_distance(a1, b0, b1))
        .min(point_segment_distance(b0, a0, a1))
        .min(point_segment_distance(b1, a0, a1))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::problem::NestSettings;
    use crate::verify::verify;
    use proptest::prelude::*;

    /// A sheet with stock enough for any test here.
    fn stock(width_mm: f64, height_mm: f64) -> NestBin {
        NestBin {
            width_mm,
            height_mm,
            stock: 1000,
        }
    }

    /// A passive-layer outline: trapezoid (base at y = 0) with a centred extension at the tip.
    fn trapezoid_with_extension(
        length: f64,
        base: f64,
        tip: f64,
        ext_width: f64,
        ext_length: f64,
    ) -> Vec<Point> {
        vec![
            [-base / 2.0, 0.0],
            [base / 2.0, 0.0],
            [tip / 2.0, length],
            [ext_width / 2.0, length],
            [ext_width / 2.0, length + ext_length],
            [-ext_width / 2.0, length + ext_length],
            [-ext_width / 2.0, length],
            [-tip / 2.0, length],
        ]
    }

    /// The crate's independent verifier on a shelf layout: every copy once, outlines as stated,
    /// allowed rotations, the gap between parts and to the sheet edge.
    fn check(items: &[NestItem], sheet: &NestBin, gap: f64, layout: &NestSolution) {
        let settings = NestSettings {
            separation_mm: (gap - 1e-9).max(0.0),
            ..NestSettings::default()
        };
        verify(items, sheet, &settings, layout, 1e-9).unwrap_or_else(|v| panic!("{v}"));
        assert!(layout.bins.iter().all(|b| b.score_lines.is_empty()));
    }

    #[test]
    fn turned_copies_interlock() {
        let outline = trapezoid_with_extension(23.0, 5.0, 1.0, 0.8, 6.0);
        let items = [NestItem {
            outline,
            demand: 60,
            rotations_deg: vec![0.0, 180.0],
        }];
        let sheet = stock(100.0, 100.0);
        let sheets = nest_shelves(&items, &sheet, 0.5).unwrap();
        check(&items, &sheet, 0.5, &sheets);
        let first = &sheets.bins[0].parts;
        assert!(first.iter().any(|p| p.rotation_deg == 180.0));
        // Bounding boxes alone (5.5 mm pitch, 29.5 mm rows) would give 18 x 3 = 54.
        assert!(first.len() >= 60, "{} parts", first.len());
    }

    #[test]
    fn rectangles_make_a_grid() {
        let items = [NestItem {
            outline: vec![[0.0, 0.0], [10.0, 0.0], [10.0, 5.0], [0.0, 5.0]],
            demand: 25,
            rotations_deg: vec![0.0],
        }];
        let sheet = stock(34.0, 40.0);
        let sheets = nest_shelves(&items, &sheet, 1.0).unwrap();
        check(&items, &sheet, 1.0, &sheets);
        // 3 per row (1 + 3 * 11 = 34), 6 rows (1 + 6 * 6 = 37).
        assert_eq!(sheets.bins[0].parts.len(), 18);
        assert_eq!(sheets.bins_used(), 2);
        let one = NestBin { stock: 1, ..sheet };
        let err = nest_shelves(&items, &one, 1.0).unwrap_err();
        assert_eq!(
            err,
            NestError::StockTooSmall {
                needed: 2,
                stock: 1
            }
        );
    }

    #[test]
    fn too_large_and_invalid_parts() {
        let long = NestItem {
            outline: vec![[0.0, 0.0], [80.0, 0.0], [80.0, 10.0], [0.0, 10.0]],
            demand: 1,
            rotations_deg: vec![0.0, 180.0],
        };
        let sheet = stock(72.4, 72.4);
        let err = nest_shelves(std::slice::from_ref(&long), &sheet, 0.2).unwrap_err();
        assert!(
            matches!(
                err,
                NestError::PartLargerThanBin { item: 0, part_width_mm, part_height_mm, .. }
                    if part_width_mm == 80.0 && part_height_mm == 10.0
            ),
            "{err}"
        );
        // A quarter turn makes it fit 80 x 10 on a tall sheet.
        let tall = stock(20.0, 90.0);
        let turned = NestItem {
            rotations_deg: vec![90.0],
            ..long.clone()
        };
        let sheets = nest_shelves(std::slice::from_ref(&turned), &tall, 0.2).unwrap();
        check(&[turned], &tall, 0.2, &sheets);
        let clockwise = NestItem {
            outline: long.outline.iter().rev().copied().collect(),
            ..long
        };
        assert!(matches!(
            nest_shelves(&[clockwise], &sheet, 0.2),
            Err(NestError::DegenerateOutline { item: 0, .. })
        ));
    }

    #[test]
    fn mixed_designs_are_deterministic() {
        let items = [
            NestItem {
                outline: trapezoid_with_extension(20.0, 6.0, 2.0, 1.0, 4.0),
                demand: 12,
                rotations_deg: vec![0.0, 180.0],
            },
            NestItem {
                outline: vec![[0.0, 0.0], [8.0, 0.0], [8.0, 3.0], [0.0, 3.0]],
                demand: 20,
                rotations_deg: vec![0.0, 90.0],
            },
        ];
        let sheet = stock(60.0, 50.0);
        let a = nest_shelves(&items, &sheet, 0.3).unwrap();
        check(&items, &sheet, 0.3, &a);
        assert_eq!(a, nest_shelves(&items, &sheet, 0.3).unwrap());
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]
        #[test]
        fn random_outlines_verify(
            length in 5.0..60.0f64,
            base in 1.0..25.0f64,
            tip in 0.3..25.0f64,
            ext_frac in 0.2..0.9f64,
            ext_length in 0.5..15.0f64,
            count in 1usize..30,
            gap in 0.0..1.0f64,
            rotation_set in 0usize..3,
            width in 40.0..200.0f64,
            height in 40.0..200.0f64,
        ) {
            let rotations_deg = match rotation_set {
                0 => vec![0.0, 180.0],
                1 => vec![0.0],
                _ => vec![0.0, 90.0, 180.0, 270.0],
            };
            let items = [NestItem {
                outline: trapezoid_with_extension(length, base, tip, tip * ext_frac, ext_length),
                demand: count,
                rotations_deg,
            }];
            let sheet = stock(width, height);
            match nest_shelves(&items, &sheet, gap) {
                Ok(sheets) => check(&items, &sheet, gap, &sheets),
                Err(NestError::PartLargerThanBin { .. }) => {
                    let (w, h) = (base.max(tip), length + ext_length);
                    let fits = |a: f64, b: f64| a <= width - 2.0 * gap && b <= height - 2.0 * gap;
                    prop_assert!(!fits(w, h));
                    prop_assert!(rotation_set != 2 || !fits(h, w));
                }
                Err(e) => prop_assert!(false, "unexpected error {e}"),
            }
        }
    }
}
