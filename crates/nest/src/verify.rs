//! An independent check of a finished nest: plain `geo` geometry, none of the nesters' code
//! (no jagua-rs, no overlap measure), so a bug in a nester cannot hide in its own check. The
//! clearance part is [`clearance()`](crate::clearance()), shared with the app's layout verifier;
//! this adds what only a nest states: outlines, rotations, copies and stock.

use cam_geometry::{place_ring, Point};
use thiserror::Error;

use crate::clearance::{clearance as check_clearance, Clearance, ClearanceViolation};
use crate::job::clean_ring;
use crate::problem::{NestBin, NestItem, NestSettings, NestSolution, PlacedPart};

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
}

/// Checks a solution against the rules without trusting the nester (plain `geo` geometry, no
/// jagua-rs): stock respected, every sheet as [`verify_sheet`] checks it with the separation of
/// `settings` between parts and to the edge, every demanded copy placed exactly once.
/// `tolerance_mm` absorbs rounding in the check itself (1e-9 is plenty).
pub fn verify(
    items: &[NestItem],
    bin: &NestBin,
    settings: &NestSettings,
    solution: &NestSolution,
    tolerance_mm: f64,
) -> Result<(), NestViolation> {
    if solution.bins.len() > bin.stock {
        return Err(NestViolation::StockExceeded {
            used: solution.bins.len(),
            stock: bin.stock,
        });
    }
    let clearance = Clearance::uniform(settings.separation_mm);
    let mut counts: Vec<Vec<usize>> = items.iter().map(|i| vec![0; i.demand]).collect();
    for (b, sheet) in solution.bins.iter().enumerate() {
        for part in &sheet.parts {
            let Some(slot) = counts.get_mut(part.item).and_then(|c| c.get_mut(part.copy)) else {
                return Err(NestViolation::UnknownCopy {
                    item: part.item,
                    copy: part.copy,
                });
            };
            *slot += 1;
        }
        verify_sheet(items, bin, clearance, b, &sheet.parts, tolerance_mm)?;
    }
    for (item, copies) in counts.iter().enumerate() {
        if let Some((copy, &count)) = copies.iter().enumerate().find(|(_, &c)| c != 1) {
            return Err(NestViolation::CopyCount { item, copy, count });
        }
    }
    Ok(())
}

/// Checks the parts of one sheet (number `sheet_index` in the violations) of size `bin`, however
/// they were laid out: every outline equal to its item's outline ([`clean_ring`]) turned by
/// `rotation_deg` and moved by `translation`, every rotation one of the item's, every part at
/// least `clearance.to_edge_mm` inside the sheet edge and `clearance.between_parts_mm` from every
/// other part (so no two overlap), as [`clearance()`](crate::clearance()) checks it; the first
/// violation found is returned. Copies are not counted: that needs all sheets ([`verify`]).
pub fn verify_sheet(
    items: &[NestItem],
    bin: &NestBin,
    clearance: Clearance,
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
        if !item.rotations_deg.contains(&part.rotation_deg) {
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
    let rings: Vec<&[Point]> = parts.iter().map(|p| p.outline.as_slice()).collect();
    let first = check_clearance(&rings, bin.width_mm, bin.height_mm, clearance, tolerance_mm)
        .into_iter()
        .next();
    match first {
        None => Ok(()),
        Some(violation) => Err(NestViolation::on_sheet(b, violation)),
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
    use crate::problem::NestedBin;

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
}
