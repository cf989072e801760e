//! Clearance: every part inside the sheet and far enough from its edge, every pair of parts far
//! enough apart and not overlapping, every rotation one its item allows.
//!
//! The distances are measured by [`cam_nest::clearance`], the one clearance check of placed rings
//! that the nester's own verifier uses too; this adds what only a laid-out sheet states (valid
//! outlines, allowed rotations) and names each part in the messages.

use super::{finish, part_ref, polygon, Violation, ANGLE_TOL};
use crate::layout::placement::{Sheet, SheetLayout};
use cam_geometry::Point;
use cam_nest::{clearance, Clearance, ClearanceViolation};
use geo::Validation;

/// Rounding the check itself absorbs, mm: a part may reach this far past the sheet edge, or
/// this much closer than required, and still pass.
const ROUNDING_MM: f64 = 1e-9;

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
    // Placements whose outline is a valid ring: only those can be measured.
    let mut measurable = Vec::new();
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
        let reason = if ring.len() < 3 {
            Some("fewer than 3 points".to_string())
        } else if ring.iter().flatten().any(|v| !v.is_finite()) {
            Some("a coordinate is not finite".to_string())
        } else {
            let poly = polygon(ring);
            (!poly.is_valid()).then(|| format!("{:?}", poly.validation_errors()))
        };
        match reason {
            Some(reason) => violations.push(Violation::InvalidOutline { part, reason }),
            None => measurable.push(index),
        }
    }

    let rings: Vec<&[Point]> = measurable
        .iter()
        .map(|&i| layout.placements[i].outline.as_slice())
        .collect();
    let required = Clearance {
        between_parts_mm: gap_mm,
        to_edge_mm: edge_gap_mm,
    };
    let part = |i: usize| part_ref(layout, measurable[i]);
    for found in clearance(
        &rings,
        sheet.width_mm,
        sheet.height_mm,
        required,
        ROUNDING_MM,
    ) {
        violations.push(match found {
            ClearanceViolation::OutsideSheet { part: i } => Violation::OutsideSheet {
                part: part(i),
                sheet_width_mm: sheet.width_mm,
                sheet_height_mm: sheet.height_mm,
            },
            ClearanceViolation::TooCloseToEdge {
                part: i,
                distance_mm,
                required_mm,
            } => Violation::EdgeGap {
                part: part(i),
                distance_mm,
                min_mm: required_mm,
            },
            ClearanceViolation::Overlap { a, b, area_mm2 } => Violation::Overlap {
                a: part(a),
                b: part(b),
                area_mm2,
            },
            ClearanceViolation::TooClose {
                a,
                b,
                distance_mm,
                required_mm,
            } => Violation::Gap {
                a: part(a),
                b: part(b),
                distance_mm,
                min_mm: required_mm,
            },
        });
    }
    finish(violations)
}
