//! The actuation stage's log residuals, evaluated once per design and drive mode rather than once per
//! row (docs/calibration.md §3, "Speed").
//!
//! An actuator's rows at one drive mode share the stack and the planform and differ only in the field;
//! so do the rows of actuators built to one design (a lab builds several of each). With the driving
//! curvature `P = κ |η (1 + β E)|` the model gives `δ = P a` and `F_b = P a / c`, where the arm `a`
//! ([`Effects::deflection_arm`](actuator_model::Effects::deflection_arm)) and the tip compliance `c`
//! ([`Effects::tip_compliance`](actuator_model::Effects::tip_compliance)) depend on the planform and the
//! boundary effects alone, and CLT's free curvature κ is linear in the field ([`StackBasis::at_field`]; a
//! model-crate test holds every primitive but the field-dependent d31 to this). So
//!
//! `ln δ = ln κ_g + ln(E / E_g) + ln |η (1 + β E)| + ln a`, `ln F_b = ln δ - ln c`,
//!
//! with `κ_g` the curvature at the group's first field `E_g`: `a`, `c` and their logarithms once per group,
//! a sum per row (and the log of the d31 factor per field when it depends on the field). Against the log
//! of [`EffectModel::outputs`] row by row this differs by rounding alone (a unit test below).
//!
//! Under a model linear in the field the rows of a group's deflections (or forces) differ from one
//! model value by constants, so a search can take their mean in place of them ([`Form::Groups`]).

use super::pooled::{Member, Pools};
use super::stacks::Stacks;
use actuator_model::effects::StackBasis;
use actuator_model::{EffectModel, Planform};
use std::collections::HashMap;

/// One row of the actuation stage.
#[derive(Debug, Clone, Copy)]
pub(crate) struct ActuationObs {
    pub(crate) group: usize,
    pub(crate) row: usize,
    pub(crate) basis: StackBasis,
    pub(crate) ln_delta: Option<f64>,
    pub(crate) ln_force: Option<f64>,
}

/// The observations of one design at one drive mode ([`Stacks::design`]).
#[derive(Debug, Clone)]
struct Group {
    /// The actuators whose observations it has.
    actuators: Vec<usize>,
    /// Its first observation, whose basis is the group's.
    first: usize,
    planform: Planform,
    /// ln of the arm with the whole PZT driven (the original model's): most models leave it.
    ln_nominal_arm: f64,
    /// ln of the beam compliance of its first observation's basis.
    ln_beam: f64,
}

/// Which residuals an evaluation gives.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Form {
    /// One per measured deflection or force.
    Rows,
    /// One per group's deflection and per group's force ([`Pools`]; a model linear in the field).
    Groups,
}

/// The actuation observations grouped by design and drive mode, groups numbered in the order their
/// first observations come, and their residuals in the order of the observations (deflection, then
/// force, where measured).
#[derive(Debug)]
pub(crate) struct DriveGroups {
    groups: Vec<Group>,
    /// Per observation, its group.
    of_obs: Vec<usize>,
    /// Per residual (the log deflection or force of an observation), the measured log less the
    /// observation's own terms: ln κ of its own basis (frozen bases, `[0]`) or ln of its field over its
    /// group's (bases solved per group, `[1]`).
    values: [Vec<f64>; 2],
    /// Per residual, twice its group, plus one for a force.
    at: Vec<u32>,
    /// Per residual, its field in `fields`.
    field_of: Vec<u32>,
    /// Per residual, its actuator.
    actuator_of: Vec<u32>,
    /// The distinct fields, V/m (a data set has a few voltages per plate thickness): a field-dependent
    /// d31 takes one logarithm per field.
    fields: Vec<f64>,
    /// Per group, its deflections and its forces pooled (at `2 g` and `2 g + 1`), each row less its own
    /// terms on frozen bases and on bases solved per group.
    pooled: Pools<2>,
}

/// A group's stack in one evaluation, at the group's field: the logs of its curvature and beam
/// compliance, and its basis (whose compliances are read only where the model's tip compliance is more
/// than the beam's).
#[derive(Debug, Clone, Copy)]
pub(crate) struct GroupBasis {
    pub(crate) basis: StackBasis,
    pub(crate) ln_curvature: f64,
    pub(crate) ln_beam: f64,
}

impl GroupBasis {
    pub(crate) fn of(basis: StackBasis) -> GroupBasis {
        GroupBasis {
            basis,
            ln_curvature: basis.free_curvature.ln(),
            ln_beam: basis.beam_compliance.ln(),
        }
    }
}

/// Where each group's stack comes from in an evaluation that changes it: `(group, compliances needed)`,
/// None where the model cannot evaluate it.
pub(crate) type Solve<'s> = &'s mut dyn FnMut(usize, bool) -> Option<GroupBasis>;

impl DriveGroups {
    pub(crate) fn new(obs: &[ActuationObs], stacks: &Stacks) -> DriveGroups {
        let mut groups: Vec<Group> = Vec::new();
        let mut of_design: HashMap<usize, usize> = HashMap::new();
        let mut of_obs = Vec::with_capacity(obs.len());
        let mut members: Vec<Member<2>> = Vec::with_capacity(2 * obs.len());
        let mut field_of = Vec::with_capacity(2 * obs.len());
        let mut fields = Vec::new();
        let mut field_index: HashMap<u64, u32> = HashMap::new();
        for (i, o) in obs.iter().enumerate() {
            let g = *of_design.entry(stacks.design(o.row)).or_insert_with(|| {
                let pl = o.basis.planform;
                groups.push(Group {
                    actuators: Vec::new(),
                    first: i,
                    planform: pl,
                    ln_nominal_arm: EffectModel::default().effects.deflection_arm(&pl).ln(),
                    ln_beam: o.basis.beam_compliance.ln(),
                });
                groups.len() - 1
            });
            if groups[g].actuators.last() != Some(&o.group) {
                groups[g].actuators.push(o.group);
            }
            of_obs.push(g);
            let own = [
                o.basis.free_curvature.ln(),
                (o.basis.field / obs[groups[g].first].basis.field).ln(),
            ];
            let field = *field_index
                .entry(o.basis.field.to_bits())
                .or_insert_with(|| {
                    fields.push(o.basis.field);
                    (fields.len() - 1) as u32
                });
            for (k, measured) in [o.ln_delta, o.ln_force].into_iter().enumerate() {
                if let Some(measured) = measured {
                    members.push(Member {
                        pool: 2 * g + k,
                        actuator: o.group,
                        value: own.map(|own| measured - own),
                    });
                    field_of.push(field);
                }
            }
        }
        for g in &mut groups {
            g.actuators.sort_unstable();
            g.actuators.dedup();
        }
        DriveGroups {
            values: [0, 1].map(|mode| members.iter().map(|m| m.value[mode]).collect()),
            at: members.iter().map(|m| m.pool as u32).collect(),
            actuator_of: members.iter().map(|m| m.actuator as u32).collect(),
            field_of,
            pooled: Pools::new(2 * groups.len(), members),
            groups,
            of_obs,
            fields,
        }
    }

    /// Whether grouped residuals are fewer than the rows ([`Form::Groups`]).
    pub(crate) fn pools(&self) -> bool {
        self.pooled.pools()
    }

    pub(crate) fn len(&self) -> usize {
        self.groups.len()
    }

    /// The first observation of group `g`.
    pub(crate) fn first(&self, g: usize) -> usize {
        self.groups[g].first
    }

    /// The group of observation `i`.
    pub(crate) fn of_obs(&self, i: usize) -> usize {
        self.of_obs[i]
    }

    /// The group of each actuator's first observation (None: no deflection or force measured).
    pub(crate) fn first_of_actuators(
        &self,
        obs: &[ActuationObs],
        actuators: usize,
    ) -> Vec<Option<usize>> {
        let mut first = vec![None; actuators];
        for (o, &g) in obs.iter().zip(&self.of_obs) {
            first[o.group].get_or_insert(g);
        }
        first
    }

    /// Push the log residuals of the observations of the actuators `keep` marks (None: all) under
    /// `model`, in `form`, and return the sum of squares they leave out (0 for the rows themselves).
    /// `solved` gives each group's stack when the model changes it; without it every observation keeps
    /// the basis it was built with. Grouped residuals need a model linear in the field
    /// ([`EffectModel::linear_in_field`]; NaN otherwise).
    pub(crate) fn evaluate(
        &self,
        obs: &[ActuationObs],
        model: &EffectModel,
        keep: Option<&[bool]>,
        solved: Option<Solve>,
        form: Form,
        out: &mut Vec<f64>,
    ) -> f64 {
        let Some(first) = self.groups.first() else {
            return 0.0;
        };
        // η, β, the dead length, the edge margins and the stiffness scale do not depend on the
        // planform; the clamp compliance does through a clamp compliance per width.
        let shared = model.boundary_effects(&first.planform);
        let mode = usize::from(solved.is_some());
        let logs = self.group_logs(obs, model, &shared, keep, solved);
        let linear = model.linear_in_field();
        let ln_d31 = shared.d31_factor(obs[first.first].basis.field).abs().ln();
        if form == Form::Groups {
            return self.pooled.with_sums(keep, |sums| {
                let mut spread = 0.0;
                for (at, s) in sums.iter().enumerate() {
                    if s.root_count > 0.0 {
                        let v = if linear { logs[at] + ln_d31 } else { f64::NAN };
                        out.push(s.root_count * (s.mean[mode] - v));
                        spread += s.spread[mode];
                    }
                }
                spread
            });
        }
        let per_field: Vec<f64> = if linear {
            Vec::new()
        } else {
            self.fields
                .iter()
                .map(|&field| shared.d31_factor(field).abs().ln())
                .collect()
        };
        let values = &self.values[mode];
        let row = |j: usize| {
            let d31 = if linear {
                ln_d31
            } else {
                per_field[self.field_of[j] as usize]
            };
            values[j] - (logs[self.at[j] as usize] + d31)
        };
        match keep {
            None if linear => out.extend(
                values
                    .iter()
                    .zip(&self.at)
                    .map(|(c, &at)| c - (logs[at as usize] + ln_d31)),
            ),
            None => out.extend((0..values.len()).map(row)),
            Some(k) => out.extend(
                (0..values.len())
                    .filter(|&j| k[self.actuator_of[j] as usize])
                    .map(row),
            ),
        }
        0.0
    }

    /// Per group, `ln κ_g + ln a` (its deflection's log less the observation's own terms) and the same
    /// less `ln c` (its force's), at `2 g` and `2 g + 1`; NaN for a group left out or that cannot be
    /// evaluated.
    fn group_logs(
        &self,
        obs: &[ActuationObs],
        model: &EffectModel,
        shared: &actuator_model::Effects,
        keep: Option<&[bool]>,
        mut solved: Option<Solve>,
    ) -> Vec<f64> {
        let uniform = model.boundary_is_uniform();
        let whole = shared.drives_whole_pzt();
        let ln_stiffness = shared.stiffness_scale.ln();
        let mut logs = vec![f64::NAN; 2 * self.groups.len()];
        for (g, group) in self.groups.iter().enumerate() {
            if keep.is_some_and(|k| !group.actuators.iter().any(|&a| k[a])) {
                continue;
            }
            let own;
            let e = if uniform {
                shared
            } else {
                own = model.boundary_effects(&group.planform);
                &own
            };
            let beam_only = e.compliance_is_beam();
            let stack;
            let (ln_curvature, ln_beam, basis) = match solved.as_mut() {
                None => (0.0, group.ln_beam, &obs[group.first].basis),
                Some(solve) => match solve(g, !beam_only) {
                    Some(s) => {
                        stack = s;
                        (s.ln_curvature, s.ln_beam, &stack.basis)
                    }
                    None => continue,
                },
            };
            let ln_arm = if whole {
                group.ln_nominal_arm
            } else {
                e.deflection_arm(&group.planform).ln()
            };
            let ln_c = if beam_only {
                ln_beam - ln_stiffness
            } else {
                e.tip_compliance(basis).ln()
            };
            logs[2 * g] = ln_curvature + ln_arm;
            logs[2 * g + 1] = logs[2 * g] - ln_c;
        }
        logs
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::calibrate::csv::{parse, Dataset};
    use crate::calibrate::select::actuation_data;
    use actuator_model::primitives::{Applied, Primitive};

    /// Two actuators, one at three voltages in two drive modes, one at one voltage.
    fn data() -> Dataset {
        parse(
            "id,l_tot_mm,l_r,w0_mm,w_r,t_p_mm,layup,voltage_V,mass_mg,free_deflection_mm,blocked_force_N,drive\n\
             a,30,0.6,8,1.2,0.191,0/90/0,150,60,0.3,0.05,parallel\n\
             a,30,0.6,8,1.2,0.191,0/90/0,100,,0.2,0.035,parallel\n\
             b,40,0,6,0.8,0.127,0/0/90/0/0,120,60,0.25,0.04,parallel\n\
             a,30,0.6,8,1.2,0.191,0/90/0,50,,0.1,,series\n",
        )
        .expect("valid rows")
    }

    /// Three actuators of one design (one at another voltage, one a force short) and one of another.
    fn replicates() -> Dataset {
        parse(
            "id,l_tot_mm,l_r,w0_mm,w_r,t_p_mm,layup,voltage_V,mass_mg,free_deflection_mm,blocked_force_N\n\
             a,30,0.6,8,1.2,0.191,0/90/0,150,60,0.3,0.05\n\
             b,40,0,6,0.8,0.127,0/0/90/0/0,120,60,0.25,0.04\n\
             c,30,0.6,8,1.2,0.191,0/90/0,150,61,0.32,0.052\n\
             d,30,0.6,8,1.2,0.191,0/90/0,100,59,0.21,\n",
        )
        .expect("valid rows")
    }

    #[test]
    fn groups_are_the_rows_of_a_design_at_one_drive_mode() {
        let data = data();
        let act = actuation_data(&data, &EffectModel::default()).expect("physical stacks");
        let groups = &act.drive_groups;
        assert_eq!(groups.len(), 3);
        assert_eq!(
            (0..4).map(|i| groups.of_obs(i)).collect::<Vec<_>>(),
            [0, 0, 1, 2]
        );
        assert_eq!(groups.first_of_actuators(&act.obs, 2), [Some(0), Some(1)]);
        assert!(groups.pools());
        let data = replicates();
        let act = actuation_data(&data, &EffectModel::default()).expect("physical stacks");
        let groups = &act.drive_groups;
        assert_eq!(groups.len(), 2);
        assert_eq!(
            (0..4).map(|i| groups.of_obs(i)).collect::<Vec<_>>(),
            [0, 1, 0, 0]
        );
    }

    /// The grouped residuals' sum of squares and the spread they leave out add up to the rows' sum of
    /// squares, for all the actuators and for a fold of them, on frozen and on solved bases.
    #[test]
    fn grouped_residuals_keep_the_rows_sum_of_squares() {
        let data = replicates();
        let act = actuation_data(&data, &EffectModel::default()).expect("physical stacks");
        let groups = &act.drive_groups;
        let mut model = EffectModel::default();
        (model.effects.d31_scale, model.effects.clamp_compliance) = (0.7, 0.4);
        let square = |r: &[f64]| r.iter().map(|x| x * x).sum::<f64>();
        for keep in [None, Some(&[true, false, false, true][..])] {
            for solved in [false, true] {
                let mut solve =
                    |g: usize, _: bool| Some(GroupBasis::of(act.obs[groups.first(g)].basis));
                let mut eval = |form: Form, out: &mut Vec<f64>| {
                    let solver = solved.then_some(&mut solve as Solve);
                    groups.evaluate(&act.obs, &model, keep, solver, form, out)
                };
                let (mut rows, mut grouped) = (Vec::new(), Vec::new());
                assert_eq!(eval(Form::Rows, &mut rows), 0.0);
                let spread = eval(Form::Groups, &mut grouped);
                assert!(grouped.len() < rows.len() && spread > 0.0);
                let (want, got) = (square(&rows), square(&grouped) + spread);
                assert!((got / want - 1.0).abs() < 1e-12, "{got} vs {want}");
            }
        }
    }

    /// The residuals per group against `ln` of [`EffectModel::outputs`] per row, on frozen bases and on
    /// bases solved per group: with every boundary effect on, and with η and the stiffness scale alone
    /// (the arm and the compliance in their original forms); each with a field-dependent d31 and a clamp
    /// compliance per width.
    #[test]
    fn group_logs_are_the_log_outputs_of_each_row() {
        let data = data();
        let mut every = EffectModel::default();
        let e = &mut every.effects;
        (e.d31_scale, e.dead_length, e.edge_margin) = (0.8, 2e-3, 0.2e-3);
        (
            e.extension_flexibility,
            e.clamp_compliance,
            e.stiffness_scale,
        ) = (1.5, 0.3, 0.9);
        e.rigid_root = 1e-3;
        let mut few = EffectModel::default();
        (few.effects.d31_scale, few.effects.stiffness_scale) = (1.2, 0.8);
        for (model, primitives) in [every, few].into_iter().flat_map(|model| {
            [
                vec![],
                vec![Applied {
                    primitive: Primitive::FieldDependentD31,
                    value: 0.5e-6,
                }],
                vec![Applied {
                    primitive: Primitive::ClampCompliancePerWidth,
                    value: 2e-3,
                }],
            ]
            .map(move |p| (model.clone(), p))
        }) {
            let model = EffectModel {
                primitives,
                ..model
            };
            let act = actuation_data(&data, &EffectModel::default()).expect("physical stacks");
            let mut want = Vec::new();
            for o in &act.obs {
                let (d, f) = model.outputs(&o.basis);
                want.extend(o.ln_delta.map(|x| x - d.ln()));
                want.extend(o.ln_force.map(|x| x - f.ln()));
            }
            let groups = &act.drive_groups;
            let mut frozen = Vec::new();
            groups.evaluate(&act.obs, &model, None, None, Form::Rows, &mut frozen);
            let mut solve = |g: usize, _: bool| {
                let o = &act.obs[groups.first(g)];
                Some(GroupBasis::of(o.basis))
            };
            let mut solved = Vec::new();
            groups.evaluate(
                &act.obs,
                &model,
                None,
                Some(&mut solve),
                Form::Rows,
                &mut solved,
            );
            assert_eq!(want.len(), 7);
            for got in [frozen, solved] {
                assert_eq!(got.len(), want.len());
                for (x, y) in got.iter().zip(&want) {
                    assert!((x - y).abs() < 1e-12, "{x} vs {y}");
                }
            }
            // A held-out actuator leaves its rows out.
            let mut kept = Vec::new();
            groups.evaluate(
                &act.obs,
                &model,
                Some(&[false, true]),
                None,
                Form::Rows,
                &mut kept,
            );
            assert_eq!(kept.len(), 2);
            assert!((kept[0] - want[4]).abs() < 1e-12);
        }
    }
}
