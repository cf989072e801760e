//! Small jobs the unit tests of several modules build on.

use crate::compress::Footprint;
use crate::overlap::Pieces;
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

/// An axis-aligned `width` x `height` rectangle's footprint, free to move from the origin to
/// `x_max` across and `y_max` up.
pub fn rectangle(width: f32, height: f32, x_max: f32, y_max: f32) -> Footprint {
    Footprint {
        pieces: Pieces::new(&[[0., 0.], [width, 0.], [width, height], [0., height]])
            .expect("a rectangle is a convex piece"),
        x: (0.0, x_max),
        y: (0.0, y_max),
    }
}
