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
//! first [`HARMONICS`] harmonics of `θ`; every nonlinear term (kinematics, drag) is integrated over the
//! period as it is; what it neglects is the harmonics above those. The time integration runs the same system in the
//! tip displacement `x` instead, so the two share no formulation.

use crate::dynamics::LumpedActuator;
use crate::error::ModelError;
use crate::kinematics::Kinematics;
use nalgebra::{DMatrix, DVector};
use std::f64::consts::PI;

/// Harmonics of the stroke the balance keeps. The quadratic drag and the linkage's falling ratio put
/// higher harmonics into a large stroke: the first harmonic alone is 0.5-1.5 % off the time
/// integration at 30-52° (`harmonic_balance_agrees_with_time_integration`), three are within 0.05 %
/// (docs/physics.md §14).
pub const HARMONICS: usize = 3;

/// Fourier coefficients of `θ`: the mean, then those of `cos kωt` and `sin kωt` for `k = 1..=HARMONICS`.
pub const COEFFICIENTS: usize = 2 * HARMONICS + 1;

/// Unknowns of the balance at a given stroke: mean, phase, force, first-harmonic amplitude, and the
/// higher harmonics' coefficients.
const AT_STROKE: usize = COEFFICIENTS + 1;

/// Samples per period in the harmonic balance's projections (the nonlinear terms alias only from
/// harmonic `SAMPLES - HARMONICS` up).
const SAMPLES: usize = 64;

/// The coupled system, SI.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FlappingSystem {
    /// The actuator at its tip.
    pub actuator: LumpedActuator,
    /// The transmission's kinematics.
    pub linkage: Kinematics,
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
    /// Mean stroke angle over the period, rad.
    pub mean_angle: f64,
    /// Half the peak-to-peak stroke angle, rad.
    pub stroke_amplitude: f64,
    /// Phase of the stroke's first harmonic behind the force, rad.
    pub phase: f64,
    /// Half the peak-to-peak tip displacement, m.
    pub displacement_amplitude: f64,
    /// Mean power into the air, `⟨K |θ̇|³⟩`, W.
    pub aero_power: f64,
    /// Peak load the tip carries, `max |F sin ωt - k x|`, N.
    pub peak_tip_load: f64,
    /// `θ`'s Fourier coefficients ([`COEFFICIENTS`]), rad.
    pub coefficients: [f64; COEFFICIENTS],
}

impl SteadyState {
    /// Stroke angle at the drive phase `ωt`, rad.
    pub fn angle_at(&self, phase: f64) -> f64 {
        series(&self.coefficients, &basis(phase))[0]
    }
}

/// `[1, cos φ, sin φ, cos 2φ, sin 2φ, …]` at the phase `φ = ωt`.
fn basis(phase: f64) -> [f64; COEFFICIENTS] {
    let (s1, c1) = phase.sin_cos();
    let mut b = [1.0; COEFFICIENTS];
    let (mut ck, mut sk) = (1.0, 0.0);
    for k in 1..=HARMONICS {
        (ck, sk) = (ck * c1 - sk * s1, sk * c1 + ck * s1);
        b[2 * k - 1] = ck;
        b[2 * k] = sk;
    }
    b
}

/// `θ`, `dθ/dφ` and `d²θ/dφ²` of the series `c` at a phase whose [`basis`] is `b`.
fn series(c: &[f64; COEFFICIENTS], b: &[f64; COEFFICIENTS]) -> [f64; 3] {
    let mut out = [c[0], 0.0, 0.0];
    for k in 1..=HARMONICS {
        let (i, j, kf) = (2 * k - 1, 2 * k, k as f64);
        out[0] += c[i] * b[i] + c[j] * b[j];
        out[1] += kf * (c[j] * b[i] - c[i] * b[j]);
        out[2] -= kf * kf * (c[i] * b[i] + c[j] * b[j]);
    }
    out
}

/// Lowest and highest `θ` of the series over a period: the extreme of [`SAMPLES`] samples, each refined
/// by Newton on `dθ/dφ = 0` (so the stroke is exact, not a sampled peak).
fn extremes(c: &[f64; COEFFICIENTS]) -> (f64, f64) {
    let n = SAMPLES;
    let step = 2.0 * PI / n as f64;
    let (mut lo, mut hi) = ((0.0, f64::INFINITY), (0.0, f64::NEG_INFINITY));
    for i in 0..n {
        let phase = i as f64 * step;
        let angle = series(c, &basis(phase))[0];
        if angle < lo.1 {
            lo = (phase, angle);
        }
        if angle > hi.1 {
            hi = (phase, angle);
        }
    }
    let refine = |(mut phase, mut angle): (f64, f64)| {
        for _ in 0..8 {
            let [_, d1, d2] = series(c, &basis(phase));
            if d2 == 0.0 {
                break;
            }
            let next = phase - (d1 / d2).clamp(-step, step);
            let at = series(c, &basis(next))[0];
            // Keep a step only when it moves toward the extreme the sample bracketed.
            if (at - angle) * d2.signum() >= 0.0 {
                break;
            }
            (phase, angle) = (next, at);
        }
        angle
    };
    (refine(lo), refine(hi))
}

/// Damped Newton on `M` unknowns `u`, the residual `f(u)`; finite-difference Jacobian with `steps`.
fn newton<const M: usize>(
    mut u: [f64; M],
    steps: [f64; M],
    scale: f64,
    f: impl Fn(&[f64; M]) -> Option<[f64; M]>,
) -> Option<[f64; M]> {
    let norm = |r: &[f64; M]| r.iter().map(|v| v * v).sum::<f64>().sqrt();
    let mut r = f(&u)?;
    'iterations: for _ in 0..100 {
        if norm(&r) < 1e-12 * scale {
            break;
        }
        let mut jac = DMatrix::<f64>::zeros(M, M);
        for j in 0..M {
            let mut up = u;
            up[j] += steps[j];
            let rp = f(&up)?;
            for i in 0..M {
                jac[(i, j)] = (rp[i] - r[i]) / steps[j];
            }
        }
        let step = jac
            .lu()
            .solve(&DVector::from_iterator(M, r.iter().map(|v| -v)))?;
        let mut lambda = 1.0;
        loop {
            let mut trial = u;
            for (t, s) in trial.iter_mut().zip(step.iter()) {
                *t += lambda * s;
            }
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

impl FlappingSystem {
    /// The stroke angle at the actuator's rest, where the flexures are unstrained, rad.
    fn rest_angle(&self) -> f64 {
        self.linkage.stroke_angle(0.0).unwrap_or(0.0)
    }

    /// Small-stroke resonance at rest: `√((k + k_t T0²) / (m + I T0²)) / 2π`, Hz.
    pub fn linear_resonance(&self) -> f64 {
        let t0 = self
            .linkage
            .ratio(0.0)
            .unwrap_or(1.0 / self.linkage.lever());
        let a = &self.actuator;
        ((a.stiffness + self.flexure_stiffness * t0 * t0) / (a.mass + self.inertia * t0 * t0))
            .sqrt()
            / (2.0 * PI)
    }

    /// The projections of the θ equation on the basis `1, cos kωt, sin kωt` for the series `c`.
    fn residual(
        &self,
        c: &[f64; COEFFICIENTS],
        force: f64,
        omega: f64,
    ) -> Option<[f64; COEFFICIENTS]> {
        let a = &self.actuator;
        let structural = a.loss_factor * a.stiffness / omega;
        let rest = self.rest_angle();
        let mut r = [0.0; COEFFICIENTS];
        for i in 0..SAMPLES {
            let b = basis(2.0 * PI * i as f64 / SAMPLES as f64);
            let [angle, d1p, d2p] = series(c, &b);
            let (rate, acc) = (omega * d1p, omega * omega * d2p);
            let (x, d1, d2) = self.linkage.travel_derivatives(angle)?;
            let e = (a.mass * d1 * d1 + self.inertia) * acc
                + a.mass * d1 * d2 * rate * rate
                + a.stiffness * x * d1
                + self.flexure_stiffness * (angle - rest)
                + self.damping * rate * rate.abs()
                + structural * d1 * d1 * rate
                - force * d1 * b[2];
            r[0] += e / SAMPLES as f64;
            for (rj, bj) in r.iter_mut().zip(b.iter()).skip(1) {
                *rj += 2.0 * e * bj / SAMPLES as f64;
            }
        }
        Some(r)
    }

    fn torque_scale(&self) -> f64 {
        self.actuator.stiffness * self.linkage.lever() * self.linkage.lever()
    }

    /// The steady state at a blocked-force amplitude (N) and frequency (Hz): harmonic balance in the
    /// stroke's mean and first [`HARMONICS`] harmonics, from `start` or from rest, continuing in the
    /// force where Newton alone does not converge. A fold near resonance (two stable strokes at one
    /// force) shows as the branch continued from `start`.
    pub fn harmonic_balance(
        &self,
        force: f64,
        frequency: f64,
        start: Option<&SteadyState>,
    ) -> Result<SteadyState, ModelError> {
        let omega = 2.0 * PI * frequency;
        let solve = |f: f64, u: [f64; COEFFICIENTS]| {
            newton(u, [1e-7; COEFFICIENTS], self.torque_scale(), |c| {
                self.residual(c, f, omega)
            })
        };
        let mut at_rest = [0.0; COEFFICIENTS];
        at_rest[0] = self.rest_angle();
        let mut found = start.and_then(|s| solve(force, s.coefficients));
        for steps in [1, 8, 32] {
            if found.is_some() {
                break;
            }
            let mut u = Some(at_rest);
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

    /// The balance with the stroke (half the peak-to-peak angle) given and the force unknown: the
    /// unknowns are the mean, the first harmonic's phase and amplitude, the force and the higher
    /// harmonics, the extra equation the stroke. The force is a function of the stroke even where the
    /// stroke is not a function of the force (a fold near resonance), so this is how a required stroke
    /// is solved.
    pub fn balance_at_stroke(
        &self,
        stroke: f64,
        frequency: f64,
        start: Option<&SteadyState>,
    ) -> Result<SteadyState, ModelError> {
        let omega = 2.0 * PI * frequency;
        // u = [θ0, φ, F, A1, a2, b2, …]; θ - θ0 = A1 sin(ωt - φ) + higher harmonics.
        let coefficients = |u: &[f64; AT_STROKE]| {
            let mut c = [0.0; COEFFICIENTS];
            c[0] = u[0];
            c[1] = -u[3] * u[1].sin();
            c[2] = u[3] * u[1].cos();
            c[3..].copy_from_slice(&u[4..]);
            c
        };
        let scale = self.torque_scale();
        let guess = match start {
            Some(s) => {
                let c = &s.coefficients;
                let mut u = [0.0; AT_STROKE];
                u[0] = c[0];
                u[1] = (-c[1]).atan2(c[2]);
                u[2] = s.force;
                u[3] = c[1].hypot(c[2]);
                u[4..].copy_from_slice(&c[3..]);
                u
            }
            None => {
                let mut u = [0.0; AT_STROKE];
                u[0] = self.rest_angle();
                u[1] = 0.5 * PI;
                u[2] = self.actuator.stiffness * stroke * self.linkage.lever();
                u[3] = stroke;
                u
            }
        };
        let mut steps = [1e-7; AT_STROKE];
        steps[2] = 1e-7 * scale / self.linkage.lever();
        let u = newton(guess, steps, scale, |u| {
            let c = coefficients(u);
            let r = self.residual(&c, u[2], omega)?;
            let (lo, hi) = extremes(&c);
            let mut out = [0.0; AT_STROKE];
            out[..COEFFICIENTS].copy_from_slice(&r);
            // The stroke's equation in torque units, so that one tolerance serves all.
            out[COEFFICIENTS] = scale * (0.5 * (hi - lo) - stroke);
            Some(out)
        })
        .ok_or(ModelError::OutOfRange {
            name: "stroke",
            value: stroke,
            range: "within the linkage's reach",
        })?;
        let (mut force, mut c) = (u[2], coefficients(&u));
        if force < 0.0 {
            // A negative force is the same motion half a period on: harmonic k changes sign when k is
            // odd.
            force = -force;
            for k in (1..=HARMONICS).step_by(2) {
                c[2 * k - 1] = -c[2 * k - 1];
                c[2 * k] = -c[2 * k];
            }
        }
        self.evaluate(force, frequency, c)
    }

    /// The reported quantities of the series `c`.
    fn evaluate(
        &self,
        force: f64,
        frequency: f64,
        c: [f64; COEFFICIENTS],
    ) -> Result<SteadyState, ModelError> {
        let omega = 2.0 * PI * frequency;
        let n = 4 * SAMPLES;
        let (mut lo, mut hi, mut power, mut load) = (f64::INFINITY, f64::NEG_INFINITY, 0.0, 0.0f64);
        for i in 0..n {
            let b = basis(2.0 * PI * i as f64 / n as f64);
            let [angle, d1p, _] = series(&c, &b);
            let rate = omega * d1p;
            let x = self.linkage.travel(angle).ok_or(ModelError::OutOfRange {
                name: "stroke",
                value: angle,
                range: "within the linkage's reach",
            })?;
            lo = lo.min(x);
            hi = hi.max(x);
            power += self.damping * rate.abs().powi(3) / n as f64;
            load = load.max((force * b[2] - self.actuator.stiffness * x).abs());
        }
        let (angle_lo, angle_hi) = extremes(&c);
        Ok(SteadyState {
            frequency,
            force,
            mean_angle: c[0],
            stroke_amplitude: 0.5 * (angle_hi - angle_lo),
            // First harmonic A1 sin(ωt - φ): c1 = -A1 sin φ, c2 = A1 cos φ.
            phase: (-c[1]).atan2(c[2]),
            displacement_amplitude: 0.5 * (hi - lo),
            aero_power: power,
            peak_tip_load: load,
            coefficients: c,
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
            let (tr, slope) = self.linkage.ratio_and_rate(angle)?;
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

    /// [`Self::balance_at_stroke`] continued from a small stroke in eight steps, so that Newton stays on
    /// the branch that starts at rest.
    fn continued_to_stroke(&self, stroke: f64, frequency: f64) -> Option<SteadyState> {
        let mut start: Option<SteadyState> = None;
        for i in 1..=8 {
            start = Some(
                self.balance_at_stroke(stroke * i as f64 / 8.0, frequency, start.as_ref())
                    .ok()?,
            );
        }
        start
    }

    /// The resonance at a stroke amplitude (rad), Hz: the frequency at which the steady stroke of that
    /// amplitude is 90° behind the drive (docs/physics.md §14, "Resonance at a stroke"). At a small stroke it is
    /// [`Self::linear_resonance`]; the linkage's ratio changes with the angle, so the system's stiffness
    /// and inertia seen at the tip change with the stroke, and so does the resonance. At a fixed
    /// amplitude the phase is one function of the frequency, rising through 90° once. The search starts
    /// at `near` (a frequency where the stroke has a steady state: the flapping frequency), walks in
    /// steps of 5 % towards the side the phase says, each step continued from the last, until the phase
    /// crosses 90° (within a factor of 4 of the small-stroke resonance), then bisects.
    pub fn resonance_at_stroke(&self, stroke: f64, near: f64) -> Result<f64, ModelError> {
        let unreached = || ModelError::OutOfRange {
            name: "stroke",
            value: stroke,
            range: "a steady stroke within the linkage's reach up to its resonance",
        };
        let state = |f: f64, from: &SteadyState| {
            self.balance_at_stroke(stroke, f, Some(from))
                .ok()
                .or_else(|| self.continued_to_stroke(stroke, f))
        };
        let behind = |s: &SteadyState| s.phase > 0.5 * PI;
        let f0 = self.linear_resonance();
        let mut lo = self
            .continued_to_stroke(stroke, near)
            .ok_or_else(unreached)?;
        let above = behind(&lo);
        let step = if above { 1.0 / 1.05 } else { 1.05 };
        let mut hi = loop {
            let next = lo.frequency * step;
            if !(0.25 * f0..=4.0 * f0).contains(&next) {
                return Err(unreached());
            }
            let s = state(next, &lo).ok_or_else(unreached)?;
            if behind(&s) != above {
                break s;
            }
            lo = s;
        };
        if above {
            std::mem::swap(&mut lo, &mut hi);
        }
        // 40 halvings of a 5 % bracket: far below the balance's own tolerance.
        for _ in 0..40 {
            let mid = state(0.5 * (lo.frequency + hi.frequency), &lo).ok_or_else(unreached)?;
            if behind(&mid) {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        Ok(0.5 * (lo.frequency + hi.frequency))
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
        let start = self.continued_to_stroke(stroke, frequency);
        match start {
            Some(s) if s.force <= force_limit => Ok(s),
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
                Err(Unreached {
                    best: best.map(Box::new),
                })
            }
        }
    }
}

/// The required stroke is out of reach: the best steady state found within the force limit.
#[derive(Debug, Clone, PartialEq)]
pub struct Unreached {
    /// The largest stroke reached, if any steady state was found (boxed: a steady state carries its
    /// series).
    pub best: Option<Box<SteadyState>>,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::DEFAULT_LOSS_FACTOR;
    use crate::transmission::Linkage;

    /// A hawk-moth-sized system (the numbers of examples/drive-hawkmoth.toml, rounded).
    fn system() -> FlappingSystem {
        FlappingSystem {
            actuator: LumpedActuator {
                stiffness: 300.0,
                mass: 40e-6,
                loss_factor: DEFAULT_LOSS_FACTOR,
            },
            linkage: Linkage::solve(0.4e-3, -PI / 3.0, PI / 3.0, 3.0)
                .unwrap()
                .into(),
            flexure_stiffness: 2e-5,
            inertia: 1.0e-9,
            damping: 3e-10,
        }
    }

    #[test]
    fn harmonic_balance_agrees_with_time_integration() {
        // The stroke amplitudes must agree within 2 % at, below and above resonance; at strokes of
        // 28-52°, where the linkage's ratio T = dθ/dx has risen (the balance in θ, the integration in
        // x), three harmonics are within 0.05 %, held here to 0.2 %.
        let s = system();
        let f_r = s.linear_resonance();
        for (ratio, force) in [(0.5, 0.07), (0.9, 0.04), (1.0, 0.08), (1.3, 0.08)] {
            let hb = s.harmonic_balance(force, ratio * f_r, None).unwrap();
            let ti = s.integrate(force, ratio * f_r, 80).unwrap();
            let rel = hb.stroke_amplitude / ti - 1.0;
            assert!(
                rel.abs() < 0.002,
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
    fn the_resonance_at_a_small_stroke_is_the_linear_one() {
        // A linear oscillator with viscous (here structural, η k / ω) and quadratic drag is 90° behind
        // its drive at ω_n = √(k_eff / m_eff) whatever the damping: the drag is in phase with the
        // velocity.
        let s = system();
        let f_n = s.linear_resonance();
        let small = s
            .resonance_at_stroke(0.2f64.to_radians(), 0.8 * f_n)
            .unwrap();
        assert!((small / f_n - 1.0).abs() < 1e-3, "{small} vs {f_n}");
        // And the phase there is 90° to the balance's tolerance.
        let at = s
            .balance_at_stroke(0.2f64.to_radians(), small, None)
            .unwrap();
        assert!((at.phase - 0.5 * PI).abs() < 1e-6, "{}", at.phase);
    }

    #[test]
    fn the_resonance_moves_with_the_stroke_and_the_phase_there_is_90_degrees() {
        // The slider-crank's ratio dθ/dx rises away from the middle of the stroke, so the wing's
        // inertia seen at the tip (I T²) grows with the stroke and the resonance falls.
        let s = system();
        let stroke = 50f64.to_radians();
        let f_r = s
            .resonance_at_stroke(stroke, 0.9 * s.linear_resonance())
            .unwrap();
        assert!(f_r < 0.97 * s.linear_resonance(), "{f_r}");
        let at = s.continued_to_stroke(stroke, f_r).unwrap();
        assert!((at.phase.to_degrees() - 90.0).abs() < 1e-6, "{}", at.phase);
        // Below it the stroke lags by less, above it by more.
        assert!(s.continued_to_stroke(stroke, 0.95 * f_r).unwrap().phase < 0.5 * PI);
        assert!(s.continued_to_stroke(stroke, 1.05 * f_r).unwrap().phase > 0.5 * PI);
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
