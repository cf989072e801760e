//! The circular arc of the drawing model ([`super::model::Shape::Arc`]): its sweep, its points, its
//! bounding box and its pieces of at most a half turn. The model's bounds and both writers take the
//! arc's geometry from here. DXF writes an arc as itself (centre, radius, start and end angle, the
//! same counter-clockwise convention as the model), so its writer needs none of it; SVG draws one from
//! end points and cannot take more than a half turn without a large-arc flag, hence [`CircularArc::pieces`].
//!
//! Angles are degrees counter-clockwise from +x, y up, as in the model.

use cam_geometry::{Bounds, Point};

/// The point at `deg` degrees (counter-clockwise from +x) on a circle.
pub(crate) fn on_circle(center: Point, radius: f64, deg: f64) -> Point {
    let (s, c) = deg.to_radians().sin_cos();
    [center[0] + radius * c, center[1] + radius * s]
}

/// An arc swept counter-clockwise from `start_deg` to `end_deg`; equal angles mean a full turn.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct CircularArc {
    pub center: Point,
    pub radius: f64,
    pub start_deg: f64,
    pub end_deg: f64,
}

impl CircularArc {
    /// Counter-clockwise sweep in degrees, in (0, 360]; equal angles mean a full turn.
    pub fn sweep_deg(&self) -> f64 {
        let sweep = (self.end_deg - self.start_deg).rem_euclid(360.0);
        if sweep == 0.0 {
            360.0
        } else {
            sweep
        }
    }

    /// The point `deg` degrees from +x on the arc's circle.
    pub fn at(&self, deg: f64) -> Point {
        on_circle(self.center, self.radius, deg)
    }

    /// Where the arc starts.
    pub fn start(&self) -> Point {
        self.at(self.start_deg)
    }

    /// Where the arc ends: the start angle plus the sweep, so a full turn ends where it starts.
    pub fn end(&self) -> Point {
        self.at(self.start_deg + self.sweep_deg())
    }

    /// Exact bounding box of the curve: its end points and the axis directions (0°, 90°, 180°, 270°)
    /// its counter-clockwise sweep passes, the only other places a circle reaches an extreme.
    pub fn bounds(&self) -> Bounds {
        let sweep = self.sweep_deg();
        let mut b = Bounds::of(&[self.start(), self.end()]);
        for axis in [0.0, 90.0, 180.0, 270.0] {
            if (axis - self.start_deg).rem_euclid(360.0) <= sweep {
                b = b.including(self.at(axis));
            }
        }
        b
    }

    /// The end points of the arc's pieces in order, each piece at most a half turn: the end alone,
    /// or the middle and the end of a sweep over 180° cut in two equal halves.
    pub fn pieces(&self) -> Vec<Point> {
        let sweep = self.sweep_deg();
        let mut ends = Vec::with_capacity(2);
        if sweep > 180.0 {
            ends.push(self.at(self.start_deg + 0.5 * sweep));
        }
        ends.push(self.end());
        ends
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn arc(start_deg: f64, end_deg: f64) -> CircularArc {
        CircularArc {
            center: [60.0, 40.0],
            radius: 3.0,
            start_deg,
            end_deg,
        }
    }

    #[test]
    fn the_sweep_is_counter_clockwise_and_equal_angles_are_a_full_turn() {
        assert_eq!(arc(0.0, 270.0).sweep_deg(), 270.0);
        assert_eq!(arc(270.0, 0.0).sweep_deg(), 90.0);
        assert_eq!(arc(-90.0, 90.0).sweep_deg(), 180.0);
        assert_eq!(arc(30.0, 30.0).sweep_deg(), 360.0);
        assert_eq!(arc(30.0, 390.0).sweep_deg(), 360.0);
    }

    #[test]
    fn a_sweep_over_a_half_turn_is_cut_in_two_equal_halves() {
        // 270° from 0°: the middle at 135°, the end at 270° = (60, 37).
        let pieces = arc(0.0, 270.0).pieces();
        assert_eq!(pieces.len(), 2);
        assert_eq!(pieces[0], on_circle([60.0, 40.0], 3.0, 135.0));
        assert!((pieces[1][0] - 60.0).abs() < 1e-12 && (pieces[1][1] - 37.0).abs() < 1e-12);
        // Exactly a half turn is one piece.
        assert_eq!(arc(0.0, 180.0).pieces().len(), 1);
    }

    #[test]
    fn the_box_holds_the_axis_points_the_sweep_passes_and_no_others() {
        // 0° to 270° passes 90° (y 43) and 180° (x 57), not 360° beyond its end.
        let b = arc(0.0, 270.0).bounds();
        assert_eq!(b.min, [57.0, 37.0]);
        assert_eq!(b.max, [63.0, 43.0]);
        // 300° to 60° passes 0° (x 63) only.
        let b = arc(300.0, 60.0).bounds();
        assert!((b.max[0] - 63.0).abs() < 1e-12);
        assert!((b.min[0] - 61.5).abs() < 1e-12, "{b:?}");
    }
}
