//! The data each stage fits: log residuals of the measured masses (mass stage) and of the measured
//! deflections and forces (actuation stage), with whole actuators maskable for cross-validation.

use crate::calibrate::csv::Dataset;
use actuator_model::effects::StackBasis;
use actuator_model::EffectModel;

/// Residuals of one stage under given effects, optionally on a subset of actuators. A model the physics
/// cannot evaluate (a declared primitive driven out of range) gives NaN residuals, which the fit refuses.
pub(crate) trait StageData: Sync {
    fn residuals(&self, effects: &EffectModel, keep: Option<&[bool]>, out: &mut Vec<f64>);
    fn groups(&self) -> usize;
    /// The residuals cross-validation scores on held-out actuators: all of them, unless the stage fits
    /// data it does not predict (the joint data score deflection and force only).
    fn held_out(&self, effects: &EffectModel, keep: Option<&[bool]>, out: &mut Vec<f64>) {
        self.residuals(effects, keep, out);
    }
    /// How many leading residuals are the stage's scored outputs (None: all): the information criteria
    /// and intervals count them; the rest (the weighted masses of the joint data) steer the fit only.
    fn scored_rows(&self) -> Option<usize> {
        None
    }
    /// The deflections and forces with the carried mass parameters held at their values in `effects`,
    /// each stack solved (or interpolated) once (None: nothing is carried; use these data).
    fn held_at(&self, effects: &EffectModel) -> Option<ActuationData<'_>> {
        let _ = effects;
        None
    }
}

pub(crate) struct MassData<'a> {
    pub(crate) data: &'a Dataset,
    /// (group, row, ln measured mass)
    pub(crate) obs: Vec<(usize, usize, f64)>,
}

impl StageData for MassData<'_> {
    fn residuals(&self, effects: &EffectModel, keep: Option<&[bool]>, out: &mut Vec<f64>) {
        out.clear();
        for &(g, row, ln_m) in &self.obs {
            if keep.is_some_and(|k| !k[g]) {
                continue;
            }
            let m = effects
                .mass(&self.data.rows[row].actuator())
                .map_or(f64::NAN, |m| m.total());
            out.push(ln_m - m.ln());
        }
    }
    fn groups(&self) -> usize {
        self.data.actuators()
    }
}

/// One row of the actuation stage.
#[derive(Debug, Clone, Copy)]
pub(crate) struct ActuationObs {
    pub(crate) group: usize,
    pub(crate) row: usize,
    pub(crate) basis: StackBasis,
    pub(crate) ln_delta: Option<f64>,
    pub(crate) ln_force: Option<f64>,
}

pub(crate) struct ActuationData<'a> {
    pub(crate) data: &'a Dataset,
    pub(crate) obs: Vec<ActuationObs>,
    pub(crate) groups: usize,
    /// How many declared primitives the bases were solved with (the frozen mass stage's): a model
    /// whose further primitives change the stack needs its bases solved again.
    pub(crate) frozen_primitives: usize,
}

impl StageData for ActuationData<'_> {
    fn residuals(&self, effects: &EffectModel, keep: Option<&[bool]>, out: &mut Vec<f64>) {
        out.clear();
        let resolve = effects
            .primitives
            .iter()
            .skip(self.frozen_primitives)
            .any(|x| x.primitive.changes_stack());
        // Re-solved bases, one stack solve per actuator: its other voltages move the basis to their
        // field (same drive mode).
        let mut solved: Vec<Option<(usize, StackBasis)>> =
            vec![None; if resolve { self.groups } else { 0 }];
        for o in &self.obs {
            if keep.is_some_and(|k| !k[o.group]) {
                continue;
            }
            let (delta, force) = if resolve {
                let rows = &self.data.rows;
                let basis = match solved[o.group] {
                    Some((row, b)) if rows[row].drive_mode == rows[o.row].drive_mode => {
                        Ok(b.at_field(o.basis.field))
                    }
                    _ => effects.basis(&rows[o.row].actuator()).inspect(|b| {
                        solved[o.group] = Some((o.row, *b));
                    }),
                };
                basis.map_or((f64::NAN, f64::NAN), |b| effects.outputs(&b))
            } else {
                effects.outputs(&o.basis)
            };
            if let Some(d) = o.ln_delta {
                out.push(d - delta.ln());
            }
            if let Some(f) = o.ln_force {
                out.push(f - force.ln());
            }
        }
    }
    fn groups(&self) -> usize {
        self.groups
    }
}

impl ActuationData<'_> {
    /// The log residuals of each observation under `effects`: `[deflection, force]`, None where not
    /// measured.
    pub(crate) fn row_residuals(&self, effects: &EffectModel) -> Vec<[Option<f64>; 2]> {
        let mut r = Vec::new();
        self.residuals(effects, None, &mut r);
        let mut rows = vec![[None, None]; self.obs.len()];
        for (&(i, output), &res) in self.labels().iter().zip(&r) {
            rows[i][(output == "blocked_force") as usize] = Some(res);
        }
        rows
    }

    /// (obs index, output name) of each residual in the unmasked order.
    pub(crate) fn labels(&self) -> Vec<(usize, &'static str)> {
        let mut labels = Vec::new();
        for (i, o) in self.obs.iter().enumerate() {
            if o.ln_delta.is_some() {
                labels.push((i, "free_deflection"));
            }
            if o.ln_force.is_some() {
                labels.push((i, "blocked_force"));
            }
        }
        labels
    }
}
