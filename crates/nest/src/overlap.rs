//! How much two placed collision shapes overlap: the measure the strip compression
//! ([`super::compress`]) drives to zero.
//!
//! The ruin-and-recreate search only places parts where they are clear. Compression instead
//! pushes parts into one another and moves them apart again, as sparrow does (Gardeyn &
//! Wauters, "An open-source heuristic to reboot 2D nesting research", 2025), so it needs to
//! know *how much* two shapes collide, with a measure that is zero exactly when they are clear.
//! Each shape is cut into convex pieces (earcut triangles merged while the union stays convex,
//! as in Hertel & Mehlhorn 1983). Between two convex pieces the separating-axis theorem gives
//! the penetration depth: the least overlap of their projections on the edge normals of either,
//! zero when one of those axes separates them. Times how far the pieces overlap across that
//! normal, it is an area: the area of the rectangle the pieces' intersection lies in, so never
//! less than their shared area, and equal to it for two boxes. Summed over the piece pairs, it
//! is zero iff the shapes are clear by at least [`CLEARANCE_MM`], and it shrinks as a part
//! moves out. What the compression minimises is [`loss`]: that area charged as sparrow charges
//! a collision, with a floor and scaled by the parts' sizes. Sparrow's measure is an area as
//! well (a sum over pairs of inscribed circles, Gardeyn & Wauters 2025, Algorithm 3). A depth
//! alone would charge a long, shallow overlap of two parts lying side by side as little as a
//! corner, and a separation on a strip of long parts would settle for many such slivers.

use geo::{Area, ConvexHull, Coord, LineString, MultiPoint, Point, Polygon, TriangulateEarcut};

use cam_geometry::area;

/// Margin the measure adds to every pair, so that shapes it calls clear are apart by this much
/// and also pass jagua-rs's own f32 collision test.
pub(crate) const CLEARANCE_MM: f32 = 2e-3;

/// A projection onto an axis: `(min, max)`.
type Interval = (f32, f32);

/// A box `[x_min, y_min, x_max, y_max]` in the collision engine's f32, beside the f64
/// [`cam_geometry::Bounds`] of the app.
pub(crate) type Box32 = [f32; 4];

/// A convex polygon, counter-clockwise, with its outward unit edge normals.
#[derive(Debug, Clone)]
struct Convex {
    vertices: Vec<[f32; 2]>,
    normals: Vec<[f32; 2]>,
    /// The piece's own projection on each of its normals: fixed, so only the other piece of a
    /// pair needs projecting on them (half the work of an overlap query).
    extents: Vec<Interval>,
    /// Its own projection on each normal turned a quarter ([`across`]), for the width of an
    /// overlap found on that normal.
    across_extents: Vec<Interval>,
    bounds: Box32,
}

/// A collision shape at the origin, as convex pieces.
#[derive(Debug, Clone)]
pub(crate) struct Pieces {
    pieces: Vec<Convex>,
    pub(crate) bounds: Box32,
    /// Largest distance between two of its vertices.
    diameter: f32,
    /// Square root of its convex hull's area: a length that grows with the part.
    size: f32,
    /// The vertex mean of its largest piece: a point well inside the shape, where sparrow uses
    /// the pole of inaccessibility (Gardeyn & Wauters 2025) to say which parts another part
    /// practically contains.
    inner: [f32; 2],
    /// Index of the first piece in a [`Projections`] table, once one holds this shape.
    first_id: Option<usize>,
}

impl Pieces {
    /// A point well inside the shape (see `inner`).
    pub(crate) fn inner_point(&self) -> [f32; 2] {
        self.inner
    }

    /// The area of its convex hull, by which sparrow ranks parts by size.
    pub(crate) fn hull_area(&self) -> f32 {
        self.size * self.size
    }

    /// True unless the two shapes are within 1 % in hull area or in diameter: sparrow's test of
    /// two parts different enough that swapping them disrupts a layout (Gardeyn & Wauters 2025).
    pub(crate) fn unlike(&self, other: &Pieces) -> bool {
        let near = |a: f32, b: f32| (a - b).abs() <= 0.01 * a;
        !near(self.hull_area(), other.hull_area()) && !near(self.diameter, other.diameter)
    }

    /// True if `p` (in the shape's own frame) lies inside one of its pieces.
    pub(crate) fn contains(&self, p: [f32; 2]) -> bool {
        self.pieces.iter().any(|c| {
            c.normals
                .iter()
                .zip(&c.extents)
                .all(|(n, e)| p[0] * n[0] + p[1] * n[1] <= e.1)
        })
    }

    /// Convex pieces of a simple polygon (vertices counter-clockwise, not closed). `None` if it
    /// does not triangulate into pieces that cover it (a degenerate ring).
    pub(crate) fn new(ring: &[[f32; 2]]) -> Option<Pieces> {
        let exterior: Vec<Coord<f64>> = ring
            .iter()
            .map(|p| Coord {
                x: f64::from(p[0]),
                y: f64::from(p[1]),
            })
            .collect();
        let raw = Polygon::new(LineString::new(exterior), Vec::new()).earcut_triangles_raw();
        let points: Vec<[f64; 2]> = raw.vertices;
        let mut polygons: Vec<Vec<usize>> = raw
            .triangle_indices
            .chunks_exact(3)
            .map(|t| {
                let mut t = t.to_vec();
                if cross(points[t[0]], points[t[1]], points[t[2]]) < 0.0 {
                    t.swap(1, 2);
                }
                t
            })
            .filter(|t| cross(points[t[0]], points[t[1]], points[t[2]]) > 0.0)
            .collect();
        let triangles_area: f64 = polygons
            .iter()
            .map(|t| cross(points[t[0]], points[t[1]], points[t[2]]) / 2.0)
            .sum();
        let ring_area = area(&points);
        if polygons.is_empty() || (triangles_area - ring_area).abs() > 1e-6 * ring_area.max(1.0) {
            return None;
        }
        merge_while_convex(&mut polygons, &points);
        let corners = |poly: &Vec<usize>| poly.iter().map(|&i| points[i]).collect::<Vec<_>>();
        let largest = polygons
            .iter()
            .map(corners)
            .max_by(|a, b| area(a).total_cmp(&area(b)))
            .expect("at least one piece");
        let k = largest.len() as f64;
        let inner = [
            (largest.iter().map(|p| p[0]).sum::<f64>() / k) as f32,
            (largest.iter().map(|p| p[1]).sum::<f64>() / k) as f32,
        ];
        let pieces: Vec<Convex> = polygons
            .iter()
            .map(|poly| {
                Convex::new(
                    poly.iter()
                        .map(|&i| [points[i][0] as f32, points[i][1] as f32])
                        .collect(),
                )
            })
            .collect();
        let bounds = pieces
            .iter()
            .fold([f32::MAX, f32::MAX, f32::MIN, f32::MIN], |b, piece| {
                union(b, piece.bounds)
            });
        let diameter = points
            .iter()
            .flat_map(|p| points.iter().map(move |q| (p[0] - q[0]).hypot(p[1] - q[1])))
            .fold(0.0, f64::max) as f32;
        let hull = MultiPoint::from(
            points
                .iter()
                .map(|p| Point::new(p[0], p[1]))
                .collect::<Vec<_>>(),
        )
        .convex_hull();
        Some(Pieces {
            pieces,
            bounds,
            diameter,
            size: hull.unsigned_area().sqrt() as f32,
            inner,
            first_id: None,
        })
    }

    /// Number of convex pieces.
    #[cfg(test)]
    fn len(&self) -> usize {
        self.pieces.len()
    }
}

/// Most pieces a [`Projections`] table is built for: it holds every ordered pair of pieces, so
/// its size grows with the square (200 pieces of up to 8 edges: about 5 MB).
const MAX_TABLE_PIECES: usize = 200;

/// Where each piece projects onto every other piece's edge normals, and onto those normals
/// turned a quarter, at the origin. Parts only translate during compression (a rotation is a
/// shape of its own), so these projections move only by an offset, and an overlap query needs
/// one addition per axis instead of a projection of every vertex: the same numbers, computed
/// once. A profile of a 60-part strip put 58 % of the nester's time in [`overlap`].
pub(crate) struct Projections {
    pieces: usize,
    /// `[a * pieces + b]`: start in `data` of `b`'s projections on `a`'s normals.
    start: Vec<usize>,
    data: Vec<Interval>,
}

impl Projections {
    /// Numbers the pieces of `shapes` and builds their table; `None` (and the shapes left
    /// unnumbered, so [`overlap`] projects as it goes) above `MAX_TABLE_PIECES` pieces.
    pub(crate) fn new(shapes: &mut [&mut Pieces]) -> Option<Projections> {
        let pieces: usize = shapes.iter().map(|s| s.pieces.len()).sum();
        if pieces > MAX_TABLE_PIECES {
            return None;
        }
        let mut next = 0;
        for shape in shapes.iter_mut() {
            shape.first_id = Some(next);
            next += shape.pieces.len();
        }
        let all: Vec<&Convex> = shapes.iter().flat_map(|s| s.pieces.iter()).collect();
        let mut start = Vec::with_capacity(pieces * pieces);
        let mut data = Vec::new();
        for a in &all {
            for b in &all {
                start.push(data.len());
                data.extend(a.normals.iter().map(|&n| project(&b.vertices, n)));
                data.extend(a.normals.iter().map(|&n| project(&b.vertices, across(n))));
            }
        }
        Some(Projections {
            pieces,
            start,
            data,
        })
    }

    /// `b`'s projections on `a`'s normals, then on those normals turned a quarter ([`across`]).
    fn of(&self, a: usize, b: usize, normals: usize) -> &[Interval] {
        let at = self.start[a * self.pieces + b];
        &self.data[at..at + 2 * normals]
    }
}

/// Overlap of shape `a` moved by `ta` with shape `b` moved by `tb`: the sum over piece pairs
/// of their separating-axis depth times their overlap across its normal (each plus
/// [`CLEARANCE_MM`]), an area; zero when they are clear. With a table that holds both shapes the
/// projections come from it, else they are computed. The sum stops once it reaches `enough`
/// (`f32::MAX` for the whole of it): a caller that only asks whether a position beats a bound
/// ([`overlap_reaching`]) need not add up the rest.
pub(crate) fn overlap(
    a: &Pieces,
    ta: [f32; 2],
    b: &Pieces,
    tb: [f32; 2],
    table: Option<&Projections>,
    enough: f32,
) -> f32 {
    // `a` in the frame where `b` sits at the origin.
    let d = [ta[0] - tb[0], ta[1] - tb[1]];
    if !bounds_meet(shifted(a.bounds, d), b.bounds) {
        return 0.0;
    }
    let known = table.zip(a.first_id).zip(b.first_id);
    let mut total = 0.0;
    for (ka, pa) in a.pieces.iter().enumerate() {
        let ba = shifted(pa.bounds, d);
        if !bounds_meet(ba, b.bounds) {
            continue;
        }
        for (kb, pb) in b.pieces.iter().enumerate() {
            if bounds_meet(ba, pb.bounds) {
                let projected = known.map(|((t, ia), ib)| {
                    let (ia, ib) = (ia + ka, ib + kb);
                    (
                        t.of(ia, ib, pa.normals.len()),
                        t.of(ib, ia, pb.normals.len()),
                    )
                });
                total += piece_overlap(pa, d, pb, projected);
                if total > 0.0 && total >= enough {
                    return total;
                }
            }
        }
    }
    total
}

/// Share of the larger diameter of two shapes that a collision between them costs at the least
/// in [`loss`] (sparrow's ε, Gardeyn & Wauters 2025, Algorithm 4: 1 %).
const LEAST_DEPTH_SHARE: f32 = 0.01;

/// How much the separation is charged for a collision of shapes `a` and `b` whose [`overlap`]
/// is the area `o`: zero when it is, else `sqrt(o + ε²) · sqrt(size_a · size_b)`, with ε
/// (`LEAST_DEPTH_SHARE` of the larger diameter) and `size` the square root of a shape's convex
/// hull area, as sparrow quantifies a collision (Gardeyn & Wauters 2025, Algorithm 4). The floor
/// ε makes every collision, however slight, cost about a hundredth of a part, so a separation
/// does not settle for many slight overlaps that each look nearly free; the size factor makes a
/// large part's collisions dearer than a small one's of the same overlap, so the small part is
/// the one that moves to a gap.
pub(crate) fn loss(o: f32, a: &Pieces, b: &Pieces) -> f32 {
    if o == 0.0 {
        return 0.0;
    }
    let least = LEAST_DEPTH_SHARE * a.diameter.max(b.diameter);
    (o + least * least).sqrt() * (a.size * b.size).sqrt()
}

/// The least overlap at which [`loss`] of shapes `a` and `b` reaches `target`: the loss solved
/// for the overlap, `(target / sqrt(size_a · size_b))² − ε²`, a little over it so that rounding
/// never puts the loss of that overlap under `target` (zero where any collision costs that much,
/// `target / sqrt(size_a · size_b) ≤ ε`; infinite for `f32::MAX`). It is what [`overlap`] may
/// stop at when the caller only asks whether the loss stays under `target`.
pub(crate) fn overlap_reaching(target: f32, a: &Pieces, b: &Pieces) -> f32 {
    let least = LEAST_DEPTH_SHARE * a.diameter.max(b.diameter);
    let per_size = target / (a.size * b.size).sqrt();
    if per_size <= least {
        return 0.0;
    }
    (per_size * per_size - least * least) * (1.0 + REACH_MARGIN)
}

/// Relative margin of [`overlap_reaching`]: far above f32 rounding, far below any difference
/// between two samples' costs that matters.
const REACH_MARGIN: f32 = 1e-3;

/// Overlap of convex `a` moved by `d` with convex `b`: their separating-axis penetration depth
/// (the smallest overlap of their projections over the edge normals of both, or zero if one is
/// negative) times the overlap of their projections across the normal it is found on.
/// `projected`: `b` on `a`'s normals and across them, and `a` on `b`'s, all at the origin, if
/// known.
fn piece_overlap(
    a: &Convex,
    d: [f32; 2],
    b: &Convex,
    projected: Option<(&[Interval], &[Interval])>,
) -> f32 {
    // On each normal: both projections (one fixed, one looked up or projected now), `a`'s
    // moved by `d`.
    let on_a = a
        .normals
        .iter()
        .zip(&a.extents)
        .enumerate()
        .map(|(k, (n, &own))| {
            let offset = d[0] * n[0] + d[1] * n[1];
            let other = projected.map_or_else(|| project(&b.vertices, *n), |p| p.0[k]);
            ((own.0 + offset, own.1 + offset), other)
        });
    let on_b = b
        .normals
        .iter()
        .zip(&b.extents)
        .enumerate()
        .map(|(k, (n, &own))| {
            let offset = d[0] * n[0] + d[1] * n[1];
            let (lo, hi) = projected.map_or_else(|| project(&a.vertices, *n), |p| p.1[k]);
            ((lo + offset, hi + offset), own)
        });
    let mut least = f32::MAX;
    let mut axis = 0;
    for (k, ((a_min, a_max), (b_min, b_max))) in on_a.chain(on_b).enumerate() {
        let o = smaller(a_max, b_max) - larger(a_min, b_min) + CLEARANCE_MM;
        if o <= 0.0 {
            return 0.0;
        }
        if o < least {
            least = o;
            axis = k;
        }
    }
    // How far the pieces overlap across the normal of least depth: both projections on that
    // normal turned a quarter, `a`'s moved by `d`.
    let na = a.normals.len();
    let ((a_lo, a_hi), (b_lo, b_hi)) = if axis < na {
        let n = across(a.normals[axis]);
        let offset = d[0] * n[0] + d[1] * n[1];
        let own = a.across_extents[axis];
        let other = projected.map_or_else(|| project(&b.vertices, n), |p| p.0[na + axis]);
        ((own.0 + offset, own.1 + offset), other)
    } else {
        let k = axis - na;
        let n = across(b.normals[k]);
        let offset = d[0] * n[0] + d[1] * n[1];
        let nb = b.normals.len();
        let (lo, hi) = projected.map_or_else(|| project(&a.vertices, n), |p| p.1[nb + k]);
        ((lo + offset, hi + offset), b.across_extents[k])
    };
    let width = smaller(a_hi, b_hi) - larger(a_lo, b_lo) + CLEARANCE_MM;
    least * larger(width, CLEARANCE_MM)
}

/// A normal turned a quarter, counter-clockwise.
fn across(n: [f32; 2]) -> [f32; 2] {
    [-n[1], n[0]]
}

fn project(vertices: &[[f32; 2]], n: [f32; 2]) -> Interval {
    let (mut lo, mut hi) = (f32::MAX, f32::MIN);
    for v in vertices {
        let p = v[0] * n[0] + v[1] * n[1];
        lo = smaller(lo, p);
        hi = larger(hi, p);
    }
    (lo, hi)
}

// `piece_overlap` and `project` are most of the nester's time. `f32::min` and `max` carry NaN
// rules that cost several instructions each; these plain comparisons are one. No projection is
// NaN (the outlines are validated finite), and on equal values either side is the same number.
fn smaller(a: f32, b: f32) -> f32 {
    if a < b {
        a
    } else {
        b
    }
}

fn larger(a: f32, b: f32) -> f32 {
    if a > b {
        a
    } else {
        b
    }
}

impl Convex {
    fn new(vertices: Vec<[f32; 2]>) -> Convex {
        let k = vertices.len();
        let normals: Vec<[f32; 2]> = (0..k)
            .map(|i| {
                let (p, q) = (vertices[i], vertices[(i + 1) % k]);
                let (dx, dy) = (q[0] - p[0], q[1] - p[1]);
                let len = dx.hypot(dy);
                [dy / len, -dx / len]
            })
            .collect();
        let bounds = vertices
            .iter()
            .fold([f32::MAX, f32::MAX, f32::MIN, f32::MIN], |b, v| {
                [
                    b[0].min(v[0]),
                    b[1].min(v[1]),
                    b[2].max(v[0]),
                    b[3].max(v[1]),
                ]
            });
        let extents = normals.iter().map(|&n| project(&vertices, n)).collect();
        let across_extents = normals
            .iter()
            .map(|&n| project(&vertices, across(n)))
            .collect();
        Convex {
            vertices,
            normals,
            extents,
            across_extents,
            bounds,
        }
    }
}

/// Hertel–Mehlhorn: merges two pieces across a shared edge whenever their union is convex,
/// until no pair merges. Pieces are index cycles, counter-clockwise.
fn merge_while_convex(polygons: &mut Vec<Vec<usize>>, points: &[[f64; 2]]) {
    'again: loop {
        for i in 0..polygons.len() {
            for j in i + 1..polygons.len() {
                if let Some(merged) = merged_if_convex(&polygons[i], &polygons[j], points) {
                    polygons[i] = merged;
                    polygons.remove(j);
                    continue 'again;
                }
            }
        }
        return;
    }
}

/// The union of two counter-clockwise cycles sharing an edge (`u → v` in `a`, `v → u` in `b`),
/// if it is convex.
fn merged_if_convex(a: &[usize], b: &[usize], points: &[[f64; 2]]) -> Option<Vec<usize>> {
    for ia in 0..a.len() {
        let (u, v) = (a[ia], a[(ia + 1) % a.len()]);
        let Some(ib) = (0..b.len()).find(|&ib| b[ib] == v && b[(ib + 1) % b.len()] == u) else {
            continue;
        };
        // a's cycle from v round to u, then b's vertices strictly between u and v.
        let mut merged: Vec<usize> = (0..a.len()).map(|k| a[(ia + 1 + k) % a.len()]).collect();
        merged.extend((2..b.len()).map(|k| b[(ib + k) % b.len()]));
        let n = merged.len();
        let convex = (0..n).all(|k| {
            cross(
                points[merged[k]],
                points[merged[(k + 1) % n]],
                points[merged[(k + 2) % n]],
            ) > 1e-12
        });
        return convex.then_some(merged);
    }
    None
}

/// Twice the signed area of triangle `p q r` (positive when counter-clockwise).
fn cross(p: [f64; 2], q: [f64; 2], r: [f64; 2]) -> f64 {
    (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0])
}

/// `b` moved by `d`.
pub(crate) fn shifted(b: Box32, d: [f32; 2]) -> Box32 {
    [b[0] + d[0], b[1] + d[1], b[2] + d[0], b[3] + d[1]]
}

pub(crate) fn union(a: Box32, b: Box32) -> Box32 {
    [
        a[0].min(b[0]),
        a[1].min(b[1]),
        a[2].max(b[2]),
        a[3].max(b[3]),
    ]
}

/// Whether two boxes come within [`CLEARANCE_MM`] of each other.
pub(crate) fn bounds_meet(a: Box32, b: Box32) -> bool {
    a[0] < b[2] + CLEARANCE_MM
        && b[0] < a[2] + CLEARANCE_MM
        && a[1] < b[3] + CLEARANCE_MM
        && b[1] < a[3] + CLEARANCE_MM
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An L: a 4 x 1 bar with a 1 x 3 upright on its left end (area 4 + 3 = 7), not convex.
    fn ell() -> Vec<[f32; 2]> {
        vec![[0., 0.], [4., 0.], [4., 1.], [1., 1.], [1., 4.], [0., 4.]]
    }

    #[test]
    fn smaller_and_larger_agree_with_min_and_max_on_numbers() {
        // Equal as numbers, not bit for bit: `f32::min` leaves the sign of a zero from -0.0 and
        // 0.0 unspecified, and -0.0 == 0.0, so the signed zeros here check only that the result
        // compares equal, which is all the overlap's comparisons and sums can see of it.
        let values = [
            f32::MIN,
            -3.5,
            -0.0,
            0.0,
            1e-7,
            2.0,
            2.0 + f32::EPSILON * 2.0,
            f32::MAX,
        ];
        for a in values {
            for b in values {
                assert_eq!(smaller(a, b), a.min(b), "{a} {b}");
                assert_eq!(larger(a, b), a.max(b), "{a} {b}");
            }
        }
    }

    #[test]
    fn pieces_are_convex_and_cover_the_ring() {
        let pieces = Pieces::new(&ell()).expect("an L triangulates");
        // Hertel–Mehlhorn leaves at most 4x the optimum (2 pieces for an L).
        assert!(
            pieces.len() >= 2 && pieces.len() <= 3,
            "{} pieces",
            pieces.len()
        );
        let area: f64 = pieces
            .pieces
            .iter()
            .map(|p| {
                let ring: Vec<[f64; 2]> = p
                    .vertices
                    .iter()
                    .map(|v| [f64::from(v[0]), f64::from(v[1])])
                    .collect();
                cam_geometry::area(&ring)
            })
            .sum();
        assert!((area - 7.0).abs() < 1e-6, "pieces cover {area}, the L is 7");
        for p in &pieces.pieces {
            let k = p.vertices.len();
            for i in 0..k {
                let f = |v: [f32; 2]| [f64::from(v[0]), f64::from(v[1])];
                let c = cross(
                    f(p.vertices[i]),
                    f(p.vertices[(i + 1) % k]),
                    f(p.vertices[(i + 2) % k]),
                );
                assert!(c > 0.0, "piece {:?} not convex", p.vertices);
            }
        }
    }

    #[test]
    fn the_projection_table_gives_the_same_numbers_as_projecting() {
        // The table only stores what `piece_overlap` would compute, so every query must agree to
        // the bit, at every offset and in both orders, across shapes of several pieces.
        let mut ell = Pieces::new(&ell()).unwrap();
        let mut diamond = Pieces::new(&[[1., 0.], [2., 1.], [1., 2.], [0., 1.]]).unwrap();
        let mut trapezoid = Pieces::new(&[[0., 0.], [5., 0.4], [5., 1.6], [0., 2.]]).unwrap();
        let plain = [ell.clone(), diamond.clone(), trapezoid.clone()];
        let table = Projections::new(&mut [&mut ell, &mut diamond, &mut trapezoid]).unwrap();
        let numbered = [ell, diamond, trapezoid];
        let mut touching = 0;
        for (i, j) in (0..3).flat_map(|i| (0..3).map(move |j| (i, j))) {
            for step in 0..400 {
                let t = [
                    (step % 20) as f32 * 0.3 - 3.0,
                    (step / 20) as f32 * 0.3 - 3.0,
                ];
                let known = overlap(
                    &numbered[i],
                    t,
                    &numbered[j],
                    [0.0, 0.0],
                    Some(&table),
                    f32::MAX,
                );
                let computed = overlap(&plain[i], t, &plain[j], [0.0, 0.0], None, f32::MAX);
                assert_eq!(known.to_bits(), computed.to_bits(), "{i} at {t:?} into {j}");
                touching += usize::from(known > 0.0);
            }
        }
        assert!(
            touching > 100,
            "only {touching} overlapping placements were compared"
        );
        // Above the size limit there is no table and the shapes stay unnumbered.
        let mut many: Vec<Pieces> = (0..=MAX_TABLE_PIECES)
            .map(|_| Pieces::new(&[[0., 0.], [1., 0.], [0., 1.]]).unwrap())
            .collect();
        let mut refs: Vec<&mut Pieces> = many.iter_mut().collect();
        assert!(Projections::new(&mut refs).is_none());
        assert!(many.iter().all(|p| p.first_id.is_none()));
    }

    #[test]
    fn overlap_is_zero_exactly_when_apart_and_equals_the_overlap_area_of_two_squares() {
        let square = Pieces::new(&[[0., 0.], [2., 0.], [2., 2.], [0., 2.]]).unwrap();
        // Closed forms: two axis-aligned 2 x 2 squares overlapping by 0.5 in x and fully in y
        // share a 0.5 x 2 rectangle; shifted 0.5 in y as well, a 0.5 x 1.5 one. Each side of
        // it counts the clearance once.
        let c = CLEARANCE_MM;
        for (t, area) in [
            ([1.5, 0.0], (0.5 + c) * (2.0 + c)),
            ([1.5, 0.5], (0.5 + c) * (1.5 + c)),
        ] {
            let o = overlap(&square, t, &square, [0.0, 0.0], None, f32::MAX);
            assert!((o - area).abs() < 1e-5, "{t:?}: {o} against {area}");
        }
        // Apart by more than the clearance: zero; closer than it: positive.
        assert_eq!(
            overlap(&square, [2.01, 0.3], &square, [0.0, 0.0], None, f32::MAX),
            0.0
        );
        assert!(overlap(&square, [2.001, 0.3], &square, [0.0, 0.0], None, f32::MAX) > 0.0);
        // Diagonal neighbours whose boxes overlap but whose edges do not meet.
        let diamond = Pieces::new(&[[1., 0.], [2., 1.], [1., 2.], [0., 1.]]).unwrap();
        assert_eq!(
            overlap(&diamond, [1.4, 1.4], &diamond, [0.0, 0.0], None, f32::MAX),
            0.0
        );
        assert!(overlap(&diamond, [0.9, 0.9], &diamond, [0.0, 0.0], None, f32::MAX) > 0.0);
    }

    #[test]
    fn the_overlap_of_two_convex_pieces_is_never_less_than_their_shared_area() {
        // The module's claim: the intersection lies in the rectangle of the two overlaps, so
        // the measure bounds the shared area from above. Checked against geo's boolean
        // intersection for triangles and quadrilaterals at many offsets.
        use geo::BooleanOps;
        use rand::{Rng, SeedableRng};
        let polygon = |pts: &[[f32; 2]], t: [f32; 2]| {
            let ring: Vec<Coord<f64>> = pts
                .iter()
                .map(|p| Coord {
                    x: f64::from(p[0] + t[0]),
                    y: f64::from(p[1] + t[1]),
                })
                .collect();
            Polygon::new(LineString::from(ring), vec![])
        };
        let shapes: [&[[f32; 2]]; 3] = [
            &[[0., 0.], [3., 0.5], [1., 2.]],
            &[[0., 0.], [4., 0.], [4.5, 1.], [0.5, 1.5]],
            &[[1., 0.], [2., 1.], [1., 2.], [0., 1.]],
        ];
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
        let mut overlapping = 0;
        for a in shapes {
            for b in shapes {
                let (pa, pb) = (Pieces::new(a).unwrap(), Pieces::new(b).unwrap());
                for _ in 0..200 {
                    let t = [rng.gen_range(-3.0..3.0), rng.gen_range(-2.0..2.0)];
                    let o = overlap(&pa, t, &pb, [0.0, 0.0], None, f32::MAX);
                    let shared = polygon(a, t)
                        .intersection(&polygon(b, [0.0, 0.0]))
                        .unsigned_area();
                    if shared > 1e-6 {
                        overlapping += 1;
                    }
                    assert!(f64::from(o) >= shared - 1e-4, "{t:?}: {o} under {shared}");
                }
            }
        }
        assert!(overlapping > 500, "only {overlapping} offsets overlap");
    }

    #[test]
    fn two_bars_overlapping_along_their_length_cost_more_than_at_their_corners() {
        // Two 10 x 1 bars 0.1 deep into each other: side by side over their whole length they
        // share 10 x 0.1, corner to corner 0.1 x 0.1. The depth is 0.1 either way; the measure
        // is the shared area, a hundred times larger along the length.
        let bar = Pieces::new(&[[0., 0.], [10., 0.], [10., 1.], [0., 1.]]).unwrap();
        let c = CLEARANCE_MM;
        let along = overlap(&bar, [0.0, 0.9], &bar, [0.0, 0.0], None, f32::MAX);
        let corner = overlap(&bar, [9.9, 0.9], &bar, [0.0, 0.0], None, f32::MAX);
        assert!((along - (0.1 + c) * (10.0 + c)).abs() < 1e-4, "{along}");
        assert!((corner - (0.1 + c) * (0.1 + c)).abs() < 1e-5, "{corner}");
        assert!(loss(along, &bar, &bar) > 5.0 * loss(corner, &bar, &bar));
    }

    #[test]
    fn the_loss_is_the_overlap_with_a_floor_scaled_by_the_sizes() {
        // Closed forms (sparrow's quantification, Gardeyn & Wauters 2025, Algorithm 4): a 2 x 2
        // square has diameter 2√2 and size √4 = 2; an 8 x 2 bar diameter √68 and size 4.
        let square = Pieces::new(&[[0., 0.], [2., 0.], [2., 2.], [0., 2.]]).unwrap();
        let bar = Pieces::new(&[[0., 0.], [8., 0.], [8., 2.], [0., 2.]]).unwrap();
        assert!((square.diameter - 8f32.sqrt()).abs() < 1e-5);
        assert!((square.size - 2.0).abs() < 1e-5 && (bar.size - 4.0).abs() < 1e-5);
        assert_eq!(loss(0.0, &square, &bar), 0.0);
        // Deep: about the root of the overlap times √(2 · 4).
        let deep = loss(0.5, &square, &bar);
        let floor = 0.01 * 68f32.sqrt();
        let expected = (0.5 + floor * floor).sqrt() * 8f32.sqrt();
        assert!((deep - expected).abs() < 1e-5, "{deep} against {expected}");
        // Shallow: never under the floor, 1 % of the larger diameter, times the sizes.
        let shallow = loss(1e-6, &square, &bar);
        assert!(shallow >= floor * 8f32.sqrt() && shallow < 1.001 * floor * 8f32.sqrt());
        // The same overlap between two squares costs less than between a square and the bar.
        assert!(loss(0.5, &square, &square) < deep);
    }

    #[test]
    fn shapes_are_unlike_only_if_both_their_hull_areas_and_their_diameters_differ() {
        // A 2 x 2 square (area 4, diameter √8), the same square turned 45° about its corner, a
        // 1 x 4 bar (area 4, diameter √17) and an L of three unit squares in an ell of 2 x 2
        // (hull area 3.5, diameter √8).
        let square = Pieces::new(&[[0., 0.], [2., 0.], [2., 2.], [0., 2.]]).unwrap();
        let h = std::f32::consts::SQRT_2;
        let turned = Pieces::new(&[[0., 0.], [h, h], [0., 2. * h], [-h, h]]).unwrap();
        let bar = Pieces::new(&[[0., 0.], [4., 0.], [4., 1.], [0., 1.]]).unwrap();
        let ell = Pieces::new(&[[0., 0.], [2., 0.], [2., 1.], [1., 1.], [1., 2.], [0., 2.]]);
        let ell = ell.unwrap();
        let big = Pieces::new(&[[0., 0.], [3., 0.], [3., 3.], [0., 3.]]).unwrap();
        assert!((ell.hull_area() - 3.5).abs() < 1e-5 && (bar.hull_area() - 4.0).abs() < 1e-5);
        assert!(!square.unlike(&turned), "one shape at two angles");
        assert!(!square.unlike(&bar), "the same area");
        assert!(!square.unlike(&ell), "the same diameter");
        assert!(square.unlike(&big) && big.unlike(&square));
        assert!(bar.unlike(&ell));
    }

    #[test]
    fn the_overlap_reaching_a_loss_is_the_inverse_of_the_loss_and_stops_the_sum_there() {
        let square = Pieces::new(&[[0., 0.], [2., 0.], [2., 2.], [0., 2.]]).unwrap();
        let bar = Pieces::new(&[[0., 0.], [8., 0.], [8., 2.], [0., 2.]]).unwrap();
        for target in [0.5f32, 1.0, 3.0, 10.0] {
            let d = overlap_reaching(target, &square, &bar);
            // Its loss reaches the target, and an overlap a little under it does not.
            assert!(loss(d, &square, &bar) >= target, "{target}: {d}");
            assert!(loss(0.99 * d, &square, &bar) < target, "{target}: {d}");
        }
        // Under the floor any collision costs the target: zero overlap reaches it.
        let floor = loss(1e-9, &square, &bar);
        assert_eq!(overlap_reaching(0.9 * floor, &square, &bar), 0.0);
        // An ell of two pieces over a square: the whole sum, or part of it once it is enough.
        let l = Pieces::new(&[[0., 0.], [3., 0.], [3., 1.], [1., 1.], [1., 3.], [0., 3.]]).unwrap();
        assert!(l.pieces.len() == 2);
        let big = Pieces::new(&[[0., 0.], [4., 0.], [4., 4.], [0., 4.]]).unwrap();
        let whole = overlap(&l, [0.5, 0.5], &big, [0.0, 0.0], None, f32::MAX);
        let part = overlap(&l, [0.5, 0.5], &big, [0.0, 0.0], None, 1e-6);
        assert!(part > 0.0 && part < whole, "{part} of {whole}");
        assert_eq!(
            overlap(&l, [0.5, 0.5], &big, [0.0, 0.0], None, whole).to_bits(),
            whole.to_bits()
        );
    }

    #[test]
    fn an_ell_does_not_collide_with_a_square_in_its_notch() {
        // The notch of the L is [1, 4] x [1, 4]: a square there is clear of it, which a
        // convex hull or a box test would miss.
        let l = Pieces::new(&ell()).unwrap();
        let square = Pieces::new(&[[0., 0.], [2., 0.], [2., 2.], [0., 2.]]).unwrap();
        assert_eq!(
            overlap(&square, [1.5, 1.5], &l, [0.0, 0.0], None, f32::MAX),
            0.0
        );
        assert_eq!(
            overlap(&l, [0.0, 0.0], &square, [1.5, 1.5], None, f32::MAX),
            0.0
        );
        assert!(overlap(&square, [0.9, 1.5], &l, [0.0, 0.0], None, f32::MAX) > 0.0);
        assert!(overlap(&square, [1.5, 0.9], &l, [0.0, 0.0], None, f32::MAX) > 0.0);
    }

    /// Independent check with geo's polygon distance: over random placements of two tapered
    /// actuator outlines (a trapezoid with a tip extension and a base tab, not convex), the
    /// measure is zero exactly when the polygons are at least the clearance apart (placements
    /// within 1e-3 mm of that boundary are skipped: f32 against f64).
    #[test]
    fn zero_exactly_when_geo_finds_the_outlines_apart() {
        use geo::{Distance, Euclidean};
        use rand::{Rng, SeedableRng};
        let ring: Vec<[f32; 2]> = vec![
            [-3., -6.],
            [0., -6.],
            [30., -1.5],
            [50., -1.5],
            [50., 1.5],
            [30., 1.5],
            [0., 6.],
            [-3., 6.],
        ];
        let pieces = Pieces::new(&ring).unwrap();
        let turned: Vec<[f32; 2]> = ring.iter().map(|p| [-p[0], -p[1]]).collect();
        let turned_pieces = Pieces::new(&turned).unwrap();
        let polygon = |r: &[[f32; 2]], t: [f32; 2]| {
            Polygon::new(
                LineString::from(
                    r.iter()
                        .map(|p| (f64::from(p[0] + t[0]), f64::from(p[1] + t[1])))
                        .collect::<Vec<_>>(),
                ),
                Vec::new(),
            )
        };
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
        let (mut apart, mut overlapping) = (0, 0);
        for _ in 0..4000 {
            let t = [rng.gen_range(-60.0..60.0f32), rng.gen_range(-14.0..14.0f32)];
            let (other, other_ring) = if rng.gen_bool(0.5) {
                (&pieces, &ring)
            } else {
                (&turned_pieces, &turned)
            };
            let distance = Euclidean.distance(&polygon(&ring, [0.0, 0.0]), &polygon(other_ring, t));
            let margin = f64::from(CLEARANCE_MM);
            if (distance - margin).abs() < 1e-3 {
                continue;
            }
            let o = overlap(&pieces, [0.0, 0.0], other, t, None, f32::MAX);
            if distance > margin {
                assert_eq!(o, 0.0, "apart by {distance} at {t:?} but overlap {o}");
                apart += 1;
            } else {
                assert!(o > 0.0, "{distance} apart at {t:?} but overlap 0");
                overlapping += 1;
            }
        }
        assert!(
            apart > 500 && overlapping > 500,
            "{apart} apart, {overlapping} overlapping"
        );
    }

    #[test]
    fn overlap_falls_as_a_part_moves_out() {
        let l = Pieces::new(&ell()).unwrap();
        let mut last = f32::MAX;
        for k in 1..=10 {
            let s = 0.5 * k as f32;
            let o = overlap(&l, [s, s], &l, [0.0, 0.0], None, f32::MAX);
            assert!(o <= last, "overlap rose from {last} to {o} at ({s}, {s})");
            last = o;
        }
        assert_eq!(last, 0.0);
    }
}
