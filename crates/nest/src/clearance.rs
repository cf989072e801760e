//! The clearance check of placed parts on one sheet, shared by every verifier of a layout (this
//! crate's [`verify_sheet`](crate::verify_sheet) and the app's scored and shelved layouts).
//!
//! Plain `geo` predicates and metrics only, none of the nesters' arithmetic (no jagua-rs, no
//! overlap measure, no bounding-box packing), so a bug in a packer cannot hide in its own check.

use cam_geometry::Point;
use geo::{Area, BooleanOps, BoundingRect, Coord, Distance, Euclidean, Polygon, Rect};
use serde::{Deserialize, Serialize};

/// The gaps a sheet's parts must keep: between two parts (the kerf and web of a cut) and to the
/// sheet edge (which may differ, e.g. scored plates keep only a margin to the edge).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Clearance {
    pub between_parts_mm: f64,
    pub to_edge_mm: f64,
}

impl Clearance {
    /// The same gap between parts and to the edge, as the nesters keep it.
    #[must_use]
    pub fn uniform(gap_mm: f64) -> Clearance {
        Clearance {
            between_parts_mm: gap_mm,
            to_edge_mm: gap_mm,
        }
    }
}

/// A placed part (by its index in the rings checked) that breaks a [`Clearance`].
#[derive(Debug, Clone, PartialEq)]
pub enum ClearanceViolation {
    /// The part's bounding box leaves `[0, width] x [0, height]`.
    OutsideSheet { part: usize },
    /// The part lies inside the sheet but closer than `required_mm` to its edge.
    TooCloseToEdge {
        part: usize,
        distance_mm: f64,
        required_mm: f64,
    },
    /// Two parts overlap by more than floating-point noise of a shared edge.
    Overlap { a: usize, b: usize, area_mm2: f64 },
    /// Two parts are closer than `required_mm` (zero when they touch).
    TooClose {
        a: usize,
        b: usize,
        distance_mm: f64,
        required_mm: f64,
    },
}

/// Overlap area that still counts as touching, mm² (floating-point noise of shared edges).
const AREA_TOL_MM2: f64 = 1e-9;

/// Checks placed rings (closed, simple, as laid on the sheet) against a sheet of
/// `sheet_width_mm` x `sheet_height_mm` with its corner at the origin: every ring inside the sheet
/// and at least `clearance.to_edge_mm` from its edge, every pair at least
/// `clearance.between_parts_mm` apart and not overlapping. `tolerance_mm` absorbs rounding in the
/// check itself. Returns every violation, per part in order and then per pair `a < b`; a pair
/// that overlaps is reported as an overlap only.
#[must_use]
pub fn clearance(
    rings: &[&[Point]],
    sheet_width_mm: f64,
    sheet_height_mm: f64,
    clearance: Clearance,
    tolerance_mm: f64,
) -> Vec<ClearanceViolation> {
    let mut violations = Vec::new();
    let sheet_edge = polygon(&[
        [0.0, 0.0],
        [sheet_width_mm, 0.0],
        [sheet_width_mm, sheet_height_mm],
        [0.0, sheet_height_mm],
    ])
    .exterior()
    .clone();
    let parts: Vec<(Polygon<f64>, Option<Rect<f64>>)> = rings
        .iter()
        .map(|ring| {
            let poly = polygon(ring);
            let rect = poly.bounding_rect();
            (poly, rect)
        })
        .collect();
    for (part, (poly, rect)) in parts.iter().enumerate() {
        let Some(rect) = rect else { continue };
        if rect.min().x < -tolerance_mm
            || rect.min().y < -tolerance_mm
            || rect.max().x > sheet_width_mm + tolerance_mm
            || rect.max().y > sheet_height_mm + tolerance_mm
        {
            violations.push(ClearanceViolation::OutsideSheet { part });
            continue;
        }
        let distance = Euclidean.distance(poly, &sheet_edge);
        if distance < clearance.to_edge_mm - tolerance_mm {
            violations.push(ClearanceViolation::TooCloseToEdge {
                part,
                distance_mm: distance,
                required_mm: clearance.to_edge_mm,
            });
        }
    }
    let gap = clearance.between_parts_mm;
    for a in 0..parts.len() {
        for b in a + 1..parts.len() {
            let ((pa, Some(ra)), (pb, Some(rb))) = (&parts[a], &parts[b]) else {
                continue;
            };
            // Bounding boxes further apart than the gap: the parts are too.
            let separation = (rb.min().x - ra.max().x)
                .max(ra.min().x - rb.max().x)
                .max(rb.min().y - ra.max().y)
                .max(ra.min().y - rb.max().y);
            if separation >= gap && separation > 0.0 {
                continue;
            }
            // Zero when the outlines touch, cross or one contains the other.
            let distance = Euclidean.distance(pa, pb);
            if distance <= 0.0 {
                let area = pa.intersection(pb).unsigned_area();
                if area > AREA_TOL_MM2 {
                    violations.push(ClearanceViolation::Overlap {
                        a,
                        b,
                        area_mm2: area,
                    });
                    continue;
                }
            }
            if distance < gap - tolerance_mm {
                violations.push(ClearanceViolation::TooClose {
                    a,
                    b,
                    distance_mm: distance,
                    required_mm: gap,
                });
            }
        }
    }
    violations
}

fn polygon(ring: &[Point]) -> Polygon<f64> {
    Polygon::new(
        ring.iter().map(|p| Coord { x: p[0], y: p[1] }).collect(),
        vec![],
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(x: f64, y: f64) -> Vec<Point> {
        vec![[x, y], [x + 10.0, y], [x + 10.0, y + 10.0], [x, y + 10.0]]
    }

    #[test]
    fn reports_every_kind_with_its_indices() {
        let rings = [
            square(0.5, 2.0),
            square(11.2, 2.0),
            square(15.0, 4.0),
            square(45.0, 2.0),
        ];
        let rings: Vec<&[Point]> = rings.iter().map(Vec::as_slice).collect();
        let v = clearance(&rings, 50.0, 30.0, Clearance::uniform(1.0), 1e-9);
        assert!(
            matches!(
                &v[..],
                [
                    ClearanceViolation::TooCloseToEdge { part: 0, .. },
                    ClearanceViolation::OutsideSheet { part: 3 },
                    ClearanceViolation::TooClose { a: 0, b: 1, .. },
                    ClearanceViolation::Overlap { a: 1, b: 2, .. },
                ]
            ),
            "{v:?}"
        );
        assert!(clearance(&rings[..1], 50.0, 30.0, Clearance::uniform(0.5), 1e-9).is_empty());
    }
}
