//! The transmission's kinematics as the drive sees them: the actuator tip's travel `x(θ)` and its
//! derivatives in the wing's stroke angle, from the one-stage slider-crank (eq. 2.5), the two-stage
//! linkage (`fourbar.rs`), or a published ratio with its nonlinearity (docs/physics.md §12.4, §16.8).

use crate::fourbar::TwoStage;
use crate::transmission::Linkage;

/// A transmission given by its ratio `T0` at rest (rad/m) and the ratio `T1` it has at the stroke angle
/// `θ1`: the travel `x(θ) = (θ + c θ³) / T0` with `c = (T0/T1 - 1) / (3 θ1²)`, so that
/// `T(θ) = T0 / (1 + 3 c θ²)` (docs/physics.md §12.4). `c = 0` is a constant ratio.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RatioLaw {
    /// `T0`, rad/m.
    pub ratio: f64,
    /// `c`, 1/rad².
    pub cubic: f64,
}

impl RatioLaw {
    /// The law of ratio `t0` at rest and `t1` at the stroke angle `angle` (rad, non-zero): `c` as above.
    pub fn through(t0: f64, angle: f64, t1: f64) -> RatioLaw {
        RatioLaw {
            ratio: t0,
            cubic: (t0 / t1 - 1.0) / (3.0 * angle * angle),
        }
    }

    /// The largest stroke angle the law holds at, rad: where the travel per radian `(1 + 3 c θ²)/T0`
    /// falls to zero for `c < 0` (a ratio rising without bound), infinite otherwise.
    pub fn reach(&self) -> f64 {
        if self.cubic < 0.0 {
            (-1.0 / (3.0 * self.cubic)).sqrt()
        } else {
            f64::INFINITY
        }
    }

    /// `x(θ)`, `x'` and `x''`: `(θ + c θ³)/T0`, `(1 + 3 c θ²)/T0`, `6 c θ / T0`. `None` at or past
    /// [`Self::reach`].
    pub fn travel_derivatives(&self, angle: f64) -> Option<(f64, f64, f64)> {
        let (t, c) = (self.ratio, self.cubic);
        let d1 = (1.0 + 3.0 * c * angle * angle) / t;
        (d1 > 0.0).then(|| ((angle + c * angle.powi(3)) / t, d1, 6.0 * c * angle / t))
    }

    /// The stroke angle at travel `x`: Newton on the cubic from `T0 x`, within [`Self::reach`].
    pub fn stroke_angle(&self, x: f64) -> Option<f64> {
        let reach = self.reach();
        let mut angle = (self.ratio * x).clamp(-0.9 * reach, 0.9 * reach);
        for _ in 0..60 {
            let (at, d1, _) = self.travel_derivatives(angle)?;
            let step = (at - x) / d1;
            angle = (angle - step).clamp(-reach, reach);
            if step.abs() <= 1e-15 * (1.0 + angle.abs()) {
                return self.travel_derivatives(angle).map(|_| angle);
            }
        }
        None
    }
}

/// The transmission between the actuator tip and the wing.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Kinematics {
    /// The one-stage slider-crank of thesis eq. 2.5.
    SliderCrank(Linkage),
    /// The slider-crank followed by an amplifying four-bar.
    TwoStage(TwoStage),
    /// A published ratio, without a linkage to draw.
    Ratio(RatioLaw),
}

impl From<Linkage> for Kinematics {
    fn from(l: Linkage) -> Self {
        Kinematics::SliderCrank(l)
    }
}

impl Kinematics {
    /// The wing's angle at tip displacement `x` from the actuator's rest, rad.
    pub fn stroke_angle(&self, x: f64) -> Option<f64> {
        match self {
            Kinematics::SliderCrank(l) => l.stroke_angle(x),
            Kinematics::TwoStage(s) => s.stroke_angle(x),
            Kinematics::Ratio(r) => r.stroke_angle(x),
        }
    }

    /// `x(θ)`, `dx/dθ`, `d²x/dθ²` (m, m/rad, m/rad²); `None` beyond the transmission's reach.
    pub fn travel_derivatives(&self, angle: f64) -> Option<(f64, f64, f64)> {
        match self {
            Kinematics::SliderCrank(l) => l.travel_derivatives(angle),
            Kinematics::TwoStage(s) => s.travel_derivatives(angle),
            Kinematics::Ratio(r) => r.travel_derivatives(angle),
        }
    }

    /// The tip displacement that puts the wing at `θ`, m.
    pub fn travel(&self, angle: f64) -> Option<f64> {
        match self {
            Kinematics::SliderCrank(l) => l.travel(angle),
            _ => self.travel_derivatives(angle).map(|d| d.0),
        }
    }

    /// The local ratio `T = dθ/dx` at the wing's `θ`, rad/m.
    pub fn ratio_at_angle(&self, angle: f64) -> f64 {
        match self {
            Kinematics::SliderCrank(l) => l.ratio_at_angle(angle),
            _ => self
                .travel_derivatives(angle)
                .map_or(f64::NAN, |d| 1.0 / d.1),
        }
    }

    /// The local ratio `T = dθ/dx = 1/x'` at the wing's `θ` and its rate along the travel
    /// `dT/dx = (dT/dθ) T = -x''/x'³` (rad/m, rad/m²), from [`Self::travel_derivatives`]: the ratio's
    /// change the time integration's `I T T' ẋ²` term takes (docs/physics.md §14). `None` beyond the
    /// transmission's reach.
    pub fn ratio_and_rate(&self, angle: f64) -> Option<(f64, f64)> {
        let (_, d1, d2) = self.travel_derivatives(angle)?;
        let t = 1.0 / d1;
        Some((t, -d2 * t * t * t))
    }

    /// The local ratio at tip displacement `x`, rad/m.
    pub fn ratio(&self, x: f64) -> Option<f64> {
        self.stroke_angle(x).map(|a| self.ratio_at_angle(a))
    }

    /// A length that scales tip travel to wing angle, `1/T` at the linkage's upright crank, m: the
    /// slider-crank's crank `L3`, the two-stage's `L3 c / a`, the law's `1/T0`. It sizes the first
    /// guess and the tolerances of the harmonic balance.
    pub fn lever(&self) -> f64 {
        match self {
            Kinematics::SliderCrank(l) => l.crank,
            Kinematics::TwoStage(s) => s.first.crank * s.second.output / s.second.input,
            Kinematics::Ratio(r) => 1.0 / r.ratio,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The central difference of a cubic overshoots its slope by `c h² / T0`.
    fn c_h(law: &RatioLaw, h: f64) -> f64 {
        law.cubic * h * h / law.ratio
    }

    #[test]
    fn the_ratio_law_passes_through_its_two_published_ratios() {
        // docs/physics.md §12.4: T(θ) = T0 / (1 + 3 c θ²) with c from T(θ1) = T1.
        for (t0, deg, t1) in [
            (3000.0, 60.0, 2400.0),
            (2150.0, 45.0, 2600.0),
            (3333.0, 30.0, 3333.0),
        ] {
            let law = RatioLaw::through(t0, f64::to_radians(deg), t1);
            let k = Kinematics::Ratio(law);
            assert!((k.ratio_at_angle(0.0) - t0).abs() < 1e-9);
            assert!((k.ratio_at_angle(f64::to_radians(deg)) - t1).abs() < 1e-9 * t1);
            for i in -10..=10 {
                let a = 0.1 * i as f64;
                let (x, d1, d2) = k.travel_derivatives(a).unwrap();
                assert!((k.stroke_angle(x).unwrap() - a).abs() < 1e-12, "{a}");
                // The differences are exact on a cubic but for rounding.
                let h = 1e-2;
                let t = |a: f64| k.travel(a).unwrap();
                assert!(
                    ((t(a + h) - t(a - h)) / (2.0 * h) - (d1 + c_h(&law, h))).abs() < 1e-12 * d1
                );
                assert!(((t(a + h) - 2.0 * x + t(a - h)) / (h * h) - d2).abs() < 1e-9 / t0);
            }
        }
        // A rising ratio reaches its dead point where 1 + 3 c θ² = 0: no travel turns it further.
        let rising = RatioLaw::through(2000.0, 1.0, 4000.0);
        assert!((rising.reach() - (2.0f64).sqrt()).abs() < 1e-12);
        assert!(rising.travel_derivatives(1.5).is_none());
    }

    #[test]
    fn the_ratio_rate_is_the_central_difference_of_the_ratio_for_every_kinematics() {
        // dT/dx = (dT/dθ) T against a central difference of `ratio_at_angle` in θ, for the slider-crank
        // (eq. 2.5), the two-stage linkage (docs/physics.md §16.8) and the ratio law (§12.4).
        let first = Linkage::solve(0.4e-3, -1.0, 1.0, 3.0).unwrap();
        let two = TwoStage {
            first: Linkage::new(2.4e-3, 0.6e-3, 0.0).unwrap(),
            second: crate::fourbar::FourBar {
                input: 1e-3,
                coupler: 2e-3,
                output: 0.5e-3,
            },
        };
        let law = RatioLaw::through(3000.0, 1.0, 2400.0);
        for k in [
            Kinematics::SliderCrank(first),
            Kinematics::TwoStage(two),
            Kinematics::Ratio(law),
        ] {
            let h = 1e-5;
            for i in -8..=8 {
                let a = 0.09 * i as f64;
                let (t, rate) = k.ratio_and_rate(a).unwrap();
                assert!((t / k.ratio_at_angle(a) - 1.0).abs() < 1e-12, "{k:?} {a}");
                let fd = (k.ratio_at_angle(a + h) - k.ratio_at_angle(a - h)) / (2.0 * h) * t;
                // The difference's rounding is about 2e-16 T / h in dT/dθ, so 2e-11 T² in the rate; its
                // truncation h² T''' / 6 is below 1e-8 of the rate.
                let tolerance = 1e-8 * rate.abs() + 1e-10 * t * t;
                assert!((rate - fd).abs() < tolerance, "{k:?} {a}: {rate} vs {fd}");
            }
        }
    }

    #[test]
    fn the_slider_crank_is_the_linkage_unchanged() {
        let l = Linkage::solve(0.3e-3, -1.0, 1.0, 4.0).unwrap();
        let k = Kinematics::from(l);
        for a in [-0.9, 0.0, 0.4] {
            assert_eq!(k.travel_derivatives(a), l.travel_derivatives(a));
            assert_eq!(k.ratio_at_angle(a), l.ratio_at_angle(a));
        }
        assert_eq!(k.lever(), l.crank);
    }
}
