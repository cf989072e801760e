//! The transmission of thesis §2.3.4, Fig. 2.12: the actuator tip drives a coupler `L1` whose far end
//! turns the wing's crank `L3` about the wing hinge (thesis eqs. 2.5, 2.6; docs/physics.md §12).

use crate::error::ModelError;

/// The linkage's geometry, SI. The actuator tip moves along the coupler's rest direction; `offset` is the
/// linkage's `δ` when the actuator is at rest (so the wing can swing symmetrically about its rest angle).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Linkage {
    /// Coupler length `L1`, m.
    pub coupler: f64,
    /// Crank length `L3` (hinge to coupler pin), m.
    pub crank: f64,
    /// The linkage's `δ` at the actuator's rest position, m.
    pub offset: f64,
}

/// The transmission as the drive sees it: the linkage, the flexure's rotational stiffness and the
/// links' inertia about the wing hinge, and their mass for the budget (SI).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Transmission {
    /// Linkage geometry.
    pub linkage: Linkage,
    /// Rotational stiffness of the flexures about the wing hinge, N·m/rad.
    pub flexure_stiffness: f64,
    /// Inertia of the links about the wing hinge, kg·m².
    pub link_inertia: f64,
    /// Mass of the transmission (links and flexures), kg.
    pub mass: f64,
}

/// Stroke angle of thesis eq. 2.5 with the garbled `e L3²` read as `2 L3²` (docs/physics.md §12.1):
/// `θ_w = acos[(δ² - 2 δ L1 + 2 L3²) / (2 L3 √((L1 - δ)² + L3²))] + atan(L3 / (L1 - δ)) - π/2`.
/// `None` where the coupler cannot reach the crank circle.
pub fn stroke_angle_eq_2_5(coupler: f64, crank: f64, delta: f64) -> Option<f64> {
    let reach = ((coupler - delta).powi(2) + crank * crank).sqrt();
    let cosine =
        (delta * delta - 2.0 * delta * coupler + 2.0 * crank * crank) / (2.0 * crank * reach);
    if !(-1.0..=1.0).contains(&cosine) {
        return None;
    }
    // atan2 keeps the angle of the slider pin right when δ passes L1.
    Some(cosine.acos() + crank.atan2(coupler - delta) - std::f64::consts::FRAC_PI_2)
}

impl Linkage {
    /// Check the lengths are positive and finite.
    pub fn new(coupler: f64, crank: f64, offset: f64) -> Result<Self, ModelError> {
        for (name, v) in [("coupler", coupler), ("crank", crank)] {
            if !(v.is_finite() && v > 0.0) {
                return Err(ModelError::OutOfRange {
                    name,
                    value: v,
                    range: "(0, inf) m",
                });
            }
        }
        if !offset.is_finite() {
            return Err(ModelError::OutOfRange {
                name: "offset",
                value: offset,
                range: "finite",
            });
        }
        Ok(Linkage {
            coupler,
            crank,
            offset,
        })
    }

    /// Stroke angle at actuator tip displacement `x` from rest (eq. 2.5 at `δ = offset + x`), rad.
    pub fn stroke_angle(&self, x: f64) -> Option<f64> {
        stroke_angle_eq_2_5(self.coupler, self.crank, self.offset + x)
    }

    /// The linkage `δ` that puts the wing at `θ` (the inverse of eq. 2.5):
    /// `δ(θ) = L1 + L3 sin θ - √(L1² - L3² (1 - cos θ)²)`. `None` beyond the coupler's reach.
    pub fn linkage_delta(&self, angle: f64) -> Option<f64> {
        let rise = self.crank * (1.0 - angle.cos());
        let under = self.coupler * self.coupler - rise * rise;
        (under >= 0.0).then(|| self.coupler + self.crank * angle.sin() - under.sqrt())
    }

    /// Actuator tip displacement from rest that puts the wing at `θ`, m.
    pub fn travel(&self, angle: f64) -> Option<f64> {
        self.linkage_delta(angle).map(|d| d - self.offset)
    }

    /// Local transmission ratio `T = dθ/dx` at stroke angle `θ`, rad/m: the reciprocal of
    /// `dδ/dθ = L3 cos θ + L3² (1 - cos θ) sin θ / √(L1² - L3² (1 - cos θ)²)`; `1/L3` at `θ = 0` (eq. 2.6).
    pub fn ratio_at_angle(&self, angle: f64) -> f64 {
        let rise = self.crank * (1.0 - angle.cos());
        let root = (self.coupler * self.coupler - rise * rise).sqrt();
        1.0 / (self.crank * angle.cos() + self.crank * rise * angle.sin() / root)
    }

    /// Actuator tip displacement `x(θ)` from rest and its first two derivatives in `θ` (m, m/rad,
    /// m/rad²), from `δ(θ)` above with `q = 1 - cos θ`, `R = √(L1² - L3² q²)`:
    /// `δ' = L3 cos θ + L3² q sin θ / R`,
    /// `δ'' = -L3 sin θ + L3² (sin² θ + q cos θ) / R + L3⁴ q² sin² θ / R³`. `None` beyond the coupler's
    /// reach.
    pub fn travel_derivatives(&self, angle: f64) -> Option<(f64, f64, f64)> {
        let (sin, cos) = angle.sin_cos();
        let (l1, l3) = (self.coupler, self.crank);
        let q = 1.0 - cos;
        let under = l1 * l1 - l3 * l3 * q * q;
        if under <= 0.0 {
            return None;
        }
        let root = under.sqrt();
        let x = l1 + l3 * sin - root - self.offset;
        let d1 = l3 * cos + l3 * l3 * q * sin / root;
        let d2 = -l3 * sin
            + l3 * l3 * (sin * sin + q * cos) / root
            + l3.powi(4) * q * q * sin * sin / (root * root * root);
        Some((x, d1, d2))
    }

    /// Local ratio `T(x) = dθ/dx` at actuator displacement `x`, rad/m.
    pub fn ratio(&self, x: f64) -> Option<f64> {
        self.stroke_angle(x).map(|a| self.ratio_at_angle(a))
    }

    /// The linkage that turns an actuator travel of `±travel` (m) into the end angles
    /// `angle_minus < angle_plus` (rad), with the coupler `coupler_ratio` times the crank
    /// (docs/physics.md §12.3): `δ(θ)/L3 = g(θ) = ρ + sin θ - √(ρ² - (1 - cos θ)²)` is linear in `L3`, so
    /// `L3 = 2 travel / (g(θ+) - g(θ-))` and the offset puts `θ+` at `+travel`.
    pub fn solve(
        travel: f64,
        angle_minus: f64,
        angle_plus: f64,
        coupler_ratio: f64,
    ) -> Result<Linkage, ModelError> {
        let bad = |name, value, range| Err(ModelError::OutOfRange { name, value, range });
        if !(travel.is_finite() && travel > 0.0) {
            return bad("travel", travel, "(0, inf) m");
        }
        if !(angle_minus < angle_plus
            && angle_minus > -std::f64::consts::FRAC_PI_2
            && angle_plus < std::f64::consts::FRAC_PI_2)
        {
            return bad("stroke angles", angle_plus, "-90° < θ- < θ+ < 90°");
        }
        let g = |a: f64| {
            let rise: f64 = 1.0 - a.cos();
            let under = coupler_ratio * coupler_ratio - rise * rise;
            (under > 0.0).then(|| coupler_ratio + a.sin() - under.sqrt())
        };
        let (Some(lo), Some(hi)) = (g(angle_minus), g(angle_plus)) else {
            return bad(
                "coupler_ratio",
                coupler_ratio,
                "long enough to reach both end angles: L1/L3 > 1 - cos θ",
            );
        };
        let crank = 2.0 * travel / (hi - lo);
        let coupler = coupler_ratio * crank;
        Linkage::new(coupler, crank, hi * crank - travel)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// Fig. 2.12 built point by point: hinge O at the origin, crank pin B on the circle of radius L3,
    /// slider pin A = (L1 - δ, L3); B is the intersection of |OB| = L3 and |AB| = L1 on the upper side.
    fn constructed(coupler: f64, crank: f64, delta: f64) -> f64 {
        let (ax, ay) = (coupler - delta, crank);
        let d = (ax * ax + ay * ay).sqrt();
        // Circle-circle intersection (O, L3) and (A, L1).
        let along = (crank * crank - coupler * coupler + d * d) / (2.0 * d);
        let height = (crank * crank - along * along).sqrt();
        let (ux, uy) = (ax / d, ay / d);
        // The branch with B left of OA (counter-clockwise), which is B = (0, L3) at δ = 0.
        let (bx, by) = (along * ux - height * uy, along * uy + height * ux);
        by.atan2(bx) - PI / 2.0
    }

    #[test]
    fn eq_2_5_is_zero_at_rest_with_slope_one_over_l3() {
        // Thesis eq. 2.6: θ_w(0) = 0, dθ_w/dδ(0) = 1/L3.
        for (l1, l3) in [(3e-3, 1e-3), (10e-3, 0.8e-3), (1.5e-3, 1.2e-3)] {
            let theta = |d: f64| stroke_angle_eq_2_5(l1, l3, d).unwrap();
            assert!(theta(0.0).abs() < 1e-15);
            let h = 1e-9;
            let slope = (theta(h) - theta(-h)) / (2.0 * h);
            assert!((slope * l3 - 1.0).abs() < 1e-6, "{slope}");
        }
    }

    #[test]
    fn eq_2_5_is_the_geometric_construction_and_its_inverse() {
        for (l1, l3) in [(3e-3, 1e-3), (10e-3, 0.8e-3), (2e-3, 1.2e-3)] {
            let link = Linkage::new(l1, l3, 0.0).unwrap();
            for i in -20..=20 {
                let delta = 0.04 * i as f64 * l3;
                let eq = stroke_angle_eq_2_5(l1, l3, delta).unwrap();
                let built = constructed(l1, l3, delta);
                assert!(
                    (eq - built).abs() < 1e-12,
                    "{l1} {l3} {delta}: {eq} vs {built}"
                );
                let back = link.linkage_delta(eq).unwrap();
                assert!(
                    (back - delta).abs() < 1e-15 + 1e-12 * l3,
                    "{delta} vs {back}"
                );
                // The local ratio against a central difference of eq. 2.5.
                let h = 1e-9 * l3;
                let fd = (stroke_angle_eq_2_5(l1, l3, delta + h).unwrap()
                    - stroke_angle_eq_2_5(l1, l3, delta - h).unwrap())
                    / (2.0 * h);
                assert!((link.ratio(delta).unwrap() / fd - 1.0).abs() < 1e-5);
            }
        }
    }

    #[test]
    fn travel_derivatives_are_those_of_the_inverse() {
        // Against central differences of `travel` (the inverse of eq. 2.5).
        let link = Linkage::solve(0.5e-3, -PI / 3.0, PI / 3.0, 2.5).unwrap();
        let h = 1e-5;
        for i in -12..=12 {
            let a = 0.09 * i as f64;
            let (x, d1, d2) = link.travel_derivatives(a).unwrap();
            let t = |a: f64| link.travel(a).unwrap();
            assert!((x - t(a)).abs() < 1e-18, "{a}");
            let fd1 = (t(a + h) - t(a - h)) / (2.0 * h);
            // A wider step for the second difference, whose rounding error grows as 1/h².
            let h2 = 1e-3;
            let fd2 = (t(a + h2) - 2.0 * t(a) + t(a - h2)) / (h2 * h2);
            assert!((d1 / fd1 - 1.0).abs() < 1e-8, "{a}: {d1} vs {fd1}");
            assert!((d2 - fd2).abs() < 1e-6 * link.crank, "{a}: {d2} vs {fd2}");
            assert!((d1 * link.ratio_at_angle(a) - 1.0).abs() < 1e-12);
        }
    }

    #[test]
    fn small_angles_follow_eq_2_6() {
        // θ ≈ δ / L3 for δ << L3, the error second order in δ.
        let (l1, l3) = (4e-3, 1e-3);
        for delta in [1e-6, 1e-5, 1e-4] {
            let theta = stroke_angle_eq_2_5(l1, l3, delta).unwrap();
            let rel = (theta - delta / l3).abs() / (delta / l3);
            assert!(rel < 2.0 * delta / l3, "{delta}: {rel}");
        }
    }

    #[test]
    fn solved_linkage_reaches_the_required_end_angles() {
        let sixty = PI / 3.0;
        for (travel, lo, hi, rho) in [
            (0.3e-3, -sixty, sixty, 3.0),
            (0.6e-3, -sixty, sixty, 1.2),
            (0.25e-3, -0.8, 1.1, 5.0),
        ] {
            let link = Linkage::solve(travel, lo, hi, rho).unwrap();
            assert!((link.stroke_angle(travel).unwrap() - hi).abs() < 1e-12);
            assert!((link.stroke_angle(-travel).unwrap() - lo).abs() < 1e-12);
            assert!((link.coupler / link.crank - rho).abs() < 1e-12);
        }
        // Symmetric ±60°: L3 = travel / sin 60° whatever the coupler (docs/physics.md §12.3).
        let link = Linkage::solve(0.3e-3, -sixty, sixty, 3.0).unwrap();
        assert!((link.crank - 0.3e-3 / sixty.sin()).abs() < 1e-15);
        assert!(Linkage::solve(0.3e-3, -sixty, sixty, 0.4).is_err());
        assert!(Linkage::solve(0.3e-3, sixty, -sixty, 3.0).is_err());
    }
}
