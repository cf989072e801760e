//! Model selection (docs/calibration.md §3): mass effects first, then every subset of at most two effects
//! (+ η) against the null models {η} and {η, uniform stiffness}, by AICc and grouped cross-validation,
//! with covariance intervals, an adequacy test and a verdict that refuses to name an effect it cannot
//! tell apart or that leaves the residual following a design variable.

mod acceptance;
pub mod adequacy;
pub mod candidate;
mod cross_validation;
pub(crate) mod fitter;
pub mod identifiability;
mod joint;
pub(crate) mod observations;
pub mod outliers;
mod resonance_weight;
pub mod separating;
pub mod settings;
pub(crate) mod stacks;
pub mod thickness;

pub use adequacy::Adequacy;
pub use candidate::{Candidate, Role};
pub use outliers::Outlier;
pub use separating::SeparatingDesign;
pub use settings::{max_parameters, Settings};

use crate::calibrate::csv::Dataset;
use crate::calibrate::library::{effect_names, EffectId, Stage};
use acceptance::{best_and_rivals, best_and_rivals_indices, judge};
use actuator_model::effects::Effects;
use actuator_model::effects::StackBasis;
use actuator_model::EffectModel;
use actuator_model::ModelError;
use adequacy::adequacy;
use cross_validation::folds;
use fitter::Fitter;
use joint::{can_carry, CarriedParameter, JointData};
use observations::{ActuationData, ActuationObs, MassData, ResonanceObs, Resonances, StageData};
use outliers::outliers;
use rayon::prelude::*;
use separating::separate;
use stacks::Stacks;

/// The verdict a calibration reports (docs/calibration.md §3).
#[derive(Debug, Clone, PartialEq)]
pub enum Verdict {
    /// The original model (no significant d31 scale) fits within the noise.
    NoEffect,
    /// The selected effects explain the residual.
    Explained,
    /// Several effect sets fit equally well.
    Ambiguous {
        /// The competing effect sets.
        contenders: Vec<Vec<String>>,
    },
    /// The residual still follows a variable no selected effect explains.
    NotExplained {
        /// The variable it follows most strongly.
        variable: String,
    },
    /// Too little data is left to support a verdict (after excluding broken actuators).
    InsufficientData {
        /// Why.
        reason: String,
    },
}

impl Verdict {
    /// The name written to report.json.
    pub fn name(&self) -> &'static str {
        match self {
            Verdict::NoEffect => "no-effect",
            Verdict::Explained => "explained",
            Verdict::Ambiguous { .. } => "ambiguous",
            Verdict::NotExplained { .. } => "not-explained",
            Verdict::InsufficientData { .. } => "insufficient-data",
        }
    }
}

/// Everything the selection concluded.
#[derive(Debug, Clone)]
pub struct Selection {
    /// Verdict.
    pub verdict: Verdict,
    /// Mass-stage models (empty without mass data).
    pub mass_candidates: Vec<Candidate>,
    /// Actuation-stage models.
    pub candidates: Vec<Candidate>,
    /// Index of the final actuation model in `candidates`.
    pub final_index: usize,
    /// Index in `candidates` of the model the selection chose before the thickness forms were compared
    /// (`final_index` when none replaced it): broken actuators are screened against it, since a
    /// thickness form fits a trend over the plate groups that a few broken actuators of one thickness
    /// can make, and against such a fit they no longer stand out (docs/calibration.md §3).
    pub screening_index: usize,
    /// Index of the final mass model in `mass_candidates`.
    pub final_mass_index: Option<usize>,
    /// The calibrated effects.
    pub model: EffectModel,
    /// Selected effects (mass stage first).
    pub selected: Vec<EffectId>,
    /// Adequacy of the final model.
    pub adequacy: Adequacy,
    /// Flagged rows.
    pub outliers: Vec<Outlier>,
    /// Designs that separate ambiguous contenders.
    pub separating_designs: Vec<SeparatingDesign>,
    /// Remarks for the report.
    pub notes: Vec<String>,
}

/// Run the whole selection.
pub fn select(data: &Dataset, settings: &Settings) -> Result<Selection, ModelError> {
    let mut notes = Vec::new();
    let groups = data.actuators();
    let folds_of = folds(groups, settings);
    let l_p_min_mm = data
        .rows
        .iter()
        .map(|r| r.planform.piezo_length() * 1e3)
        .fold(f64::INFINITY, f64::min);
    let dead_length_max_mm = 0.8 * l_p_min_mm;
    let shared = identifiability::shared_design(data);

    // --- Stage 1: mass effects on the measured masses, then frozen.
    let mut seen = vec![false; groups];
    let mut mass_obs = Vec::new();
    for (i, r) in data.rows.iter().enumerate() {
        let g = data.group_of[i];
        if let (false, Some(m)) = (seen[g], r.mass) {
            seen[g] = true;
            mass_obs.push((g, i, m.ln()));
        }
    }
    let mass_data = MassData {
        data,
        obs: mass_obs,
    };
    let mut mass_candidates = Vec::new();
    let mut selected = Vec::new();
    let mut contenders: Vec<Vec<String>> = Vec::new();
    let mut final_mass_index = None;
    // Mass models to carry into the actuation stage: the one the masses choose, and every other whose own
    // effects are significant on the masses (docs/calibration.md §3, "Mass effects on all the data").
    let mut bases: Vec<Option<usize>> = vec![None];
    // Index in `bases` of the original mass model carried beside a mass effect the masses chose.
    let mut no_mass_effect: Option<usize> = None;
    let mut mass_ranking: Vec<usize> = Vec::new();
    if mass_data.obs.len() >= 4 {
        let fitter = Fitter {
            data: &mass_data,
            base: EffectModel::default(),
            folds: folds_of.clone(),
            dead_length_max_mm,
            shared: shared.clone(),
            carried: Vec::new(),
        };
        // Each effect with its parameters (a declared effect may have several).
        let mass_effects: Vec<Vec<EffectId>> = [EffectId::PlyThickness, EffectId::BondLayer]
            .into_iter()
            .map(|e| vec![e])
            .chain(declared_in(settings, Stage::Mass))
            .collect();
        let mut sets: Vec<(Vec<EffectId>, Role)> = vec![(vec![], Role::Original)];
        for e in &mass_effects {
            sets.push((e.clone(), Role::Candidate));
        }
        if settings.max_effects >= 2 && mass_data.obs.len() >= 8 {
            for (i, a) in mass_effects.iter().enumerate() {
                for b in &mass_effects[i + 1..] {
                    sets.push(([a.as_slice(), b].concat(), Role::Candidate));
                }
            }
        }
        mass_candidates = sets
            .par_iter()
            .map(|(ids, role)| fitter.fit(ids, Stage::Mass, *role))
            .collect();
        judge(&mut mass_candidates, &[0], settings);
        note_not_identifiable(&mass_candidates, &mut notes);
        mass_ranking = best_and_rivals_indices(&mass_candidates, settings);
        let chosen = mass_ranking.first().copied().unwrap_or(0);
        bases = vec![Some(chosen)];
        for (i, c) in mass_candidates.iter().enumerate() {
            if i != chosen && c.role == Role::Candidate && c.not_identifiable.is_empty() {
                let significant = (0..c.effects.len()).all(|k| c.excludes_null(k));
                if significant {
                    bases.push(Some(i));
                }
            }
        }
        // With measured resonances the original mass model is carried too: `f1` measures the mass a
        // second way, and a mass effect the masses chose by chance is one the resonances can refute
        // (docs/calibration.md §3, "No mass effect").
        let resonances = data.rows.iter().any(|r| r.resonance.is_some());
        if resonances && chosen != 0 {
            bases.push(Some(0));
            no_mass_effect = Some(bases.len() - 1);
        }
    } else {
        notes.push(
            "fewer than 4 actuators with a measured mass: mass effects (ply-thickness, bond-layer) \
             were not fitted"
                .into(),
        );
    }

    // --- Stage 2: actuation and compliance effects on deflection and force, on each mass model carried.
    // A library mass model's parameters are fitted again with every actuation effect set, on the masses,
    // deflections and forces together, each weighted by its noise (docs/calibration.md §3).
    let carries = |b: &Option<usize>| b.is_some_and(|i| can_carry(&mass_candidates[i]));
    let mass_weight = if bases.iter().any(carries) {
        let original = EffectModel::default();
        let act = actuation_data(data, &original)?;
        let sigma_act2 = adequacy::pure_error_variance(&act, &original).unwrap_or_else(|| {
            let mut r = Vec::new();
            act.residuals(&original, None, &mut r);
            let n = r.len().max(2) as f64;
            let mean = r.iter().sum::<f64>() / n;
            r.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0)
        });
        joint::mass_weight(&mass_candidates, sigma_act2)
    } else {
        1.0
    };
    let mut stages = Vec::with_capacity(bases.len());
    for b in &bases {
        let base = b.map_or_else(EffectModel::default, |i| mass_candidates[i].model.clone());
        let joint = b.filter(|_| carries(b)).map(|i| {
            let m = &mass_candidates[i];
            let carried = (0..m.effects.len())
                .map(|k| CarriedParameter::of(m, k))
                .collect();
            (carried, &mass_data, mass_weight)
        });
        stages.push(actuation_stage(
            data,
            base,
            joint,
            settings,
            &folds_of,
            dead_length_max_mm,
            &shared,
        )?);
    }
    // The mass model the masses chose stands unless another fits masses, deflections and forces (and
    // resonances) together better by the acceptance margin (joint AICc: the two data sets' likelihoods
    // add; the masses' at the final model's mass parameters, where those were fitted on all the data).
    // With two resonances or more, the actuation part is that of each final model as estimated, with
    // the resonances weighted by their noise, one weight for all (resonance_weight.rs): the resonances
    // are the readings that tell a mass on the plates from a mass at the clamp, and they count by their
    // precision.
    let splits: Option<Vec<_>> = stages.iter().map(|st| st.split).collect();
    let weighted = splits
        .as_ref()
        .and_then(|s| Some((s, resonance_weight::weight(s)?)));
    let joint: Vec<f64> = bases
        .iter()
        .zip(&stages)
        .enumerate()
        .map(|(j, (b, st))| {
            let (fin, act) = match weighted {
                Some((splits, w)) => {
                    let s = &splits[j];
                    let n = s.n_act + s.n_f1;
                    let p = st.estimate.values.len();
                    let aicc = crate::calibrate::stats::aicc(n, p, s.weighted(w));
                    (&st.estimate, aicc)
                }
                None => {
                    let fin = &st.candidates[st.final_index];
                    (fin, fin.aicc)
                }
            };
            b.map_or(0.0, |i| {
                if fin.carried.is_empty() {
                    return mass_candidates[i].aicc;
                }
                let mut r = Vec::new();
                mass_data.residuals(&fin.model, None, &mut r);
                let rss = r.iter().map(|x| x * x).sum();
                crate::calibrate::stats::aicc(r.len(), mass_candidates[i].values.len(), rss)
            }) + act
        })
        .collect();
    let mut pick = 0;
    for j in 1..bases.len() {
        if joint[j] < joint[0] - settings.min_delta_aicc && joint[j] < joint[pick] {
            pick = j;
        }
    }
    // A mass effect is an added effect: on all the data it must beat no mass effect by the acceptance
    // margin, as every candidate must beat its nulls (§3, step 4); else the original mass model stands
    // (also where a joint AICc is not a number).
    let beats = |j: usize, o: usize| joint[j] < joint[o] - settings.min_delta_aicc;
    let refuted = no_mass_effect.filter(|&o| pick != o && !beats(pick, o));
    let mass_pick = pick;
    if let Some(o) = refuted {
        pick = o;
    }
    if let Some(i) = bases[pick] {
        final_mass_index = Some(i);
        selected.extend(mass_candidates[i].library_effects());
        let label = |k: usize| mass_candidates[k].label();
        if refuted.is_some() {
            let best = bases[mass_pick].map_or("original".into(), label);
            notes.push(format!(
                "the masses alone chose {}; on the masses, deflections, forces and resonances together {best} does not beat no mass effect by more than {} (joint AICc {:.1} with it, {:.1} without), so no mass effect was kept",
                bases[0].map_or("original".into(), label),
                settings.min_delta_aicc,
                joint[mass_pick],
                joint[pick]
            ));
        } else if pick != 0 {
            notes.push(format!(
                "the masses alone chose {}; {} fits the masses, deflections and forces{} together better (joint AICc {:.1} lower), so it was kept",
                bases[0].map_or("original".into(), label),
                label(i),
                if weighted.is_some() { " (and resonances)" } else { "" },
                joint[0] - joint[pick]
            ));
        }
        // Mass rivals stay contenders only if the joint fit cannot tell them apart either.
        for &r in mass_ranking.iter() {
            if r == i {
                continue;
            }
            let close = bases
                .iter()
                .position(|b| *b == Some(r))
                .is_none_or(|j| joint[j] < joint[pick] + 2.0);
            if close {
                contenders.push(
                    mass_candidates[r]
                        .library_effects()
                        .iter()
                        .map(|e| e.name().to_string())
                        .collect(),
                );
            }
        }
    }
    let ActuationStage {
        mut act_data,
        mut candidates,
        estimate,
        rivals,
        split: _,
        final_index,
        screening_index,
        notes: stage_notes,
    } = stages.swap_remove(pick);
    notes.extend(stage_notes);
    contenders.extend(rivals);
    candidates[final_index] = estimate;
    let eta = EffectId::D31Scale;
    let chosen = &candidates[final_index];
    if let Some(k) = chosen.effects.iter().position(|e| *e == eta) {
        if chosen.excludes_null(k)
            && (chosen.values[k] - 1.0).abs() >= settings.min_relevant_d31_change
        {
            selected.insert(0, eta);
        }
    }
    selected.extend(chosen.library_effects());
    let model = chosen.model.clone();
    // The final model's stacks solved exactly at its mass parameters (refitted on all the data).
    let mass_model = if chosen.carried.is_empty() {
        final_mass_index.map(|i| mass_candidates[i].model.clone())
    } else {
        let mut m = EffectModel::default();
        for c in &chosen.carried {
            c.id.apply(&mut m, c.value);
        }
        act_data = actuation_data(data, &m)?;
        Some(m)
    };

    let adequacy = adequacy(
        data,
        &act_data,
        chosen,
        mass_model.as_ref(),
        &mass_data,
        settings,
    );
    let outliers = outliers(data, &act_data, chosen);
    let mut separating_designs = Vec::new();
    let verdict = if !adequacy.passed {
        Verdict::NotExplained {
            variable: adequacy
                .worst_variable
                .clone()
                .unwrap_or_else(|| "(lack of fit, no single variable)".into()),
        }
    } else if !contenders.is_empty() {
        let mut all = vec![effect_names(&selected)
            .into_iter()
            .map(String::from)
            .collect()];
        all.extend(contenders);
        if let Some(&rival) = best_and_rivals_indices(&candidates, settings).get(1) {
            separating_designs = separate(
                data,
                &candidates[final_index].model,
                &candidates[rival].model,
            );
        }
        Verdict::Ambiguous { contenders: all }
    } else if selected.is_empty() {
        Verdict::NoEffect
    } else {
        Verdict::Explained
    };
    Ok(Selection {
        verdict,
        mass_candidates,
        candidates,
        final_index,
        screening_index,
        final_mass_index,
        model,
        selected,
        adequacy,
        outliers,
        separating_designs,
        notes,
    })
}

/// What the actuation stage concluded on one mass model.
struct ActuationStage<'a> {
    act_data: ActuationData<'a>,
    candidates: Vec<Candidate>,
    /// The final candidate as estimated (resonance_weight.rs): its values, intervals and model.
    estimate: Candidate,
    /// The sums of squares of the estimate's deflections and forces and of its resonances (None
    /// without two resonances).
    split: Option<resonance_weight::Split>,
    /// Effect sets of the rivals of the best accepted model.
    rivals: Vec<Vec<String>>,
    final_index: usize,
    /// The final index before the thickness forms ([`Selection::screening_index`]).
    screening_index: usize,
    notes: Vec<String>,
}

/// Stage 2 on top of the mass model `base`: the nulls and every subset of at most two library effects
/// with η, judged; the final model is the best accepted one, else {η} if it beats the original, else
/// the original.
fn actuation_stage<'a>(
    data: &'a Dataset,
    base: EffectModel,
    joint: Option<(Vec<CarriedParameter>, &MassData, f64)>,
    settings: &Settings,
    folds_of: &[Vec<usize>],
    dead_length_max_mm: f64,
    shared: &Option<String>,
) -> Result<ActuationStage<'a>, ModelError> {
    let mut notes = Vec::new();
    let groups = data.actuators();
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
    let act_data = ActuationData {
        data,
        obs,
        groups,
        frozen_primitives: base.primitives.len(),
        resonances: resonance_obs(data, &base, &stacks)?,
        stacks,
    };
    // With a carried mass model, every model starts from the original and applies the mass parameters
    // it fits; the stacks are held as quadratics in them (joint.rs).
    let (stage_data, carried, base) = match joint {
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
    };
    let fitter = Fitter {
        data: stage_data.as_dyn(),
        base,
        folds: folds_of.to_vec(),
        dead_length_max_mm,
        shared: shared.clone(),
        carried,
    };
    let eta = EffectId::D31Scale;
    // Each effect with its parameters (a declared effect may have several).
    let library: Vec<Vec<EffectId>> = EffectId::LIBRARY
        .into_iter()
        .filter(|e| *e != eta && e.stage() == Stage::Actuation)
        .map(|e| vec![e])
        .chain(declared_in(settings, Stage::Actuation))
        .collect();
    let mut sets: Vec<(Vec<EffectId>, Role)> = vec![
        (vec![], Role::Original),
        (vec![eta], Role::Null),
        (vec![eta, EffectId::StiffnessScale], Role::Null),
    ];
    let n_points: usize = stage_data
        .act()
        .obs
        .iter()
        .map(|o| o.ln_delta.is_some() as usize + o.ln_force.is_some() as usize)
        .sum();
    // Parameter count at most n/10 (docs/calibration.md §3).
    let max_effects = settings.max_effects.min((n_points / 10).saturating_sub(1));
    if max_effects < settings.max_effects {
        notes.push(format!(
            "{n_points} data points: models limited to {max_effects} effect(s) besides eta (parameters <= n/10)"
        ));
    }
    // An effect with several parameters counts them all against the n/10 rule.
    let max_params = n_points / 10;
    if max_effects >= 1 {
        for a in &library {
            sets.push(([&[eta], a.as_slice()].concat(), Role::Candidate));
        }
    }
    if max_effects >= 2 {
        for (i, a) in library.iter().enumerate() {
            for b in &library[i + 1..] {
                sets.push(([&[eta], a.as_slice(), b].concat(), Role::Candidate));
            }
        }
    }
    sets.retain(|(ids, role)| *role != Role::Candidate || ids.len() <= max_params);
    let mut candidates: Vec<Candidate> = sets
        .par_iter()
        .map(|(ids, role)| fitter.fit(ids, Stage::Actuation, *role))
        .collect();
    judge(&mut candidates, &[1, 2], settings);
    note_not_identifiable(&candidates, &mut notes);
    let (best, mut rivals) = best_and_rivals(&candidates, settings);
    let mut final_index = match best {
        Some(b) => b,
        None => {
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
    };
    let screening_index = final_index;
    // The chosen model against its thickness-dependent alternatives, when the PZT thickness varies.
    let thickness_forms = thickness::forms(data, &settings.declared);
    if !thickness_forms.is_empty() {
        let own = candidates[final_index].library_effects();
        let mut forms = Vec::new();
        for &t in &thickness_forms {
            forms.push(vec![eta, t]);
            if !own.is_empty() && effect_names(&own).len() < max_effects {
                forms.push([&[eta], own.as_slice(), &[t]].concat());
            }
        }
        forms.retain(|ids| ids.len() <= max_params);
        // Screened on AICc and intervals first; only a form that passes those is cross-validated.
        let fits: Vec<Candidate> = forms
            .par_iter()
            .map(|ids| fitter.fit_without_cv(ids, Stage::Actuation, Role::Candidate))
            .filter(|c| thickness::qualifies(c, &candidates[final_index]))
            .map(|c| fitter.fit(&c.effects, Stage::Actuation, Role::Candidate))
            .collect();
        if let Some(i) = thickness::preferred(&fits, &candidates[final_index]) {
            let mut c = fits[i].clone();
            let was = &candidates[final_index];
            notes.push(format!(
                "the PZT thickness varies: {} fits better than {} by AICc {:.1} (more than {}), so the \
                 loss is taken as thickness-dependent",
                c.label(),
                was.label(),
                was.aicc - c.aicc,
                thickness::DECISIVE_GAIN
            ));
            c.accepted = true;
            c.note = format!(
                "thickness form: dAICc vs {} {:.1}",
                was.label(),
                was.aicc - c.aicc
            );
            candidates.push(c);
            final_index = candidates.len() - 1;
            rivals.clear();
        }
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

/// The declared effects fitted on one stage's data, each as the list of its parameters on that stage
/// (fitted together).
fn declared_in(settings: &Settings, stage: Stage) -> Vec<Vec<EffectId>> {
    let mut groups: Vec<Vec<EffectId>> = Vec::new();
    for &d in &settings.declared {
        let id = EffectId::Declared(d);
        if id.stage() != stage {
            continue;
        }
        match groups.last_mut() {
            Some(g) if g[0].name() == id.name() => g.push(id),
            _ => groups.push(vec![id]),
        }
    }
    groups
}

/// One note per effect the data cannot determine, from the models that fit it alone (with η).
fn note_not_identifiable(candidates: &[Candidate], notes: &mut Vec<String>) {
    for c in candidates {
        if effect_names(&c.library_effects()).len() != 1 {
            continue;
        }
        for (id, reason) in &c.not_identifiable {
            notes.push(format!(
                "{} ({}) is not identifiable and was not selected: {reason}",
                id.name(),
                id.param().name
            ));
        }
    }
}

/// The adequacy tests (§3) of a given model on `data`, without a selection: `effects` with `params` of
/// them fitted to the deflections and forces (mass residuals are not tested). Used by the power study.
pub fn adequacy_of(
    data: &Dataset,
    effects: &Effects,
    params: usize,
    settings: &Settings,
) -> Result<Adequacy, ModelError> {
    let effects = EffectModel::from(*effects);
    let act = actuation_data(data, &effects)?;
    let mut res = Vec::new();
    act.residuals(&effects, None, &mut res);
    Ok(adequacy::adequacy_of_fit(
        data,
        &act,
        (&effects, params),
        None,
        settings,
    ))
}

/// The actuation stage's data on top of `base` (its stack effects solved once per row).
pub(crate) fn actuation_data<'a>(
    data: &'a Dataset,
    base: &EffectModel,
) -> Result<ActuationData<'a>, ModelError> {
    let stacks = Stacks::new(data);
    Ok(ActuationData {
        data,
        obs: actuation_obs(data, base, &stacks)?,
        groups: data.actuators(),
        frozen_primitives: base.primitives.len(),
        resonances: resonance_obs(data, base, &stacks)?,
        stacks,
    })
}

/// Row `row`'s stack basis under `base` from the solved stacks, or the model's own error where it cannot
/// be evaluated.
fn basis_of(
    data: &Dataset,
    base: &EffectModel,
    solver: &mut stacks::Solver,
    row: usize,
) -> Result<StackBasis, ModelError> {
    match solver.basis(row) {
        Some(b) => Ok(b),
        None => base.basis(&data.rows[row].actuator()),
    }
}

/// The actuators with a measured first resonance, each with its stack solved under `base`.
fn resonance_obs(
    data: &Dataset,
    base: &EffectModel,
    stacks: &Stacks,
) -> Result<Resonances, ModelError> {
    let mut solver = stacks.solver(data, base);
    let mut obs = Vec::new();
    for (group, rows) in data.groups.iter().enumerate() {
        let row = rows[0];
        let r = &data.rows[row];
        if let Some(f) = r.resonance {
            obs.push(ResonanceObs {
                group,
                row,
                basis: basis_of(data, base, &mut solver, row)?,
                ln_frequency: f.ln(),
            });
        }
    }
    Ok(Resonances::new(obs))
}

/// The rows with a measured deflection or force at a non-zero drive, each with its stack solved under the
/// stack effects of `base`.
fn actuation_obs(
    data: &Dataset,
    base: &EffectModel,
    stacks: &Stacks,
) -> Result<Vec<ActuationObs>, ModelError> {
    let mut solver = stacks.solver(data, base);
    let mut obs = Vec::new();
    for (i, r) in data.rows.iter().enumerate() {
        if r.voltage <= 0.0 || (r.free_deflection.is_none() && r.blocked_force.is_none()) {
            continue;
        }
        obs.push(ActuationObs {
            group: data.group_of[i],
            row: i,
            basis: basis_of(data, base, &mut solver, i)?,
            ln_delta: r.free_deflection.map(f64::ln),
            ln_force: r.blocked_force.map(f64::ln),
        });
    }
    Ok(obs)
}
