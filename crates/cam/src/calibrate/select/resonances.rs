//! The measured first resonances of an actuation stage and their log residuals, each actuator's `f1`
//! kept for the models a fit asks for again: many of a fit's evaluations move the drive alone (a
//! Jacobian column of d31 or a dead length, a fold's refit of them), and those leave every `f1` as it
//! was.

use crate::calibrate::csv::Dataset;
use actuator_model::effects::StackBasis;
use actuator_model::nearby_modes::{ModeCache, NearbyModes};
use actuator_model::{EffectModel, Planform};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{LazyLock, Mutex};

/// The cells the resonances' beams are solved in, one for every calibration in the process: a cell's
/// forms are a function of the cell alone ([`ModeCache`]), so fits, stages and data sets share them
/// without any value depending on which asked first.
static CELLS: LazyLock<ModeCache> = LazyLock::new(ModeCache::default);

/// One actuator's measured first resonance.
#[derive(Debug, Clone, Copy)]
pub(crate) struct ResonanceObs {
    pub(crate) group: usize,
    /// The actuator's first row.
    pub(crate) row: usize,
    /// Its stack basis under the stage's base model (any field: `k = F_b / δ` does not depend on it).
    pub(crate) basis: StackBasis,
    pub(crate) ln_frequency: f64,
}

/// How many of the latest models each actuator keeps its `f1` for: a Jacobian's base point and its
/// columns that move the beam, for the two fits that may run at once on the same data.
const KEPT: usize = 8;

/// One actuator's modes: the beams solved near the ones asked for, and the latest models asked for
/// with the log residual each gave (before the weight; NaN where the model could not be evaluated), in
/// a ring whose oldest entry the next model takes.
#[derive(Debug, Default)]
struct Solved {
    modes: NearbyModes,
    recent: Vec<Kept>,
    /// The entry the next model takes once the ring is full.
    next: usize,
}

/// A model and basis asked for, and the log residual they gave.
#[derive(Debug)]
struct Kept {
    digest: u64,
    model: EffectModel,
    basis: StackBasis,
    residual: f64,
}

/// A model as the resonances are asked for it: with a digest of the values its beam depends on, which
/// [`EffectModel::same_beam`] leaves to compare only where the digests agree.
pub(crate) struct BeamModel<'m> {
    model: &'m EffectModel,
    digest: u64,
}

impl<'m> BeamModel<'m> {
    /// `model` with its digest ([`EffectModel::beam_digest`]).
    pub(crate) fn of(model: &'m EffectModel) -> Self {
        BeamModel {
            model,
            digest: model.beam_digest(),
        }
    }
}

/// True when two bases give the same beam and tip stiffness: the same compliances and planform, to the
/// bit ([`EffectModel::beam`] and [`EffectModel::tip_stiffness`] read nothing else of a basis; the
/// free curvature and the field are the drive's).
fn same_stiffness(a: &StackBasis, b: &StackBasis) -> bool {
    // Every field named, so that a field added to a basis or a planform is classed here.
    let StackBasis {
        free_curvature: _,
        beam_compliance,
        extension_compliance,
        field: _,
        planform,
    } = *a;
    let Planform {
        length,
        extension_ratio,
        base_width,
        width_ratio,
        base_tab,
    } = planform;
    let q = &b.planform;
    [
        (beam_compliance, b.beam_compliance),
        (extension_compliance, b.extension_compliance),
        (length, q.length),
        (extension_ratio, q.extension_ratio),
        (base_width, q.base_width),
        (width_ratio, q.width_ratio),
        (base_tab, q.base_tab),
    ]
    .iter()
    .all(|(x, y)| x.to_bits() == y.to_bits())
}

impl Solved {
    /// The log residual kept for a model with the same beam and tip stiffness as `asked` on `basis`
    /// ([`EffectModel::same_beam`]), if one is kept.
    fn kept(&self, asked: &BeamModel, basis: &StackBasis) -> Option<f64> {
        self.recent
            .iter()
            .find(|k| {
                k.digest == asked.digest
                    && same_stiffness(&k.basis, basis)
                    && k.model.same_beam(asked.model)
            })
            .map(|k| k.residual)
    }

    /// Keeps `residual` for `asked` on `basis`, in place of the oldest past [`KEPT`].
    fn keep(&mut self, asked: &BeamModel, basis: &StackBasis, residual: f64) {
        if self.recent.len() < KEPT {
            self.recent.push(Kept {
                digest: asked.digest,
                model: asked.model.clone(),
                basis: *basis,
                residual,
            });
            return;
        }
        let kept = &mut self.recent[self.next];
        kept.digest = asked.digest;
        kept.model.clone_from(asked.model);
        kept.basis = *basis;
        kept.residual = residual;
        self.next = (self.next + 1) % KEPT;
    }
}

/// The measured resonances with the beams each was solved for: a fit moves its parameters a little at
/// a time, and the mode of a beam near a solved one follows from the solved one's shapes
/// ([`NearbyModes`], docs/physics.md §11.6), whatever order the models fitted in parallel on the same
/// data ask in. A model whose beam, mass and tip stiffness are those of one asked for lately gets that
/// one's `f1` back unsolved; as each `f1` is a function of those alone, the residuals are the same bits
/// whatever was asked before.
#[derive(Debug)]
pub(crate) struct Resonances {
    pub(crate) obs: Vec<ResonanceObs>,
    /// Factor on every log residual, as f64 bits: 1 while the models are compared (a resonance counts
    /// as one more deflection or force reading), σ_actuation / σ_f1 while the chosen model is estimated
    /// (`resonance_weight.rs`). Set between fits, on the data the fitter already holds.
    weight: AtomicU64,
    /// Each actuator's modes, one set per thread of the pool (`slots` per actuator, actuator-major):
    /// the fits that run at once ask for the actuators in the same order, and one shared set per
    /// actuator had both threads passing its lock back and forth on every `f1`. A set's values are
    /// functions of the beam alone, so which thread's set answers makes no difference to them.
    solved: Vec<Own<Mutex<Solved>>>,
    slots: usize,
}

/// A value on cache lines of its own: the resonances of neighbouring actuators, locked by different
/// threads, do not share one.
#[derive(Debug, Default)]
#[repr(align(128))]
struct Own<T>(T);

impl Default for Resonances {
    fn default() -> Self {
        Resonances::new(Vec::new())
    }
}

impl Clone for Resonances {
    fn clone(&self) -> Self {
        let copy = Resonances::new(self.obs.clone());
        copy.set_weight(self.weight());
        copy
    }
}

impl Resonances {
    pub(crate) fn new(obs: Vec<ResonanceObs>) -> Self {
        let slots = rayon::current_num_threads().max(1);
        let solved = (0..obs.len() * slots).map(|_| Own::default()).collect();
        Resonances {
            obs,
            weight: AtomicU64::new(1.0f64.to_bits()),
            solved,
            slots,
        }
    }

    /// The factor on every log residual.
    pub(crate) fn weight(&self) -> f64 {
        f64::from_bits(self.weight.load(Ordering::Relaxed))
    }

    /// Sets the factor on every log residual (between fits).
    pub(crate) fn set_weight(&self, weight: f64) {
        self.weight.store(weight.to_bits(), Ordering::Relaxed);
    }

    /// The same resonances with each basis replaced (the joint data's bases at the carried values), given
    /// each resonance's index and observation.
    pub(crate) fn with_bases(&self, basis: impl Fn(usize, &ResonanceObs) -> StackBasis) -> Self {
        let obs = self
            .obs
            .iter()
            .enumerate()
            .map(|(k, o)| ResonanceObs {
                basis: basis(k, o),
                ..*o
            })
            .collect();
        let copy = Resonances::new(obs);
        copy.set_weight(self.weight());
        copy
    }

    pub(crate) fn len(&self) -> usize {
        self.obs.len()
    }

    /// Actuator `k`'s modes as the calling thread keeps them (a thread outside the pool shares the
    /// first pool thread's).
    fn own_set(&self, k: usize) -> &Mutex<Solved> {
        let slot = rayon::current_thread_index().map_or(0, |i| i % self.slots);
        &self.solved[k * self.slots + slot].0
    }

    /// Log residual of resonance `k` under the model `asked` on `basis`, times [`Resonances::weight`]: measured
    /// over the model's `f1` as [`EffectModel::modes`] computes it, on the coarse mesh
    /// (`ActuatorBeam::solve_coarse`, within 1e-4 of `predict`'s, a hundredth of a 1 % reading) to
    /// [`actuator_model::nearby_modes::TOLERANCE`]; NaN where the model cannot evaluate it.
    pub(crate) fn residual(
        &self,
        data: &Dataset,
        k: usize,
        asked: &BeamModel,
        basis: &StackBasis,
    ) -> f64 {
        // Held through the solve: the set is the calling thread's own (a thread outside the pool
        // shares the first pool thread's).
        let mut solved = match self.own_set(k).lock() {
            Ok(solved) => solved,
            Err(poisoned) => poisoned.into_inner(),
        };
        if let Some(r) = solved.kept(asked, basis) {
            return r * self.weight();
        }
        let o = &self.obs[k];
        let model = asked.model;
        let beam = model
            .mass(&data.rows[o.row].actuator())
            .map(|mass| (model.beam(basis, &mass), model.tip_stiffness(basis)));
        let residual = match beam {
            Ok((beam, stiffness)) => match solved.modes.modal(&CELLS, &beam) {
                Ok(mode) => o.ln_frequency - mode.frequency_at(stiffness).ln(),
                Err(_) => f64::NAN,
            },
            Err(_) => f64::NAN,
        };
        solved.keep(asked, basis, residual);
        residual * self.weight()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::calibrate::csv::parse;
    use actuator_model::primitives::{Applied, Primitive};

    /// The residuals a fit asks for in turn (a model, its d31 and dead-length columns, a clamp step, a
    /// drive-alone value the mass refuses, the first model again) are those of resonances asked for
    /// nothing before, to the bit, and each kept one is found again.
    #[test]
    fn kept_resonances_are_those_solved_afresh() {
        let data = parse(
            "id,l_tot_mm,l_r,w0_mm,w_r,t_p_mm,layup,voltage_V,mass_mg,free_deflection_mm,blocked_force_N,resonance_Hz\n\
             a,30,0.6,8,1.2,0.191,0/90/0/90/0,150,60,0.3,0.05,450\n\
             b,22,0,6,0.8,0.267,0/90/0,100,40,0.1,0.08,900\n",
        )
        .expect("valid rows");
        let base = EffectModel::default();
        let obs: Vec<ResonanceObs> = data
            .groups
            .iter()
            .enumerate()
            .map(|(group, rows)| {
                let row = rows[0];
                ResonanceObs {
                    group,
                    row,
                    basis: base.basis(&data.rows[row].actuator()).expect("a stack"),
                    ln_frequency: data.rows[row].resonance.expect("an f1").ln(),
                }
            })
            .collect();
        let model = |d31: f64, margin: f64, clamp: f64| {
            let mut m = EffectModel::default();
            m.effects.d31_scale = d31;
            m.primitives = vec![
                Applied {
                    primitive: Primitive::ElectrodeMargin,
                    value: margin,
                },
                Applied {
                    primitive: Primitive::ClampCompliance,
                    value: clamp,
                },
            ];
            m
        };
        let asked = [
            model(1.0, 1e-3, 0.2),
            model(0.8, 1e-3, 0.2),
            model(1.0, 2e-3, 0.2),
            model(1.0, 1e-3, 0.3),
            model(1.0, f64::NAN, 0.2),
            model(1.0, 1e-3, 0.2),
        ];
        let kept = Resonances::new(obs.clone());
        kept.set_weight(1.5);
        for m in &asked {
            for (k, o) in obs.iter().enumerate() {
                let afresh = Resonances::new(obs.clone());
                afresh.set_weight(1.5);
                let want = afresh.residual(&data, k, &BeamModel::of(m), &o.basis);
                let got = kept.residual(&data, k, &BeamModel::of(m), &o.basis);
                assert_eq!(got.to_bits(), want.to_bits(), "{m:?} {k}");
            }
        }
        for (k, o) in obs.iter().enumerate() {
            let solved = kept.own_set(k).lock().expect("not poisoned");
            // The first model's d31 and margin columns share its entry; the clamp step and the refused
            // margin take their own.
            assert_eq!(solved.recent.len(), 3);
            assert!(solved.kept(&BeamModel::of(&asked[1]), &o.basis).is_some());
            assert!(solved
                .kept(&BeamModel::of(&asked[4]), &o.basis)
                .unwrap()
                .is_nan());
        }
    }
}
