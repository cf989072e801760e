//! An independent check of a finished nest: plain `geo` geometry, none of the nesters' code
//! (no jagua-rs, no overlap measure), so a bug in a nester cannot hide in its own check. The
//! clearance part is [`clearance()`](crate::clearance()), shared with the app's layout verifier;
//! this adds what only a nest states: outlines, rotations, copies and stock.

use cam_geometry::{place_ring, Point};
use thiserror::Error;

use crate::clearance::{clearance as check_clearance, Clearance, ClearanceViolation};
use crate::job::clean_ring;
use crate::problem::{
    NestBin, NestItem, NestSettings, NestSolution, NestedBin, PlacedPart, SheetShape,
};
use geo::{Contains, Distance, Euclidean, Intersects, LineString, Polygon};

/// A placement that breaks a rule, found by [`verify`].
#[derive(Debug, Clone, PartialEq, Error)]
pub enum NestViolation {
    #[error("sheet {bin}: part {part} comes {distance_mm:.4} mm from the sheet edge (needs {required_mm} mm)")]
    TooCloseToEdge {
        bin: usize,
        part: usize,
        distance_mm: f64,
        required_mm: f64,
    },
    #[error("sheet {bin}: part {part} lies (partly) outside the sheet")]
    OutsideSheet { bin: usize, part: usize },
    #[error("sheet {bin}: parts {a} and {b} overlap ({area_mm2:.6} mm²)")]
    Overlap {
        bin: usize,
        a: usize,
        b: usize,
        area_mm2: f64,
    },
    #[error(
        "sheet {bin}: parts {a} and {b} are {distance_mm:.4} mm apart (needs {required_mm} mm)"
    )]
    TooClose {
        bin: usize,
        a: usize,
        b: usize,
        distance_mm: f64,
        required_mm: f64,
    },
    #[error("sheet {bin}: part {part} has rotation {rotation_deg} not allowed for item {item}")]
    RotationNotAllowed {
        bin: usize,
        part: usize,
        item: usize,
        rotation_deg: f64,
    },
    #[error("sheet {bin}: part {part} outline differs from item outline + rotation + translation")]
    OutlineMismatch { bin: usize, part: usize },
    #[error("item {item} copy {copy}: placed {count} times (must be exactly once)")]
    CopyCount {
        item: usize,
        copy: usize,
        count: usize,
    },
    #[error("part references item {item}, copy {copy}, which was not demanded")]
    UnknownCopy { item: usize, copy: usize },
    #[error("{used} sheets used but only {stock} in stock")]
    StockExceeded { used: usize, stock: usize },
    #[error("sheet {bin}: part {part} comes {distance_mm:.4} mm from keep-out {keep_out} (needs {required_mm} mm)")]
    NearKeepOut {
        bin: usize,
        part: usize,
        keep_out: usize,
        distance_mm: f64,
        required_mm: f64,
    },
    #[error("sheet {bin}: part {part} comes {distance_mm:.4} mm from the stock's outline or leaves it (needs {required_mm} mm)")]
    OutsideOutline {
        bin: usize,
        part: usize,
        distance_mm: f64,
        required_mm: f64,
    },
}

/// Checks the parts of one sheet (number `sheet_index` in the violations) against the stock's
/// `shape` ([`SheetShape`]): every part inside its outline and at least `to_edge_mm` from it, and
/// at least `to_edge_mm` from every keep-out (so none touches one), in plain `geo` geometry.
/// The rectangle of the sheet is [`verify_sheet`]'s to check.
pub fn verify_shape(
    shape: &SheetShape,
    to_edge_mm: f64,
    sheet_index: usize,
    parts: &[PlacedPart],
    tolerance_mm: f64,
) -> Result<(), NestViolation> {
    let polygon = |ring: &[Point]| {
        Polygon::new(
            LineString::from(ring.iter().map(|q| (q[0], q[1])).collect::<Vec<_>>()),
            Vec::new(),
        )
    };
    let outline = (!shape.outline.is_empty()).then(|| polygon(&clean_ring(&shape.outline)));
    let keep_outs: Vec<Polygon<f64>> = shape
        .keep_outs
        .iter()
        .map(|k| polygon(&clean_ring(k)))
        .collect();
    let required_mm = to_edge_mm;
    for (part, placed) in parts.iter().enumerate() {
        let p = polygon(&placed.outline);
        if let Some(o) = &outline {
            let distance_mm = if o.contains(&p) {
                Euclidean.distance(p.exterior(), o.exterior())
            } else {
                0.0
            };
            if distance_mm < required_mm - tolerance_mm {
                return Err(NestViolation::OutsideOutline {
                    bin: sheet_index,
                    part,
                    distance_mm,
                    required_mm,
                });
            }
        }
        for (keep_out, k) in keep_outs.iter().enumerate() {
            let distance_mm = if p.intersects(k) {
                0.0
            } else {
                Euclidean.distance(&p, k)
            };
            if distance_mm < required_mm - tolerance_mm {
                return Err(NestViolation::NearKeepOut {
                    bin: sheet_index,
                    part,
                    keep_out,
                    distance_mm,
                    required_mm,
                });
            }
        }
    }
    Ok(())
}

/// Checks a solution against the rules without trusting the nester (plain `geo` geometry, no
/// jagua-rs): stock respected ([`verify_stock`]), every sheet as [`verify_sheet`] checks it with the
/// separation of `settings` between parts and to the edge, every demanded copy placed exactly once
/// ([`verify_copies`]). `tolerance_mm` absorbs rounding in the check itself (1e-9 is plenty).
pub fn verify(
    items: &[NestItem],
    bin: &NestBin,
    settings: &NestSettings,
    solution: &NestSolution,
    tolerance_mm: f64,
) -> Result<(), NestViolation> {
    verify_stock(&solution.bins, bin.stock)?;
    let clearance = Clearance::uniform(settings.separation_mm);
    for (b, sheet) in solution.bins.iter().enumerate() {
        verify_sheet(items, bin, clearance, b, &sheet.parts, tolerance_mm)?;
    }
    verify_copies(items, &solution.bins)
}

/// Checks that `sheets` use at most `stock` sheets.
pub fn verify_stock(sheets: &[NestedBin], stock: usize) -> Result<(), NestViolation> {
    if sheets.len() > stock {
        return Err(NestViolation::StockExceeded {
            used: sheets.len(),
            stock,
        });
    }
    Ok(())
}

/// Checks that over all `sheets` every item's copies `0..demand` are each placed exactly once, and
/// that no part names an item or copy that was not demanded.
pub fn verify_copies(items: &[NestItem], sheets: &[NestedBin]) -> Result<(), NestViolation> {
    let mut counts: Vec<Vec<usize>> = items.iter().map(|i| vec![0; i.demand]).collect();
    for part in sheets.iter().flat_map(|s| &s.parts) {
        let Some(slot) = counts.get_mut(part.item).and_then(|c| c.get_mut(part.copy)) else {
            return Err(NestViolation::UnknownCopy {
                item: part.item,
                copy: part.copy,
            });
        };
        *slot += 1;
    }
    for (item, copies) in counts.iter().enumerate() {
        if let Some((copy, &count)) = copies.iter().enumerate().find(|(_, &c)| c != 1) {
            return Err(NestViolation::CopyCount { item, copy, count });
        }
    }
    Ok(())
}

/// Rotations closer than this (degrees, modulo 360) are the same rotation: a packer may report
/// an allowed -90° as 270°.
const ANGLE_TOL_DEG: f64 = 1e-9;

/// Checks that every part of one sheet (number `sheet_index` in the violations) is its item's
/// outline ([`clean_ring`]) turned by `rotation_deg` and moved by `translation`, vertex for vertex
/// within `tolerance_mm`, at one of the item's rotations. This is what makes the rotation check
/// meaningful, and what lets a layout carry another ring of each part (a cut path) than the one it
/// was packed by.
pub fn verify_outlines(
    items: &[NestItem],
    sheet_index: usize,
    parts: &[PlacedPart],
    tolerance_mm: f64,
) -> Result<(), NestViolation> {
    let b = sheet_index;
    for (k, part) in parts.iter().enumerate() {
        let Some(item) = items.get(part.item) else {
            return Err(NestViolation::UnknownCopy {
                item: part.item,
                copy: part.copy,
            });
        };
        let turn = |a: f64| (part.rotation_deg - a).rem_euclid(360.0);
        if !item
            .rotations_deg
            .iter()
            .any(|&a| turn(a) < ANGLE_TOL_DEG || turn(a) > 360.0 - ANGLE_TOL_DEG)
        {
            return Err(NestViolation::RotationNotAllowed {
                bin: b,
                part: k,
                item: part.item,
                rotation_deg: part.rotation_deg,
            });
        }
        let expected = place_ring(
            &clean_ring(&item.outline),
            part.rotation_deg,
            part.translation,
        );
        let matches = expected.len() == part.outline.len()
            && expected.iter().zip(&part.outline).all(|(e, o)| {
                (e[0] - o[0]).abs() <= tolerance_mm && (e[1] - o[1]).abs() <= tolerance_mm
            });
        if !matches {
            return Err(NestViolation::OutlineMismatch { bin: b, part: k });
        }
    }
    Ok(())
}

/// Checks the parts of one sheet (number `sheet_index` in the violations) of size `bin`, however
/// they were laid out: the outlines and rotations as [`verify_outlines`] checks them, every part at
/// least `clearance.to_edge_mm` inside the sheet edge and `clearance.between_parts_mm` from every
/// other part (so no two overlap), as [`clearance()`](crate::clearance()) checks it; the first
/// violation found is returned. Copies are not counted: that needs all sheets ([`verify_copies`]).
pub fn verify_sheet(
    items: &[NestItem],
    bin: &NestBin,
    clearance: Clearance,
    sheet_index: usize,
    parts: &[PlacedPart],
    tolerance_mm: f64,
) -> Result<(), NestViolation> {
    verify_outlines(items, sheet_index, parts, tolerance_mm)?;
    let rings: Vec<&[Point]> = parts.iter().map(|p| p.outline.as_slice()).collect();
    let first = check_clearance(&rings, bin.width_mm, bin.height_mm, clearance, tolerance_mm)
        .into_iter()
        .next();
    match first {
        None => Ok(()),
        Some(violation) => Err(NestViolation::on_sheet(sheet_index, violation)),
    }
}

impl NestViolation {
    /// The shared clearance check's finding on sheet `bin`, in this crate's words.
    fn on_sheet(bin: usize, violation: ClearanceViolation) -> NestViolation {
        match violation {
            ClearanceViolation::OutsideSheet { part } => NestViolation::OutsideSheet { bin, part },
            ClearanceViolation::TooCloseToEdge {
                part,
                distance_mm,
                required_mm,
            } => NestViolation::TooCloseToEdge {
                bin,
                part,
                distance_mm,
                required_mm,
            },
            ClearanceViolation::Overlap { a, b, area_mm2 } => NestViolation::Overlap {
                bin,
                a,
                b,
                area_mm2,
            },
            ClearanceViolation::TooClose {
                a,
                b,
                distance_mm,
                required_mm,
            } => NestViolation::TooClose {
                bin,
                a,
                b,
                distance_mm,
                required_mm,
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::test_support::{square, squares_job};

    #[test]
    fn verify_catches_parts_too_close() {
        let (items, bin) = squares_job(2, 1);
        let settings = NestSettings {
            separation_mm: 0.5,
            ..NestSettings::default()
        };
        let part = |copy, x: f64| PlacedPart {
            item: 0,
            copy,
            rotation_deg: 0.0,
            translation: [x, 1.0],
            outline: place_ring(&square(10.0), 0.0, [x, 1.0]),
        };
        let mut solution = NestSolution {
            bins: vec![NestedBin {
                index: 0,
                parts: vec![part(0, 1.0), part(1, 11.4)],
                utilization: 0.02,
                score_lines: Vec::new(),
            }],
        };
        assert!(matches!(
            verify(&items, &bin, &settings, &solution, 1e-9),
            Err(NestViolation::TooClose { .. })
        ));
        solution.bins[0].parts[1] = part(1, 11.5);
        assert_eq!(verify(&items, &bin, &settings, &solution, 1e-9), Ok(()));
        solution.bins[0].parts[1] = part(1, 0.2);
        assert!(verify(&items, &bin, &settings, &solution, 1e-9).is_err());
    }

    #[test]
    fn a_sheet_may_keep_less_to_its_edge_than_between_parts() {
        // Two 10 mm squares 0.5 mm apart, the first 0.1 mm from the left and bottom edges.
        let (items, bin) = squares_job(2, 1);
        let part = |copy, x: f64| PlacedPart {
            item: 0,
            copy,
            rotation_deg: 0.0,
            translation: [x, 0.1],
            outline: place_ring(&square(10.0), 0.0, [x, 0.1]),
        };
        let parts = [part(0, 0.1), part(1, 10.6)];
        let scored = Clearance {
            between_parts_mm: 0.5,
            to_edge_mm: 0.1,
        };
        assert_eq!(verify_sheet(&items, &bin, scored, 0, &parts, 1e-9), Ok(()));
        assert!(matches!(
            verify_sheet(&items, &bin, Clearance::uniform(0.5), 0, &parts, 1e-9),
            Err(NestViolation::TooCloseToEdge { part: 0, .. })
        ));
        let wider = Clearance {
            between_parts_mm: 0.6,
            ..scored
        };
        assert!(matches!(
            verify_sheet(&items, &bin, wider, 3, &parts, 1e-9),
            Err(NestViolation::TooClose {
                bin: 3,
                a: 0,
                b: 1,
                ..
            })
        ));
    }

    /// A 10 mm square of item 0 placed at (x, y) turned by `rotation_deg` about its corner.
    fn placed(copy: usize, x: f64, y: f64, rotation_deg: f64) -> PlacedPart {
        PlacedPart {
            item: 0,
            copy,
            rotation_deg,
            translation: [x, y],
            outline: place_ring(&square(10.0), rotation_deg, [x, y]),
        }
    }

    fn one_sheet(parts: Vec<PlacedPart>) -> NestSolution {
        NestSolution {
            bins: vec![NestedBin {
                index: 0,
                parts,
                utilization: 0.0,
                score_lines: Vec::new(),
            }],
        }
    }

    #[test]
    fn overlap_and_parts_outside_the_sheet_are_caught() {
        let (items, bin) = squares_job(2, 1);
        let settings = NestSettings::default();
        let overlapping = one_sheet(vec![placed(0, 2.0, 2.0, 0.0), placed(1, 7.0, 4.0, 0.0)]);
        let found = verify(&items, &bin, &settings, &overlapping, 1e-9);
        assert!(
            matches!(found, Err(NestViolation::Overlap { area_mm2, .. }) if (area_mm2 - 40.0).abs() < 1e-9),
            "{found:?}"
        );
        let outside = one_sheet(vec![placed(0, 95.0, 2.0, 0.0), placed(1, 2.0, 2.0, 0.0)]);
        assert!(matches!(
            verify(&items, &bin, &settings, &outside, 1e-9),
            Err(NestViolation::OutsideSheet { part: 0, .. })
        ));
    }

    #[test]
    fn rotations_are_compared_modulo_a_turn() {
        let (mut items, bin) = squares_job(1, 1);
        let settings = NestSettings::default();
        // A quarter turn about the corner puts the square left of x = 12.
        let turned = one_sheet(vec![placed(0, 12.0, 2.0, 90.0)]);
        assert!(matches!(
            verify(&items, &bin, &settings, &turned, 1e-9),
            Err(NestViolation::RotationNotAllowed { rotation_deg, .. }) if rotation_deg == 90.0
        ));
        // Allowed as -270°, the same rotation passes; 360° is 0°.
        items[0].rotations_deg = vec![0.0, -270.0];
        assert_eq!(verify(&items, &bin, &settings, &turned, 1e-9), Ok(()));
        let full_turn = one_sheet(vec![placed(0, 2.0, 2.0, 360.0)]);
        assert_eq!(verify(&items, &bin, &settings, &full_turn, 1e-9), Ok(()));
    }

    #[test]
    fn an_outline_must_be_its_item_moved_as_stated() {
        let (items, _) = squares_job(1, 1);
        let mut part = placed(0, 2.0, 2.0, 0.0);
        assert_eq!(verify_outlines(&items, 0, &[part.clone()], 1e-9), Ok(()));
        part.translation = [2.0, 2.5];
        assert_eq!(
            verify_outlines(&items, 0, &[part], 1e-9),
            Err(NestViolation::OutlineMismatch { bin: 0, part: 0 })
        );
    }

    #[test]
    fn every_copy_once_and_the_stock_kept() {
        let (items, _) = squares_job(2, 1);
        let sheet = one_sheet(vec![placed(0, 2.0, 2.0, 0.0), placed(1, 20.0, 2.0, 0.0)]);
        assert_eq!(verify_copies(&items, &sheet.bins), Ok(()));
        let (three, _) = squares_job(3, 1);
        assert_eq!(
            verify_copies(&three, &sheet.bins),
            Err(NestViolation::CopyCount {
                item: 0,
                copy: 2,
                count: 0
            })
        );
        let twice = [sheet.bins[0].clone(), sheet.bins[0].clone()];
        assert!(matches!(
            verify_copies(&items, &twice),
            Err(NestViolation::CopyCount { count: 2, .. })
        ));
        assert_eq!(verify_stock(&twice, 2), Ok(()));
        assert_eq!(
            verify_stock(&twice, 1),
            Err(NestViolation::StockExceeded { used: 2, stock: 1 })
        );
    }
}
