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
                    range: "greater than 0 m",
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

    /// Angle of the coupler from its rest direction (`BA` horizontal at `θ = 0`) when the wing is at `θ`:
    /// `B = L3 (-sin θ, cos θ)` rises by `L3 (1 - cos θ)` above the slider line while `|AB| = L1`, so
    /// `ψ(θ) = asin(L3 (1 - cos θ) / L1)` (docs/physics.md §16.3). `None` beyond the coupler's reach.
    pub fn coupler_angle(&self, angle: f64) -> Option<f64> {
        let sine = self.crank * (1.0 - angle.cos()) / self.coupler;
        (sine.abs() <= 1.0).then(|| sine.asin())
    }

    /// `dψ/dθ = L3 sin θ / √(L1² - L3² (1 - cos θ)²)`, the derivative of [`Self::coupler_angle`].
    pub fn coupler_angle_rate(&self, angle: f64) -> f64 {
        let rise = self.crank * (1.0 - angle.cos());
        self.crank * angle.sin() / (self.coupler * self.coupler - rise * rise).sqrt()
    }

    /// Turn of the three joints from their rest (actuator at rest, `x = 0`) when the wing is at `θ`, rad:
    /// `[hinge O (crank on airframe), B (crank on coupler), A (coupler on actuator tip)]` =
    /// `[θ - θ0, (θ - ψ) - (θ0 - ψ0), ψ - ψ0]`, with the actuator tip translating without turning
    /// (docs/physics.md §16.3). `None` when the rest or `θ` is beyond the coupler's reach.
    pub fn joint_rotations(&self, angle: f64) -> Option<[f64; 3]> {
        let rest = self.stroke_angle(0.0)?;
        let (psi, psi0) = (self.coupler_angle(angle)?, self.coupler_angle(rest)?);
        Some([angle - rest, (angle - psi) - (rest - psi0), psi - psi0])
    }

    /// Bend of joint B's film from the flat laminate when the wing is at `θ`, rad: the links are cut in
    /// a row, O-B-A, so B's film is flat when the crank lies along the coupler; assembled, the angle
    /// between `BO = -B` (direction `θ - π/2`) and `BA` (direction `ψ`) is `π/2 + ψ - θ`, and the film is
    /// bent by its supplement, `β(θ) = π/2 + θ - ψ(θ)` (docs/physics.md §16.7). `β(θ0)` is the fold set
    /// at assembly, and `β(θ) - β(θ0)` is B's turn of [`Self::joint_rotations`]. `None` beyond the
    /// coupler's reach.
    pub fn bend_at_b(&self, angle: f64) -> Option<f64> {
        self.coupler_angle(angle)
            .map(|psi| std::f64::consts::FRAC_PI_2 + angle - psi)
    }

    /// `dφ_i/dθ` of the three joints at the rest position: `[1, 1 - ψ'(θ0), ψ'(θ0)]`. A flexure of
    /// stiffness `k_i` at joint `i` holds the wing with `Σ k_i (dφ_i/dθ)²` about the hinge, linearised at
    /// rest (docs/physics.md §16.4).
    pub fn joint_rates_at_rest(&self) -> Option<[f64; 3]> {
        let rest = self.stroke_angle(0.0)?;
        let rate = self.coupler_angle_rate(rest);
        Some([1.0, 1.0 - rate, rate])
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
            return bad("travel", travel, "greater than 0 m");
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
    fn joint_rotations_are_those_of_the_constructed_linkage() {
        // Build A and B point by point (the circle intersection above) and take the link directions.
        let link = Linkage::solve(0.75e-3, -PI / 3.0, PI / 3.0, 4.0).unwrap();
        let (l1, l3) = (link.coupler, link.crank);
        let coupler_dir = |delta: f64| {
            let theta = constructed(l1, l3, delta);
            let b = [-l3 * theta.sin(), l3 * theta.cos()];
            let a = [l1 - delta, l3];
            ((b[1] - a[1]).atan2(a[0] - b[0]), theta)
        };
        let (psi0, theta0) = coupler_dir(link.offset);
        for x in [-0.75e-3, -0.3e-3, 0.0, 0.4e-3, 0.75e-3] {
            let (psi, theta) = coupler_dir(link.offset + x);
            // The coupler direction BA against the horizontal: B rises above A by L3 (1 - cos θ).
            let joints = link.joint_rotations(theta).unwrap();
            assert!((joints[0] - (theta - theta0)).abs() < 1e-12);
            assert!(
                (joints[2] + (psi - psi0)).abs() < 1e-12,
                "{x}: {joints:?} {psi}"
            );
            assert!((joints[1] - (joints[0] - joints[2])).abs() < 1e-15);
        }
        // B's film bend from the flat row O-B-A: π less the angle between BO and BA of the construction.
        for x in [-0.75e-3, 0.0, 0.75e-3] {
            let theta = constructed(l1, l3, link.offset + x);
            let (b, a) = (
                [-l3 * theta.sin(), l3 * theta.cos()],
                [l1 - link.offset - x, l3],
            );
            let (bo, ba) = ([-b[0], -b[1]], [a[0] - b[0], a[1] - b[1]]);
            let between = (bo[0] * ba[1] - bo[1] * ba[0])
                .abs()
                .atan2(bo[0] * ba[0] + bo[1] * ba[1]);
            let bend = link.bend_at_b(theta).unwrap();
            assert!((bend - (PI - between)).abs() < 1e-12, "{x}: {bend}");
            let rest = link.stroke_angle(0.0).unwrap();
            let turn = link.joint_rotations(theta).unwrap()[1];
            assert!((bend - link.bend_at_b(rest).unwrap() - turn).abs() < 1e-12);
        }
        // The rates against central differences.
        let rest = link.stroke_angle(0.0).unwrap();
        let h = 1e-7;
        let fd = |i: usize| {
            (link.joint_rotations(rest + h).unwrap()[i]
                - link.joint_rotations(rest - h).unwrap()[i])
                / (2.0 * h)
        };
        let rates = link.joint_rates_at_rest().unwrap();
        for (i, rate) in rates.iter().enumerate() {
            assert!((rate - fd(i)).abs() < 1e-7, "{i}: {rate} vs {}", fd(i));
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

    #[test]
    fn the_hawk_moth_ratio_rises_with_stroke() {
        // Source: docs/physics.md §12.2, T = 1/(dδ/dθ) with dδ/dθ written out here, on the hawk-moth
        // linkage of examples/drive-hawkmoth.toml (solved for ±60° from a 0.75 mm travel, coupler 4 times
        // the crank: L3 = 0.75 mm / sin 60° = 0.866 mm, §12.3). T L3 is 1 at rest (eq. 2.6) and rises
        // toward both ends of the stroke, faster on the side the crank swings toward the coupler.
        let sixty = PI / 3.0;
        let link = Linkage::solve(0.75e-3, -sixty, sixty, 4.0).unwrap();
        let (l1, l3) = (link.coupler, link.crank);
        assert!((l3 - 0.75e-3 / sixty.sin()).abs() < 1e-15);
        let by_hand = |t: f64| {
            let q = 1.0 - t.cos();
            1.0 / (l3 * t.cos() + l3 * l3 * q * t.sin() / (l1 * l1 - l3 * l3 * q * q).sqrt())
        };
        let table = [
            (-60.0, 2.5583),
            (-45.0, 1.5263),
            (-30.0, 1.1775),
            (0.0, 1.0),
            (30.0, 1.1328),
            (45.0, 1.3175),
            (60.0, 1.6417),
        ];
        for (deg, want) in table {
            let t = f64::to_radians(deg);
            let got = link.ratio_at_angle(t) * l3;
            assert!((got - by_hand(t) * l3).abs() < 1e-12);
            assert!((got - want).abs() < 5e-5, "{deg}°: {got}");
        }
    }
}
