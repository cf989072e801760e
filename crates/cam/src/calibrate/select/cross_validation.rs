//! Repeated grouped K-fold cross-validation: whole actuators are held out, so a model is scored on
//! actuators it has not seen (docs/calibration.md §3).

use super::observations::StageData;
use super::settings::Settings;
use actuator_model::EffectModel;
use rand::seq::SliceRandom;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

/// Fold of each actuator for each repeat: the actuators shuffled by one seeded ChaCha8 stream (the
/// nester's generator; the same folds on every machine), then dealt round-robin into the folds.
pub(super) fn folds(groups: usize, settings: &Settings) -> Vec<Vec<usize>> {
    let k = settings.folds.clamp(2, groups.max(2));
    let mut rng = ChaCha8Rng::seed_from_u64(settings.seed);
    (0..settings.repeats.max(1))
        .map(|_| {
            let mut order: Vec<usize> = (0..groups).collect();
            order.shuffle(&mut rng);
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
    fit_train: impl Fn(&[bool]) -> EffectModel,
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
            data.held_out(&e, Some(&test), &mut out);
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn folds_are_balanced_seeded_and_differ_between_repeats() {
        let settings = Settings::default();
        let a = folds(23, &settings);
        assert_eq!(a, folds(23, &settings), "same seed, same folds");
        assert_eq!(a.len(), settings.repeats);
        for fold_of in &a {
            let mut sizes = vec![0; settings.folds];
            for &f in fold_of {
                sizes[f] += 1;
            }
            assert!(sizes.iter().all(|&n| n == 4 || n == 5), "{sizes:?}");
        }
        assert_ne!(a[0], a[1], "repeats shuffle differently");
        let other = Settings {
            seed: 2,
            ..settings.clone()
        };
        assert_ne!(a, folds(23, &other), "the seed changes the folds");
    }
}
