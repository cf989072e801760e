//! Bookkeeping: each placed outline is its part turned and moved as the placement states, every copy
//! is placed once, and the layout keeps to the stock.

use super::{coord, finish, part_ref, Violation};
use crate::layout::placement::SheetLayout;
use cam_geometry::Point;
use geo::{Coord, Distance, Euclidean, LineString, Rotate, Translate};

/// Checks that every placed outline is its item's nominal ring (`nominal(item)`) rotated about
/// the origin by `rotation_deg` and translated by `offset`, vertex for vertex within `tol_mm`
/// (any starting vertex). This makes the rotation check of [`verify_sheet`](super::verify_sheet) meaningful.
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
