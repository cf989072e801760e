//! The mass parameters fitted again with every actuation model, on the masses, deflections and forces
//! together (docs/calibration.md §3, "Mass effects on all the data").
//!
//! Why: with 1 % mass noise the masses alone leave the ply-thickness scale a few per cent uncertain
//! (and the split between resin-rich plies and a bond layer worse), and a frozen value a few per cent off
//! leaves a deflection and stiffness residual that an extra effect absorbs or the lack-of-fit test sees.
//!
//! How it stays cheap: the library's mass effects change the laminate, so moving them means solving every
//! stack again. Instead each actuator's stack basis (free curvature, beam and extension compliance) is
//! solved once at a few values of the mass parameters around their masses-only estimate and held as a
//! quadratic in them (in the log of each basis quantity: smooth, and exact at the nodes); an evaluation
//! of the fit then costs no stack solve. The masses are linear in the thickness and density scales and
//! need no stack, so they are evaluated exactly. The mass parameters move only within a trust region of
//! a few masses-only standard errors, where the quadratic holds (a unit test bounds its error).

use super::candidate::Candidate;
use super::drive_groups::{Form, GroupBasis};
use super::observations::{ActuationData, ActuationObs, BeamModel, MassData, StageData};
use super::pooled::{Member, Pools};
use crate::calibrate::fit::ParameterRange;
use crate::calibrate::library::EffectId;
use actuator_model::effects::StackBasis;
use actuator_model::{EffectModel, ModelError};
use std::collections::HashMap;

/// One carried mass parameter: its masses-only estimate, the centre and step of the stencil the stacks
/// are solved on, and the trust region the joint fit keeps it in.
#[derive(Debug, Clone)]
pub(super) struct CarriedParameter {
    pub(super) id: EffectId,
    /// The masses-only estimate (the fit's start).
    pub(super) start: f64,
    /// Centre of the stencil (the estimate, moved inside the bounds by one step if need be).
    centre: f64,
    /// Step of the stencil.
    step: f64,
    /// Where the joint fit may move it: two steps either side of the centre, inside the bounds.
    pub(super) bounds: ParameterRange,
}

impl CarriedParameter {
    /// The mass model `mass`'s parameter `k`: the step is two masses-only standard errors, at least
    /// 1/1000 and at most 1/16 of the parameter's range (a quadratic over 1/4 of the range of a ply
    /// thickness or bond is still accurate to well below the noise).
    pub(super) fn of(mass: &Candidate, k: usize) -> CarriedParameter {
        let id = &mass.effects[k];
        let p = id.param();
        let range = p.hi - p.lo;
        let se = mass.std_errors[k];
        let step = if se.is_finite() {
            (2.0 * se).clamp(1e-3 * range, range / 16.0)
        } else {
            range / 16.0
        };
        let start = mass.values[k];
        let centre = start.clamp(p.lo + step, p.hi - step);
        CarriedParameter {
            id: id.clone(),
            start,
            centre,
            step,
            bounds: ParameterRange {
                lo: (centre - 2.0 * step).max(p.lo),
                hi: (centre + 2.0 * step).min(p.hi),
            },
        }
    }
}

/// Only library mass effects are fitted jointly (their values are read back from a model); a mass model
/// with a declared effect stays frozen at its masses-only values.
pub(super) fn can_carry(mass: &Candidate) -> bool {
    !mass.effects.is_empty()
        && mass
            .effects
            .iter()
            .all(|e| matches!(e, EffectId::PlyThickness | EffectId::BondLayer))
}

/// A stack quantity as a quadratic in the stencil coordinates `t_k = (θ_k - centre_k) / step_k`:
/// `f0 + Σ a_k t_k + Σ b_k t_k² + Σ_{a<b} c_ab t_a t_b`, of ln|q| (times its sign) when the quantity
/// keeps one sign over the stencil, else of q itself.
#[derive(Debug, Clone)]
struct Quadratic {
    log_sign: Option<f64>,
    f0: f64,
    a: Vec<f64>,
    b: Vec<f64>,
    /// Cross terms in the order (0,1), (0,2), ..., (1,2), ...
    c: Vec<f64>,
}

impl Quadratic {
    /// From the values at the stencil's nodes ([`nodes`] order).
    fn fit(values: &[f64], k: usize) -> Quadratic {
        let same_sign = values.iter().all(|v| *v > 0.0) || values.iter().all(|v| *v < 0.0);
        let log_sign = same_sign.then(|| values[0].signum());
        let f: Vec<f64> = match log_sign {
            Some(_) => values.iter().map(|v| v.abs().ln()).collect(),
            None => values.to_vec(),
        };
        let f0 = f[0];
        let (mut a, mut b) = (Vec::with_capacity(k), Vec::with_capacity(k));
        for j in 0..k {
            let (plus, minus) = (f[1 + 2 * j], f[2 + 2 * j]);
            a.push(0.5 * (plus - minus));
            b.push(0.5 * (plus + minus) - f0);
        }
        let mut c = Vec::new();
        let mut at = 1 + 2 * k;
        for i in 0..k {
            for j in i + 1..k {
                c.push(f[at] - f0 - a[i] - a[j] - b[i] - b[j]);
                at += 1;
            }
        }
        Quadratic {
            log_sign,
            f0,
            a,
            b,
            c,
        }
    }

    /// ln of the quantity at `t` (NaN where it is negative).
    fn ln_eval(&self, t: &[f64]) -> f64 {
        match self.log_sign {
            Some(sign) if sign > 0.0 => self.log_eval(t),
            _ => self.eval(t).ln(),
        }
    }

    fn eval(&self, t: &[f64]) -> f64 {
        let v = self.log_eval(t);
        match self.log_sign {
            Some(sign) => sign * v.exp(),
            None => v,
        }
    }

    /// The quadratic itself (of ln|q| where it is one of the logarithm).
    fn log_eval(&self, t: &[f64]) -> f64 {
        let mut v = self.f0;
        for (j, tj) in t.iter().enumerate() {
            v += self.a[j] * tj + self.b[j] * tj * tj;
        }
        let mut at = 0;
        for i in 0..t.len() {
            for j in i + 1..t.len() {
                v += self.c[at] * t[i] * t[j];
                at += 1;
            }
        }
        v
    }
}

/// The stencil's nodes in coordinates `t`: the centre, ±1 along each parameter, and +1 along each pair.
fn nodes(k: usize) -> Vec<Vec<f64>> {
    let mut out = vec![vec![0.0; k]];
    for j in 0..k {
        for s in [1.0, -1.0] {
            let mut t = vec![0.0; k];
            t[j] = s;
            out.push(t);
        }
    }
    for i in 0..k {
        for j in i + 1..k {
            let mut t = vec![0.0; k];
            t[i] = 1.0;
            t[j] = 1.0;
            out.push(t);
        }
    }
    out
}

/// One actuator's stack (at one drive mode) as quadratics in the carried mass parameters.
#[derive(Debug, Clone)]
struct StackModel {
    /// The field the free curvature was solved at.
    field: f64,
    planform: actuator_model::Planform,
    free_curvature: Quadratic,
    beam_compliance: Quadratic,
    extension_compliance: Quadratic,
}

/// The actuation data with the carried mass parameters free, and the masses beside them: the log
/// residuals of deflection and force, then each measured mass's log residual times `mass_weight`
/// (σ_actuation / σ_mass, so that both count by their noise).
pub(crate) struct JointData<'a> {
    pub(crate) act: ActuationData<'a>,
    pub(super) carried: Vec<CarriedParameter>,
    /// Per group of the observations ([`ActuationData::drive_groups`]: an actuator at one drive mode),
    /// its stack model.
    stacks: Vec<StackModel>,
    /// The measured masses (apart: the variant of the stage's input that holds these data stays near
    /// the size of the one that holds the actuation data alone).
    masses: Box<JointMasses>,
    mass_weight: f64,
    /// Number of deflection, force and resonance residuals.
    scored: usize,
    /// Per measured resonance, the stack model of its actuator.
    resonance_stack: Vec<Option<usize>>,
}

impl<'a> JointData<'a> {
    /// Solve each actuator's stack on the stencil of `carried` (1 + 2k + k(k-1)/2 solves per actuator).
    pub(super) fn new(
        act: ActuationData<'a>,
        carried: Vec<CarriedParameter>,
        mass: Option<&MassData>,
        mass_weight: f64,
    ) -> Result<JointData<'a>, ModelError> {
        let k = carried.len();
        let models: Vec<EffectModel> = nodes(k)
            .iter()
            .map(|t| {
                let mut m = EffectModel::default();
                for (c, tj) in carried.iter().zip(t) {
                    c.id.apply(&mut m, c.centre + tj * c.step);
                }
                m
            })
            .collect();
        let rows = &act.data.rows;
        // Each node's stacks solved once per distinct stack; a stack model per group, so the solves stay
        // linear in the actuators.
        let mut solvers: Vec<_> = models
            .iter()
            .map(|m| act.stacks.solver(act.data, m))
            .collect();
        let mut stacks: Vec<StackModel> = Vec::with_capacity(act.drive_groups.len());
        for g in 0..act.drive_groups.len() {
            let row = act.obs[act.drive_groups.first(g)].row;
            let bases = solvers
                .iter_mut()
                .zip(&models)
                .map(|(s, m)| {
                    s.basis(row)
                        .map_or_else(|| m.basis(&rows[row].actuator()), Ok)
                })
                .collect::<Result<Vec<StackBasis>, _>>()?;
            let quad = |q: fn(&StackBasis) -> f64| {
                Quadratic::fit(&bases.iter().map(q).collect::<Vec<_>>(), k)
            };
            stacks.push(StackModel {
                field: bases[0].field,
                planform: bases[0].planform,
                free_curvature: quad(|b| b.free_curvature),
                beam_compliance: quad(|b| b.beam_compliance),
                extension_compliance: quad(|b| b.extension_compliance),
            });
        }
        drop(solvers);
        let masses = Box::new(JointMasses::new(&act, mass, &models, k));
        let scored = act
            .obs
            .iter()
            .map(|o| o.ln_delta.is_some() as usize + o.ln_force.is_some() as usize)
            .sum::<usize>()
            + act.resonances.len();
        // Each resonance's stack: its actuator's first (None: no deflection or force measured, so no
        // stack was solved; its basis stays the frozen one).
        let first_group = act.drive_groups.first_of_actuators(&act.obs, act.groups);
        let resonance_stack = act
            .resonances
            .obs
            .iter()
            .map(|r| first_group.get(r.group).copied().flatten())
            .collect();
        Ok(JointData {
            act,
            carried,
            stacks,
            masses,
            mass_weight,
            scored,
            resonance_stack,
        })
    }

    /// The stencil coordinates of the carried parameters' values in `effects`.
    fn coordinates(&self, effects: &EffectModel) -> Vec<f64> {
        self.carried
            .iter()
            .map(|c| (c.id.value(effects).unwrap_or(c.centre) - c.centre) / c.step)
            .collect()
    }

    /// Each observation's stack basis at the carried parameters' values in `effects`.
    fn bases(&self, effects: &EffectModel) -> Vec<StackBasis> {
        let t = self.coordinates(effects);
        let at: Vec<StackBasis> = self
            .stacks
            .iter()
            .map(|m| StackBasis {
                free_curvature: m.free_curvature.eval(&t),
                beam_compliance: m.beam_compliance.eval(&t),
                extension_compliance: m.extension_compliance.eval(&t),
                field: m.field,
                planform: m.planform,
            })
            .collect();
        self.act
            .obs
            .iter()
            .enumerate()
            .map(|(i, o)| at[self.act.drive_groups.of_obs(i)].at_field(o.basis.field))
            .collect()
    }

    /// The deflections' and forces' log residuals in `form`, then the resonances'; the sum of squares
    /// the form leaves out.
    fn actuation_residuals(
        &self,
        effects: &EffectModel,
        keep: Option<&[bool]>,
        form: Form,
        out: &mut Vec<f64>,
    ) -> f64 {
        out.clear();
        let t = self.coordinates(effects);
        // Each stack model once per evaluation (its voltages share it).
        let mut solve =
            |g: usize, compliances: bool| Some(self.stacks[g].group_basis(&t, compliances));
        let left_out = self.act.drive_groups.evaluate(
            &self.act.obs,
            effects,
            keep,
            Some(&mut solve),
            form,
            out,
        );
        let res = &self.act.resonances;
        let asked = BeamModel::of(effects);
        for (k, (o, stack)) in res.obs.iter().zip(&self.resonance_stack).enumerate() {
            if keep.is_some_and(|k| !k[o.group]) {
                continue;
            }
            let basis = match *stack {
                Some(s) => self.stacks[s].at(&t, o.basis.planform),
                None => o.basis,
            };
            out.push(res.residual(self.act.data, k, &asked, &basis));
        }
        left_out
    }

    /// Each measured mass's log residual times the mass weight, in `form` (pooled by design); the sum
    /// of squares the form leaves out.
    fn mass_residuals(
        &self,
        effects: &EffectModel,
        keep: Option<&[bool]>,
        form: Form,
        out: &mut Vec<f64>,
    ) -> f64 {
        let t = self.coordinates(effects);
        let w = self.mass_weight;
        let m = &self.masses;
        let ln_model: Vec<f64> = m
            .models
            .iter()
            .map(|(m0, slopes)| (m0 + slopes.iter().zip(&t).map(|(s, t)| s * t).sum::<f64>()).ln())
            .collect();
        if form == Form::Groups {
            return m.pooled.with_sums(keep, |sums| {
                let mut spread = 0.0;
                for (s, ln_model) in sums.iter().zip(&ln_model) {
                    if s.root_count > 0.0 {
                        out.push(w * s.root_count * (s.mean[0] - ln_model));
                        spread += w * w * s.spread[0];
                    }
                }
                spread
            });
        }
        for &(g, design, ln_m) in &m.measured {
            if keep.is_none_or(|k| k[g]) {
                out.push((ln_m - ln_model[design]) * w);
            }
        }
        0.0
    }
}

/// The joint data's measured masses: per weighed actuator (group, design, ln measured mass), per design
/// the model mass at the stencil's centre and its change per unit step of each carried parameter, and the
/// log masses pooled by design. The library's mass effects change the mass linearly (a thicker resin-rich
/// ply adds resin, a bond adds its layer), so this is exact; actuators of one design have one model mass.
#[derive(Debug)]
struct JointMasses {
    measured: Vec<(usize, usize, f64)>,
    models: Vec<(f64, Vec<f64>)>,
    pooled: Pools<1>,
}

impl JointMasses {
    /// The masses of `mass` (none without it), with the model masses of the stencil's `models` ([`nodes`]
    /// of `k` parameters).
    fn new(
        act: &ActuationData,
        mass: Option<&MassData>,
        models: &[EffectModel],
        k: usize,
    ) -> JointMasses {
        let mut of_design: HashMap<usize, usize> = HashMap::new();
        let mut masses = JointMasses {
            measured: Vec::new(),
            models: Vec::new(),
            pooled: Pools::new(0, Vec::new()),
        };
        for &(g, row, ln_m) in mass.map_or(&[][..], |m| &m.obs[..]) {
            let design = *of_design.entry(act.stacks.design(row)).or_insert_with(|| {
                let a = act.data.rows[row].actuator();
                let total = |m: &EffectModel| m.mass(&a).map_or(f64::NAN, |x| x.total());
                let m0 = total(&models[0]);
                // Nodes 1, 3, 5, ...: +1 step along each parameter.
                let slopes = (0..k).map(|j| total(&models[1 + 2 * j]) - m0).collect();
                masses.models.push((m0, slopes));
                masses.models.len() - 1
            });
            masses.measured.push((g, design, ln_m));
        }
        let members = masses
            .measured
            .iter()
            .map(|&(actuator, pool, ln_m)| Member {
                pool,
                actuator,
                value: [ln_m],
            })
            .collect();
        masses.pooled = Pools::new(masses.models.len(), members);
        masses
    }
}

impl StackModel {
    /// The stack at stencil coordinates `t` for [`DriveGroups`](super::drive_groups::DriveGroups): the
    /// logs of its curvature and beam compliance (the quadratics themselves where they are of the
    /// logarithm), and the basis on its own planform with its compliances only if `compliances`.
    fn group_basis(&self, t: &[f64], compliances: bool) -> GroupBasis {
        let basis = if compliances {
            self.at(t, self.planform)
        } else {
            StackBasis {
                free_curvature: f64::NAN,
                beam_compliance: f64::NAN,
                extension_compliance: f64::NAN,
                field: self.field,
                planform: self.planform,
            }
        };
        GroupBasis {
            basis,
            ln_curvature: self.free_curvature.ln_eval(t),
            ln_beam: self.beam_compliance.ln_eval(t),
        }
    }

    /// The stack basis at stencil coordinates `t`.
    fn at(&self, t: &[f64], planform: actuator_model::Planform) -> StackBasis {
        StackBasis {
            free_curvature: self.free_curvature.eval(t),
            beam_compliance: self.beam_compliance.eval(t),
            extension_compliance: self.extension_compliance.eval(t),
            field: self.field,
            planform,
        }
    }
}

impl StageData for JointData<'_> {
    fn residuals(&self, effects: &EffectModel, keep: Option<&[bool]>, out: &mut Vec<f64>) {
        self.actuation_residuals(effects, keep, Form::Rows, out);
        self.mass_residuals(effects, keep, Form::Rows, out);
    }
    fn grouped(
        &self,
        effects: &EffectModel,
        keep: Option<&[bool]>,
        out: &mut Vec<f64>,
    ) -> Option<f64> {
        if !self.act.drive_groups.pools() && !self.masses.pooled.pools() {
            return None;
        }
        let left_out = self.actuation_residuals(effects, keep, Form::Groups, out);
        Some(left_out + self.mass_residuals(effects, keep, Form::Groups, out))
    }
    fn groups(&self) -> usize {
        self.act.groups
    }
    fn held_out(&self, effects: &EffectModel, keep: Option<&[bool]>, out: &mut Vec<f64>) {
        self.actuation_residuals(effects, keep, Form::Rows, out);
    }
    fn grouped_held_out(
        &self,
        effects: &EffectModel,
        keep: Option<&[bool]>,
        out: &mut Vec<f64>,
    ) -> Option<f64> {
        let pools = self.act.drive_groups.pools();
        pools.then(|| self.actuation_residuals(effects, keep, Form::Groups, out))
    }
    fn scored_rows(&self) -> Option<usize> {
        Some(self.scored)
    }
    fn held_at(&self, effects: &EffectModel) -> Option<ActuationData<'_>> {
        let obs = self
            .act
            .obs
            .iter()
            .zip(self.bases(effects))
            .map(|(o, basis)| ActuationObs { basis, ..*o })
            .collect();
        let t = self.coordinates(effects);
        let resonances = self
            .act
            .resonances
            .with_bases(|k, r| match self.resonance_stack[k] {
                Some(s) => self.stacks[s].at(&t, r.basis.planform),
                None => r.basis,
            });
        Some(ActuationData::new(
            self.act.data,
            obs,
            0,
            resonances,
            self.act.stacks.clone(),
        ))
    }
}

/// The weight of a log mass residual beside the log deflection and force residuals, σ_act / σ_mass:
/// σ_mass² is the smallest RSS/(n - p) of the mass models (the best model that fits within the noise),
/// σ_act² the voltage sweeps' pure error (`pure_error`, which no library effect moves), or without
/// sweeps the variance of the residuals of `act`'s bases. σ_mass is held above 1e-4 so that noise-free
/// masses do not pin the fit.
pub(super) fn mass_weight(mass_candidates: &[Candidate], sigma_act2: f64) -> f64 {
    let sigma_mass2 = mass_candidates
        .iter()
        .filter(|c| c.n > c.values.len())
        .map(|c| c.rss / (c.n - c.values.len()) as f64)
        .fold(f64::INFINITY, f64::min)
        .max(1e-8);
    let w = (sigma_act2 / sigma_mass2).sqrt();
    if w.is_finite() && w > 0.0 {
        w
    } else {
        1.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_quadratic_is_exact_on_a_quadratic_in_two_parameters() {
        // ln q = 1 + 0.3 t0 - 0.2 t1 + 0.05 t0² + 0.02 t1² - 0.07 t0 t1, sampled at the nodes.
        let f = |t: &[f64]| {
            (1.0 + 0.3 * t[0] - 0.2 * t[1] + 0.05 * t[0] * t[0] + 0.02 * t[1] * t[1]
                - 0.07 * t[0] * t[1])
                .exp()
        };
        let values: Vec<f64> = nodes(2).iter().map(|t| f(t)).collect();
        let q = Quadratic::fit(&values, 2);
        for t in [[0.3, -1.7], [2.0, 2.0], [-1.2, 0.4]] {
            assert!((q.eval(&t) / f(&t) - 1.0).abs() < 1e-12);
        }
    }

    #[test]
    fn the_stack_quadratic_holds_the_exact_stack_over_the_trust_region() {
        use crate::calibrate::csv::parse;
        // A thesis-like actuator with an extension; ply thickness and bond layer moved together over
        // two steps either side of the centre (s 1.3 ± 0.3, t_b 30 ± 24 µm).
        let data = parse(
            "id,l_tot_mm,l_r,w0_mm,w_r,t_p_mm,layup,voltage_V,mass_mg,free_deflection_mm,blocked_force_N\n\
             a,30,0.6,8,1.2,0.191,0/90/0/90/0,150,60,0.3,0.05\n",
        )
        .expect("a valid row");
        let a = data.rows[0].actuator();
        let (s0, hs, b0, hb) = (1.3, 0.15, 30.0, 12.0);
        let at = |s: f64, b: f64| {
            let mut m = EffectModel::default();
            EffectId::PlyThickness.apply(&mut m, s);
            EffectId::BondLayer.apply(&mut m, b);
            m.basis(&a).expect("a physical stack")
        };
        let bases: Vec<StackBasis> = nodes(2)
            .iter()
            .map(|t| at(s0 + t[0] * hs, b0 + t[1] * hb))
            .collect();
        type Pick = fn(&StackBasis) -> f64;
        let picks: [Pick; 3] = [
            |b| b.free_curvature,
            |b| b.beam_compliance,
            |b| b.extension_compliance,
        ];
        let mut worst: f64 = 0.0;
        for pick in picks {
            let q = Quadratic::fit(&bases.iter().map(pick).collect::<Vec<_>>(), 2);
            for (ts, tb) in [
                (2.0, -2.0),
                (-2.0, 2.0),
                (1.5, 1.5),
                (-0.5, -2.0),
                (0.5, 0.5),
            ] {
                let exact = pick(&at(s0 + ts * hs, b0 + tb * hb));
                worst = worst.max((q.eval(&[ts, tb]) / exact - 1.0).abs());
            }
        }
        // 1 %, five times below the 5 % noise of one deflection or force, with the largest steps the
        // stencil takes (0.75 % measured; the usual step, two masses-only standard errors, is smaller).
        assert!(worst < 1e-2, "worst relative error {worst}");
    }
}
