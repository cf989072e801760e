//! The one geometry vocabulary of the workspace: points and rings in millimetres on a sheet (y up),
//! their area and bounds, and rigid placement (a rotation about the origin, then a translation).
//!
//! [`offset`] grows or shrinks a ring with mitred corners (kerf compensation).
//!
//! A ring is a closed polygon given without its repeated closing point; counter-clockwise rings have
//! positive signed area. Rotations by multiples of 90° are exact, so a part turned by 180° lands on
//! exactly the coordinates one computes by hand, and axis-aligned layouts carry no 1e-17 noise.
//!
//! Every crate that draws, lays out or nests parts uses these definitions; none writes its own
//! shoelace, bounding box or rotation.
//!
//! ```
//! use cam_geometry::{place_ring, signed_area, Bounds};
//! let square = [[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]];
//! assert_eq!(signed_area(&square), 4.0);
//! let turned = place_ring(&square, 180.0, [10.0, 10.0]);
//! assert_eq!(Bounds::of(&turned), Bounds { min: [8.0, 8.0], max: [10.0, 10.0] });
//! ```

use serde::{Deserialize, Serialize};

pub mod offset;

/// A point in sheet coordinates, mm, y up.
pub type Point = [f64; 2];

/// Signed area of a ring by the shoelace formula: positive when counter-clockwise (y up). The ring
/// is implicitly closed; fewer than three points give 0.
#[must_use]
pub fn signed_area(ring: &[Point]) -> f64 {
    let n = ring.len();
    if n < 3 {
        return 0.0;
    }
    (0..n)
        .map(|i| {
            let (p, q) = (ring[i], ring[(i + 1) % n]);
            p[0] * q[1] - q[0] * p[1]
        })
        .sum::<f64>()
        / 2.0
}

/// Area of a ring, whichever way it runs.
#[must_use]
pub fn area(ring: &[Point]) -> f64 {
    signed_area(ring).abs()
}

/// An axis-aligned box from `min` to `max`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Bounds {
    pub min: Point,
    pub max: Point,
}

impl Bounds {
    /// The bounds of a set of points; an empty set gives the inverted box (+inf, -inf), which
    /// [`Bounds::union`] treats as empty.
    #[must_use]
    pub fn of(points: &[Point]) -> Bounds {
        points.iter().fold(Bounds::EMPTY, |b, p| b.including(*p))
    }

    /// The box that contains nothing: the identity of [`Bounds::union`].
    pub const EMPTY: Bounds = Bounds {
        min: [f64::INFINITY; 2],
        max: [f64::NEG_INFINITY; 2],
    };

    /// This box grown to contain `p`.
    #[must_use]
    pub fn including(self, p: Point) -> Bounds {
        Bounds {
            min: [self.min[0].min(p[0]), self.min[1].min(p[1])],
            max: [self.max[0].max(p[0]), self.max[1].max(p[1])],
        }
    }

    /// The smallest box containing both.
    #[must_use]
    pub fn union(self, other: Bounds) -> Bounds {
        Bounds {
            min: [self.min[0].min(other.min[0]), self.min[1].min(other.min[1])],
            max: [self.max[0].max(other.max[0]), self.max[1].max(other.max[1])],
        }
    }

    #[must_use]
    pub fn width(&self) -> f64 {
        self.max[0] - self.min[0]
    }

    #[must_use]
    pub fn height(&self) -> f64 {
        self.max[1] - self.min[1]
    }
}

/// An angle in degrees reduced to [0, 360).
#[must_use]
pub fn normalize_deg(deg: f64) -> f64 {
    let r = deg.rem_euclid(360.0);
    // rem_euclid can round a tiny negative angle up to exactly 360.
    if r >= 360.0 {
        0.0
    } else {
        r
    }
}

/// `(cos, sin)` of an angle in degrees, exact at multiples of 90°.
#[must_use]
pub fn cos_sin_deg(deg: f64) -> (f64, f64) {
    let d = normalize_deg(deg);
    if d == 0.0 {
        (1.0, 0.0)
    } else if d == 90.0 {
        (0.0, 1.0)
    } else if d == 180.0 {
        (-1.0, 0.0)
    } else if d == 270.0 {
        (0.0, -1.0)
    } else {
        let r = d.to_radians();
        (r.cos(), r.sin())
    }
}

/// `p` turned counter-clockwise by `deg` about the origin.
#[must_use]
pub fn rotate(p: Point, deg: f64) -> Point {
    let (c, s) = cos_sin_deg(deg);
    [c * p[0] - s * p[1], s * p[0] + c * p[1]]
}

/// `p` turned by `deg` about the origin, then moved by `offset`: how a placement carries any feature
/// of its part (outline, holes, labels) onto the sheet.
#[must_use]
pub fn place_point(p: Point, deg: f64, offset: Point) -> Point {
    let r = rotate(p, deg);
    [r[0] + offset[0], r[1] + offset[1]]
}

/// [`place_point`] over a ring or polyline.
#[must_use]
pub fn place_ring(ring: &[Point], deg: f64, offset: Point) -> Vec<Point> {
    ring.iter().map(|p| place_point(*p, deg, offset)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quarter_turns_are_exact() {
        // Source: rotation matrix of 90°, 180°, 270° has entries in {-1, 0, 1}.
        let p = [3.25, -1.5];
        assert_eq!(rotate(p, 90.0), [1.5, 3.25]);
        assert_eq!(rotate(p, 180.0), [-3.25, 1.5]);
        assert_eq!(rotate(p, 270.0), [-1.5, -3.25]);
        assert_eq!(rotate(p, -90.0), rotate(p, 270.0));
        assert_eq!(rotate(p, 720.0), p);
    }

    #[test]
    fn a_general_angle_matches_the_rotation_matrix() {
        let (c, s) = (30f64.to_radians().cos(), 30f64.to_radians().sin());
        let q = rotate([2.0, 1.0], 30.0);
        assert!((q[0] - (2.0 * c - s)).abs() < 1e-15 && (q[1] - (2.0 * s + c)).abs() < 1e-15);
    }

    #[test]
    fn shoelace_area_of_a_trapezoid_and_its_reverse() {
        // Source: trapezoid area (a + b) h / 2 = (4 + 2) * 3 / 2 = 9.
        let ring = [[0.0, 0.0], [4.0, 0.0], [3.0, 3.0], [1.0, 3.0]];
        assert_eq!(signed_area(&ring), 9.0);
        let rev: Vec<Point> = ring.iter().rev().copied().collect();
        assert_eq!(signed_area(&rev), -9.0);
        assert_eq!(area(&rev), 9.0);
        assert_eq!(signed_area(&ring[..2]), 0.0);
    }

    #[test]
    fn bounds_of_a_placed_ring() {
        let ring = [[0.0, 0.0], [4.0, 0.0], [3.0, 3.0]];
        let b = Bounds::of(&place_ring(&ring, 90.0, [10.0, 0.0]));
        assert_eq!(
            b,
            Bounds {
                min: [7.0, 0.0],
                max: [10.0, 4.0]
            }
        );
        assert_eq!((b.width(), b.height()), (3.0, 4.0));
        assert_eq!(Bounds::EMPTY.union(b), b);
    }

    #[test]
    fn angles_normalize_into_one_turn() {
        assert_eq!(normalize_deg(-90.0), 270.0);
        assert_eq!(normalize_deg(360.0), 0.0);
        assert_eq!(normalize_deg(-1e-20), 0.0);
    }
}
