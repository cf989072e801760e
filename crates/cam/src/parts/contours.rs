//! From the contours a file holds to parts, with the checks every format shares: LINE/ARC pieces
//! chained into closed loops, each loop a simple ring (no self-intersection, no zero area), no two
//! loops crossing, and loops nested into parts: an outer contour with the contours directly inside
//! it as its cut-outs. Every refusal names the file and the entity.

use super::crossing::{rings_in_contact, self_contact};
use super::extent::{check_width, Extent};
use super::{entity_error, ImportedPart};
use crate::input::InputError;
use cam_geometry::{signed_area, Point};
use geo::{BoundingRect, Contains, Coord, Intersects, LineString, Polygon, Rect};
use std::collections::HashMap;
use std::path::Path;

/// Ends of two pieces closer than this join, mm: CAD files store the shared end of a line and an arc
/// twice, computed separately, so they differ in the last digits.
pub const JOIN_MM: f64 = 1e-4;

/// A closed contour as read, named by the entity (or entities) it came from.
#[derive(Debug, Clone)]
pub struct Contour {
    /// `LWPOLYLINE handle 2F`, `path id="slot"`, …
    pub entity: String,
    /// Points in mm, y up, without the closing repeat.
    pub ring: Vec<Point>,
}

/// An open piece (a DXF LINE or ARC): points from its start to its end, in mm.
#[derive(Debug, Clone)]
pub struct Piece {
    /// `LINE handle 1F`.
    pub entity: String,
    /// At least two points.
    pub points: Vec<Point>,
}

fn close(a: Point, b: Point) -> bool {
    (a[0] - b[0]).hypot(a[1] - b[1]) <= JOIN_MM
}

fn xy(p: Point) -> String {
    format!("({:.4}, {:.4})", p[0], p[1])
}

/// The grid cell, [`JOIN_MM`] on a side, an end lies in: two ends that join lie in the same cell
/// or in neighbouring ones.
fn cell(p: Point) -> (i64, i64) {
    // `as` saturates (and takes NaN to 0): a huge coordinate only shares its cell with others.
    (
        (p[0] / JOIN_MM).floor() as i64,
        (p[1] / JOIN_MM).floor() as i64,
    )
}

/// Chain open pieces end to end into closed loops; a piece that cannot be closed is an open contour.
/// Each piece's ends are filed by grid cell ([`cell`]), so the piece that continues a chain is looked
/// up among the few filed around its end rather than among every piece: a drawing exploded into
/// tens of thousands of LINE entities chains in linear time. Of the pieces that could continue a
/// chain, the first in the file is taken, and each loop starts at the first piece left.
pub fn chain(file: &Path, pieces: Vec<Piece>) -> Result<Vec<Contour>, InputError> {
    let mut filed: HashMap<(i64, i64), Vec<usize>> = HashMap::new();
    for (k, piece) in pieces.iter().enumerate() {
        for end in [piece.points[0], *piece.points.last().expect("points")] {
            let here = filed.entry(cell(end)).or_default();
            if here.last() != Some(&k) {
                here.push(k);
            }
        }
    }
    let mut left: Vec<Option<Piece>> = pieces.into_iter().map(Some).collect();
    let mut loops = Vec::new();
    for start in 0..left.len() {
        let Some(first) = left[start].take() else {
            continue;
        };
        let head = first.points[0];
        let mut names = vec![first.entity.clone()];
        let mut points = first.points;
        loop {
            let end = *points.last().expect("pieces have points");
            if points.len() > 2 && close(end, head) {
                points.pop();
                break;
            }
            let (x, y) = cell(end);
            let next = (x.saturating_sub(1)..=x.saturating_add(1))
                .flat_map(|x| (y.saturating_sub(1)..=y.saturating_add(1)).map(move |y| (x, y)))
                .filter_map(|c| filed.get(&c))
                .flatten()
                .copied()
                .filter(|&k| {
                    left[k].as_ref().is_some_and(|p| {
                        close(p.points[0], end) || close(*p.points.last().expect("points"), end)
                    })
                })
                .min();
            let Some(k) = next else {
                return Err(entity_error(
                    file,
                    &names[names.len() - 1],
                    format!(
                        "open contour: nothing continues it at {} mm (it started at {} mm); an outline (of a part or a drawn sheet) must be closed",
                        xy(end),
                        xy(head)
                    ),
                ));
            };
            let mut piece = left[k].take().expect("found above");
            if !close(piece.points[0], end) {
                piece.points.reverse();
            }
            names.push(piece.entity);
            points.extend_from_slice(&piece.points[1..]);
        }
        let entity = match names.len() {
            1 => names.remove(0),
            n => format!("{} (+{} joined entities)", names[0], n - 1),
        };
        loops.push(Contour {
            entity,
            ring: points,
        });
    }
    Ok(loops)
}

fn line_string(ring: &[Point]) -> LineString<f64> {
    let mut coords: Vec<Coord<f64>> = ring.iter().map(|p| Coord { x: p[0], y: p[1] }).collect();
    coords.push(coords[0]);
    LineString::new(coords)
}

/// A contour's ring without repeated points, counter-clockwise, checked to be a simple ring.
fn simple_ring(file: &Path, contour: &Contour) -> Result<Vec<Point>, InputError> {
    let mut ring = cam_nest::clean_ring(&contour.ring);
    if ring.iter().flatten().any(|c| !c.is_finite()) {
        return Err(entity_error(
            file,
            &contour.entity,
            "a coordinate is not a finite number",
        ));
    }
    let a = signed_area(&ring);
    // A ring whose points do not lie on one line but whose signed area is nil crosses itself: the
    // lobes of a symmetric bow-tie cancel.
    if ring.len() >= 3 && a.abs() < 1e-9 && !on_one_line(&ring) {
        return Err(self_intersecting(file, contour));
    }
    if ring.len() < 3 || a.abs() < 1e-9 {
        return Err(entity_error(
            file,
            &contour.entity,
            "zero area: a closed contour needs at least three points not on one line",
        ));
    }
    if a < 0.0 {
        ring.reverse();
    }
    let mut extent = Extent::default();
    ring.iter().for_each(|p| extent.add(*p));
    extent.check(file, &contour.entity)?;
    if self_contact(&ring).is_some() {
        return Err(self_intersecting(file, contour));
    }
    Ok(ring)
}

fn self_intersecting(file: &Path, contour: &Contour) -> InputError {
    entity_error(
        file,
        &contour.entity,
        "self-intersecting contour: its edges cross or touch; an outline (of a part or a drawn sheet) must be a simple closed curve",
    )
}

/// True when every point lies on the line through the first point and the one farthest from it
/// (within 1e-9 of the ring's size).
fn on_one_line(ring: &[Point]) -> bool {
    let p0 = ring[0];
    let d = |p: &Point| [p[0] - p0[0], p[1] - p0[1]];
    let far = ring
        .iter()
        .map(d)
        .max_by(|a, b| a[0].hypot(a[1]).total_cmp(&b[0].hypot(b[1])))
        .unwrap_or([0.0, 0.0]);
    let size = far[0].hypot(far[1]);
    ring.iter()
        .map(d)
        .all(|v| (v[0] * far[1] - v[1] * far[0]).abs() <= 1e-9 * size.max(1.0) * size.max(1.0))
}

/// Nest the file's closed contours into parts: each contour not inside another is a part's outline,
/// each contour directly inside one is a cut-out of that part. File order is kept.
pub fn assemble(file: &Path, contours: Vec<Contour>) -> Result<Vec<ImportedPart>, InputError> {
    if contours.is_empty() {
        return Err(InputError::whole_file(
            file,
            "no closed contour: a drawing needs at least one closed LWPOLYLINE/POLYLINE, CIRCLE or loop of LINE/ARC entities (DXF), or a closed path, polygon, rect, circle or ellipse (SVG)",
        ));
    }
    let rings: Vec<Vec<Point>> = contours
        .iter()
        .map(|c| simple_ring(file, c))
        .collect::<Result<_, _>>()?;
    if let Some((i, j)) = rings_in_contact(&rings) {
        return Err(entity_error(
            file,
            &contours[j].entity,
            format!(
                "crosses or touches {}: contours of parts and their cut-outs must not meet",
                contours[i].entity
            ),
        ));
    }
    let boxes: Vec<Rect<f64>> = rings
        .iter()
        .map(|r| {
            let s = line_string(r);
            s.bounding_rect().expect("a ring has points")
        })
        .collect();
    let polygons: Vec<Polygon<f64>> = rings
        .iter()
        .map(|r| Polygon::new(line_string(r), Vec::new()))
        .collect();
    // Contours do not cross, so one is inside another exactly when one of its points is; the
    // bounding boxes rule out most pairs before a point-in-polygon test of the whole ring.
    let inside = |i: usize, j: usize| {
        let p = Coord {
            x: rings[i][0][0],
            y: rings[i][0][1],
        };
        i != j && boxes[j].intersects(&p) && polygons[j].contains(&p)
    };
    let depth: Vec<usize> = (0..rings.len())
        .map(|i| (0..rings.len()).filter(|&j| inside(i, j)).count())
        .collect();
    let mut parts: Vec<(usize, ImportedPart)> = Vec::new();
    for i in 0..rings.len() {
        match depth[i] {
            0 => {
                check_width(file, &contours[i].entity, &rings[i])?;
                parts.push((
                i,
                ImportedPart {
                    file: file.to_path_buf(),
                    entity: contours[i].entity.clone(),
                    outer: rings[i].clone(),
                    holes: Vec::new(),
                },
                ))
            }
            1 => {}
            _ => {
                return Err(entity_error(
                    file,
                    &contours[i].entity,
                    "lies inside a cut-out of another part: draw it beside the other part (the nester puts parts into cut-outs itself)",
                ))
            }
        }
    }
    for i in (0..rings.len()).filter(|&i| depth[i] == 1) {
        let (_, part) = parts
            .iter_mut()
            .find(|(o, _)| inside(i, *o))
            .expect("a depth-1 contour lies inside one outer contour");
        part.holes.push(rings[i].clone());
    }
    Ok(parts.into_iter().map(|(_, p)| p).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn piece(name: &str, points: &[Point]) -> Piece {
        Piece {
            entity: name.into(),
            points: points.to_vec(),
        }
    }

    #[test]
    fn pieces_in_any_direction_chain_into_one_loop() {
        let loops = chain(
            Path::new("f.dxf"),
            vec![
                piece("LINE handle A", &[[0.0, 0.0], [1.0, 0.0]]),
                piece("LINE handle B", &[[1.0, 1.0], [1.0, 0.0]]),
                piece("LINE handle C", &[[1.0, 1.0], [0.0, 1.0]]),
                piece("LINE handle D", &[[0.0, 1.0], [0.0, 0.00001]]),
            ],
        )
        .unwrap();
        assert_eq!(loops.len(), 1);
        assert_eq!(loops[0].ring.len(), 4);
        assert!(loops[0].entity.starts_with("LINE handle A"));
    }

    #[test]
    fn a_loop_of_100000_lines_in_shuffled_order_chains_in_linear_time() {
        // A circle exploded into LINE entities, filed in a scrambled order. Scanning every piece for
        // the one that continues a chain grows as the square of the count (some 10^9 end tests
        // here, a minute or more); the grid finds it among a few, some tenths of a second of CPU. 5 s leaves
        // room for a loaded machine.
        let n = 100_000;
        let at = |k: usize| {
            let a = std::f64::consts::TAU * (k % n) as f64 / n as f64;
            [1000.0 * a.cos(), 1000.0 * a.sin()]
        };
        // k -> 7919 k mod n is a permutation (7919 is prime and does not divide 100,000).
        let pieces: Vec<Piece> = (0..n)
            .map(|i| {
                let k = i * 7919 % n;
                piece(&format!("LINE handle {k:X}"), &[at(k), at(k + 1)])
            })
            .collect();
        let start = std::time::Instant::now();
        let loops = chain(Path::new("f.dxf"), pieces).unwrap();
        let seconds = start.elapsed().as_secs_f64();
        assert_eq!(loops.len(), 1);
        assert_eq!(loops[0].ring.len(), n);
        assert_eq!(loops[0].entity, "LINE handle 0 (+99999 joined entities)");
        assert!(seconds < 5.0, "{seconds} s");
    }

    #[test]
    fn a_dangling_piece_is_an_open_contour_named_by_its_entity() {
        let err = chain(
            Path::new("f.dxf"),
            vec![
                piece("LINE handle A", &[[0.0, 0.0], [1.0, 0.0]]),
                piece("LINE handle B", &[[1.0, 0.0], [1.0, 1.0]]),
            ],
        )
        .unwrap_err()
        .to_string();
        assert!(
            err.starts_with("f.dxf: LINE handle B: open contour"),
            "{err}"
        );
    }

    #[test]
    fn a_contour_inside_another_is_its_cut_out() {
        let square = |s: f64, o: f64| vec![[o, o], [o + s, o], [o + s, o + s], [o, o + s]];
        let parts = assemble(
            Path::new("f.svg"),
            vec![
                Contour {
                    entity: "hole".into(),
                    ring: square(1.0, 1.0),
                },
                Contour {
                    entity: "outer".into(),
                    ring: square(4.0, 0.0),
                },
                Contour {
                    entity: "beside".into(),
                    ring: square(1.0, 10.0),
                },
            ],
        )
        .unwrap();
        assert_eq!(parts.len(), 2);
        assert_eq!(parts[0].entity, "outer");
        assert_eq!(parts[0].holes.len(), 1);
        assert!((parts[0].area_mm2() - 15.0).abs() < 1e-12);
    }
}
