//! Independent placement verifier.
//!
//! Checks a finished [`SheetLayout`] without trusting the code that made it: distances, overlaps
//! and containment come from `geo` predicates and metrics, and the snap check replays the breaks
//! on the sheet itself. Nothing here reuses the arithmetic of [`super::plates`] or
//! [`super::shelf`].

use super::placement::{Sheet, SheetLayout};
use cam_geometry::Point;
use geo::{
    Area, BooleanOps, BoundingRect, Coord, Distance, Euclidean, Length, Line, LineString,
    MultiLineString, Polygon, Rotate, Translate, Validation,
};
use std::fmt;
use thiserror::Error;

/// Which part a violation is about: its index in `placements`, its item and copy.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PartRef {
    pub index: usize,
    pub item: usize,
    pub copy: usize,
}

impl fmt::Display for PartRef {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "part {} (item {} copy {})",
            self.index, self.item, self.copy
        )
    }
}

/// One thing wrong with a layout.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum Violation {
    #[error("{part} has an invalid outline: {reason}")]
    InvalidOutline { part: PartRef, reason: String },
    #[error("{part} lies (partly) outside the {sheet_width_mm} x {sheet_height_mm} mm sheet")]
    OutsideSheet {
        part: PartRef,
        sheet_width_mm: f64,
        sheet_height_mm: f64,
    },
    #[error(
        "{part} is {distance_mm:.6} mm from the sheet edge, less than the required {min_mm:.6} mm"
    )]
    EdgeGap {
        part: PartRef,
        distance_mm: f64,
        min_mm: f64,
    },
    #[error("{a} and {b} overlap ({area_mm2:.6} mm²)")]
    Overlap {
        a: PartRef,
        b: PartRef,
        area_mm2: f64,
    },
    #[error("{a} and {b} are {distance_mm:.6} mm apart, less than the required {min_mm:.6} mm")]
    Gap {
        a: PartRef,
        b: PartRef,
        distance_mm: f64,
        min_mm: f64,
    },
    #[error("{part} is rotated by {rotation_deg}°, not one of the allowed {allowed:?}")]
    ForbiddenRotation {
        part: PartRef,
        rotation_deg: f64,
        allowed: Vec<f64>,
    },
    #[error("{part} outline is not its item's nominal outline rotated and moved as stated (off by {deviation_mm:.3e} mm)")]
    OutlineMismatch { part: PartRef, deviation_mm: f64 },
    #[error("score line {line} is not a proper segment (too short or not finite)")]
    DegenerateScoreLine { line: usize },
    #[error("score line {line} leaves the sheet")]
    ScoreLineOutsideSheet { line: usize },
    #[error("score line {line} ends in mid-air at ({x:.4}, {y:.4}): not on the sheet edge nor on another score line")]
    ScoreLineMidAir { line: usize, x: f64, y: f64 },
    #[error("score lines {lines:?} cannot be snapped in any order: each ends on another of them")]
    NotGuillotine { lines: Vec<usize> },
    #[error("score line {line} is listed before the line its end ({x:.4}, {y:.4}) rests on")]
    OutOfOrder { line: usize, x: f64, y: f64 },
    #[error("score line {line} ends inside a piece it should split edge to edge")]
    ScoreLineEndsInPiece { line: usize },
    #[error("score line {line} crosses the interior of {part}")]
    ScoreLineCrossesPlate { line: usize, part: PartRef },
    #[error("{part} does not lie inside one cell of the score lines")]
    PlateNotInCell { part: PartRef },
    #[error("{a} and {b} lie in the same cell: no score line separates them")]
    SharedCell { a: PartRef, b: PartRef },
    #[error("the layout uses {used} sheets but the stock is {stock}")]
    StockExceeded { used: usize, stock: usize },
    #[error("item {item}: copies placed {placed:?}, wanted each of 0..{wanted} once")]
    WrongCopies {
        item: usize,
        wanted: usize,
        placed: Vec<usize>,
    },
}

/// Tolerance for "lies on" in the snap check, mm (as specified for score line ends).
const ON_TOL: f64 = 1e-6;
/// Overlap area that still counts as touching, mm² (floating-point noise of shared edges).
const AREA_TOL: f64 = 1e-9;
/// Tolerance for rotations, degrees.
const ANGLE_TOL: f64 = 1e-9;

fn part_ref(layout: &SheetLayout, index: usize) -> PartRef {
    let p = &layout.placements[index];
    PartRef {
        index,
        item: p.item,
        copy: p.copy,
    }
}

fn coord(p: Point) -> Coord<f64> {
    Coord { x: p[0], y: p[1] }
}

fn polygon(ring: &[Point]) -> Polygon<f64> {
    Polygon::new(ring.iter().map(|&p| coord(p)).collect(), vec![])
}

fn sheet_polygon(sheet: &Sheet) -> Polygon<f64> {
    polygon(&[
        [0.0, 0.0],
        [sheet.width_mm, 0.0],
        [sheet.width_mm, sheet.height_mm],
        [0.0, sheet.height_mm],
    ])
}

fn finish(violations: Vec<Violation>) -> Result<(), Vec<Violation>> {
    if violations.is_empty() {
        Ok(())
    } else {
        Err(violations)
    }
}

/// Checks a layout of cut parts: every part inside the sheet at least `gap_mm` from the edge,
/// every pair at least `gap_mm` apart and not overlapping, every rotation allowed for its item.
pub fn verify_sheet(
    layout: &SheetLayout,
    sheet: &Sheet,
    gap_mm: f64,
    allowed_rotations: &dyn Fn(usize) -> Vec<f64>,
) -> Result<(), Vec<Violation>> {
    verify_sheet_edges(layout, sheet, gap_mm, gap_mm, allowed_rotations)
}

/// [`verify_sheet`] with its own clearance to the sheet edge, `edge_gap_mm` (scored plates keep
/// the kerf between each other but only the margin to the edge).
pub fn verify_sheet_edges(
    layout: &SheetLayout,
    sheet: &Sheet,
    gap_mm: f64,
    edge_gap_mm: f64,
    allowed_rotations: &dyn Fn(usize) -> Vec<f64>,
) -> Result<(), Vec<Violation>> {
    let mut violations = Vec::new();
    let sheet_poly = sheet_polygon(sheet);
    let sheet_edge = sheet_poly.exterior().clone();
    let sheet_rect = sheet_poly.bounding_rect().expect("sheet is not empty");
    let mut parts: Vec<Option<Polygon<f64>>> = Vec::new();
    for (index, placement) in layout.placements.iter().enumerate() {
        let part = part_ref(layout, index);
        let allowed = allowed_rotations(placement.item);
        let turn = |a: f64| (placement.rotation_deg - a).rem_euclid(360.0);
        if !allowed
            .iter()
            .any(|&a| turn(a) < ANGLE_TOL || turn(a) > 360.0 - ANGLE_TOL)
        {
            violations.push(Violation::ForbiddenRotation {
                part,
                rotation_deg: placement.rotation_deg,
                allowed,
            });
        }
        let ring = &placement.outline;
        let poly = polygon(ring);
        let reason = if ring.len() < 3 {
            Some("fewer than 3 points".to_string())
        } else if ring.iter().flatten().any(|v| !v.is_finite()) {
            Some("a coordinate is not finite".to_string())
        } else if !poly.is_valid() {
            Some(format!("{:?}", poly.validation_errors()))
        } else {
            None
        };
        if let Some(reason) = reason {
            violations.push(Violation::InvalidOutline { part, reason });
            parts.push(None);
            continue;
        }
        let rect = poly.bounding_rect().expect("valid polygon");
        let tol = 1e-9;
        if rect.min().x < sheet_rect.min().x - tol
            || rect.min().y < sheet_rect.min().y - tol
            || rect.max().x > sheet_rect.max().x + tol
            || rect.max().y > sheet_rect.max().y + tol
        {
            violations.push(Violation::OutsideSheet {
                part,
                sheet_width_mm: sheet.width_mm,
                sheet_height_mm: sheet.height_mm,
            });
        } else {
            let distance = Euclidean.distance(&poly, &sheet_edge);
            if distance < edge_gap_mm {
                violations.push(Violation::EdgeGap {
                    part,
                    distance_mm: distance,
                    min_mm: edge_gap_mm,
                });
            }
        }
        parts.push(Some(poly));
    }

    let rects: Vec<_> = parts
        .iter()
        .map(|p| p.as_ref().and_then(|p| p.bounding_rect()))
        .collect();
    for a in 0..parts.len() {
        for b in a + 1..parts.len() {
            let (Some(pa), Some(pb), Some(ra), Some(rb)) =
                (&parts[a], &parts[b], rects[a], rects[b])
            else {
                continue;
            };
            // Bounding boxes further apart than the gap: the parts are too.
            let separation = (rb.min().x - ra.max().x)
                .max(ra.min().x - rb.max().x)
                .max(rb.min().y - ra.max().y)
                .max(ra.min().y - rb.max().y);
            if separation >= gap_mm && separation > 0.0 {
                continue;
            }
            let distance = Euclidean.distance(pa, pb);
            if distance <= 0.0 {
                let area = pa.intersection(pb).unsigned_area();
                if area > AREA_TOL {
                    violations.push(Violation::Overlap {
                        a: part_ref(layout, a),
                        b: part_ref(layout, b),
                        area_mm2: area,
                    });
                    continue;
                }
            }
            if distance < gap_mm {
                violations.push(Violation::Gap {
                    a: part_ref(layout, a),
                    b: part_ref(layout, b),
                    distance_mm: distance,
                    min_mm: gap_mm,
                });
            }
        }
    }
    finish(violations)
}

/// Checks that every placed outline is its item's nominal ring (`nominal(item)`) rotated about
/// the origin by `rotation_deg` and translated by `offset`, vertex for vertex within `tol_mm`
/// (any starting vertex). This makes the rotation check of [`verify_sheet`] meaningful.
pub fn verify_outlines(
    layout: &SheetLayout,
    nominal: &dyn Fn(usize) -> Vec<Point>,
    tol_mm: f64,
) -> Result<(), Vec<Violation>> {
    let mut violations = Vec::new();
    for (index, placement) in layout.placements.iter().enumerate() {
        let expected: LineString<f64> = nominal(placement.item)
            .into_iter()
            .map(coord)
            .collect::<LineString<f64>>()
            .rotate_around_point(placement.rotation_deg, geo::Point::new(0.0, 0.0))
            .translate(placement.offset[0], placement.offset[1]);
        let expected: Vec<Coord<f64>> = expected.0;
        let actual: Vec<Coord<f64>> = placement.outline.iter().map(|&p| coord(p)).collect();
        let deviation = if expected.len() != actual.len() || actual.is_empty() {
            f64::INFINITY
        } else {
            let n = actual.len();
            (0..n)
                .map(|shift| {
                    (0..n)
                        .map(|i| Euclidean.distance(expected[i], actual[(i + shift) % n]))
                        .fold(0.0, f64::max)
                })
                .fold(f64::INFINITY, f64::min)
        };
        if deviation.is_nan() || deviation > tol_mm {
            violations.push(Violation::OutlineMismatch {
                part: part_ref(layout, index),
                deviation_mm: deviation,
            });
        }
    }
    finish(violations)
}

/// Checks that over all `sheets` every item `i` has copies `0..counts[i]`, each placed once, and
/// no other items.
pub fn verify_copies(sheets: &[SheetLayout], counts: &[usize]) -> Result<(), Vec<Violation>> {
    let mut placed: Vec<Vec<usize>> = vec![Vec::new(); counts.len()];
    let mut violations = Vec::new();
    for p in sheets.iter().flat_map(|s| &s.placements) {
        match placed.get_mut(p.item) {
            Some(copies) => copies.push(p.copy),
            None => violations.push(Violation::WrongCopies {
                item: p.item,
                wanted: 0,
                placed: vec![p.copy],
            }),
        }
    }
    for (item, (mut copies, &wanted)) in placed.into_iter().zip(counts).enumerate() {
        copies.sort_unstable();
        if !copies.iter().copied().eq(0..wanted) {
            violations.push(Violation::WrongCopies {
                item,
                wanted,
                placed: copies,
            });
        }
    }
    finish(violations)
}

/// Checks that `sheets` use at most `stock` sheets.
pub fn verify_stock(sheets: &[SheetLayout], stock: usize) -> Result<(), Vec<Violation>> {
    if sheets.len() > stock {
        Err(vec![Violation::StockExceeded {
            used: sheets.len(),
            stock,
        }])
    } else {
        Ok(())
    }
}

/// Checks that the score lines make the sheet snappable and free every plate:
/// - every line is a straight segment inside the sheet whose two ends lie on the sheet edge or
///   on another score line (within 1e-6 mm);
/// - the lines can be broken one after another, each ending on the edge or on earlier breaks
///   (a pinwheel of lines ending on each other cannot);
/// - replaying the breaks, every plate lies in its own cell and no line crosses a plate.
pub fn verify_snappable(layout: &SheetLayout, sheet: &Sheet) -> Result<(), Vec<Violation>> {
    let mut violations = Vec::new();
    let sheet_poly = sheet_polygon(sheet);
    let Support {
        lines,
        usable,
        on_edge,
        rests_on,
    } = Support::new(layout, sheet, &mut violations);

    // A break order: repeatedly take a line whose ends rest on the edge or on lines taken before.
    let mut order = Vec::new();
    let mut taken = vec![false; lines.len()];
    loop {
        let next = (0..lines.len()).find(|&i| {
            usable[i]
                && !taken[i]
                && (0..2).all(|e| on_edge[i][e] || rests_on[i][e].iter().any(|&j| taken[j]))
        });
        match next {
            Some(i) => {
                taken[i] = true;
                order.push(i);
            }
            None => break,
        }
    }
    let stuck: Vec<usize> = (0..lines.len())
        .filter(|&i| usable[i] && !taken[i])
        .collect();
    if !stuck.is_empty() {
        violations.push(Violation::NotGuillotine { lines: stuck });
    }

    // Replay the breaks. Pieces stay convex: each break is a full chord of the pieces it splits.
    let mut pieces: Vec<Vec<Coord<f64>>> = vec![sheet_poly.exterior().0[..4].to_vec()];
    for &i in &order {
        let mut next_pieces = Vec::with_capacity(pieces.len() + 4);
        for piece in pieces {
            match split_piece(&piece, &lines[i]) {
                Split::Apart(a, b) => {
                    next_pieces.push(a);
                    next_pieces.push(b);
                }
                Split::Untouched => next_pieces.push(piece),
                Split::EndsInside => {
                    violations.push(Violation::ScoreLineEndsInPiece { line: i });
                    next_pieces.push(piece);
                }
            }
        }
        pieces = next_pieces;
    }

    // Every plate in a cell of its own; name the lines that cut through plates.
    let mut owner: Vec<Option<usize>> = vec![None; pieces.len()];
    for (index, placement) in layout.placements.iter().enumerate() {
        let part = part_ref(layout, index);
        let plate = polygon(&placement.outline);
        let Some(plate_rect) = plate.bounding_rect() else {
            continue;
        };
        let mut crossed = false;
        for (i, line) in lines.iter().enumerate() {
            if usable[i] && crosses_interior(&plate, plate_rect, line) {
                violations.push(Violation::ScoreLineCrossesPlate { line: i, part });
                crossed = true;
            }
        }
        let cell = pieces.iter().position(|piece| {
            placement
                .outline
                .iter()
                .all(|&v| inside_convex(piece, coord(v)))
        });
        match cell {
            Some(c) => match owner[c] {
                Some(other) => violations.push(Violation::SharedCell {
                    a: part_ref(layout, other),
                    b: part,
                }),
                None => owner[c] = Some(index),
            },
            None if !crossed => violations.push(Violation::PlateNotInCell { part }),
            None => {}
        }
    }
    finish(violations)
}

/// The score lines of a layout and what each of their ends rests on.
struct Support {
    lines: Vec<Line<f64>>,
    /// False for lines that are degenerate, leave the sheet or end in mid-air.
    usable: Vec<bool>,
    /// Whether each end lies on the sheet edge.
    on_edge: Vec<[bool; 2]>,
    /// The other usable lines each end lies on.
    rests_on: Vec<[Vec<usize>; 2]>,
}

impl Support {
    fn new(layout: &SheetLayout, sheet: &Sheet, violations: &mut Vec<Violation>) -> Support {
        let sheet_edge = sheet_polygon(sheet).exterior().clone();
        let lines: Vec<Line<f64>> = layout
            .score_lines
            .iter()
            .map(|s| Line::new(coord(s[0]), coord(s[1])))
            .collect();
        let mut usable = vec![true; lines.len()];
        let mut rests_on: Vec<[Vec<usize>; 2]> = vec![[Vec::new(), Vec::new()]; lines.len()];
        let mut on_edge = vec![[false; 2]; lines.len()];
        for (i, line) in lines.iter().enumerate() {
            let ends = [line.start, line.end];
            let finite = ends.iter().all(|c| c.x.is_finite() && c.y.is_finite());
            if !finite || Euclidean.length(line) <= ON_TOL {
                violations.push(Violation::DegenerateScoreLine { line: i });
                usable[i] = false;
                continue;
            }
            if ends.iter().any(|c| {
                c.x < -ON_TOL
                    || c.y < -ON_TOL
                    || c.x > sheet.width_mm + ON_TOL
                    || c.y > sheet.height_mm + ON_TOL
            }) {
                violations.push(Violation::ScoreLineOutsideSheet { line: i });
                usable[i] = false;
            }
        }
        for (i, line) in lines.iter().enumerate() {
            if !usable[i] {
                continue;
            }
            for (e, end) in [line.start, line.end].into_iter().enumerate() {
                let point = geo::Point::from(end);
                on_edge[i][e] = Euclidean.distance(&point, &sheet_edge) <= ON_TOL;
                rests_on[i][e] = (0..lines.len())
                    .filter(|&j| {
                        j != i && usable[j] && Euclidean.distance(&point, &lines[j]) <= ON_TOL
                    })
                    .collect();
                if !on_edge[i][e] && rests_on[i][e].is_empty() {
                    violations.push(Violation::ScoreLineMidAir {
                        line: i,
                        x: end.x,
                        y: end.y,
                    });
                    usable[i] = false;
                }
            }
        }
        Support {
            lines,
            usable,
            on_edge,
            rests_on,
        }
    }
}

/// Checks that the score lines are listed in a break order: each line's ends rest on the sheet
/// edge or on lines listed before it (for writers whose document order is the laser order).
pub fn verify_break_order(layout: &SheetLayout, sheet: &Sheet) -> Result<(), Vec<Violation>> {
    let mut violations = Vec::new();
    let support = Support::new(layout, sheet, &mut violations);
    for (i, line) in support.lines.iter().enumerate() {
        if !support.usable[i] {
            continue;
        }
        for (e, end) in [line.start, line.end].into_iter().enumerate() {
            if !support.on_edge[i][e] && !support.rests_on[i][e].iter().any(|&j| j < i) {
                violations.push(Violation::OutOfOrder {
                    line: i,
                    x: end.x,
                    y: end.y,
                });
            }
        }
    }
    finish(violations)
}

enum Split {
    Apart(Vec<Coord<f64>>, Vec<Coord<f64>>),
    Untouched,
    EndsInside,
}

/// Splits a convex piece by a break line if the line crosses it as a full chord.
fn split_piece(piece: &[Coord<f64>], line: &Line<f64>) -> Split {
    let d = line.delta();
    let len = (d.x * d.x + d.y * d.y).sqrt();
    let (dir, normal) = (
        Coord {
            x: d.x / len,
            y: d.y / len,
        },
        Coord {
            x: -d.y / len,
            y: d.x / len,
        },
    );
    let side = |p: Coord<f64>| (p - line.start).x * normal.x + (p - line.start).y * normal.y;
    let along = |p: Coord<f64>| (p - line.start).x * dir.x + (p - line.start).y * dir.y;
    let sides: Vec<f64> = piece.iter().map(|&p| side(p)).collect();
    let max = sides.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let min = sides.iter().copied().fold(f64::INFINITY, f64::min);
    if max <= ON_TOL || min >= -ON_TOL {
        return Split::Untouched;
    }
    // Where the infinite line enters and leaves the piece, as distances along the break.
    let n = piece.len();
    let mut left = Vec::new();
    let mut right = Vec::new();
    let mut chord = (f64::INFINITY, f64::NEG_INFINITY);
    for k in 0..n {
        let (p, q) = (piece[k], piece[(k + 1) % n]);
        let (sp, sq) = (sides[k], sides[(k + 1) % n]);
        if sp >= 0.0 {
            left.push(p);
        }
        if sp <= 0.0 {
            right.push(p);
        }
        if (sp > 0.0 && sq < 0.0) || (sp < 0.0 && sq > 0.0) {
            let t = sp / (sp - sq);
            let x = p + (q - p) * t;
            left.push(x);
            right.push(x);
            chord = (chord.0.min(along(x)), chord.1.max(along(x)));
        } else if sp == 0.0 {
            chord = (chord.0.min(along(p)), chord.1.max(along(p)));
        }
    }
    let overlap = chord.1.min(len) - chord.0.max(0.0);
    if overlap <= ON_TOL {
        return Split::Untouched;
    }
    if chord.0 < -ON_TOL || chord.1 > len + ON_TOL {
        // The piece goes on past an end of the break: the break would stop in mid-air.
        return Split::EndsInside;
    }
    Split::Apart(left, right)
}

/// Whether `p` lies inside the convex CCW piece, allowing `ON_TOL` outside its edges.
fn inside_convex(piece: &[Coord<f64>], p: Coord<f64>) -> bool {
    let n = piece.len();
    (0..n).all(|k| {
        let (a, b) = (piece[k], piece[(k + 1) % n]);
        let e = b - a;
        let len = (e.x * e.x + e.y * e.y).sqrt();
        len == 0.0 || (e.x * (p - a).y - e.y * (p - a).x) / len >= -ON_TOL
    })
}

/// Whether a line passes through the interior of a plate (not just along its boundary).
fn crosses_interior(plate: &Polygon<f64>, plate_rect: geo::Rect<f64>, line: &Line<f64>) -> bool {
    let line_rect = line.bounding_rect();
    if line_rect.min().x > plate_rect.max().x
        || line_rect.max().x < plate_rect.min().x
        || line_rect.min().y > plate_rect.max().y
        || line_rect.max().y < plate_rect.min().y
    {
        return false;
    }
    let clipped = plate.clip(
        &MultiLineString::new(vec![LineString::new(vec![line.start, line.end])]),
        false,
    );
    clipped.0.iter().any(|piece| {
        piece.lines().any(|seg| {
            let mid = geo::Point::from((seg.start + seg.end) / 2.0);
            Euclidean.length(&seg) > 2.0 * ON_TOL
                && Euclidean.distance(&mid, plate.exterior()) > ON_TOL
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::layout::placement::Placement;

    const SHEET: Sheet = Sheet {
        width_mm: 50.0,
        height_mm: 30.0,
    };

    fn square(item: usize, copy: usize, x: f64, y: f64, rotation_deg: f64) -> Placement {
        Placement {
            item,
            copy,
            rotation_deg,
            offset: [x, y],
            outline: vec![[x, y], [x + 10.0, y], [x + 10.0, y + 10.0], [x, y + 10.0]],
        }
    }

    fn layout(placements: Vec<Placement>, score_lines: Vec<[Point; 2]>) -> SheetLayout {
        SheetLayout {
            sheet_index: 0,
            placements,
            score_lines,
        }
    }

    fn upright(_: usize) -> Vec<f64> {
        vec![0.0, 180.0]
    }

    /// Two squares in two cells of a vertical break, then a horizontal break on the left.
    fn good() -> SheetLayout {
        layout(
            vec![square(0, 0, 2.0, 2.0, 0.0), square(0, 1, 20.0, 2.0, 180.0)],
            vec![[[15.0, 0.0], [15.0, 30.0]], [[0.0, 20.0], [15.0, 20.0]]],
        )
    }

    #[test]
    fn a_good_layout_passes() {
        verify_sheet(&good(), &SHEET, 1.0, &upright).unwrap();
        verify_snappable(&good(), &SHEET).unwrap();
    }

    #[test]
    fn catches_overlap() {
        let l = layout(
            vec![square(0, 0, 2.0, 2.0, 0.0), square(0, 1, 7.0, 4.0, 0.0)],
            vec![],
        );
        let v = verify_sheet(&l, &SHEET, 1.0, &upright).unwrap_err();
        assert!(
            matches!(&v[..], [Violation::Overlap { area_mm2, .. }] if (area_mm2 - 40.0).abs() < 1e-9),
            "{v:?}"
        );
        assert_eq!(
            v[0].to_string(),
            "part 0 (item 0 copy 0) and part 1 (item 0 copy 1) overlap (40.000000 mm²)"
        );
    }

    #[test]
    fn catches_part_outside_sheet() {
        let l = layout(vec![square(0, 0, 45.0, 2.0, 0.0)], vec![]);
        let v = verify_sheet(&l, &SHEET, 1.0, &upright).unwrap_err();
        assert!(matches!(&v[..], [Violation::OutsideSheet { .. }]), "{v:?}");
    }

    #[test]
    fn catches_small_gaps() {
        let l = layout(
            vec![square(0, 0, 0.5, 2.0, 0.0), square(0, 1, 11.2, 2.0, 0.0)],
            vec![],
        );
        let v = verify_sheet(&l, &SHEET, 1.0, &upright).unwrap_err();
        assert_eq!(v.len(), 2, "{v:?}");
        assert!(
            matches!(v[0], Violation::EdgeGap { distance_mm, .. } if (distance_mm - 0.5).abs() < 1e-12)
        );
        assert!(
            matches!(v[1], Violation::Gap { distance_mm, .. } if (distance_mm - 0.7).abs() < 1e-12)
        );
        // The same layout passes a looser requirement.
        verify_sheet(&l, &SHEET, 0.5, &upright).unwrap();
    }

    #[test]
    fn catches_forbidden_rotation() {
        let l = layout(vec![square(0, 0, 2.0, 2.0, 90.0)], vec![]);
        let v = verify_sheet(&l, &SHEET, 1.0, &upright).unwrap_err();
        assert!(
            matches!(
                &v[..],
                [Violation::ForbiddenRotation {
                    rotation_deg: 90.0,
                    ..
                }]
            ),
            "{v:?}"
        );
        // 360 is the same as 0.
        let l = layout(vec![square(0, 0, 2.0, 2.0, 360.0)], vec![]);
        verify_sheet(&l, &SHEET, 1.0, &upright).unwrap();
    }

    #[test]
    fn catches_outline_that_does_not_match_its_rotation() {
        let nominal = |_: usize| vec![[0.0, 0.0], [10.0, 0.0], [10.0, 10.0], [0.0, 10.0]];
        let mut l = layout(vec![square(0, 0, 2.0, 2.0, 0.0)], vec![]);
        verify_outlines(&l, &nominal, 1e-9).unwrap();
        l.placements[0].rotation_deg = 90.0;
        let v = verify_outlines(&l, &nominal, 1e-9).unwrap_err();
        assert!(
            matches!(&v[..], [Violation::OutlineMismatch { .. }]),
            "{v:?}"
        );
        // Stated as a quarter turn with the matching offset, the same square agrees.
        l.placements[0].offset = [12.0, 2.0];
        verify_outlines(&l, &nominal, 1e-9).unwrap();
    }

    #[test]
    fn catches_score_line_in_mid_air() {
        let mut l = good();
        l.score_lines[1] = [[0.0, 20.0], [12.0, 20.0]];
        let v = verify_snappable(&l, &SHEET).unwrap_err();
        assert!(
            matches!(v[0], Violation::ScoreLineMidAir { line: 1, x, y } if x == 12.0 && y == 20.0),
            "{v:?}"
        );
    }

    #[test]
    fn catches_score_line_through_a_plate() {
        let mut l = good();
        l.score_lines.push([[0.0, 7.0], [15.0, 7.0]]);
        let v = verify_snappable(&l, &SHEET).unwrap_err();
        assert!(
            v.iter().any(|x| matches!(x, Violation::ScoreLineCrossesPlate { line: 2, part } if part.index == 0)),
            "{v:?}"
        );
    }

    #[test]
    fn catches_plates_sharing_a_cell() {
        let mut l = good();
        l.score_lines.clear();
        let v = verify_snappable(&l, &SHEET).unwrap_err();
        assert!(matches!(&v[..], [Violation::SharedCell { .. }]), "{v:?}");
    }

    #[test]
    fn catches_pinwheel() {
        // Four lines around a square, each ending on the next: none can be snapped first.
        let pinwheel = layout(
            vec![],
            vec![
                [[20.0, 0.0], [20.0, 20.0]],
                [[50.0, 20.0], [10.0, 20.0]],
                [[10.0, 30.0], [10.0, 10.0]],
                [[0.0, 10.0], [20.0, 10.0]],
            ],
        );
        let v = verify_snappable(&pinwheel, &SHEET).unwrap_err();
        assert!(
            matches!(&v[..], [Violation::NotGuillotine { lines }] if lines.len() == 4),
            "{v:?}"
        );
        // Run one of them edge to edge and there is an order again.
        let mut ok = pinwheel;
        ok.score_lines[3] = [[0.0, 10.0], [50.0, 10.0]];
        verify_snappable(&ok, &SHEET).unwrap();
    }

    #[test]
    fn catches_missing_and_doubled_copies() {
        let sheets = [good()];
        verify_copies(&sheets, &[2]).unwrap();
        let v = verify_copies(&sheets, &[3]).unwrap_err();
        assert_eq!(
            v[0].to_string(),
            "item 0: copies placed [0, 1], wanted each of 0..3 once"
        );
        let twice = [good(), good()];
        assert!(verify_copies(&twice, &[2]).is_err());
        verify_stock(&twice, 2).unwrap();
        assert_eq!(
            verify_stock(&twice, 1).unwrap_err()[0].to_string(),
            "the layout uses 2 sheets but the stock is 1"
        );
    }

    #[test]
    fn catches_lines_listed_out_of_break_order() {
        let l = good();
        verify_break_order(&l, &SHEET).unwrap();
        let mut swapped = l;
        swapped.score_lines.reverse();
        // Still snappable in some order, but not in the order listed.
        verify_snappable(&swapped, &SHEET).unwrap();
        let v = verify_break_order(&swapped, &SHEET).unwrap_err();
        assert!(
            matches!(v[..], [Violation::OutOfOrder { line: 0, x, y }] if x == 15.0 && y == 20.0),
            "{v:?}"
        );
    }
}
