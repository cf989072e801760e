//! The two-stage transmission of insect-scale flapping vehicles: the slider-crank of thesis eq. 2.5
//! (`transmission.rs`) whose crank drives a four-bar that amplifies its turn onto the wing (the
//! arrangement of Wood, IEEE Trans. Robot. 24(2), 2008, and of Sreetharan & Wood's later vehicles;
//! docs/physics.md §16.8).
//!
//! The four-bar is planar. Its input link `a` is the slider-crank's crank, extended: both turn about the
//! wing-side hinge `O` by the first stage's angle `θ1`. At rest the input stands upright, `C = (0, a)`, the
//! four-bar's coupler `b` lies horizontal, `D = (b, a)`, and the output rocker `c` stands upright on its
//! pivot `W = (b, a - c)`: both links are perpendicular to the coupler, so each turn of the input moves
//! `C` and `D` alike along the coupler and the output turns `a/c` times as far. The wing is on the output
//! rocker; its stroke angle `θ` is the rocker's turn from upright, counter-clockwise like `θ1`.

use crate::transmission::Linkage;
use std::f64::consts::{FRAC_PI_2, PI};

/// The four-bar, SI: input link, coupler and output rocker lengths; the ground link follows from the
/// rest pose, `d = √(b² + (a - c)²)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FourBar {
    /// Input link `a` (on the first stage's crank, about `O`), m.
    pub input: f64,
    /// Coupler `b`, m.
    pub coupler: f64,
    /// Output rocker `c` (the wing's, about `W`), m.
    pub output: f64,
}

/// The pose of the four-bar: absolute link angles from the `+x` axis, rad (input `θ2`, coupler `θ3`,
/// output `θ4`; upright is `π/2`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pose {
    /// Input link `O → C`.
    pub input: f64,
    /// Coupler `C → D`.
    pub coupler: f64,
    /// Output rocker `W → D`.
    pub output: f64,
}

/// The point at distance `r1` from `p` and `r2` from `q` on the left of `p → q` (the cross product of
/// `q - p` and the point `- p` positive); `None` where the circles do not meet.
fn intersect(p: [f64; 2], r1: f64, q: [f64; 2], r2: f64) -> Option<[f64; 2]> {
    let (dx, dy) = (q[0] - p[0], q[1] - p[1]);
    let d = dx.hypot(dy);
    let along = (r1 * r1 - r2 * r2 + d * d) / (2.0 * d);
    let h2 = r1 * r1 - along * along;
    if !(h2 >= 0.0 && d > 0.0) {
        return None;
    }
    let (ux, uy) = (dx / d, dy / d);
    let h = h2.sqrt();
    Some([p[0] + along * ux - h * uy, p[1] + along * uy + h * ux])
}

/// `x` wrapped into `(-π, π]`.
fn wrap(x: f64) -> f64 {
    let w = (x + PI).rem_euclid(2.0 * PI) - PI;
    if w == -PI {
        PI
    } else {
        w
    }
}

impl FourBar {
    /// The output rocker's pivot `W = (b, a - c)`, m.
    pub fn pivot(&self) -> [f64; 2] {
        [self.coupler, self.input - self.output]
    }

    /// The ground link `d = |O W| = √(b² + (a - c)²)`, m.
    pub fn ground(&self) -> f64 {
        self.coupler.hypot(self.input - self.output)
    }

    /// Grashof's criterion: `s + l ≤ p + q` over the four lengths (shortest `s`, longest `l`), which
    /// lets the shortest link turn fully (Norton, *Design of Machinery*, §2.12).
    pub fn is_grashof(&self) -> bool {
        let mut l = [self.input, self.coupler, self.output, self.ground()];
        l.sort_by(f64::total_cmp);
        l[0] + l[3] <= l[1] + l[2]
    }

    /// The pose with the input turned `θ1` from upright: `C = a (-sin θ1, cos θ1)`, `D` on the circles
    /// `|CD| = b`, `|WD| = c`, on the branch of the rest pose (`D` left of `C → W`). `None` past a
    /// toggle, where the circles part.
    pub fn pose(&self, input_turn: f64) -> Option<Pose> {
        let input = FRAC_PI_2 + input_turn;
        let a = [self.input * input.cos(), self.input * input.sin()];
        let o2 = self.pivot();
        let b = intersect(a, self.coupler, o2, self.output)?;
        Some(Pose {
            input,
            coupler: (b[1] - a[1]).atan2(b[0] - a[0]),
            output: (b[1] - o2[1]).atan2(b[0] - o2[0]),
        })
    }

    /// The wing's stroke angle `θ = θ4 - π/2` at the input's turn `θ1`, rad.
    pub fn output_angle(&self, input_turn: f64) -> Option<f64> {
        self.pose(input_turn).map(|p| wrap(p.output - FRAC_PI_2))
    }

    /// The input's turn `θ1` that puts the wing at `θ`: `D = W + c (-sin θ, cos θ)`, `C` on the circles
    /// `|OC| = a`, `|CD| = b`, left of `O → D` as at rest. `None` past a toggle.
    pub fn input_angle(&self, angle: f64) -> Option<f64> {
        let o2 = self.pivot();
        let b = [
            o2[0] - self.output * angle.sin(),
            o2[1] + self.output * angle.cos(),
        ];
        let a = intersect([0.0, 0.0], self.input, b, self.coupler)?;
        Some(wrap(a[1].atan2(a[0]) - FRAC_PI_2))
    }

    /// The gain `g = dθ/dθ1 = a sin(θ3 - θ2) / (c sin(θ3 - θ4))` and its rate `dg/dθ1` at a pose
    /// (the loop `a e^{iθ2} + b e^{iθ3} = W + c e^{iθ4}` differentiated, and its coupler rate
    /// `θ3' = a sin(θ4 - θ2) / (b sin(θ3 - θ4))`; Norton §6.7; docs/physics.md §16.8). `a/c` at rest.
    pub fn gain(&self, p: &Pose) -> (f64, f64) {
        let (a, b, c) = (self.input, self.coupler, self.output);
        let s34 = (p.coupler - p.output).sin();
        let g = a * (p.coupler - p.input).sin() / (c * s34);
        let w3 = a * (p.output - p.input).sin() / (b * s34);
        let rate = a / c
            * ((p.coupler - p.input).cos() * (w3 - 1.0) * s34
                - (p.coupler - p.input).sin() * (p.coupler - p.output).cos() * (w3 - g))
            / (s34 * s34);
        (g, rate)
    }

    /// The transmission angle `μ` between the coupler and the output rocker at a pose, in `[0, π]`; 90° at
    /// rest. Near 0 or 180° the coupler pushes along the rocker and the linkage toggles.
    pub fn transmission_angle(p: &Pose) -> f64 {
        wrap(p.output - p.coupler).abs()
    }

    /// The smallest and largest transmission angle over the wing's stroke between `lo` and `hi` (rad),
    /// 65 samples; `None` where a stroke angle has no pose.
    pub fn transmission_angle_range(&self, lo: f64, hi: f64) -> Option<(f64, f64)> {
        let mut range = (PI, 0.0f64);
        for i in 0..=64 {
            let angle = lo + (hi - lo) * i as f64 / 64.0;
            let mu = Self::transmission_angle(&self.pose(self.input_angle(angle)?)?);
            range = (range.0.min(mu), range.1.max(mu));
        }
        Some(range)
    }

    /// The film bends of the four-bar's two moving joints from the flat laminate at a pose, rad: links cut
    /// in a row `O-C-D-W` are flat when the coupler continues the input (`θ3 = θ2`) and the rocker
    /// continues the coupler (`θ4 = θ3 - π`: from D the rocker runs on to W), so `C` (input on coupler) is bent
    /// `θ3 - θ2` and `D` (coupler on rocker) `θ4 + π - θ3`, wrapped; both -90° at rest
    /// (docs/physics.md §16.8).
    pub fn bends(p: &Pose) -> [f64; 2] {
        [wrap(p.coupler - p.input), wrap(p.output + PI - p.coupler)]
    }
}

/// The slider-crank followed by the four-bar.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TwoStage {
    /// The first stage: actuator tip to the crank's turn `θ1`.
    pub first: Linkage,
    /// The second: `θ1` to the wing's `θ`.
    pub second: FourBar,
}

/// The joints of the two-stage linkage, in the order of [`TwoStage::bends`].
pub const TWO_STAGE_JOINTS: [&str; 6] = [
    "O (crank on airframe)",
    "B (crank on coupler)",
    "A (coupler on actuator tip)",
    "C (crank on four-bar coupler)",
    "D (four-bar coupler on wing rocker)",
    "W (rocker on airframe, the wing hinge)",
];

impl TwoStage {
    /// The linkage that turns an actuator travel of `±travel` into the wing's end angles: the four-bar's
    /// input turns `θ1± = θ1(θ±)` for them, and the first stage is solved for those
    /// ([`Linkage::solve`], docs/physics.md §12.3). `None` past the four-bar's toggle.
    pub fn solve(
        travel: f64,
        angle_minus: f64,
        angle_plus: f64,
        coupler_ratio: f64,
        second: FourBar,
    ) -> Option<Result<TwoStage, crate::ModelError>> {
        let lo = second.input_angle(angle_minus)?;
        let hi = second.input_angle(angle_plus)?;
        Some(Linkage::solve(travel, lo, hi, coupler_ratio).map(|first| TwoStage { first, second }))
    }

    /// The wing's angle at actuator tip displacement `x` from rest, rad.
    pub fn stroke_angle(&self, x: f64) -> Option<f64> {
        self.second.output_angle(self.first.stroke_angle(x)?)
    }

    /// The tip displacement `x(θ)` and its first two derivatives in the wing's `θ`, by the chain rule
    /// through `θ1(θ)`: `θ1' = 1/g`, `θ1'' = -g'/g³` ([`FourBar::gain`]), so `x' = x1' θ1'` and
    /// `x'' = x1'' θ1'² + x1' θ1''` with `x1` the first stage's [`Linkage::travel_derivatives`].
    pub fn travel_derivatives(&self, angle: f64) -> Option<(f64, f64, f64)> {
        let turn = self.second.input_angle(angle)?;
        let (x, d1, d2) = self.first.travel_derivatives(turn)?;
        let (g, rate) = self.second.gain(&self.second.pose(turn)?);
        let (t1, t2) = (1.0 / g, -rate / g.powi(3));
        Some((x, d1 * t1, d2 * t1 * t1 + d1 * t2))
    }

    /// The ratio `T = dθ/dx` at the wing's `θ`: the first stage's at `θ1` times the four-bar's gain;
    /// `(1/L3)(a/c)` with both stages at rest.
    pub fn ratio_at_angle(&self, angle: f64) -> f64 {
        self.travel_derivatives(angle)
            .map_or(f64::NAN, |(_, d1, _)| 1.0 / d1)
    }

    /// Each joint's film bend from the flat laminate with the wing at `θ`, rad, in the order of
    /// [`TWO_STAGE_JOINTS`]: `O`, `A` and the wing hinge `W` are laid flat at rest (their bend is their
    /// turn), `B` is the first stage's fold (`Linkage::bend_at_b`), `C` and `D` the four-bar's
    /// ([`FourBar::bends`]). `None` past either stage's reach.
    pub fn bends(&self, angle: f64) -> Option<[f64; 6]> {
        let turn = self.second.input_angle(angle)?;
        let rest_turn = self.first.stroke_angle(0.0)?;
        let rest = self.second.output_angle(rest_turn)?;
        let [o, _, a] = self.first.joint_rotations(turn)?;
        let [c, d] = FourBar::bends(&self.second.pose(turn)?);
        Some([o, self.first.bend_at_b(turn)?, a, c, d, angle - rest])
    }

    /// `dφ_i/dθ` of the six joints at rest, for the flexures' stiffness about the wing hinge
    /// `Σ k_i (dφ_i/dθ)²` (docs/physics.md §16.4): the first stage's rates over the gain, the four-bar's
    /// fold rates `θ3' - 1` and `g - θ3'` over the gain, and 1 at the wing hinge.
    pub fn joint_rates_at_rest(&self) -> Option<[f64; 6]> {
        let rest_turn = self.first.stroke_angle(0.0)?;
        let p = self.second.pose(rest_turn)?;
        let (g, _) = self.second.gain(&p);
        let (a, b) = (self.second.input, self.second.coupler);
        let w3 = a * (p.output - p.input).sin() / (b * (p.coupler - p.output).sin());
        let [o, bb, aa] = self.first.joint_rates_at_rest()?;
        Some([o / g, bb / g, aa / g, (w3 - 1.0) / g, (g - w3) / g, 1.0])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bar() -> FourBar {
        FourBar {
            input: 1.0e-3,
            coupler: 2.0e-3,
            output: 0.4e-3,
        }
    }

    #[test]
    fn the_rest_pose_gains_input_over_output() {
        // docs/physics.md §16.8: both links perpendicular to the coupler at rest, g = a/c.
        let f = bar();
        let p = f.pose(0.0).unwrap();
        assert!((p.input - FRAC_PI_2).abs() < 1e-15 && p.coupler.abs() < 1e-12);
        assert!((p.output - FRAC_PI_2).abs() < 1e-12, "{p:?}");
        assert!((f.gain(&p).0 - 2.5).abs() < 1e-12);
        assert!((FourBar::transmission_angle(&p) - FRAC_PI_2).abs() < 1e-12);
        // Ground d = √(b² + (a - c)²) = √(4 + 0.36) mm.
        assert!((f.ground() - 4.36f64.sqrt() * 1e-3).abs() < 1e-15);
    }

    #[test]
    fn the_output_is_the_constructed_one_and_the_input_its_inverse() {
        // Each pose against the loop closure |CD| = b, |WD| = c; θ1(θ(θ1)) = θ1; the gain and its rate
        // against central differences.
        let f = bar();
        for i in -10..=10 {
            let t1 = 0.035 * i as f64;
            let p = f.pose(t1).unwrap();
            let a = [f.input * p.input.cos(), f.input * p.input.sin()];
            let b = [
                a[0] + f.coupler * p.coupler.cos(),
                a[1] + f.coupler * p.coupler.sin(),
            ];
            let o2 = f.pivot();
            let rocker = (b[0] - o2[0]).hypot(b[1] - o2[1]);
            assert!((rocker - f.output).abs() < 1e-15, "{t1}");
            let out = f.output_angle(t1).unwrap();
            assert!((f.input_angle(out).unwrap() - t1).abs() < 1e-12, "{t1}");
            let h = 1e-6;
            let fd =
                (f.output_angle(t1 + h).unwrap() - f.output_angle(t1 - h).unwrap()) / (2.0 * h);
            let (g, rate) = f.gain(&p);
            assert!((g - fd).abs() < 1e-7 * g, "{t1}: {g} vs {fd}");
            let gain_at = |t: f64| f.gain(&f.pose(t).unwrap()).0;
            let fd2 = (gain_at(t1 + h) - gain_at(t1 - h)) / (2.0 * h);
            assert!((rate - fd2).abs() < 1e-6 * g, "{t1}: {rate} vs {fd2}");
        }
    }

    #[test]
    fn grashof_and_the_transmission_angle_limits_are_the_closed_forms() {
        // Norton §2.12: s + l ≤ p + q. a = 1, b = 2, c = 0.4 mm: d = 2.088 mm, 0.4 + 2.088 ≤ 1 + 2, Grashof
        // with the output rocker the shortest: it could turn fully while the input rocks. b = 0.5 mm:
        // d = 0.781 mm, 0.4 + 1 > 0.5 + 0.781, not Grashof. a = c, a parallelogram, is the limit s + l = p + q.
        assert!(bar().is_grashof());
        assert!(!FourBar {
            coupler: 0.5e-3,
            ..bar()
        }
        .is_grashof());
        assert!(FourBar {
            output: 1.0e-3,
            ..bar()
        }
        .is_grashof());
        // The transmission angle with the input along the ground line O W is the law of cosines in the
        // triangle C D W with |CW| = d - a: cos μ = (b² + c² - (d - a)²) / (2 b c) (Norton §4.10).
        let f = FourBar {
            input: 1.0e-3,
            coupler: 2.0e-3,
            output: 1.6e-3,
        };
        let o2 = f.pivot();
        let along = o2[1].atan2(o2[0]) - FRAC_PI_2;
        let p = f.pose(along).unwrap();
        let (a, b, c, d) = (f.input, f.coupler, f.output, f.ground());
        let closed = ((b * b + c * c - (d - a).powi(2)) / (2.0 * b * c)).acos();
        assert!(
            (FourBar::transmission_angle(&p) - closed).abs() < 1e-9,
            "{p:?}"
        );
        // The input rocks between the toggles |CW| = b ± c, where the coupler and the rocker lie in line
        // (μ = 180° and 0): cos ∠(OW, OC) = (a² + d² - (b ± c)²) / (2 a d), the input that far
        // counter-clockwise of O W, the upper toggle at b + c (22.2°), the lower at b - c (-25.4°). No pose
        // lies past them.
        let t = bar();
        let (a, b, c, d) = (t.input, t.coupler, t.output, t.ground());
        let o2 = t.pivot();
        let ground = o2[1].atan2(o2[0]);
        for (reach, side) in [(b + c, 1.0), (b - c, -1.0)] {
            let at = ((a * a + d * d - reach * reach) / (2.0 * a * d)).acos();
            let limit = ground + at - FRAC_PI_2;
            let inside = t.pose(limit - side * 1e-6).unwrap();
            assert!(
                t.pose(limit + side * 1e-6).is_none(),
                "{}",
                limit.to_degrees()
            );
            let mu = FourBar::transmission_angle(&inside);
            assert!(!(0.01..=PI - 0.01).contains(&mu), "{}", mu.to_degrees());
        }
        // Over a stroke the range of μ; 90° at rest; the drive file refuses a stroke that takes it past 30-150°.
        let (lo, hi) = t.transmission_angle_range(-0.3, 0.3).unwrap();
        assert!(lo < FRAC_PI_2 && hi > FRAC_PI_2 && lo > 0.0 && hi < PI);
    }

    #[test]
    fn the_small_angle_ratio_is_the_product_of_the_stages() {
        // T0 = (1/L3)(a/c): a 0.5 mm crank (2000 rad/m) and a 2.5 gain give 5000 rad/m.
        let s = TwoStage {
            first: Linkage::new(2e-3, 0.5e-3, 0.0).unwrap(),
            second: bar(),
        };
        assert!(s.stroke_angle(0.0).unwrap().abs() < 1e-15);
        assert!((s.ratio_at_angle(0.0) - 5000.0).abs() < 1e-9);
        let h = 1e-9;
        let fd = (s.stroke_angle(h).unwrap() - s.stroke_angle(-h).unwrap()) / (2.0 * h);
        assert!((fd / 5000.0 - 1.0).abs() < 1e-6, "{fd}");
        // The derivatives of x(θ) against central differences of its inverse.
        for i in -8..=8 {
            let th = 0.1 * i as f64;
            let (x, d1, d2) = s.travel_derivatives(th).unwrap();
            assert!((s.stroke_angle(x).unwrap() - th).abs() < 1e-10, "{th}");
            let t = |a: f64| s.travel_derivatives(a).unwrap().0;
            let h = 1e-4;
            let fd1 = (t(th + h) - t(th - h)) / (2.0 * h);
            let fd2 = (t(th + h) - 2.0 * x + t(th - h)) / (h * h);
            assert!((d1 - fd1).abs() < 1e-6 * d1.abs(), "{th}: {d1} vs {fd1}");
            assert!((d2 - fd2).abs() < 1e-4 * d1.abs(), "{th}: {d2} vs {fd2}");
        }
    }

    #[test]
    fn the_bend_at_each_joint_is_the_hand_computed_one() {
        // A 0.5 mm crank, coupler 2 mm, δ0 = 0 (θ1 = 0 at rest), and the four-bar a = 1, b = 2, c = 0.4 mm,
        // at the first stage's θ1 = 10°. By hand: C = (-0.17365, 0.98481) mm; W = (2, 0.6) mm;
        // |CW| = √(2.17365² + 0.38481²) = 2.20745 mm. D on |CD| = 2, |WD| = 0.4 left of C → W:
        // along = (4 - 0.16 + |CW|²)/(2 |CW|) = 1.97351 mm from C toward W, and
        // h = √(4 - along²) = 0.32446 mm across.
        let s = TwoStage {
            first: Linkage::new(2e-3, 0.5e-3, 0.0).unwrap(),
            second: bar(),
        };
        let t1 = 10f64.to_radians();
        let (ax, ay) = (-t1.sin(), t1.cos());
        let d = (2.0 - ax).hypot(0.6 - ay);
        let (ux, uy) = ((2.0 - ax) / d, (0.6 - ay) / d);
        let along = (4.0 - 0.16 + d * d) / (2.0 * d);
        let h = (4.0 - along * along).sqrt();
        let (bx, by) = (ax + along * ux - h * uy, ay + along * uy + h * ux);
        let theta = (-(bx - 2.0)).atan2(by - 0.6);
        assert!(
            (s.second.output_angle(t1).unwrap() - theta).abs() < 1e-9,
            "{theta}"
        );
        let bends = s.bends(theta).unwrap();
        // C: the coupler's direction less the input's; D: the rocker's plus π less the coupler's.
        let coupler = (by - ay).atan2(bx - ax);
        let c = coupler - (FRAC_PI_2 + t1);
        let d = (FRAC_PI_2 + theta) + PI - coupler;
        assert!((bends[3] - c).abs() < 1e-9, "{} vs {c}", bends[3]);
        assert!((bends[4] - wrap(d)).abs() < 1e-9, "{} vs {d}", bends[4]);
        // O turns θ1, W the wing's θ; B is the slider-crank's β(θ1) = π/2 + θ1 - ψ, with
        // ψ = asin(0.5 (1 - cos 10°) / 2).
        let psi = (0.25 * (1.0 - t1.cos())).asin();
        assert!((bends[0] - t1).abs() < 1e-9 && (bends[5] - theta).abs() < 1e-9);
        assert!((bends[1] - (FRAC_PI_2 + t1 - psi)).abs() < 1e-9);
        assert!((bends[2] - psi).abs() < 1e-9);
        // At rest both four-bar joints are folded a right angle.
        let rest = s.bends(0.0).unwrap();
        assert!(
            (rest[3].abs() - FRAC_PI_2).abs() < 1e-12 && (rest[4].abs() - FRAC_PI_2).abs() < 1e-12
        );
        // The rates at rest against central differences of the bends.
        let rates = s.joint_rates_at_rest().unwrap();
        let hh = 1e-7;
        let (up, down) = (s.bends(hh).unwrap(), s.bends(-hh).unwrap());
        for i in 0..6 {
            let fd = (up[i] - down[i]) / (2.0 * hh);
            assert!((rates[i] - fd).abs() < 1e-6, "{i}: {} vs {fd}", rates[i]);
        }
    }

    #[test]
    fn solving_for_a_stroke_reaches_the_wing_end_angles() {
        let (lo, hi) = (-55f64.to_radians(), 55f64.to_radians());
        let s = TwoStage::solve(0.17e-3, lo, hi, 4.0, bar())
            .unwrap()
            .unwrap();
        assert!((s.stroke_angle(0.17e-3).unwrap() - hi).abs() < 1e-10);
        assert!((s.stroke_angle(-0.17e-3).unwrap() - lo).abs() < 1e-10);
        // Past the four-bar's toggle there is no input turn: the wing's rocker cannot be turned past the
        // input's reach from the slider-crank side (c = 1.6 mm, a = 1 mm: the rocker swings less than the input).
        let slow = FourBar {
            output: 1.6e-3,
            ..bar()
        };
        assert!(TwoStage::solve(0.17e-3, -1.5, 1.5, 4.0, slow).is_none());
    }
}
