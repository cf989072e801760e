//! The data each stage fits: log residuals of the measured masses (mass stage) and of the measured
//! deflections and forces (actuation stage), with whole actuators maskable for cross-validation.

use crate::calibrate::csv::Dataset;
use actuator_model::effects::{Effects, StackBasis};

/// Residuals of one stage under given effects, optionally on a subset of actuators.
pub(crate) trait StageData: Sync {
    fn residuals(&self, effects: &Effects, keep: Option<&[bool]>, out: &mut Vec<f64>);
    fn groups(&self) -> usize;
}

pub(crate) struct MassData<'a> {
    pub(crate) data: &'a Dataset,
    /// (group, row, ln measured mass)
    pub(crate) obs: Vec<(usize, usize, f64)>,
}

impl StageData for MassData<'_> {
    fn residuals(&self, effects: &Effects, keep: Option<&[bool]>, out: &mut Vec<f64>) {
        out.clear();
        for &(g, row, ln_m) in &self.obs {
            if keep.is_some_and(|k| !k[g]) {
                continue;
            }
            let m = effects.mass(&self.data.rows[row].actuator()).total();
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

pub(crate) struct ActuationData {
    pub(crate) obs: Vec<ActuationObs>,
    pub(crate) groups: usize,
}

impl StageData for ActuationData {
    fn residuals(&self, effects: &Effects, keep: Option<&[bool]>, out: &mut Vec<f64>) {
        out.clear();
        for o in &self.obs {
            if keep.is_some_and(|k| !k[o.group]) {
                continue;
            }
            let (delta, force) = effects.outputs(&o.basis);
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

impl ActuationData {
    /// The log residuals of each observation under `effects`: `[deflection, force]`, None where not
    /// measured.
    pub(crate) fn row_residuals(&self, effects: &Effects) -> Vec<[Option<f64>; 2]> {
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
