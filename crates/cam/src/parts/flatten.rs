//! Curves to polylines: circular and elliptical arcs and Bézier segments become chords that stay
//! within [`TOLERANCE_MM`] of the true curve, so a flattened part is never more than that smaller
//! (arcs: chords lie inside) or larger (Béziers) than drawn.

use cam_geometry::Point;
use std::f64::consts::PI;

/// Largest distance between a curve and its chords, mm: 10 µm, well under a laser kerf (25-50 µm),
/// so flattening never shows in a cut part. The area a flattened arc loses is at most its length
/// times this.
pub const TOLERANCE_MM: f64 = 0.01;

/// Chords of a circular arc: `sweep_rad` from `start_rad` (negative = clockwise) around `centre`,
/// each chord's sagitta at most `tolerance` (the same units as the radius). The points run from
/// the start point to the end point inclusive.
pub fn circular_arc(
    centre: Point,
    radius: f64,
    start_rad: f64,
    sweep_rad: f64,
    tolerance: f64,
) -> Vec<Point> {
    let n = arc_segments(radius, sweep_rad, tolerance);
    (0..=n)
        .map(|i| {
            let a = start_rad + sweep_rad * i as f64 / n as f64;
            [centre[0] + radius * a.cos(), centre[1] + radius * a.sin()]
        })
        .collect()
}

/// A full ellipse (a circle when `rx == ry`) as a polygon that circumscribes it: every edge touches
/// the curve at its midpoint and every vertex lies outside it, at most `tolerance` (for the larger
/// radius) away. A hole drawn as a circle is then never smaller than drawn, so a Ø1.50 mm spar hole
/// still takes a Ø1.50 mm pin, and an outline drawn as one never shrinks. The vertices of the
/// circle's circumscribed polygon, `r / cos(π/n)` from the centre, mapped by the ellipse's axes: an
/// affine map keeps the edges tangent.
pub fn circumscribed_ellipse(centre: Point, rx: f64, ry: f64, tolerance: f64) -> Vec<Point> {
    let r = rx.max(ry);
    // The vertex stands r (1/cos(π/n) - 1) outside: n chosen so that is within the tolerance.
    let mut n = arc_segments(r, 2.0 * PI, tolerance).max(8);
    while r * (1.0 / (PI / n as f64).cos() - 1.0) > tolerance && n < 100_000 {
        n += 1;
    }
    let grow = 1.0 / (PI / n as f64).cos();
    (0..n)
        .map(|i| {
            let a = 2.0 * PI * i as f64 / n as f64;
            [
                centre[0] + rx * grow * a.cos(),
                centre[1] + ry * grow * a.sin(),
            ]
        })
        .collect()
}

/// Chords a circular arc needs so that the sagitta r (1 - cos(θ/2)) of each stays within the
/// tolerance; at least one, and at least 8 on a full circle.
fn arc_segments(radius: f64, sweep_rad: f64, tolerance: f64) -> usize {
    let ratio = (1.0 - tolerance / radius).clamp(-1.0, 1.0);
    let step = 2.0 * ratio.acos();
    let n = if step > 0.0 {
        (sweep_rad.abs() / step).ceil()
    } else {
        1.0
    };
    let floor = (8.0 * sweep_rad.abs() / (2.0 * PI)).ceil().max(1.0);
    n.max(floor).min(100_000.0) as usize
}

/// The chords of an SVG elliptical arc from `from` to `to` (SVG 1.1 appendix F.6.5, endpoint to
/// centre parameterisation), without the start point. Radii too small for the endpoints are scaled
/// up as the SVG specification says; a zero radius is a straight line.
#[allow(clippy::too_many_arguments)]
pub fn elliptical_arc(
    from: Point,
    to: Point,
    rx: f64,
    ry: f64,
    x_rotation_deg: f64,
    large_arc: bool,
    sweep: bool,
    tolerance: f64,
) -> Vec<Point> {
    let (mut rx, mut ry) = (rx.abs(), ry.abs());
    if rx == 0.0 || ry == 0.0 || from == to {
        return vec![to];
    }
    let phi = x_rotation_deg.to_radians();
    let (s, c) = phi.sin_cos();
    let dx = (from[0] - to[0]) / 2.0;
    let dy = (from[1] - to[1]) / 2.0;
    let x1 = c * dx + s * dy;
    let y1 = -s * dx + c * dy;
    let lambda = (x1 * x1) / (rx * rx) + (y1 * y1) / (ry * ry);
    if lambda > 1.0 {
        rx *= lambda.sqrt();
        ry *= lambda.sqrt();
    }
    let num = rx * rx * ry * ry - rx * rx * y1 * y1 - ry * ry * x1 * x1;
    let den = rx * rx * y1 * y1 + ry * ry * x1 * x1;
    let mut k = (num / den).max(0.0).sqrt();
    if large_arc == sweep {
        k = -k;
    }
    let cx1 = k * rx * y1 / ry;
    let cy1 = -k * ry * x1 / rx;
    let cx = c * cx1 - s * cy1 + (from[0] + to[0]) / 2.0;
    let cy = s * cx1 + c * cy1 + (from[1] + to[1]) / 2.0;
    let angle = |ux: f64, uy: f64| uy.atan2(ux);
    let theta1 = angle((x1 - cx1) / rx, (y1 - cy1) / ry);
    let mut dtheta = angle((-x1 - cx1) / rx, (-y1 - cy1) / ry) - theta1;
    if sweep && dtheta < 0.0 {
        dtheta += 2.0 * PI;
    } else if !sweep && dtheta > 0.0 {
        dtheta -= 2.0 * PI;
    }
    // The larger radius bounds the curvature radius of the ellipse: its chords are the finest needed.
    let n = arc_segments(rx.max(ry), dtheta, tolerance);
    let mut out: Vec<Point> = (1..n)
        .map(|i| {
            let t = theta1 + dtheta * i as f64 / n as f64;
            let (ex, ey) = (rx * t.cos(), ry * t.sin());
            [c * ex - s * ey + cx, s * ex + c * ey + cy]
        })
        .collect();
    out.push(to);
    out
}

/// The chords of a cubic Bézier segment, without the start point. Uniform steps: a cubic's chords
/// deviate from it by at most (1/8) max|B''| / n², and |B''| ≤ 6 max(|P0 - 2P1 + P2|, |P1 - 2P2 + P3|).
pub fn cubic(p: [Point; 4], tolerance: f64) -> Vec<Point> {
    let dd = |a: Point, b: Point, c: Point| {
        ((a[0] - 2.0 * b[0] + c[0]).powi(2) + (a[1] - 2.0 * b[1] + c[1]).powi(2)).sqrt()
    };
    let l = dd(p[0], p[1], p[2]).max(dd(p[1], p[2], p[3]));
    let n = ((0.75 * l / tolerance).sqrt().ceil() as usize).clamp(1, 10_000);
    (1..=n)
        .map(|i| {
            let t = i as f64 / n as f64;
            let u = 1.0 - t;
            let w = [u * u * u, 3.0 * u * u * t, 3.0 * u * t * t, t * t * t];
            [
                (0..4).map(|k| w[k] * p[k][0]).sum(),
                (0..4).map(|k| w[k] * p[k][1]).sum(),
            ]
        })
        .collect()
}

/// A quadratic Bézier segment as the cubic it equals (degree elevation).
pub fn quadratic(p0: Point, p1: Point, p2: Point, tolerance: f64) -> Vec<Point> {
    let lerp = |a: Point, b: Point| {
        [
            a[0] + 2.0 / 3.0 * (b[0] - a[0]),
            a[1] + 2.0 / 3.0 * (b[1] - a[1]),
        ]
    };
    cubic([p0, lerp(p0, p1), lerp(p2, p1), p2], tolerance)
}

/// A circular arc: centre, radius, start angle and sweep (radians, negative clockwise).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Arc {
    /// Centre.
    pub centre: Point,
    /// Radius.
    pub radius: f64,
    /// Angle of the start point.
    pub start_rad: f64,
    /// Angle swept from the start point.
    pub sweep_rad: f64,
}

/// The arc a DXF bulge describes between two polyline vertices: bulge = tan(θ/4), θ the included
/// angle, positive counter-clockwise. `None` for a straight edge (bulge 0, or the two vertices equal).
pub fn bulge_arc(from: Point, to: Point, bulge: f64) -> Option<Arc> {
    if bulge == 0.0 || from == to {
        return None;
    }
    let theta = 4.0 * bulge.atan();
    let chord = ((to[0] - from[0]).powi(2) + (to[1] - from[1]).powi(2)).sqrt();
    let radius = chord / (2.0 * (theta / 2.0).sin().abs());
    // The centre lies on the chord's perpendicular bisector, (chord/2) / tan(θ/2) to the left of
    // the chord for a counter-clockwise arc, to the right for a clockwise one.
    let mid = [(from[0] + to[0]) / 2.0, (from[1] + to[1]) / 2.0];
    let left = [-(to[1] - from[1]) / chord, (to[0] - from[0]) / chord];
    let h = chord / 2.0 / (theta / 2.0).tan();
    let centre = [mid[0] + left[0] * h, mid[1] + left[1] * h];
    Some(Arc {
        centre,
        radius,
        start_rad: (from[1] - centre[1]).atan2(from[0] - centre[0]),
        sweep_rad: theta,
    })
}

/// The chords of the arc a DXF bulge describes ([`bulge_arc`]). The points exclude the start
/// vertex and include the end.
pub fn bulge(from: Point, to: Point, bulge: f64, tolerance: f64) -> Vec<Point> {
    let Some(arc) = bulge_arc(from, to, bulge) else {
        return vec![to];
    };
    let mut points = circular_arc(
        arc.centre,
        arc.radius,
        arc.start_rad,
        arc.sweep_rad,
        tolerance,
    );
    points.remove(0);
    if let Some(last) = points.last_mut() {
        *last = to;
    }
    points
}

#[cfg(test)]
mod tests {
    use super::*;
    use cam_geometry::area;

    #[test]
    fn a_circumscribed_circle_holds_the_circle_within_the_tolerance() {
        // Every edge's nearest point to the centre is at least r away (the circle fits inside), and no
        // vertex is more than the tolerance outside it. A Ø1.5 mm hole: never below 1.5 mm.
        for (r, tol) in [(0.75, TOLERANCE_MM), (10.0, TOLERANCE_MM), (0.3, 0.001)] {
            let ring = circumscribed_ellipse([2.0, -1.0], r, r, tol);
            let n = ring.len();
            for k in 0..n {
                let (a, b) = (ring[k], ring[(k + 1) % n]);
                let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
                let t = (((2.0 - a[0]) * dx + (-1.0 - a[1]) * dy) / (dx * dx + dy * dy))
                    .clamp(0.0, 1.0);
                let near = ((a[0] + t * dx - 2.0).powi(2) + (a[1] + t * dy + 1.0).powi(2)).sqrt();
                assert!(
                    near >= r - 1e-12,
                    "r {r}: edge {k} comes {near} from the centre"
                );
                let vertex = ((a[0] - 2.0).powi(2) + (a[1] + 1.0).powi(2)).sqrt();
                assert!(vertex - r <= tol + 1e-12, "r {r}: vertex {k} {vertex}");
            }
        }
    }

    #[test]
    fn a_flattened_circle_loses_less_area_than_its_circumference_times_the_tolerance() {
        // Closed form: πr²; chords inside the circle lose at most 2πr · tolerance.
        for r in [0.5, 2.0, 20.0] {
            let mut ring = circular_arc([1.0, 2.0], r, 0.0, 2.0 * PI, TOLERANCE_MM);
            ring.pop();
            let lost = PI * r * r - area(&ring);
            assert!(
                lost > 0.0 && lost <= 2.0 * PI * r * TOLERANCE_MM,
                "r {r}: lost {lost}"
            );
        }
    }

    #[test]
    fn a_bulge_of_one_is_a_half_circle_on_the_left_for_positive() {
        // bulge 1 = tan(180°/4): a semicircle; from (0,0) to (2,0) counter-clockwise passes (1,-1).
        let pts = bulge([0.0, 0.0], [2.0, 0.0], 1.0, 1e-4);
        let lowest = pts.iter().map(|p| p[1]).fold(f64::INFINITY, f64::min);
        assert!((lowest + 1.0).abs() < 1e-3, "{lowest}");
        assert_eq!(*pts.last().unwrap(), [2.0, 0.0]);
        for p in &pts {
            let d = ((p[0] - 1.0).powi(2) + p[1].powi(2)).sqrt();
            assert!((d - 1.0).abs() < 1e-12);
        }
    }

    #[test]
    fn an_svg_half_ellipse_passes_through_its_far_point() {
        // From (0,0) to (4,0) with rx 2, ry 1, sweep = 1 (positive angles in SVG's y-down space).
        let pts = elliptical_arc([0.0, 0.0], [4.0, 0.0], 2.0, 1.0, 0.0, false, true, 1e-4);
        let extreme = pts.iter().map(|p| p[1].abs()).fold(0.0, f64::max);
        assert!((extreme - 1.0).abs() < 1e-3, "{extreme}");
        for p in &pts {
            let e = ((p[0] - 2.0) / 2.0).powi(2) + p[1].powi(2);
            assert!((e - 1.0).abs() < 1e-9);
        }
    }
}
