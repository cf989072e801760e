//! The energy an actuator needs to flap a wing through a linkage of a given shape, with the linkage's
//! scale chosen for it (docs/physics.md §17).
//!
//! A linkage of fixed shape (coupler ratio and end angles) scales with its crank `L3`: `x(θ) = L3 h(θ)`.
//! In the equation of §14 the actuator then enters only through the reflected stiffness `v = k L3²`, the
//! reflected mass `m L3² = v / ω1²` and the torque amplitude `τ = F L3`; its structural loss is `η v / ω`.
//! So for one wing, frequency and stroke the torque needed is a function `τ(v; ω1)`, and an actuator of
//! stiffness `k` needs `F = τ(v) √k / √v` at the crank `L3 = √(v/k)`. The best crank asks for the least
//! force, `F ≥ √k G(ω1)` with `G(ω1) = min_v τ(v; ω1) / √v`. With `k = F/δ` this is
//!
//! `U = ½ F δ ≥ ½ G(ω1)²`:
//!
//! the thesis' "energy is what matters" (§2.3.4) made exact for a dynamic drive, with the energy needed
//! depending on the actuator's own resonance `ω1` and on nothing else of it.

use crate::dynamics::LumpedActuator;
use crate::error::ModelError;
use crate::flapping::{FlappingSystem, SteadyState};
use crate::transmission::Linkage;
use std::f64::consts::PI;

/// Travel of the reference linkage the torques are computed through, m (any value: the result scales).
const REFERENCE_TRAVEL: f64 = 1e-3;

/// Points of the coarse scan of `v` (log-spaced over four decades about the wing's own stiffness).
const SCAN: usize = 25;

/// A wing, its flexures and the shape of its linkage, at a flapping frequency and stroke (SI).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WingLoad {
    /// Lower and upper end angle the linkage is solved for, rad.
    pub end_angles: (f64, f64),
    /// Coupler over crank, `L1 / L3`.
    pub coupler_ratio: f64,
    /// Flexure stiffness about the hinge, N·m/rad.
    pub flexure_stiffness: f64,
    /// Wing and link inertia about the hinge, kg·m².
    pub inertia: f64,
    /// Wing drag coefficient `K`, N·m·s².
    pub damping: f64,
    /// Flapping frequency, Hz.
    pub frequency: f64,
    /// Required stroke (half the peak-to-peak angle), rad.
    pub stroke: f64,
    /// Structural loss factor of the actuator.
    pub loss_factor: f64,
}

/// What the wing asks of an actuator whose bare resonance is given (SI).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Requirement {
    /// The actuator's first natural frequency, Hz.
    pub actuator_frequency: f64,
    /// The least energy `½ F_b δ` that holds the stroke, `½ G²`, J.
    pub energy: f64,
    /// The best reflected stiffness `v = k L3²`, N·m/rad.
    pub reflected_stiffness: f64,
    /// The small-stroke resonance of actuator + linkage + wing at that `v`, Hz.
    pub resonance: f64,
}

impl WingLoad {
    /// The reference linkage (crank `L3_ref`) of this shape.
    pub fn reference_linkage(&self) -> Result<Linkage, ModelError> {
        Linkage::solve(
            REFERENCE_TRAVEL,
            self.end_angles.0,
            self.end_angles.1,
            self.coupler_ratio,
        )
    }

    /// The one-sided actuator travel (m) of this shape's linkage whose crank makes the reflected
    /// stiffness of an actuator of stiffness `k` (N/m) equal to `v` (N·m/rad): `L3 = √(v/k)`, the travel
    /// linear in `L3` (§12.3).
    pub fn travel_for(&self, stiffness: f64, reflected_stiffness: f64) -> Result<f64, ModelError> {
        let reference = self.reference_linkage()?;
        Ok(REFERENCE_TRAVEL * (reflected_stiffness / stiffness).sqrt() / reference.crank)
    }

    fn system(&self, reference: &Linkage, v: f64, omega1: f64) -> FlappingSystem {
        let stiffness = v / (reference.crank * reference.crank);
        FlappingSystem {
            actuator: LumpedActuator {
                stiffness,
                mass: stiffness / (omega1 * omega1),
                loss_factor: self.loss_factor,
            },
            linkage: (*reference).into(),
            flexure_stiffness: self.flexure_stiffness,
            inertia: self.inertia,
            damping: self.damping,
        }
    }

    /// `τ(v)/√v` at `v`, continuing from `start` where given (`None` where no steady stroke holds).
    fn cost(
        &self,
        reference: &Linkage,
        v: f64,
        omega1: f64,
        start: Option<&SteadyState>,
    ) -> Option<(f64, SteadyState)> {
        let system = self.system(reference, v, omega1);
        let state = start
            .and_then(|s| {
                system
                    .balance_at_stroke(self.stroke, self.frequency, Some(s))
                    .ok()
            })
            .filter(|s| (s.stroke_amplitude / self.stroke - 1.0).abs() < 1e-6)
            .or_else(|| {
                // Continued from a small stroke, as `force_for_stroke` does, without its search for
                // the best stroke when the continuation fails: here a failure only means no stroke.
                let mut state: Option<SteadyState> = None;
                for i in 1..=8 {
                    let part = self.stroke * i as f64 / 8.0;
                    state = Some(
                        system
                            .balance_at_stroke(part, self.frequency, state.as_ref())
                            .ok()?,
                    );
                }
                state
            })?;
        Some((state.force * reference.crank / v.sqrt(), state))
    }

    /// The requirement on an actuator whose bare first resonance is `actuator_frequency` (Hz): a
    /// log-spaced scan of `v` over four decades about `I ω² + k_t`, then golden-section search in `log v`
    /// about the scan's best point. `Err` when no `v` holds the stroke.
    pub fn requirement(&self, actuator_frequency: f64) -> Result<Requirement, ModelError> {
        let reference = self.reference_linkage()?;
        let omega1 = 2.0 * PI * actuator_frequency;
        let omega = 2.0 * PI * self.frequency;
        let centre = (self.inertia * omega * omega + self.flexure_stiffness).ln();
        let log_v = |i: usize| centre + (i as f64 / (SCAN - 1) as f64 * 4.0 - 2.0) * 10f64.ln();
        let mut start: Option<SteadyState> = None;
        let mut best: Option<(usize, f64, SteadyState)> = None;
        for i in 0..SCAN {
            match self.cost(&reference, log_v(i).exp(), omega1, start.as_ref()) {
                Some((c, s)) => {
                    start = Some(s);
                    if best.is_none_or(|(_, b, _)| c < b) {
                        best = Some((i, c, s));
                    }
                }
                None => start = None,
            }
        }
        let (i, _, near) = best.ok_or(ModelError::OutOfRange {
            name: "stroke",
            value: self.stroke,
            range: "a steady stroke through the linkage at some crank length",
        })?;
        let (mut a, mut b) = (log_v(i.saturating_sub(1)), log_v((i + 1).min(SCAN - 1)));
        let at = |x: f64| {
            self.cost(&reference, x.exp(), omega1, Some(&near))
                .map_or(f64::INFINITY, |(c, _)| c)
        };
        let golden = (5f64.sqrt() - 1.0) / 2.0;
        let (mut x1, mut x2) = (b - golden * (b - a), a + golden * (b - a));
        let (mut f1, mut f2) = (at(x1), at(x2));
        while b - a > 1e-3 {
            if f1 <= f2 {
                (b, x2, f2) = (x2, x1, f1);
                x1 = b - golden * (b - a);
                f1 = at(x1);
            } else {
                (a, x1, f1) = (x1, x2, f2);
                x2 = a + golden * (b - a);
                f2 = at(x2);
            }
        }
        let (v, g) = if f1 <= f2 {
            (x1.exp(), f1)
        } else {
            (x2.exp(), f2)
        };
        // The scan's own best point when the bracket's interior holds no stroke.
        let (v, g) = if g.is_finite() {
            (v, g)
        } else {
            let x = log_v(i);
            (x.exp(), at(x))
        };
        if !g.is_finite() {
            return Err(ModelError::OutOfRange {
                name: "stroke",
                value: self.stroke,
                range: "a steady stroke through the linkage at some crank length",
            });
        }
        Ok(Requirement {
            actuator_frequency,
            energy: 0.5 * g * g,
            reflected_stiffness: v,
            resonance: self.system(&reference, v, omega1).linear_resonance(),
        })
    }
}

impl WingLoad {
    /// The least energy `½ (τ(v)/√v)²` that holds the stroke with the system's small-stroke resonance
    /// at least `resonance` (Hz), for an actuator of bare resonance `actuator_frequency` whose best crank
    /// gives `optimum` (docs/physics.md §17.4). The resonance rises with `v` (the actuator's stiffness
    /// over its mass seen through the crank, from the wing's `√(k_t/I)` towards the actuator's own
    /// `ω1`), so above the optimum's resonance the cheapest crank is the one that puts it at
    /// `resonance` exactly: a stiffer actuator coupling than the energy optimum, bought with energy.
    /// `None` when no crank reaches that resonance or holds the stroke there.
    pub fn energy_at_resonance(&self, optimum: &Requirement, resonance: f64) -> Option<f64> {
        if optimum.resonance >= resonance {
            return Some(optimum.energy);
        }
        let reference = self.reference_linkage().ok()?;
        let omega1 = 2.0 * PI * optimum.actuator_frequency;
        let at = |log_v: f64| {
            self.system(&reference, log_v.exp(), omega1)
                .linear_resonance()
        };
        let (mut a, mut b) = (
            optimum.reflected_stiffness.ln(),
            optimum.reflected_stiffness.ln(),
        );
        // Bracket: the resonance approaches the actuator's own as v grows.
        for _ in 0..40 {
            if at(b) >= resonance {
                break;
            }
            a = b;
            b += 10f64.ln();
        }
        if at(b) < resonance {
            return None;
        }
        while b - a > 1e-6 {
            let mid = 0.5 * (a + b);
            if at(mid) >= resonance {
                b = mid;
            } else {
                a = mid;
            }
        }
        let (g, _) = self.cost(&reference, b.exp(), omega1, None)?;
        Some(0.5 * g * g)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::DEFAULT_LOSS_FACTOR;

    /// The hawk-moth-sized wing of the flapping tests (examples/drive-hawkmoth.toml, rounded).
    fn hawk_moth() -> WingLoad {
        WingLoad {
            end_angles: (-PI / 3.0, PI / 3.0),
            coupler_ratio: 4.0,
            flexure_stiffness: 250e-6,
            inertia: 28e-9,
            damping: 20e-9,
            frequency: 25.0,
            stroke: PI / 3.0,
            loss_factor: DEFAULT_LOSS_FACTOR,
        }
    }

    #[test]
    fn small_strokes_without_drag_meet_the_closed_form() {
        // Linear, no drag: τ = Θ |a v - b + i η v| with a = 1 - ω²/ω1², b = I ω² - k_t, so
        // τ²/v = Θ² ((a² + η²) v - 2ab + b²/v), least at v* = b / √(a² + η²):
        // G² = 2 Θ² b (√(a² + η²) - a) (docs/physics.md §17).
        let stroke = 0.2f64.to_radians();
        let load = WingLoad {
            end_angles: (-stroke, stroke),
            damping: 0.0,
            stroke,
            ..hawk_moth()
        };
        // A heavy, a middling and a light actuator (a from 0.61 to 1).
        for f1 in [40.0, 90.0, 1000.0] {
            let got = load.requirement(f1).unwrap();
            let (w, w1) = (2.0 * PI * load.frequency, 2.0 * PI * f1);
            let a = 1.0 - w * w / (w1 * w1);
            let b = load.inertia * w * w - load.flexure_stiffness;
            let eta = load.loss_factor;
            let g2 = 2.0 * stroke * stroke * b * ((a * a + eta * eta).sqrt() - a);
            assert!(
                (got.energy / (0.5 * g2) - 1.0).abs() < 1e-3,
                "f1 {f1}: {} vs {}",
                got.energy,
                0.5 * g2
            );
            let v = b / (a * a + eta * eta).sqrt();
            assert!(
                (got.reflected_stiffness / v - 1.0).abs() < 0.02,
                "{got:?} {v}"
            );
            // a v* = b a / √(a² + η²) ≈ b: the drive frequency is the resonance to O(η²).
            assert!(
                (got.resonance / load.frequency - 1.0).abs() < 1e-2,
                "{got:?}"
            );
        }
    }

    #[test]
    fn the_requirement_holds_for_a_real_actuator_through_its_own_crank() {
        // The scaling argument: an actuator of any stiffness, at the travel the requirement names,
        // needs exactly F = √(2 U k) at the stroke, and more through a longer or shorter crank.
        let load = hawk_moth();
        let f1 = 400.0;
        let req = load.requirement(f1).unwrap();
        for k in [300.0, 1200.0, 5000.0] {
            let mass = k / (2.0 * PI * f1).powi(2);
            let force_through = |travel: f64| {
                let system = FlappingSystem {
                    actuator: LumpedActuator {
                        stiffness: k,
                        mass,
                        loss_factor: load.loss_factor,
                    },
                    linkage: Linkage::solve(travel, -PI / 3.0, PI / 3.0, 4.0)
                        .unwrap()
                        .into(),
                    flexure_stiffness: load.flexure_stiffness,
                    inertia: load.inertia,
                    damping: load.damping,
                };
                system
                    .force_for_stroke(load.stroke, load.frequency, f64::INFINITY)
                    .unwrap()
                    .force
            };
            let travel = load.travel_for(k, req.reflected_stiffness).unwrap();
            let force = force_through(travel);
            let want = (2.0 * req.energy * k).sqrt();
            assert!(
                (force / want - 1.0).abs() < 1e-6,
                "k {k}: {force} vs {want}"
            );
            for other in [0.8, 1.25] {
                assert!(
                    force_through(travel * other) > force,
                    "k {k} travel x{other}"
                );
            }
        }
    }
}
