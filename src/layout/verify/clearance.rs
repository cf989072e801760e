//! Clearance: every part inside the sheet and far enough from its edge, every pair of parts far
//! enough apart and not overlapping, every rotation one its item allows.

use super::{finish, part_ref, polygon, sheet_polygon, Violation, ANGLE_TOL, AREA_TOL};
use crate::layout::placement::{Sheet, SheetLayout};
use geo::{Area, BooleanOps, BoundingRect, Distance, Euclidean, Polygon, Validation};

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
