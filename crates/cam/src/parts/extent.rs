//! How large and how narrow a drawn part may be, checked on the drawing's own numbers.
//!
//! - Size: every contour lies within [`MAX_SIDE_MM`] along x and y, the largest sheet side a
//!   template or batch accepts ([`SHEET_SIDE_MM`]): a part is centimetres across, so a contour
//!   metres long is a unit slip (a drawing in µm, a radius typed into the wrong field). Curves are
//!   checked by their analytic extent ([`arc_bounds`], [`Extent`]) before they are cut into chords,
//!   so a CIRCLE of radius 1e9 is refused at once rather than after 100,000 chords.
//! - Width: an outline at least [`MIN_WIDTH_MM`] across in every direction ([`narrowest_width`]), the
//!   narrowest feature any cut part may have (`MIN_FEATURE_MM`, docs/limits.md): the laser takes
//!   about a kerf (25-50 µm) along every cut, so a narrower part is burnt away or left a sliver.

use super::entity_error;
use crate::input::limits::{MIN_FEATURE_MM, SHEET_SIDE_MM};
use crate::input::{short_number, InputError};
use cam_geometry::Point;
use geo::{ConvexHull, Coord, LineString, MultiPoint};
use std::f64::consts::{FRAC_PI_2, TAU};
use std::path::Path;

/// Largest extent of a contour along x or y, mm.
pub const MAX_SIDE_MM: f64 = SHEET_SIDE_MM.hi;

/// Narrowest outline, mm, across its narrowest direction.
pub const MIN_WIDTH_MM: f64 = MIN_FEATURE_MM;

/// A bounding box grown point by point (or by a curve's analytic bounds), in mm.
#[derive(Debug, Clone, Copy)]
pub struct Extent {
    lo: Point,
    hi: Point,
}

impl Default for Extent {
    fn default() -> Self {
        Extent {
            lo: [f64::INFINITY; 2],
            hi: [f64::NEG_INFINITY; 2],
        }
    }
}

impl Extent {
    /// Grow to hold `p`.
    pub fn add(&mut self, p: Point) {
        self.lo = [self.lo[0].min(p[0]), self.lo[1].min(p[1])];
        self.hi = [self.hi[0].max(p[0]), self.hi[1].max(p[1])];
    }

    /// Grow to hold a box given by two opposite corners.
    pub fn add_box(&mut self, (lo, hi): (Point, Point)) {
        self.add(lo);
        self.add(hi);
    }

    /// Width and height, mm (zero for an empty extent).
    pub fn size(&self) -> [f64; 2] {
        [0, 1].map(|k| (self.hi[k] - self.lo[k]).max(0.0))
    }

    /// Refuse the entity when its extent passes [`MAX_SIDE_MM`] on either axis. Readers check as the
    /// extent grows, segment by segment, to refuse a huge curve before it is cut into chords: the
    /// message names the larger side found so far, which the whole entity reaches at least.
    pub fn check(&self, file: &Path, entity: &str) -> Result<(), InputError> {
        let [w, h] = self.size();
        if w <= MAX_SIDE_MM && h <= MAX_SIDE_MM {
            return Ok(());
        }
        Err(entity_error(
            file,
            entity,
            format!(
                "{} mm or more across: too large for a drawing, which must lie within {MAX_SIDE_MM} x {MAX_SIDE_MM} mm (the largest sheet); is the drawing in mm?",
                short_number(w.max(h)),
            ),
        ))
    }
}

/// The bounding box of a circular arc (`sweep_rad` from `start_rad`, negative clockwise): its end
/// points and each of the four axis extremes the arc passes through. A sweep of a full turn or more
/// is the whole circle.
pub fn arc_bounds(centre: Point, radius: f64, start_rad: f64, sweep_rad: f64) -> (Point, Point) {
    let (from, sweep) = if sweep_rad < 0.0 {
        (start_rad + sweep_rad, -sweep_rad)
    } else {
        (start_rad, sweep_rad)
    };
    let at = |a: f64| [centre[0] + radius * a.cos(), centre[1] + radius * a.sin()];
    let mut extent = Extent::default();
    extent.add(at(from));
    extent.add(at(from + sweep));
    for k in 0..4 {
        let extreme = k as f64 * FRAC_PI_2;
        if sweep >= TAU || (extreme - from).rem_euclid(TAU) <= sweep {
            extent.add(at(extreme));
        }
    }
    (extent.lo, extent.hi)
}

/// The narrowest width of a ring, mm: the least distance between two parallel lines that hold it,
/// found on its convex hull by rotating calipers (one of the two lines lies along a hull edge;
/// Toussaint 1983), O(n log n) with the hull.
pub fn narrowest_width(ring: &[Point]) -> f64 {
    let points: MultiPoint<f64> = ring.iter().map(|p| Coord { x: p[0], y: p[1] }).collect();
    let hull: LineString<f64> = points.convex_hull().exterior().clone();
    // The hull is closed (last = first) and counter-clockwise.
    let h: Vec<Coord<f64>> = hull.0[..hull.0.len().saturating_sub(1)].to_vec();
    let n = h.len();
    if n < 3 {
        return 0.0;
    }
    let cross = |a: Coord<f64>, b: Coord<f64>, p: Coord<f64>| {
        (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x)
    };
    let mut far = 1;
    let mut narrowest = f64::INFINITY;
    for i in 0..n {
        let (a, b) = (h[i], h[(i + 1) % n]);
        // The vertex farthest from edge i moves forward as i does: advance it while the next is farther.
        while cross(a, b, h[(far + 1) % n]) > cross(a, b, h[far]) {
            far = (far + 1) % n;
        }
        let length = (b.x - a.x).hypot(b.y - a.y);
        narrowest = narrowest.min(cross(a, b, h[far]) / length);
    }
    narrowest
}

/// Refuse an outline narrower than [`MIN_WIDTH_MM`].
pub fn check_width(file: &Path, entity: &str, ring: &[Point]) -> Result<(), InputError> {
    let width = narrowest_width(ring);
    if width >= MIN_WIDTH_MM {
        return Ok(());
    }
    Err(entity_error(
        file,
        entity,
        format!(
            "{} mm wide at its narrowest: a part must be at least {MIN_WIDTH_MM} mm wide, the narrowest feature a laser cuts without burning it away (docs/limits.md)",
            short_number(width)
        ),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn arc_bounds_hold_exactly_the_axis_extremes_the_arc_passes() {
        // A quarter from 45° to 135° about (1, 2), radius 2: the top (1, 4) and both ends.
        let (lo, hi) = arc_bounds([1.0, 2.0], 2.0, PI / 4.0, PI / 2.0);
        let s = 2f64.sqrt();
        for (got, want) in [(lo, [1.0 - s, 2.0 + s]), (hi, [1.0 + s, 4.0])] {
            for k in 0..2 {
                assert!((got[k] - want[k]).abs() < 1e-12, "{got:?} {want:?}");
            }
        }
        // The same arc run clockwise from 135°; and a full turn is the circle.
        let (lo2, hi2) = arc_bounds([1.0, 2.0], 2.0, 3.0 * PI / 4.0, -PI / 2.0);
        assert!((lo2[0] - lo[0]).abs() < 1e-12 && (hi2[1] - hi[1]).abs() < 1e-12);
        let (lo, hi) = arc_bounds([0.0, 0.0], 1.0, 0.3, 2.0 * PI);
        assert_eq!((lo, hi), ([-1.0, -1.0], [1.0, 1.0]));
    }

    #[test]
    fn the_narrowest_width_of_a_turned_bar_is_its_thickness() {
        // A 10 x 0.05 mm bar turned by 30°, with extra points along its long sides; a regular
        // hexagon of side 1 is sqrt(3) across its flats.
        let (s, c) = (PI / 6.0).sin_cos();
        let bar: Vec<Point> = [
            [0.0, 0.0],
            [5.0, 0.0],
            [10.0, 0.0],
            [10.0, 0.05],
            [3.0, 0.05],
            [0.0, 0.05],
        ]
        .iter()
        .map(|p| [c * p[0] - s * p[1], s * p[0] + c * p[1]])
        .collect();
        assert!((narrowest_width(&bar) - 0.05).abs() < 1e-12);
        let hexagon: Vec<Point> = (0..6)
            .map(|k| {
                let a = PI / 3.0 * k as f64;
                [a.cos(), a.sin()]
            })
            .collect();
        assert!((narrowest_width(&hexagon) - 3f64.sqrt()).abs() < 1e-12);
    }
}
