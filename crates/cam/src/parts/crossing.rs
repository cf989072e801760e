//! Where the edges of a drawing's contours meet: a ring that crosses or touches itself, and two
//! rings that cross or touch each other. A traced or finely flattened outline has tens of thousands
//! of edges, so the pairs are found by geo's sweep line ([`geo::algorithm::sweep::Intersections`]),
//! which tests only edges whose extents along the sweep axis overlap: on a drawn outline each edge
//! overlaps a handful of others, O(n log n) in all, where testing every pair of edges is O(n²)
//! (17 s for one ring of 10,000 vertices). The sweep runs along the longer side of the rings'
//! bounding box, so the edges of a tall, narrow part do not all overlap along a short axis.

use cam_geometry::Point;
use geo::algorithm::sweep::{Cross, Intersections};
use geo::{Coord, Line, LineIntersection};

/// One edge of a ring: `ring`'s edge `index` runs from its vertex `index` to the next one.
#[derive(Debug, Clone, Copy)]
struct Edge {
    ring: usize,
    index: usize,
    line: Line<f64>,
}

impl Cross for Edge {
    type Scalar = f64;

    fn line(&self) -> Line<f64> {
        self.line
    }
}

/// Every edge of the rings (each without its closing repeat), with x and y exchanged when the
/// rings are taller than wide: the sweep then runs along their longer side. Exchanging the axes
/// changes no intersection.
fn edges<'r>(rings: impl Iterator<Item = (usize, &'r [Point])> + Clone) -> Vec<Edge> {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in rings.clone().flat_map(|(_, r)| r.iter()) {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let swap = hi[1] - lo[1] > hi[0] - lo[0];
    let coord = |p: Point| {
        if swap {
            Coord { x: p[1], y: p[0] }
        } else {
            Coord { x: p[0], y: p[1] }
        }
    };
    rings
        .flat_map(|(ring, points)| {
            let n = points.len();
            (0..n).map(move |index| Edge {
                ring,
                index,
                line: Line::new(coord(points[index]), coord(points[(index + 1) % n])),
            })
        })
        .collect()
}

/// True when two edges of one ring of `n` edges meet where a simple ring allows: neighbours
/// (sharing a vertex) meeting at that vertex alone. Neighbours that overlap along a stretch fold
/// back on each other (a spike of no width); any other two edges must not meet at all.
fn allowed(a: &Edge, b: &Edge, n: usize, meeting: &LineIntersection<f64>) -> bool {
    let neighbours = (a.index + 1) % n == b.index || (b.index + 1) % n == a.index;
    neighbours
        && match meeting {
            LineIntersection::SinglePoint { .. } => true,
            LineIntersection::Collinear { intersection } => intersection.start == intersection.end,
        }
}

/// The first two edges of `ring` (without its closing repeat, no two consecutive points equal) that
/// cross or touch, other than neighbours meeting at their shared vertex; `None` for a simple ring.
pub fn self_contact(ring: &[Point]) -> Option<(usize, usize)> {
    let n = ring.len();
    Intersections::from_iter(edges(std::iter::once((0, ring))))
        .find(|(a, b, meeting)| !allowed(a, b, n, meeting))
        .map(|(a, b, _)| (a.index.min(b.index), a.index.max(b.index)))
}

/// Two rings, each simple ([`self_contact`]), whose edges cross or touch: `(earlier, later)` by
/// their index in `rings`; `None` when no two meet.
pub fn rings_in_contact(rings: &[Vec<Point>]) -> Option<(usize, usize)> {
    let all = rings.iter().enumerate().map(|(k, r)| (k, r.as_slice()));
    Intersections::from_iter(edges(all))
        .find(|(a, b, _)| a.ring != b.ring)
        .map(|(a, b, _)| (a.ring.min(b.ring), a.ring.max(b.ring)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use geo::line_intersection::line_intersection;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// Every pair of edges, the definition `self_contact` implements in O(n log n).
    fn every_pair(ring: &[Point]) -> bool {
        let e = edges(std::iter::once((0, ring)));
        let n = ring.len();
        (0..n).any(|i| {
            (i + 1..n).any(|j| {
                line_intersection(e[i].line, e[j].line)
                    .is_some_and(|m| !allowed(&e[i], &e[j], n, &m))
            })
        })
    }

    #[test]
    fn the_sweep_finds_a_contact_exactly_when_testing_every_pair_does() {
        // Random rings on a coarse grid (so vertices coincide, edges overlap along stretches and
        // touch at vertices, not only cross), stars and rings with a spike, 4000 in all: the
        // sweep agrees with the pairwise test on every one, and both kinds occur.
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let (mut simple, mut not) = (0, 0);
        for _ in 0..4000 {
            let n = rng.gen_range(3..12);
            let mut ring: Vec<Point> = (0..n)
                .map(|_| [rng.gen_range(0..6) as f64, rng.gen_range(0..6) as f64])
                .collect();
            if rng.gen_bool(0.3) {
                // A star: vertices sorted by angle about the centre, simple unless degenerate.
                ring = (0..n)
                    .map(|k| {
                        let a = std::f64::consts::TAU * k as f64 / n as f64;
                        let r = rng.gen_range(1..4) as f64;
                        [r * a.cos(), r * a.sin()]
                    })
                    .collect();
            }
            ring = cam_nest::clean_ring(&ring);
            if ring.len() < 3 {
                continue;
            }
            let expected = every_pair(&ring);
            assert_eq!(self_contact(&ring).is_some(), expected, "{ring:?}");
            if expected {
                not += 1
            } else {
                simple += 1
            }
        }
        assert!(simple > 100 && not > 100, "{simple} simple, {not} not");
    }

    #[test]
    fn a_spike_a_touching_vertex_and_a_crossing_are_contacts_a_square_is_not() {
        let square = vec![[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]];
        assert_eq!(self_contact(&square), None);
        // Out along the bottom edge and back: neighbours overlapping along a stretch.
        let spike = vec![[0.0, 0.0], [3.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]];
        assert!(self_contact(&spike).is_some());
        // Two squares sharing a corner, drawn as one ring through (1, 1) twice.
        let bow = vec![
            [0.0, 0.0],
            [1.0, 0.0],
            [1.0, 1.0],
            [2.0, 1.0],
            [2.0, 2.0],
            [1.0, 2.0],
            [1.0, 1.0],
            [0.0, 1.0],
        ];
        assert!(self_contact(&bow).is_some());
        let figure_eight = vec![[0.0, 0.0], [2.0, 2.0], [2.0, 0.0], [0.0, 2.0]];
        assert_eq!(self_contact(&figure_eight), Some((0, 2)));
    }

    #[test]
    fn rings_in_contact_names_the_earlier_ring_first() {
        let square = |o: f64, s: f64| vec![[o, o], [o + s, o], [o + s, o + s], [o, o + s]];
        let rings = vec![square(0.0, 1.0), square(5.0, 1.0), square(0.5, 1.0)];
        assert_eq!(rings_in_contact(&rings), Some((0, 2)));
        let apart = vec![square(0.0, 1.0), square(5.0, 1.0), square(0.25, 0.5)];
        assert_eq!(rings_in_contact(&apart), None);
        // Tall rings, swept along y: a touch at one vertex still counts.
        let tall = |x: f64| vec![[x, 0.0], [x + 1.0, 0.0], [x + 1.0, 50.0], [x, 50.0]];
        assert_eq!(rings_in_contact(&[tall(0.0), tall(1.0)]), Some((0, 1)));
        assert_eq!(rings_in_contact(&[tall(0.0), tall(1.5)]), None);
    }
}
