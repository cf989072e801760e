//! Snapping: the score lines of a PZT sheet can be broken one after another, each edge to edge of the
//! piece it splits, listed in that order, leaving every plate in a cell of its own.

use super::{coord, finish, part_ref, polygon, sheet_polygon, Violation, ON_TOL};
use cam_nest::{NestBin, NestedBin};
use geo::{
    BooleanOps, BoundingRect, Coord, Distance, Euclidean, Length, Line, LineString,
    MultiLineString, Polygon,
};

/// Checks that the score lines make the sheet snappable and free every plate:
/// - every line is a straight segment inside the sheet whose two ends lie on the sheet edge or
///   on another score line (within 1e-6 mm);
/// - the lines can be broken one after another, each ending on the edge or on earlier breaks
///   (a pinwheel of lines ending on each other cannot);
/// - replaying the breaks, every plate lies in its own cell and no line crosses a plate.
pub fn verify_snappable(layout: &NestedBin, sheet: &NestBin) -> Result<(), Vec<Violation>> {
    let mut violations = Vec::new();
    let sheet_poly = sheet_polygon(sheet);
    let support = Support::new(layout, sheet, &mut violations);

    let (order, stuck) = support.break_order();
    if !stuck.is_empty() {
        violations.push(Violation::NotGuillotine { lines: stuck });
    }
    let pieces = replay(
        &support.lines,
        &order,
        &sheet_poly,
        &mut violations,
        |_, _| {},
    );
    let Support { lines, usable, .. } = support;

    // Every plate in a cell of its own; name the lines that cut through plates.
    let mut owner: Vec<Option<usize>> = vec![None; pieces.len()];
    for (index, placement) in layout.parts.iter().enumerate() {
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
    fn new(layout: &NestedBin, sheet: &NestBin, violations: &mut Vec<Violation>) -> Support {
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

impl Support {
    /// A break order: repeatedly take a line whose ends rest on the edge or on lines taken
    /// before. Also the usable lines that can never be taken (each ends on another of them).
    fn break_order(&self) -> (Vec<usize>, Vec<usize>) {
        let n = self.lines.len();
        let mut order = Vec::new();
        let mut taken = vec![false; n];
        loop {
            let next = (0..n).find(|&i| {
                self.usable[i]
                    && !taken[i]
                    && (0..2).all(|e| {
                        self.on_edge[i][e] || self.rests_on[i][e].iter().any(|&j| taken[j])
                    })
            });
            match next {
                Some(i) => {
                    taken[i] = true;
                    order.push(i);
                }
                None => break,
            }
        }
        let stuck = (0..n).filter(|&i| self.usable[i] && !taken[i]).collect();
        (order, stuck)
    }
}

/// Replays the breaks in `order` on the sheet and returns the pieces. Pieces stay convex: each
/// break is a full chord of the pieces it splits. `split(line, piece)` sees each of the two
/// pieces every break makes; a break that ends inside a piece is a violation.
fn replay(
    lines: &[Line<f64>],
    order: &[usize],
    sheet: &Polygon<f64>,
    violations: &mut Vec<Violation>,
    mut split: impl FnMut(usize, &[Coord<f64>]),
) -> Vec<Vec<Coord<f64>>> {
    let mut pieces: Vec<Vec<Coord<f64>>> = vec![sheet.exterior().0[..4].to_vec()];
    for &i in order {
        let mut next_pieces = Vec::with_capacity(pieces.len() + 4);
        for piece in pieces {
            match split_piece(&piece, &lines[i]) {
                Split::Apart(a, b) => {
                    split(i, &a);
                    split(i, &b);
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
    pieces
}

/// Checks that no break leaves an offcut (a piece without a plate) narrower than `min_strip_mm`
/// (docs/cam.md §4, "Snappable strips"): a strip that narrow cannot be snapped off cleanly and
/// chips the plate beside it. An offcut's width at each end of its break is the distance, square
/// to the break, of the offcut's corner next to that end: the strip's width for a strip, the
/// narrow end for a wedge, the height for a triangle. The breaks are replayed in a break order
/// as [`verify_snappable`] does; its other findings are left to it.
pub fn verify_offcuts(
    layout: &NestedBin,
    sheet: &NestBin,
    min_strip_mm: f64,
) -> Result<(), Vec<Violation>> {
    let mut ignored = Vec::new();
    let support = Support::new(layout, sheet, &mut ignored);
    let (order, _) = support.break_order();
    let mut violations = Vec::new();
    replay(
        &support.lines,
        &order,
        &sheet_polygon(sheet),
        &mut ignored,
        |line, piece| {
            let holds_plate = layout
                .parts
                .iter()
                .any(|p| p.outline.iter().all(|&v| inside_convex(piece, coord(v))));
            if holds_plate {
                return;
            }
            if let Some(width) = offcut_width(piece, &support.lines[line]) {
                if width < min_strip_mm - ON_TOL {
                    violations.push(Violation::NarrowOffcut {
                        line,
                        width_mm: width,
                        min_mm: min_strip_mm,
                    });
                }
            }
        },
    );
    finish(violations)
}

/// Width of an offcut at the ends of the break that made it: for each corner on the break, the
/// distance to the break of its neighbouring corner off the break; the smaller of them.
fn offcut_width(piece: &[Coord<f64>], line: &Line<f64>) -> Option<f64> {
    let carrier = geo::Line::new(line.start, line.end);
    let d = carrier.delta();
    let len = (d.x * d.x + d.y * d.y).sqrt();
    // Distance to the infinite line through the break.
    let off =
        |p: Coord<f64>| ((p - carrier.start).x * d.y - (p - carrier.start).y * d.x).abs() / len;
    let n = piece.len();
    let on: Vec<bool> = piece.iter().map(|&p| off(p) <= ON_TOL).collect();
    let mut width: Option<f64> = None;
    for k in (0..n).filter(|&k| on[k]) {
        for j in [(k + n - 1) % n, (k + 1) % n] {
            if !on[j] {
                let w = off(piece[j]);
                width = Some(width.map_or(w, |x: f64| x.min(w)));
            }
        }
    }
    width
}

/// Checks that the score lines are listed in a break order: each line's ends rest on the sheet
/// edge or on lines listed before it (for writers whose document order is the laser order).
pub fn verify_break_order(layout: &NestedBin, sheet: &NestBin) -> Result<(), Vec<Violation>> {
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
