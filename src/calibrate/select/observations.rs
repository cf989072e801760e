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
    /// [`StageData::residuals`] reusing the stacks in `cache` while the fit's stack parameters stay
    /// the same (`cache.key`, set by the caller); only data that solve stacks per evaluation use it.
    fn residuals_cached(
        &self,
        effects: &EffectModel,
        keep: Option<&[bool]>,
        out: &mut Vec<f64>,
        cache: &mut StackCache,
    ) {
        let _ = cache;
        self.residuals(effects, keep, out);
    }
    /// The residuals cross-validation scores on held-out actuators: all of them, unless the stage fits
    /// data it does not predict (the joint data score deflection and force only).
    fn held_out(&self, effects: &EffectModel, keep: Option<&[bool]>, out: &mut Vec<f64>) {
        self.residuals(effects, keep, out);
    }
    /// How many leading residuals are the stage's scored outputs (None: all): the information criteria
    /// count them, and identifiability's uniform scale (the d31 scale) acts on them. The rest (the
    /// weighted masses of the joint data) steer the fit only.
    fn scored_rows(&self) -> Option<usize> {
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

/// Stacks solved under one value of a fit's stack parameters (the mass effects fitted with the actuation
/// effects): a Jacobian column of a parameter that leaves the stack alone, or a cross-validation refit
/// with the stack parameters held, costs no stack solve.
#[derive(Debug, Default)]
pub(crate) struct StackCache {
    /// The stack parameters of the next evaluation.
    pub(crate) key: Vec<f64>,
    /// The last few keys' stacks, per actuator the row it was solved for and its basis (the fit's
    /// point and its stack-parameter shifts of one Jacobian).
    entries: Vec<(Vec<f64>, SolvedStacks)>,
}

/// Per actuator: the row its stack was solved for, and the basis.
type SolvedStacks = Vec<Option<(usize, StackBasis)>>;

/// Keys a [`StackCache`] keeps: a Jacobian's shifts of two mass parameters, its point and a trial step.
const STACK_CACHE_KEYS: usize = 4;

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
    /// The fit moves stack effects the bases were not solved with (the mass parameters fitted jointly
    /// with the actuation effects): solve every actuator's stack again on each evaluation.
    pub(crate) resolve_stack: bool,
}

impl StageData for ActuationData<'_> {
    fn residuals(&self, effects: &EffectModel, keep: Option<&[bool]>, out: &mut Vec<f64>) {
        self.residuals_cached(effects, keep, out, &mut StackCache::default());
    }
    fn residuals_cached(
        &self,
        effects: &EffectModel,
        keep: Option<&[bool]>,
        out: &mut Vec<f64>,
        cache: &mut StackCache,
    ) {
        out.clear();
        let resolve = self.resolve_stack
            || effects
                .primitives
                .iter()
                .skip(self.frozen_primitives)
                .any(|x| x.primitive.changes_stack());
        // Re-solved bases, one stack solve per actuator: its other voltages move the basis to their
        // field (same drive mode). Kept while the cache's key stands.
        let mut unused = Vec::new();
        let solved = if resolve {
            let at = match cache.entries.iter().position(|(k, _)| *k == cache.key) {
                Some(at) => at,
                None => {
                    if cache.entries.len() >= STACK_CACHE_KEYS {
                        cache.entries.remove(0);
                    }
                    cache
                        .entries
                        .push((cache.key.clone(), vec![None; self.groups]));
                    cache.entries.len() - 1
                }
            };
            &mut cache.entries[at].1
        } else {
            &mut unused
        };
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

/// The actuation stage's data with the measured masses beside them (docs/calibration.md §3, "Mass
/// effects on all the data"): the log residuals of deflection and force, then each actuator's log mass
/// residual times `mass_weight` = σ_actuation / σ_mass, so that both kinds of residual count by their
/// noise. Mass parameters fitted on these data trade against the actuation effects instead of being
/// frozen at their masses-only values.
pub(crate) struct JointData<'a> {
    pub(crate) act: ActuationData<'a>,
    /// The masses (None without at least 4 measured masses).
    pub(crate) mass: Option<&'a MassData<'a>>,
    pub(crate) mass_weight: f64,
}

impl JointData<'_> {
    /// Number of deflection and force residuals (the leading part of the full residual vector).
    pub(crate) fn actuation_len(&self) -> usize {
        self.act
            .obs
            .iter()
            .map(|o| o.ln_delta.is_some() as usize + o.ln_force.is_some() as usize)
            .sum()
    }
}

impl StageData for JointData<'_> {
    fn residuals(&self, effects: &EffectModel, keep: Option<&[bool]>, out: &mut Vec<f64>) {
        self.residuals_cached(effects, keep, out, &mut StackCache::default());
    }
    fn residuals_cached(
        &self,
        effects: &EffectModel,
        keep: Option<&[bool]>,
        out: &mut Vec<f64>,
        cache: &mut StackCache,
    ) {
        self.act.residuals_cached(effects, keep, out, cache);
        if let Some(mass) = self.mass {
            let mut m = Vec::new();
            mass.residuals(effects, keep, &mut m);
            out.extend(m.iter().map(|r| r * self.mass_weight));
        }
    }
    fn groups(&self) -> usize {
        self.act.groups
    }
    fn held_out(&self, effects: &EffectModel, keep: Option<&[bool]>, out: &mut Vec<f64>) {
        self.act.residuals(effects, keep, out);
    }
    fn scored_rows(&self) -> Option<usize> {
        Some(self.actuation_len())
    }
}
