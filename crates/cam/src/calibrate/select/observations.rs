//! The data each stage fits: log residuals of the measured masses (mass stage) and of the measured
//! deflections and forces, then the measured first resonances (actuation stage), with whole actuators
//! maskable for cross-validation.

pub(crate) use super::drive_groups::ActuationObs;
use super::drive_groups::{DriveGroups, Form, GroupBasis, Solve};
use super::pooled::{Member, Pools};
pub(crate) use super::resonances::{BeamModel, ResonanceObs, Resonances};
use super::stacks::Stacks;
use crate::calibrate::csv::Dataset;
use actuator_model::effects::StackBasis;
use actuator_model::EffectModel;
use std::collections::HashMap;

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
    /// The residuals of [`StageData::residuals`] in the grouped form of a search
    /// ([`crate::calibrate::fit::least_squares_grouped`]): the rows of each actuator's deflections (and
    /// forces) at one drive mode as their weighted mean, and the sum of squares that leaves out; for a
    /// model linear in the field. None (and `out` untouched) where the stage has no grouped form.
    fn grouped(
        &self,
        effects: &EffectModel,
        keep: Option<&[bool]>,
        out: &mut Vec<f64>,
    ) -> Option<f64> {
        let _ = (effects, keep, out);
        None
    }
    /// The grouped form of [`StageData::held_out`].
    fn grouped_held_out(
        &self,
        effects: &EffectModel,
        keep: Option<&[bool]>,
        out: &mut Vec<f64>,
    ) -> Option<f64> {
        self.grouped(effects, keep, out)
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
    /// Per observation its design (actuators of one design have one model mass), and a row of each.
    design_of_obs: Vec<usize>,
    design_rows: Vec<usize>,
    /// The log masses pooled by design.
    pooled: Pools<1>,
}

impl<'a> MassData<'a> {
    /// The measured masses `obs` (group, row, ln mass) of `data`.
    pub(crate) fn new(data: &'a Dataset, obs: Vec<(usize, usize, f64)>) -> MassData<'a> {
        let stacks = Stacks::new(data);
        let mut of_design: HashMap<usize, usize> = HashMap::new();
        let mut design_rows = Vec::new();
        let design_of_obs: Vec<usize> = obs
            .iter()
            .map(|&(_, row, _)| {
                *of_design.entry(stacks.design(row)).or_insert_with(|| {
                    design_rows.push(row);
                    design_rows.len() - 1
                })
            })
            .collect();
        let members = obs
            .iter()
            .zip(&design_of_obs)
            .map(|(&(actuator, _, ln_m), &pool)| Member {
                pool,
                actuator,
                value: [ln_m],
            })
            .collect();
        MassData {
            data,
            pooled: Pools::new(design_rows.len(), members),
            obs,
            design_of_obs,
            design_rows,
        }
    }

    /// ln of the model mass of each design under `effects` (NaN where the model cannot evaluate it).
    fn ln_model_masses(&self, effects: &EffectModel) -> Vec<f64> {
        self.design_rows
            .iter()
            .map(|&row| {
                let m = effects.mass(&self.data.rows[row].actuator());
                m.map_or(f64::NAN, |m| m.total()).ln()
            })
            .collect()
    }
}

impl StageData for MassData<'_> {
    fn residuals(&self, effects: &EffectModel, keep: Option<&[bool]>, out: &mut Vec<f64>) {
        out.clear();
        let ln_model = self.ln_model_masses(effects);
        for (&(g, _, ln_m), &design) in self.obs.iter().zip(&self.design_of_obs) {
            if keep.is_none_or(|k| k[g]) {
                out.push(ln_m - ln_model[design]);
            }
        }
    }
    fn grouped(
        &self,
        effects: &EffectModel,
        keep: Option<&[bool]>,
        out: &mut Vec<f64>,
    ) -> Option<f64> {
        if !self.pooled.pools() {
            return None;
        }
        out.clear();
        let ln_model = self.ln_model_masses(effects);
        Some(self.pooled.with_sums(keep, |sums| {
            let mut spread = 0.0;
            for (s, ln_model) in sums.iter().zip(&ln_model) {
                if s.root_count > 0.0 {
                    out.push(s.root_count * (s.mean[0] - ln_model));
                    spread += s.spread[0];
                }
            }
            spread
        }))
    }
    fn groups(&self) -> usize {
        self.data.actuators()
    }
}

pub(crate) struct ActuationData<'a> {
    pub(crate) data: &'a Dataset,
    pub(crate) obs: Vec<ActuationObs>,
    pub(crate) groups: usize,
    /// How many declared primitives the bases were solved with (the frozen mass stage's): a model
    /// whose further primitives change the stack needs its bases solved again.
    pub(crate) frozen_primitives: usize,
    /// The measured first resonances, one per actuator that has one; their log residuals follow the
    /// deflections' and forces' (docs/calibration.md §3, "The resonance").
    pub(crate) resonances: Resonances,
    /// The data's distinct stacks: a model that changes the stack solves each once per evaluation.
    pub(crate) stacks: Stacks,
    /// The observations by design and drive mode, which the residuals are evaluated per.
    pub(crate) drive_groups: DriveGroups,
}

impl StageData for ActuationData<'_> {
    fn residuals(&self, effects: &EffectModel, keep: Option<&[bool]>, out: &mut Vec<f64>) {
        self.evaluate(effects, keep, Form::Rows, out);
    }
    fn grouped(
        &self,
        effects: &EffectModel,
        keep: Option<&[bool]>,
        out: &mut Vec<f64>,
    ) -> Option<f64> {
        let pools = self.drive_groups.pools();
        pools.then(|| self.evaluate(effects, keep, Form::Groups, out))
    }
    fn groups(&self) -> usize {
        self.groups
    }
}

impl ActuationData<'_> {
    /// The deflections' and forces' log residuals in `form`, then the resonances'; the sum of squares
    /// the form leaves out.
    fn evaluate(
        &self,
        effects: &EffectModel,
        keep: Option<&[bool]>,
        form: Form,
        out: &mut Vec<f64>,
    ) -> f64 {
        out.clear();
        let resolve = effects
            .primitives
            .iter()
            .skip(self.frozen_primitives)
            .any(|x| x.primitive.changes_stack());
        let groups = &self.drive_groups;
        // Re-solved bases: one stack solve per distinct stack, one basis per group.
        let mut stacks = self.stacks.solver(self.data, effects);
        let mut bases: Vec<Option<StackBasis>> = vec![None; if resolve { groups.len() } else { 0 }];
        let mut solve = |g: usize, _: bool| {
            let basis = stacks.basis(self.obs[groups.first(g)].row);
            bases[g] = basis;
            basis.map(GroupBasis::of)
        };
        let solved = resolve.then_some(&mut solve as Solve);
        let left_out = groups.evaluate(&self.obs, effects, keep, solved, form, out);
        // A resonance's basis: its actuator's first group's, solved again, or its own when the actuator
        // has no deflection or force.
        let first_group = if resolve && self.resonances.len() > 0 {
            groups.first_of_actuators(&self.obs, self.groups)
        } else {
            Vec::new()
        };
        let asked = BeamModel::of(effects);
        for (k, o) in self.resonances.obs.iter().enumerate() {
            if keep.is_some_and(|k| !k[o.group]) {
                continue;
            }
            let basis = if resolve {
                match first_group[o.group] {
                    Some(g) => bases[g],
                    None => stacks.basis(o.row),
                }
            } else {
                Some(o.basis)
            };
            out.push(basis.map_or(f64::NAN, |b| {
                self.resonances.residual(self.data, k, &asked, &b)
            }));
        }
        left_out
    }
}

impl<'a> ActuationData<'a> {
    /// The actuation data of `obs` (and `resonances`) of `data`, on stacks solved with the model's first
    /// `frozen_primitives` primitives.
    pub(crate) fn new(
        data: &'a Dataset,
        obs: Vec<ActuationObs>,
        frozen_primitives: usize,
        resonances: Resonances,
        stacks: Stacks,
    ) -> ActuationData<'a> {
        ActuationData {
            drive_groups: DriveGroups::new(&obs, &stacks),
            data,
            obs,
            groups: data.actuators(),
            frozen_primitives,
            resonances,
            stacks,
        }
    }
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

    /// The observations of each actuator, in their order.
    pub(crate) fn obs_by_actuator(&self) -> Vec<Vec<usize>> {
        let mut by = vec![Vec::new(); self.groups];
        for (i, o) in self.obs.iter().enumerate() {
            by[o.group].push(i);
        }
        by
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
