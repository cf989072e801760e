//! Small jobs the unit tests of several modules build on.

use crate::problem::{NestBin, NestItem};
use cam_geometry::Point;

/// A square of side `side` with a corner at the origin.
pub fn square(side: f64) -> Vec<Point> {
    vec![[0.0, 0.0], [side, 0.0], [side, side], [0.0, side]]
}

/// `demand` 10 mm squares and a 100 mm sheet with `stock`.
pub fn squares_job(demand: usize, stock: usize) -> (Vec<NestItem>, NestBin) {
    let items = vec![NestItem {
        outline: square(10.0),
        demand,
        rotations_deg: vec![0.0],
    }];
    let bin = NestBin {
        width_mm: 100.0,
        height_mm: 100.0,
        stock,
    };
    (items, bin)
}
