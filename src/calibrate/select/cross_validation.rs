//! Repeated grouped K-fold cross-validation: whole actuators are held out, so a model is scored on
//! actuators it has not seen (CALIBRATION-NOTES §3).

use super::observations::StageData;
use super::settings::Settings;
use actuator_model::effects::Effects;

/// splitmix64: a fixed, dependency-free generator for the fold assignment.
fn splitmix(state: &mut u64) -> u64 {
    *state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// Fold of each actuator for each repeat (deterministic from the seed).
pub(super) fn folds(groups: usize, settings: &Settings) -> Vec<Vec<usize>> {
    let k = settings.folds.clamp(2, groups.max(2));
    (0..settings.repeats.max(1))
        .map(|rep| {
            let mut state = settings.seed ^ (0xA5A5_0000 + rep as u64);
            let mut order: Vec<usize> = (0..groups).collect();
            for i in (1..groups).rev() {
                let j = (splitmix(&mut state) % (i as u64 + 1)) as usize;
                order.swap(i, j);
            }
            let mut fold = vec![0; groups];
            for (pos, &g) in order.iter().enumerate() {
                fold[g] = pos % k;
            }
            fold
        })
        .collect()
}

/// Root-mean-square held-out residual over every fold of every repeat. `fit_train` fits the model on
/// the actuators marked `true` and returns its effects.
pub(super) fn rmse(
    data: &dyn StageData,
    folds: &[Vec<usize>],
    fit_train: impl Fn(&[bool]) -> Effects,
) -> f64 {
    let groups = data.groups();
    let (mut sum, mut count) = (0.0, 0usize);
    let mut out = Vec::new();
    for fold_of in folds {
        let k = fold_of.iter().copied().max().unwrap_or(0) + 1;
        for fold in 0..k {
            let test: Vec<bool> = (0..groups).map(|g| fold_of[g] == fold).collect();
            let train: Vec<bool> = test.iter().map(|t| !t).collect();
            let e = fit_train(&train);
            data.residuals(&e, Some(&test), &mut out);
            sum += out.iter().map(|r| r * r).sum::<f64>();
            count += out.len();
        }
    }
    if count == 0 {
        f64::INFINITY
    } else {
        (sum / count as f64).sqrt()
    }
}
