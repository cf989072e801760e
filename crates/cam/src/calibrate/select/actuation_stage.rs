//! Stage 2 of the selection (docs/calibration.md §3): actuation and compliance effects on deflection and
//! force, on each mass model the mass stage carries. A library mass model's parameters are fitted again
//! with every actuation effect set, on the masses, deflections and forces together, each weighted by its
//! noise.

use super::acceptance::{best_and_rivals, judge};
use super::adequacy;
use super::candidate::{Candidate, Role};
use super::fitter::Fitter;
use super::joint::{self, can_carry, CarriedParameter, JointData};
use super::mass_stage::MassStage;
use super::observations::{ActuationData, MassData, StageData};
use super::stacks::Stacks;
use super::{
    actuation_data, actuation_obs, declared_in, max_parameters, note_not_identifiable,
    resonance_obs, resonance_weight, thickness, FitSetup, Settings,
};
use crate::calibrate::csv::Dataset;
use crate::calibrate::library::{effect_names, EffectId, Stage};
use actuator_model::EffectModel;
use actuator_model::ModelError;
use rayon::prelude::*;

/// What the actuation stage concluded on one mass model.
pub(super) struct ActuationStage<'a> {
    pub(super) act_data: ActuationData<'a>,
    pub(super) candidates: Vec<Candidate>,
    /// The final candidate as estimated (resonance_weight.rs): its values, intervals and model.
    pub(super) estimate: Candidate,
    /// The sums of squares of the estimate's deflections and forces and of its resonances (None
    /// without two resonances).
    pub(super) split: Option<resonance_weight::Split>,
    /// Effect sets of the rivals of the best accepted model.
    pub(super) rivals: Vec<Vec<String>>,
    pub(super) final_index: usize,
    /// The final index before the thickness forms ([`super::Selection::screening_index`]).
    pub(super) screening_index: usize,
    pub(super) notes: Vec<String>,
}

/// The actuation stage on each mass model the mass stage carries, in the order of `mass.bases`.
pub(super) fn actuation_stages<'a>(
    data: &'a Dataset,
    mass: &MassStage,
    settings: &Settings,
    setup: &FitSetup,
) -> Result<Vec<ActuationStage<'a>>, ModelError> {
    let carries = |b: &Option<usize>| b.is_some_and(|i| can_carry(&mass.candidates[i]));
    let mass_weight = if mass.bases.iter().any(carries) {
        mass_weight(data, &mass.candidates)?
    } else {
        1.0
    };
    let mut stages = Vec::with_capacity(mass.bases.len());
    for b in &mass.bases {
        let base = b.map_or_else(EffectModel::default, |i| mass.candidates[i].model.clone());
        let joint = b.filter(|_| carries(b)).map(|i| {
            let m = &mass.candidates[i];
            let carried = (0..m.effects.len())
                .map(|k| CarriedParameter::of(m, k))
                .collect();
            (carried, &mass.data, mass_weight)
        });
        stages.push(actuation_stage(data, base, joint, settings, setup)?);
    }
    Ok(stages)
}

/// The weight of the masses beside the deflections and forces in a joint fit ([`joint::mass_weight`]),
/// with the actuation noise from the voltage sweeps' pure error, or without sweeps the variance of the
/// original model's residuals.
fn mass_weight(data: &Dataset, mass_candidates: &[Candidate]) -> Result<f64, ModelError> {
    let original = EffectModel::default();
    let act = actuation_data(data, &original)?;
    let sigma_act2 = adequacy::pure_error_variance(&act, &original).unwrap_or_else(|| {
        let mut r = Vec::new();
        act.residuals(&original, None, &mut r);
        let n = r.len().max(2) as f64;
        let mean = r.iter().sum::<f64>() / n;
        r.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0)
    });
    Ok(joint::mass_weight(mass_candidates, sigma_act2))
}

/// Stage 2 on top of the mass model `base`: the nulls and every subset of at most two library effects
/// with η, judged; the final model is the best accepted one, else {η} if it beats the original, else
/// the original, unless a thickness form beats it decisively.
fn actuation_stage<'a>(
    data: &'a Dataset,
    base: EffectModel,
    joint: Option<(Vec<CarriedParameter>, &MassData, f64)>,
    settings: &Settings,
    setup: &FitSetup,
) -> Result<ActuationStage<'a>, ModelError> {
    let mut notes = Vec::new();
    let (stage_data, carried, base) = stage_input(data, base, joint, settings)?;
    let fitter = setup.fitter(stage_data.as_dyn(), base, carried);
    let n_points: usize = stage_data
        .act()
        .obs
        .iter()
        .map(|o| o.ln_delta.is_some() as usize + o.ln_force.is_some() as usize)
        .sum();
    // Parameter count at most n/10 (docs/calibration.md §3).
    let limits = Limits {
        max_effects: settings.max_effects.min((n_points / 10).saturating_sub(1)),
        // An effect with several parameters counts them all against the n/10 rule.
        max_params: n_points / 10,
    };
    if limits.max_effects < settings.max_effects {
        notes.push(format!(
            "{n_points} data points: models limited to {} effect(s) besides eta (parameters <= n/10)",
            limits.max_effects
        ));
    }
    let sets = actuation_sets(settings, &limits);
    let mut candidates: Vec<Candidate> = sets
        .par_iter()
        .map(|(ids, role)| fitter.fit(ids, Stage::Actuation, *role))
        .collect();
    judge(&mut candidates, &[1, 2], settings);
    note_not_identifiable(&candidates, &mut notes);
    let (best, mut rivals) = best_and_rivals(&candidates, settings);
    let screening_index = best.unwrap_or_else(|| null_choice(&candidates, settings));
    let mut final_index = screening_index;
    // The chosen model against its thickness-dependent alternatives, when the PZT thickness varies.
    if let Some(c) = thickness_form(data, &candidates[final_index], &fitter, settings, &limits) {
        notes.push(c.1);
        candidates.push(c.0);
        final_index = candidates.len() - 1;
        rivals.clear();
    }
    let (estimate, split) = weighted_estimate(&candidates[final_index], &stage_data, &fitter);
    drop(fitter);
    Ok(ActuationStage {
        act_data: stage_data.into_act(),
        candidates,
        estimate,
        split,
        rivals,
        final_index,
        screening_index,
        notes,
    })
}

/// How large a model the data support: effects besides η, and parameters in all.
struct Limits {
    max_effects: usize,
    max_params: usize,
}

/// The data an actuation stage fits on top of `base`, the mass parameters it fits again, and the model
/// every fit starts from. With a carried mass model, every model starts from the original and applies the
/// mass parameters it fits; the stacks are held as quadratics in them (joint.rs).
fn stage_input<'a>(
    data: &'a Dataset,
    base: EffectModel,
    joint: Option<(Vec<CarriedParameter>, &MassData, f64)>,
    settings: &Settings,
) -> Result<(StageInput<'a>, Vec<CarriedParameter>, EffectModel), ModelError> {
    let stacks = Stacks::new(data);
    let obs = actuation_obs(data, &base, &stacks)?;
    let act_groups: std::collections::BTreeSet<usize> = obs.iter().map(|o| o.group).collect();
    if act_groups.len() < max_parameters(settings) + 2 {
        return Err(ModelError::Fit(format!(
            "{} actuators with deflection or force data: the largest model has {} parameters and \
             needs at least {} actuators",
            act_groups.len(),
            max_parameters(settings),
            max_parameters(settings) + 2
        )));
    }
    let resonances = resonance_obs(data, &base, &stacks)?;
    let act_data = ActuationData::new(data, obs, base.primitives.len(), resonances, stacks);
    Ok(match joint {
        Some((carried, mass, weight)) => (
            StageInput::Joint(JointData::new(
                act_data,
                carried.clone(),
                Some(mass),
                weight,
            )?),
            carried,
            EffectModel::default(),
        ),
        None => (StageInput::Frozen(act_data), Vec::new(), base),
    })
}

/// The actuation stage's effect sets: the original, the nulls {η} and {η, stiffness-scale}, and η with
/// each actuation effect (each with its parameters: a declared effect may have several) and each pair,
/// as far as `limits` allow.
fn actuation_sets(settings: &Settings, limits: &Limits) -> Vec<(Vec<EffectId>, Role)> {
    let eta = EffectId::D31Scale;
    let library: Vec<Vec<EffectId>> = EffectId::LIBRARY
        .into_iter()
        .filter(|e| *e != eta && e.stage() == Stage::Actuation)
        .map(|e| vec![e])
        .chain(declared_in(settings, Stage::Actuation))
        .collect();
    let mut sets: Vec<(Vec<EffectId>, Role)> = vec![
        (vec![], Role::Original),
        (vec![eta.clone()], Role::Null),
        (vec![eta.clone(), EffectId::StiffnessScale], Role::Null),
    ];
    if limits.max_effects >= 1 {
        for a in &library {
            sets.push((
                [std::slice::from_ref(&eta), a.as_slice()].concat(),
                Role::Candidate,
            ));
        }
    }
    if limits.max_effects >= 2 {
        for (i, a) in library.iter().enumerate() {
            for b in &library[i + 1..] {
                sets.push((
                    [std::slice::from_ref(&eta), a.as_slice(), b.as_slice()].concat(),
                    Role::Candidate,
                ));
            }
        }
    }
    sets.retain(|(ids, role)| *role != Role::Candidate || ids.len() <= limits.max_params);
    sets
}

/// The final model when no candidate is accepted: {η} (index 1) if it beats the original by the margin
/// with a significant and relevant d31 scale, else the original (index 0).
fn null_choice(candidates: &[Candidate], settings: &Settings) -> usize {
    let (original, null_eta) = (&candidates[0], &candidates[1]);
    if null_eta.aicc < original.aicc - settings.min_delta_aicc
        && null_eta.excludes_null(0)
        && (null_eta.values[0] - 1.0).abs() >= settings.min_relevant_d31_change
    {
        1
    } else {
        0
    }
}

/// The thickness form that replaces `chosen` when the PZT thickness varies, accepted, with the note that
/// says why (None when none beats it decisively).
fn thickness_form(
    data: &Dataset,
    chosen: &Candidate,
    fitter: &Fitter,
    settings: &Settings,
    limits: &Limits,
) -> Option<(Candidate, String)> {
    let thickness_forms = thickness::forms(data, &settings.declared);
    if thickness_forms.is_empty() {
        return None;
    }
    let eta = EffectId::D31Scale;
    let own = chosen.library_effects();
    let mut forms = Vec::new();
    for t in thickness_forms {
        forms.push(vec![eta.clone(), t.clone()]);
        if !own.is_empty() && effect_names(&own).len() < limits.max_effects {
            forms.push([std::slice::from_ref(&eta), own.as_slice(), &[t]].concat());
        }
    }
    forms.retain(|ids| ids.len() <= limits.max_params);
    // Screened on AICc and intervals first; only a form that passes those is cross-validated.
    let fits: Vec<Candidate> = forms
        .par_iter()
        .map(|ids| fitter.fit_without_cv(ids, Stage::Actuation, Role::Candidate))
        .filter(|c| thickness::qualifies(c, chosen))
        .map(|c| fitter.fit(&c.effects, Stage::Actuation, Role::Candidate))
        .collect();
    let i = thickness::preferred(&fits, chosen)?;
    let mut c = fits[i].clone();
    let note = format!(
        "the PZT thickness varies: {} fits better than {} by AICc {:.1} (more than {}), so the \
         loss is taken as thickness-dependent",
        c.label(),
        chosen.label(),
        chosen.aicc - c.aicc,
        thickness::DECISIVE_GAIN
    );
    c.accepted = true;
    c.note = format!(
        "thickness form: dAICc vs {} {:.1}",
        chosen.label(),
        chosen.aicc - c.aicc
    );
    Some((c, note))
}

/// The chosen candidate fitted again with the resonances weighted by their noise (resonance_weight.rs),
/// or as it is without two resonances or anything to fit; with its residuals' sums of squares (None
/// without two resonances).
fn weighted_estimate(
    chosen: &Candidate,
    stage_data: &StageInput,
    fitter: &Fitter,
) -> (Candidate, Option<resonance_weight::Split>) {
    let resonances = &stage_data.act().resonances;
    let mut estimate = chosen.clone();
    let mut used = 1.0;
    let fixed = chosen.effects.is_empty() && chosen.carried.is_empty();
    for _ in 0..if fixed { 0 } else { resonance_weight::ROUNDS } {
        let Some(w) = resonance_weight::split(&estimate.fit.residuals, resonances.len(), used)
            .and_then(|s| resonance_weight::weight(&[s]))
        else {
            break;
        };
        if (w / used - 1.0).abs() < resonance_weight::SETTLED {
            break;
        }
        resonances.set_weight(w);
        let refit = fitter.fit_without_cv(&chosen.effects, chosen.stage, chosen.role);
        if refit.values.iter().any(|v| !v.is_finite()) {
            break;
        }
        estimate = resonance_weight::with_estimate(chosen, refit);
        used = w;
    }
    resonances.set_weight(1.0);
    let split = resonance_weight::split(&estimate.fit.residuals, resonances.len(), used);
    (estimate, split)
}

/// The data an actuation stage fits: deflection and force on a frozen mass model, or with the mass
/// model's parameters free and the masses beside them.
enum StageInput<'a> {
    Frozen(ActuationData<'a>),
    Joint(JointData<'a>),
}

impl<'a> StageInput<'a> {
    fn as_dyn(&self) -> &dyn StageData {
        match self {
            StageInput::Frozen(a) => a,
            StageInput::Joint(j) => j,
        }
    }
    fn act(&self) -> &ActuationData<'a> {
        match self {
            StageInput::Frozen(a) => a,
            StageInput::Joint(j) => &j.act,
        }
    }
    fn into_act(self) -> ActuationData<'a> {
        match self {
            StageInput::Frozen(a) => a,
            StageInput::Joint(j) => j.act,
        }
    }
}
