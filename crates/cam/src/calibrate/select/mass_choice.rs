//! Which mass model the selection keeps: the one the masses chose stands unless another fits the
//! masses, deflections and forces (and resonances) together better by the acceptance margin, and a mass
//! effect must beat no mass effect on all the data (docs/calibration.md §3, "Mass effects on all the
//! data", "No mass effect").

use super::actuation_stage::ActuationStage;
use super::mass_stage::MassStage;
use super::observations::StageData;
use super::{resonance_weight, Settings};
use crate::calibrate::library::EffectId;
use crate::calibrate::stats::aicc;

/// The mass model kept.
pub(super) struct MassChoice {
    /// Index in the mass stage's `bases` (and in the actuation stages) of the model kept.
    pub(super) pick: usize,
    /// Its index in the mass stage's candidates (None: the original mass model).
    pub(super) final_mass_index: Option<usize>,
    /// Its library effects.
    pub(super) selected: Vec<EffectId>,
    /// The mass rivals the joint fit cannot tell from it either, as effect names.
    pub(super) contenders: Vec<Vec<String>>,
}

/// The mass model kept, from the actuation stage fitted on each carried mass model (`stages`, in the
/// order of `mass.bases`).
pub(super) fn choose(
    mass: &MassStage,
    stages: &[ActuationStage],
    settings: &Settings,
    notes: &mut Vec<String>,
) -> MassChoice {
    // With two resonances or more, the actuation part is that of each final model as estimated, with
    // the resonances weighted by their noise, one weight for all (resonance_weight.rs): the resonances
    // are the readings that tell a mass on the plates from a mass at the clamp, and they count by their
    // precision.
    let splits: Option<Vec<_>> = stages.iter().map(|st| st.split).collect();
    let weighted = splits
        .as_ref()
        .and_then(|s| Some((s, resonance_weight::weight(s)?)));
    let joint = joint_aicc(mass, stages, weighted);
    let mut pick = 0;
    for j in 1..mass.bases.len() {
        if joint[j] < joint[0] - settings.min_delta_aicc && joint[j] < joint[pick] {
            pick = j;
        }
    }
    // A mass effect is an added effect: on all the data it must beat no mass effect by the acceptance
    // margin, as every candidate must beat its nulls (§3, step 4); else the original mass model stands
    // (also where a joint AICc is not a number).
    let beats = |j: usize, o: usize| joint[j] < joint[o] - settings.min_delta_aicc;
    let refuted = mass
        .no_mass_effect
        .filter(|&o| pick != o && !beats(pick, o));
    let mass_pick = pick;
    if let Some(o) = refuted {
        pick = o;
    }
    let mut choice = MassChoice {
        pick,
        final_mass_index: None,
        selected: Vec::new(),
        contenders: Vec::new(),
    };
    let Some(i) = mass.bases[pick] else {
        return choice;
    };
    let candidates = &mass.candidates;
    choice.final_mass_index = Some(i);
    choice.selected.extend(candidates[i].library_effects());
    let label = |k: usize| candidates[k].label();
    if refuted.is_some() {
        let best = mass.bases[mass_pick].map_or("original".into(), label);
        notes.push(format!(
            "the masses alone chose {}; on the masses, deflections, forces and resonances together {best} does not beat no mass effect by more than {} (joint AICc {:.1} with it, {:.1} without), so no mass effect was kept",
            mass.bases[0].map_or("original".into(), label),
            settings.min_delta_aicc,
            joint[mass_pick],
            joint[pick]
        ));
    } else if pick != 0 {
        notes.push(format!(
            "the masses alone chose {}; {} fits the masses, deflections and forces{} together better (joint AICc {:.1} lower), so it was kept",
            mass.bases[0].map_or("original".into(), label),
            label(i),
            if weighted.is_some() { " (and resonances)" } else { "" },
            joint[0] - joint[pick]
        ));
    }
    // Mass rivals stay contenders only if the joint fit cannot tell them apart either.
    for &r in mass.ranking.iter() {
        if r == i {
            continue;
        }
        let close = mass
            .bases
            .iter()
            .position(|b| *b == Some(r))
            .is_none_or(|j| joint[j] < joint[pick] + 2.0);
        if close {
            choice.contenders.push(
                candidates[r]
                    .library_effects()
                    .iter()
                    .map(|e| e.name().to_string())
                    .collect(),
            );
        }
    }
    choice
}

/// The joint AICc of each carried mass model with its actuation stage: the two data sets' likelihoods
/// add; the masses' at the final model's mass parameters, where those were fitted on all the data.
/// With `weighted` (each stage's sums of squares and the resonances' weight), the actuation part is that
/// of each final model as estimated.
fn joint_aicc(
    mass: &MassStage,
    stages: &[ActuationStage],
    weighted: Option<(&Vec<resonance_weight::Split>, f64)>,
) -> Vec<f64> {
    mass.bases
        .iter()
        .zip(stages)
        .enumerate()
        .map(|(j, (b, st))| {
            let (fin, act) = match weighted {
                Some((splits, w)) => {
                    let s = &splits[j];
                    let n = s.n_act + s.n_f1;
                    let p = st.estimate.values.len();
                    (&st.estimate, aicc(n, p, s.weighted(w)))
                }
                None => {
                    let fin = &st.candidates[st.final_index];
                    (fin, fin.aicc)
                }
            };
            b.map_or(0.0, |i| {
                if fin.carried.is_empty() {
                    return mass.candidates[i].aicc;
                }
                let mut r = Vec::new();
                mass.data.residuals(&fin.model, None, &mut r);
                let rss = r.iter().map(|x| x * x).sum();
                aicc(r.len(), mass.candidates[i].values.len(), rss)
            }) + act
        })
        .collect()
}
