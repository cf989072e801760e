//! The remnant of a scored PZT sheet: the part of the sheet beyond a score line that runs from edge to
//! edge with no plate past it. The lines across the whole sheet come first in the break order, so
//! snapping that line first frees the remnant as a rectangle with straight edges, which a later batch
//! lays plates out on from its edges as on a whole sheet (`[[stock]] sheet = "pzt"`, docs/cam.md §4).

use cam_geometry::{Bounds, Point};
use cam_nest::{NestBin, NestedBin};

/// How far a line's end may sit from the sheet edge and still be on it, mm (the planner's lines end
/// on the edge exactly; this absorbs rounding only).
const ON_EDGE_MM: f64 = 1e-6;

/// The largest rectangle (`[min, max]` corners, in the sheet's frame) that a score line of `bin`
/// running from edge to edge of `sheet` cuts off with no plate in it, if its shorter side is at
/// least `min_side_mm`.
pub fn pzt_remnant(bin: &NestedBin, sheet: &NestBin, min_side_mm: f64) -> Option<[Point; 2]> {
    let size = [sheet.width_mm, sheet.height_mm];
    let plates: Vec<Bounds> = bin.parts.iter().map(|p| Bounds::of(&p.outline)).collect();
    let mut best: Option<([Point; 2], f64)> = None;
    for [a, b] in &bin.score_lines {
        // A line across the sheet at `c` along `axis`: both ends on the two opposite edges.
        for axis in 0..2 {
            let across = 1 - axis;
            let at_c = (a[axis] - b[axis]).abs() <= ON_EDGE_MM;
            let spans = (a[across].min(b[across]) <= ON_EDGE_MM)
                && (a[across].max(b[across]) >= size[across] - ON_EDGE_MM);
            if !(at_c && spans) {
                continue;
            }
            let c = a[axis];
            let mut sides = Vec::new();
            if plates.iter().all(|p| p.max[axis] <= c + ON_EDGE_MM) {
                let mut lo = [0.0, 0.0];
                lo[axis] = c;
                sides.push([lo, size]);
            }
            if plates.iter().all(|p| p.min[axis] >= c - ON_EDGE_MM) {
                let mut hi = size;
                hi[axis] = c;
                sides.push([[0.0, 0.0], hi]);
            }
            for r in sides {
                let (w, h) = (r[1][0] - r[0][0], r[1][1] - r[0][1]);
                if w.min(h) >= min_side_mm && best.is_none_or(|(_, area)| w * h > area) {
                    best = Some((r, w * h));
                }
            }
        }
    }
    best.map(|(r, _)| r)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::layout::{layout_plates, PlateSpec};

    fn sheet() -> NestBin {
        NestBin {
            width_mm: 72.4,
            height_mm: 72.4,
            stock: 10,
        }
    }

    fn plates(count: usize) -> [PlateSpec; 1] {
        [PlateSpec {
            length_mm: 20.0,
            base_width_mm: 6.0,
            tip_width_mm: 4.0,
            count,
        }]
    }

    #[test]
    fn a_part_filled_sheet_leaves_the_rest_beyond_its_last_strip() {
        // One strip of plates 20 mm long: the rest of the sheet beyond the strip's line is free.
        let layout = layout_plates(&plates(6), &sheet(), 0.05, 0.5, 0.8).unwrap();
        let bin = &layout.bins[0];
        let r = pzt_remnant(bin, &sheet(), 5.0).expect("a remnant");
        let (w, h) = (r[1][0] - r[0][0], r[1][1] - r[0][1]);
        // The remnant is a full-width or full-height band of the sheet, longer than 40 mm across.
        assert!((w - 72.4).abs() < 1e-9 || (h - 72.4).abs() < 1e-9, "{r:?}");
        assert!(w.min(h) > 40.0, "{r:?}");
        // No plate has any corner inside it.
        for p in &bin.parts {
            for q in &p.outline {
                let inside = (0..2).all(|k| q[k] > r[0][k] + 1e-9 && q[k] < r[1][k] - 1e-9);
                assert!(!inside, "{q:?} in {r:?}");
            }
        }
        // Its inner side lies on a score line that runs edge to edge.
        let on_line = bin.score_lines.iter().any(|[a, b]| {
            (0..2).any(|k| {
                let c = if r[0][k] > 1e-9 { r[0][k] } else { r[1][k] };
                (a[k] - c).abs() < 1e-9 && (b[k] - c).abs() < 1e-9 && c < 72.4 - 1e-9
            })
        });
        assert!(on_line, "{:?}", bin.score_lines);
    }

    #[test]
    fn a_full_sheet_or_a_narrow_rest_leaves_none() {
        let full = layout_plates(&plates(200), &sheet(), 0.05, 0.5, 0.8).unwrap();
        assert!(pzt_remnant(&full.bins[0], &sheet(), 5.0).is_none());
        let one = layout_plates(&plates(6), &sheet(), 0.05, 0.5, 0.8).unwrap();
        assert!(pzt_remnant(&one.bins[0], &sheet(), 72.5).is_none());
    }
}
