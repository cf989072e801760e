//! Model selection (docs/calibration.md §3): mass effects first, then every subset of at most two effects
//! (+ η) against the null models {η} and {η, uniform stiffness}, by AICc and grouped cross-validation,
//! with covariance intervals, an adequacy test and a verdict that refuses to name an effect it cannot
//! tell apart or that leaves the residual following a design variable.

mod acceptance;
mod actuation_stage;
pub mod adequacy;
pub mod candidate;
mod cross_validation;
pub(crate) mod drive_groups;
pub(crate) mod fitter;
pub mod identifiability;
mod joint;
mod mass_choice;
mod mass_stage;
pub(crate) mod observations;
pub mod outliers;
mod pooled;
pub mod resonance_tests;
mod resonance_weight;
mod resonances;
mod robust;
pub mod separating;
pub mod settings;
pub(crate) mod stacks;
pub mod thickness;
mod touches;
pub mod verdict;

pub use adequacy::Adequacy;
pub use candidate::{Candidate, Role};
pub use outliers::Outlier;
pub use separating::SeparatingDesign;
pub use settings::{max_parameters, Settings};
pub use verdict::Verdict;

use crate::calibrate::csv::Dataset;
use crate::calibrate::library::{effect_names, EffectId, Stage};
use acceptance::best_and_rivals_indices;
use actuation_stage::{actuation_stages, ActuationStage};
use actuator_model::effects::Effects;
use actuator_model::effects::StackBasis;
use actuator_model::EffectModel;
use actuator_model::ModelError;
use adequacy::adequacy;
use cross_validation::folds;
use fitter::Fitter;
use joint::CarriedParameter;
use mass_choice::MassChoice;
use mass_stage::MassStage;
use observations::{ActuationData, ActuationObs, ResonanceObs, Resonances, StageData};
use outliers::outliers;
use separating::separate;
use stacks::Stacks;
use verdict::{decide, Grounds};

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

/// Run the whole selection: the mass stage, the actuation stage on each mass model it carries, the mass
/// model kept, and the final model's adequacy, outliers and verdict.
pub fn select(data: &Dataset, settings: &Settings) -> Result<Selection, ModelError> {
    let mut notes = Vec::new();
    let setup = FitSetup::of(data, settings);
    let mass = mass_stage::mass_stage(data, settings, &setup, &mut notes);
    let mut stages = actuation_stages(data, &mass, settings, &setup)?;
    let choice = mass_choice::choose(&mass, &stages, settings, &mut notes);
    let stage = stages.swap_remove(choice.pick);
    conclude(data, settings, mass, choice, stage, notes)
}

/// What every fit of one selection shares.
struct FitSetup {
    /// Fold of each actuator, per repeat.
    folds: Vec<Vec<usize>>,
    /// Upper bound of the dead length: 80% of the shortest piezo length in the data.
    dead_length_max_mm: f64,
    /// What all actuators share (identifiability reasons), if anything.
    shared: Option<String>,
}

impl FitSetup {
    fn of(data: &Dataset, settings: &Settings) -> Self {
        let l_p_min_mm = data
            .rows
            .iter()
            .map(|r| r.planform.piezo_length() * 1e3)
            .fold(f64::INFINITY, f64::min);
        FitSetup {
            folds: folds(data.actuators(), settings),
            dead_length_max_mm: 0.8 * l_p_min_mm,
            shared: identifiability::shared_design(data),
        }
    }

    /// A fitter of `data` on top of `base`, fitting the `carried` mass parameters again with every set.
    fn fitter<'a>(
        &self,
        data: &'a dyn StageData,
        base: EffectModel,
        carried: Vec<CarriedParameter>,
    ) -> Fitter<'a> {
        Fitter {
            data,
            base,
            folds: self.folds.clone(),
            dead_length_max_mm: self.dead_length_max_mm,
            shared: self.shared.clone(),
            carried,
        }
    }
}

/// The selection from the actuation stage on the mass model kept: η selected when its scale is
/// significant and relevant, the final model's stacks solved at its mass parameters, its adequacy,
/// outliers and verdict, and the designs that separate it from a rival when the verdict is ambiguous.
fn conclude(
    data: &Dataset,
    settings: &Settings,
    mass: MassStage,
    choice: MassChoice,
    stage: ActuationStage,
    mut notes: Vec<String>,
) -> Result<Selection, ModelError> {
    let ActuationStage {
        mut act_data,
        mut candidates,
        estimate,
        rivals,
        split: _,
        final_index,
        screening_index,
        notes: stage_notes,
    } = stage;
    let MassChoice {
        final_mass_index,
        mut selected,
        mut contenders,
        ..
    } = choice;
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
        final_mass_index.map(|i| mass.candidates[i].model.clone())
    } else {
        let mut m = EffectModel::default();
        for c in &chosen.carried {
            c.id.apply(&mut m, c.value);
        }
        act_data = actuation_data(data, &m)?;
        Some(m)
    };
    let mut adequacy = adequacy(
        data,
        &act_data,
        chosen,
        mass_model.as_ref(),
        &mass.data,
        settings,
    );
    let mass_pair = mass_model.as_ref().map(|m| (m, &mass.data));
    let after = touches::quantities(&act_data, &chosen.model, mass_pair);
    touches::name_in(&mut adequacy, data, &after, settings.alpha);
    let outliers = outliers(data, &act_data, chosen);
    // The actuation effects: a mass effect's interval is judged on the masses by the mass stage, and the
    // joint refit's interval beside the actuation model is not its acceptance (the loop study's added mass
    // per area leaves a bond layer's joint interval over its null).
    let actuation: Vec<EffectId> = selected
        .iter()
        .filter(|e| e.stage() != Stage::Mass)
        .cloned()
        .collect();
    let reported = acceptance::reported_intervals(
        &actuation,
        final_mass_index.map(|i| &mass.candidates[i]),
        chosen,
    );
    let contradicts = contradiction(
        data,
        (&act_data, mass_pair),
        &candidates,
        &after,
        &selected,
        settings,
    );
    let verdict = decide(Grounds::Fitted {
        adequacy: &adequacy,
        selected: &selected,
        contenders,
        holding_null: acceptance::holding_null(&reported),
        contradicts,
    });
    // The designs that would tell the selected model from its closest rival, when the data cannot.
    let rival = matches!(verdict, Verdict::Ambiguous { .. })
        .then(|| {
            best_and_rivals_indices(&candidates, settings)
                .get(1)
                .copied()
        })
        .flatten();
    let separating_designs = rival.map_or_else(Vec::new, |r| {
        separate(data, &candidates[final_index].model, &candidates[r].model)
    });
    Ok(Selection {
        verdict,
        mass_candidates: mass.candidates,
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

/// Why the chosen model, whose quantities' residuals are `after`, is refused, if it makes a measured
/// quantity follow a design variable that the original model among `candidates` fits
/// (docs/calibration.md §3, "Verdicts").
fn contradiction(
    data: &Dataset,
    (act, mass): (
        &ActuationData,
        Option<(&EffectModel, &observations::MassData)>,
    ),
    candidates: &[Candidate],
    after: &[(&'static str, touches::Points)],
    selected: &[EffectId],
    settings: &Settings,
) -> Option<String> {
    let original = candidates.iter().find(|c| c.role == Role::Original)?;
    let before = touches::quantities(act, &original.model, mass);
    touches::refusal(
        data,
        &before,
        after,
        &effect_names(selected),
        settings.alpha,
    )
}

/// The declared effects fitted on one stage's data, each as the list of its parameters on that stage
/// (fitted together).
fn declared_in(settings: &Settings, stage: Stage) -> Vec<Vec<EffectId>> {
    let mut groups: Vec<Vec<EffectId>> = Vec::new();
    for d in &settings.declared {
        let id = EffectId::Declared(d.clone());
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
    Ok(ActuationData::new(
        data,
        actuation_obs(data, base, &stacks)?,
        base.primitives.len(),
        resonance_obs(data, base, &stacks)?,
        stacks,
    ))
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
