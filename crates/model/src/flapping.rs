//! Actuator, transmission and wing at a flapping frequency: the steady stroke by harmonic balance, and a
//! time integration to check it (docs/physics.md §14).
//!
//! With the stroke angle `θ` as the coordinate, the actuator tip at `x(θ)` (the inverse of eq. 2.5,
//! `x' = dx/dθ = 1/T`), Lagrange's equation of kinetic energy `½ (m x'² + I) θ̇²` and potential energy
//! `½ k x² + ½ k_t (θ - θ_r)²` is
//!
//! `(m x'² + I) θ̈ + m x' x'' θ̇² + k x x' + k_t (θ - θ_r) + K θ̇|θ̇| + c_s x'² θ̇ = F x' sin ωt`
//!
//! (`m`, `k` the lumped actuator, `I` wing + links about the hinge, `K` the wing's drag coefficient,
//! `k_t` the flexures, unstrained at the rest angle `θ_r`, `c_s = η k / ω` the actuator's structural loss
//! at the drive frequency, `F` the blocked-force amplitude). The harmonic balance keeps the mean and the
//! first harmonic of `θ`; every nonlinear term (kinematics, drag) is integrated over the period as it
//! is; what it neglects is the higher harmonics of `θ`. The time integration runs the same system in the
//! tip displacement `x` instead, so the two share no formulation.

use crate::dynamics::LumpedActuator;
use crate::error::ModelError;
use crate::transmission::Linkage;
use std::f64::consts::PI;

/// Samples per period in the harmonic balance's projections.
const SAMPLES: usize = 64;

/// The coupled system, SI.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FlappingSystem {
    /// The actuator at its tip.
    pub actuator: LumpedActuator,
    /// The transmission's geometry.
    pub linkage: Linkage,
    /// Flexure stiffness about the hinge, N·m/rad.
    pub flexure_stiffness: f64,
    /// Wing and link inertia about the hinge, kg·m².
    pub inertia: f64,
    /// Wing drag coefficient `K` (`τ = K θ̇|θ̇|`), N·m·s².
    pub damping: f64,
}

/// One steady state (SI).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SteadyState {
    /// Drive frequency, Hz.
    pub frequency: f64,
    /// Blocked-force amplitude, N.
    pub force: f64,
    /// Mean stroke angle, rad.
    pub mean_angle: f64,
    /// Half the peak-to-peak stroke angle, rad.
    pub stroke_amplitude: f64,
    /// Phase of the stroke behind the force, rad.
    pub phase: f64,
    /// Half the peak-to-peak tip displacement, m.
    pub displacement_amplitude: f64,
    /// Mean power into the air, `⟨K |θ̇|³⟩`, W.
    pub aero_power: f64,
    /// Peak load the tip carries, `max |F sin ωt - k x|`, N.
    pub peak_tip_load: f64,
}

impl FlappingSystem {
    /// The stroke angle at the actuator's rest, where the flexures are unstrained, rad.
    fn rest_angle(&self) -> f64 {
        self.linkage.stroke_angle(0.0).unwrap_or(0.0)
    }

    /// Small-stroke resonance at rest: `√((k + k_t T0²) / (m + I T0²)) / 2π`, Hz.
    pub fn linear_resonance(&self) -> f64 {
        let t0 = self.linkage.ratio(0.0).unwrap_or(1.0 / self.linkage.crank);
        let a = &self.actuator;
        ((a.stiffness + self.flexure_stiffness * t0 * t0) / (a.mass + self.inertia * t0 * t0))
            .sqrt()
            / (2.0 * PI)
    }

    /// `x(θ)`, `x'` and `x''` of the linkage.
    fn travel(&self, angle: f64) -> Option<(f64, f64, f64)> {
        let x = self.linkage.travel(angle)?;
        let d1 = 1.0 / self.linkage.ratio_at_angle(angle);
        let h = 1e-5;
        let d2 = (1.0 / self.linkage.ratio_at_angle(angle + h)
            - 1.0 / self.linkage.ratio_at_angle(angle - h))
            / (2.0 * h);
        d1.is_finite().then_some((x, d1, d2))
    }

    /// The projections of the θ equation on 1, cos ωt, sin ωt for `θ = c0 + c1 cos ωt + c2 sin ωt`.
    fn residual(&self, c: &[f64; 3], force: f64, omega: f64) -> Option<[f64; 3]> {
        let a = &self.actuator;
        let structural = a.loss_factor * a.stiffness / omega;
        let rest = self.rest_angle();
        let mut r = [0.0; 3];
        for i in 0..SAMPLES {
            let phase = 2.0 * PI * i as f64 / SAMPLES as f64;
            let (cs, sn) = (phase.cos(), phase.sin());
            let angle = c[0] + c[1] * cs + c[2] * sn;
            let rate = omega * (-c[1] * sn + c[2] * cs);
            let acc = -omega * omega * (c[1] * cs + c[2] * sn);
            let (x, d1, d2) = self.travel(angle)?;
            let e = (a.mass * d1 * d1 + self.inertia) * acc
                + a.mass * d1 * d2 * rate * rate
                + a.stiffness * x * d1
                + self.flexure_stiffness * (angle - rest)
                + self.damping * rate * rate.abs()
                + structural * d1 * d1 * rate
                - force * d1 * sn;
            r[0] += e / SAMPLES as f64;
            r[1] += 2.0 * e * cs / SAMPLES as f64;
            r[2] += 2.0 * e * sn / SAMPLES as f64;
        }
        Some(r)
    }

    /// Damped Newton on three unknowns `u`, the residual `f(u)`; finite-difference Jacobian.
    fn newton(
        &self,
        mut u: [f64; 3],
        steps: [f64; 3],
        scale: f64,
        f: impl Fn(&[f64; 3]) -> Option<[f64; 3]>,
    ) -> Option<[f64; 3]> {
        let norm = |r: &[f64; 3]| r.iter().map(|v| v * v).sum::<f64>().sqrt();
        let mut r = f(&u)?;
        'iterations: for _ in 0..100 {
            if norm(&r) < 1e-12 * scale {
                break;
            }
            let mut jac = nalgebra::Matrix3::<f64>::zeros();
            for j in 0..3 {
                let mut up = u;
                up[j] += steps[j];
                let rp = f(&up)?;
                for i in 0..3 {
                    jac[(i, j)] = (rp[i] - r[i]) / steps[j];
                }
            }
            let step = jac
                .lu()
                .solve(&nalgebra::Vector3::new(-r[0], -r[1], -r[2]))?;
            let mut lambda = 1.0;
            loop {
                let trial = [
                    u[0] + lambda * step[0],
                    u[1] + lambda * step[1],
                    u[2] + lambda * step[2],
                ];
                match f(&trial) {
                    Some(rt) if norm(&rt) < norm(&r) => {
                        u = trial;
                        r = rt;
                        break;
                    }
                    // No descent left (the finite-difference Jacobian's noise floor): the final
                    // tolerance decides.
                    _ if lambda < 1e-4 => break 'iterations,
                    _ => lambda *= 0.5,
                }
            }
        }
        (norm(&r) < 1e-7 * scale).then_some(u)
    }

    fn torque_scale(&self) -> f64 {
        self.actuator.stiffness * self.linkage.crank * self.linkage.crank
    }

    /// The steady state at a blocked-force amplitude (N) and frequency (Hz): harmonic balance in the
    /// stroke's mean and first harmonic, from `start` (`[mean, cos, sin]` coefficients of θ) or from a
    /// small stroke, continuing in the force where Newton alone does not converge. A fold near
    /// resonance (two stable strokes at one force) shows as the branch continued from `start`.
    pub fn harmonic_balance(
        &self,
        force: f64,
        frequency: f64,
        start: Option<[f64; 3]>,
    ) -> Result<SteadyState, ModelError> {
        let omega = 2.0 * PI * frequency;
        let solve = |f: f64, u: [f64; 3]| {
            self.newton(u, [1e-7; 3], self.torque_scale(), |c| {
                self.residual(c, f, omega)
            })
        };
        let rest = self.rest_angle();
        let mut found = start.and_then(|u| solve(force, u));
        for steps in [1, 8, 32] {
            if found.is_some() {
                break;
            }
            let mut u = Some([rest, 0.0, 0.0]);
            for i in 1..=steps {
                u = u.and_then(|u| solve(force * i as f64 / steps as f64, u));
            }
            found = u;
        }
        let c = found.ok_or(ModelError::OutOfRange {
            name: "stroke",
            value: force,
            range: "a steady stroke within the linkage's reach",
        })?;
        self.evaluate(force, frequency, c)
    }

    /// The balance with the stroke amplitude given and the force unknown: `θ = θ0 + Θ sin(ωt - φ)`,
    /// unknowns `(θ0, φ, F)`. The force is a function of the stroke even where the stroke is not a
    /// function of the force (a fold near resonance), so this is how a required stroke is solved.
    pub fn balance_at_stroke(
        &self,
        stroke: f64,
        frequency: f64,
        start: Option<[f64; 3]>,
    ) -> Result<SteadyState, ModelError> {
        let omega = 2.0 * PI * frequency;
        let coefficients = |u: &[f64; 3]| [u[0], -stroke * u[1].sin(), stroke * u[1].cos()];
        let guess = start.unwrap_or([
            self.rest_angle(),
            0.5 * PI,
            self.actuator.stiffness * stroke * self.linkage.crank,
        ]);
        let scale = self.torque_scale();
        let u = self
            .newton(
                guess,
                [1e-7, 1e-7, 1e-7 * scale / self.linkage.crank],
                scale,
                |u| self.residual(&coefficients(u), u[2], omega),
            )
            .ok_or(ModelError::OutOfRange {
                name: "stroke",
                value: stroke,
                range: "within the linkage's reach",
            })?;
        // A negative force is the same motion half a period on.
        let (force, phase) = if u[2] < 0.0 {
            (-u[2], u[1] + PI)
        } else {
            (u[2], u[1])
        };
        self.evaluate(force, frequency, coefficients(&[u[0], phase, force]))
    }

    /// The reported quantities of `θ = c0 + c1 cos ωt + c2 sin ωt`.
    fn evaluate(&self, force: f64, frequency: f64, c: [f64; 3]) -> Result<SteadyState, ModelError> {
        let omega = 2.0 * PI * frequency;
        let n = 4 * SAMPLES;
        let (mut lo, mut hi, mut power, mut load) = (f64::INFINITY, f64::NEG_INFINITY, 0.0, 0.0f64);
        for i in 0..n {
            let phase = 2.0 * PI * i as f64 / n as f64;
            let (cs, sn) = (phase.cos(), phase.sin());
            let angle = c[0] + c[1] * cs + c[2] * sn;
            let rate = omega * (-c[1] * sn + c[2] * cs);
            let x = self.linkage.travel(angle).ok_or(ModelError::OutOfRange {
                name: "stroke",
                value: angle,
                range: "within the linkage's reach",
            })?;
            lo = lo.min(x);
            hi = hi.max(x);
            power += self.damping * rate.abs().powi(3) / n as f64;
            load = load.max((force * sn - self.actuator.stiffness * x).abs());
        }
        Ok(SteadyState {
            frequency,
            force,
            mean_angle: c[0],
            stroke_amplitude: c[1].hypot(c[2]),
            // θ - θ0 = Θ sin(ωt - φ): c1 = -Θ sin φ, c2 = Θ cos φ.
            phase: (-c[1]).atan2(c[2]),
            displacement_amplitude: 0.5 * (hi - lo),
            aero_power: power,
            peak_tip_load: load,
        })
    }

    /// The stroke by time integration in the tip displacement `x` (classical Runge-Kutta, 2000 steps a
    /// period, from rest, `periods` periods): half the peak-to-peak stroke angle over the last period.
    pub fn integrate(&self, force: f64, frequency: f64, periods: usize) -> Result<f64, ModelError> {
        let omega = 2.0 * PI * frequency;
        let a = &self.actuator;
        let structural = a.loss_factor * a.stiffness / omega;
        let rest = self.rest_angle();
        let steps = 2000;
        let dt = 1.0 / (frequency * steps as f64);
        // (m + I T²) ẍ + I T T' ẋ² + K T³ ẋ|ẋ| + c_s ẋ + k x + k_t (θ - θ_r) T = F sin ωt, T = dθ/dx.
        let accel = |t: f64, x: f64, v: f64| -> Option<f64> {
            let angle = self.linkage.stroke_angle(x)?;
            let tr = self.linkage.ratio_at_angle(angle);
            let h = 1e-6;
            let slope = (self.linkage.ratio_at_angle(angle + h)
                - self.linkage.ratio_at_angle(angle - h))
                / (2.0 * h)
                * tr;
            let rest_of = self.inertia * tr * slope * v * v
                + self.damping * tr.powi(3) * v * v.abs()
                + structural * v
                + a.stiffness * x
                + self.flexure_stiffness * (angle - rest) * tr;
            Some((force * (omega * t).sin() - rest_of) / (a.mass + self.inertia * tr * tr))
        };
        let fail = || ModelError::OutOfRange {
            name: "stroke",
            value: force,
            range: "within the linkage's reach",
        };
        let (mut x, mut v) = (0.0, 0.0);
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for p in 0..periods {
            if p + 1 == periods {
                (lo, hi) = (f64::INFINITY, f64::NEG_INFINITY);
            }
            for s in 0..steps {
                let t = (p * steps + s) as f64 * dt;
                let angle = self.linkage.stroke_angle(x).ok_or_else(fail)?;
                lo = lo.min(angle);
                hi = hi.max(angle);
                let k1 = (v, accel(t, x, v).ok_or_else(fail)?);
                let (x2, v2) = (x + 0.5 * dt * k1.0, v + 0.5 * dt * k1.1);
                let k2 = (v2, accel(t + 0.5 * dt, x2, v2).ok_or_else(fail)?);
                let (x3, v3) = (x + 0.5 * dt * k2.0, v + 0.5 * dt * k2.1);
                let k3 = (v3, accel(t + 0.5 * dt, x3, v3).ok_or_else(fail)?);
                let (x4, v4) = (x + dt * k3.0, v + dt * k3.1);
                let k4 = (v4, accel(t + dt, x4, v4).ok_or_else(fail)?);
                x += dt / 6.0 * (k1.0 + 2.0 * k2.0 + 2.0 * k3.0 + k4.0);
                v += dt / 6.0 * (k1.1 + 2.0 * k2.1 + 2.0 * k3.1 + k4.1);
            }
        }
        Ok(0.5 * (hi - lo))
    }

    /// The blocked-force amplitude (N) that gives a stroke amplitude (rad) at a frequency (Hz), by
    /// [`Self::balance_at_stroke`]. `Err` with the largest stroke whose force is within `force_limit`
    /// when the limit binds, or when the linkage cannot reach the stroke.
    pub fn force_for_stroke(
        &self,
        stroke: f64,
        frequency: f64,
        force_limit: f64,
    ) -> Result<SteadyState, Unreached> {
        // Continue from a small stroke so Newton stays on the branch that starts at rest.
        let mut start = None;
        let mut last = None;
        for i in 1..=8 {
            match self.balance_at_stroke(stroke * i as f64 / 8.0, frequency, start) {
                Ok(s) => {
                    start = Some([s.mean_angle, s.phase, s.force]);
                    last = Some(s);
                }
                Err(_) => break,
            }
        }
        match last {
            Some(s) if s.stroke_amplitude >= stroke * (1.0 - 1e-12) && s.force <= force_limit => {
                Ok(s)
            }
            _ => {
                // The largest stroke within the force limit (the force grows with the stroke).
                let (mut a, mut b) = (0.0, stroke);
                let mut best = None;
                for _ in 0..40 {
                    let mid = 0.5 * (a + b);
                    match self.balance_at_stroke(mid, frequency, None) {
                        Ok(t) if t.force <= force_limit => {
                            best = Some(t);
                            a = mid;
                        }
                        _ => b = mid,
                    }
                }
                Err(Unreached { best })
            }
        }
    }
}

/// The required stroke is out of reach: the best steady state found within the force limit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Unreached {
    /// The largest stroke reached, if any steady state was found.
    pub best: Option<SteadyState>,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::DEFAULT_LOSS_FACTOR;

    /// A hawk-moth-sized system (the numbers of examples/drive-hawkmoth.toml, rounded).
    fn system() -> FlappingSystem {
        FlappingSystem {
            actuator: LumpedActuator {
                stiffness: 300.0,
                mass: 40e-6,
                loss_factor: DEFAULT_LOSS_FACTOR,
            },
            linkage: Linkage::solve(0.4e-3, -PI / 3.0, PI / 3.0, 3.0).unwrap(),
            flexure_stiffness: 2e-5,
            inertia: 1.0e-9,
            damping: 3e-10,
        }
    }

    #[test]
    fn harmonic_balance_agrees_with_time_integration() {
        // The check: stroke amplitude within 2 % at, below and above resonance, at strokes of
        // 30-53° where the linkage's ratio has fallen by a third (the balance in θ, the integration in x).
        let s = system();
        let f_r = s.linear_resonance();
        for (ratio, force) in [(0.5, 0.07), (0.9, 0.04), (1.0, 0.08), (1.3, 0.08)] {
            let hb = s.harmonic_balance(force, ratio * f_r, None).unwrap();
            let ti = s.integrate(force, ratio * f_r, 80).unwrap();
            let rel = hb.stroke_amplitude / ti - 1.0;
            assert!(
                rel.abs() < 0.02,
                "f/f_r {ratio}: HB {:.2}° vs time {:.2}°",
                hb.stroke_amplitude.to_degrees(),
                ti.to_degrees()
            );
            assert!(
                hb.stroke_amplitude > 5f64.to_radians(),
                "a stroke worth checking"
            );
        }
    }

    #[test]
    fn small_strokes_are_the_linear_oscillator() {
        // Without drag, at a small force: X = F / |k_eff - m_eff ω² + i η k|.
        let mut s = system();
        s.damping = 0.0;
        let t0 = s.linkage.ratio(0.0).unwrap();
        let k_eff = s.actuator.stiffness + s.flexure_stiffness * t0 * t0;
        let m_eff = s.actuator.mass + s.inertia * t0 * t0;
        let f = 0.6 * s.linear_resonance();
        let w = 2.0 * PI * f;
        let force = 1e-6;
        let want =
            force / (k_eff - m_eff * w * w).hypot(s.actuator.loss_factor * s.actuator.stiffness);
        let got = s
            .harmonic_balance(force, f, None)
            .unwrap()
            .displacement_amplitude;
        assert!((got / want - 1.0).abs() < 1e-4, "{got} vs {want}");
    }

    #[test]
    fn the_force_for_a_stroke_gives_that_stroke() {
        let s = system();
        let f = 0.9 * s.linear_resonance();
        let target = 50f64.to_radians();
        let found = s.force_for_stroke(target, f, 5.0).unwrap();
        assert!((found.stroke_amplitude - target).abs() < 1e-6);
        // Too little force available: the best stroke is below the target.
        let short = s
            .force_for_stroke(target, f, found.force * 0.5)
            .unwrap_err();
        assert!(short.best.unwrap().stroke_amplitude < target);
    }
}
