//! Stage 1 of the selection (docs/calibration.md §3): the mass effects fitted on the measured masses,
//! and the mass models carried into the actuation stage.

use super::acceptance::{best_and_rivals_indices, gains_among, judge};
use super::candidate::{Candidate, Role};
use super::observations::MassData;
use super::{declared_in, note_not_identifiable, FitSetup, Settings};
use crate::calibrate::csv::Dataset;
use crate::calibrate::library::{EffectId, Stage};
use actuator_model::EffectModel;
use rayon::prelude::*;

/// What the mass stage concluded.
pub(super) struct MassStage<'a> {
    /// The log mass of each weighed actuator.
    pub(super) data: MassData<'a>,
    /// Mass-stage models (empty with fewer than 4 weighed actuators).
    pub(super) candidates: Vec<Candidate>,
    /// The model the masses choose and its rivals, best first (indices in `candidates`).
    pub(super) ranking: Vec<usize>,
    /// Mass models to carry into the actuation stage (None: the original): the one the masses choose,
    /// and every other whose own effects are significant on the masses (docs/calibration.md §3, "Mass
    /// effects on all the data").
    pub(super) bases: Vec<Option<usize>>,
    /// Index in `bases` of the original mass model carried beside a mass effect the masses chose.
    pub(super) no_mass_effect: Option<usize>,
}

/// Stage 1: every mass effect, and every pair with 8 weighed actuators or more, against the original
/// mass model, judged on the measured masses.
pub(super) fn mass_stage<'a>(
    data: &'a Dataset,
    settings: &Settings,
    setup: &FitSetup,
    notes: &mut Vec<String>,
) -> MassStage<'a> {
    let mut stage = MassStage {
        data: weighed(data),
        candidates: Vec::new(),
        ranking: Vec::new(),
        bases: vec![None],
        no_mass_effect: None,
    };
    if stage.data.obs.len() < 4 {
        notes.push(
            "fewer than 4 actuators with a measured mass: mass effects (ply-thickness, bond-layer) \
             were not fitted"
                .into(),
        );
        return stage;
    }
    let fitter = setup.fitter(&stage.data, EffectModel::default(), Vec::new());
    let sets = mass_sets(settings, stage.data.obs.len());
    let mut candidates: Vec<Candidate> = sets
        .par_iter()
        .map(|(ids, role)| fitter.fit(ids, Stage::Mass, *role))
        .collect();
    judge(&mut candidates, &[0], settings);
    note_not_identifiable(&candidates, notes);
    stage.ranking = best_and_rivals_indices(&candidates, settings);
    let chosen = stage.ranking.first().copied().unwrap_or(0);
    stage.bases = vec![Some(chosen)];
    for (i, c) in candidates.iter().enumerate() {
        if i != chosen && c.role == Role::Candidate && c.not_identifiable.is_empty() {
            // Significant on the masses, after the multiplicity of the mass stage's candidates: a
            // rival carried by chance would be one more way to select an effect on null data.
            let significant = (0..c.effects.len()).all(|k| c.excludes_null(k))
                && gains_among(&candidates, i, 0, settings);
            if significant {
                stage.bases.push(Some(i));
            }
        }
    }
    // With measured resonances the original mass model is carried too: `f1` measures the mass a
    // second way, and a mass effect the masses chose by chance is one the resonances can refute
    // (docs/calibration.md §3, "No mass effect").
    let resonances = data.rows.iter().any(|r| r.resonance.is_some());
    if resonances && chosen != 0 {
        stage.bases.push(Some(0));
        stage.no_mass_effect = Some(stage.bases.len() - 1);
    }
    stage.candidates = candidates;
    stage
}

/// The log of each weighed actuator's mass, from its first row with one.
fn weighed(data: &Dataset) -> MassData<'_> {
    let mut seen = vec![false; data.actuators()];
    let mut obs = Vec::new();
    for (i, r) in data.rows.iter().enumerate() {
        let g = data.group_of[i];
        if let (false, Some(m)) = (seen[g], r.mass) {
            seen[g] = true;
            obs.push((g, i, m.ln()));
        }
    }
    MassData::new(data, obs)
}

/// The mass stage's effect sets: the original, each mass effect with its parameters (a declared effect
/// may have several), and with two effects allowed and 8 weighed actuators or more, every pair.
fn mass_sets(settings: &Settings, weighed: usize) -> Vec<(Vec<EffectId>, Role)> {
    let mass_effects: Vec<Vec<EffectId>> = [EffectId::PlyThickness, EffectId::BondLayer]
        .into_iter()
        .map(|e| vec![e])
        .chain(declared_in(settings, Stage::Mass))
        .collect();
    let mut sets: Vec<(Vec<EffectId>, Role)> = vec![(vec![], Role::Original)];
    for e in &mass_effects {
        sets.push((e.clone(), Role::Candidate));
    }
    if settings.max_effects >= 2 && weighed >= 8 {
        for (i, a) in mass_effects.iter().enumerate() {
            for b in &mass_effects[i + 1..] {
                sets.push(([a.as_slice(), b].concat(), Role::Candidate));
            }
        }
    }
    sets
}
