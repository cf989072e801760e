//! The order parts are cut in on a sheet: a part in another's cut-out (parts in holes) is cut,
//! cut-outs and outline, before the part around it, whose cut-out would free it; and the parts
//! one after the other along a short path, so the head travels less between them.

use cam_geometry::{Bounds, Point};
use cam_nest::PlacedPart;

/// Which of `parts` lie inside another part's outline (in one of its cut-outs: parts do not
/// overlap): a vertex of each inside the other's ring, their boxes one inside the other.
pub(super) fn in_cutouts(parts: &[PlacedPart]) -> Vec<bool> {
    let boxes: Vec<Bounds> = parts.iter().map(|p| Bounds::of(&p.outline)).collect();
    let within = |a: &Bounds, b: &Bounds| {
        a.min[0] >= b.min[0] && a.min[1] >= b.min[1] && a.max[0] <= b.max[0] && a.max[1] <= b.max[1]
    };
    parts
        .iter()
        .enumerate()
        .map(|(i, p)| {
            parts.iter().enumerate().any(|(j, q)| {
                i != j && within(&boxes[i], &boxes[j]) && inside(p.outline[0], &q.outline)
            })
        })
        .collect()
}

/// Whether `point` lies inside `ring` (even-odd rule).
fn inside(point: Point, ring: &[Point]) -> bool {
    let mut inside = false;
    for (k, a) in ring.iter().enumerate() {
        let b = ring[(k + 1) % ring.len()];
        if (a[1] > point[1]) != (b[1] > point[1])
            && point[0] < a[0] + (point[1] - a[1]) * (b[0] - a[0]) / (b[1] - a[1])
        {
            inside = !inside;
        }
    }
    inside
}

/// The order to cut `parts` in: those `inner` (in another's cut-out) first, then the others; each
/// group by nearest neighbour, from the sheet's corner, from box centre to box centre (a greedy
/// tour: each next part the nearest of those left to the one before, ties to the first listed).
pub(super) fn cut_order(parts: &[PlacedPart], inner: &[bool]) -> Vec<usize> {
    let centre = |i: usize| {
        let b = Bounds::of(&parts[i].outline);
        [(b.min[0] + b.max[0]) / 2.0, (b.min[1] + b.max[1]) / 2.0]
    };
    let mut order = Vec::with_capacity(parts.len());
    let mut at = [0.0, 0.0];
    for group in [true, false] {
        let mut left: Vec<usize> = (0..parts.len()).filter(|&i| inner[i] == group).collect();
        while !left.is_empty() {
            let distance = |i: usize| {
                let c = centre(i);
                (c[0] - at[0]).hypot(c[1] - at[1])
            };
            let k = (0..left.len())
                .min_by(|&a, &b| distance(left[a]).total_cmp(&distance(left[b])))
                .expect("a part is left");
            let next = left.remove(k);
            at = centre(next);
            order.push(next);
        }
    }
    order
}
