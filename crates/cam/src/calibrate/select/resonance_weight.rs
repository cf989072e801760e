//! The chosen model estimated with each measured resonance weighted by its noise (docs/calibration.md
//! §3, "The resonance"): the models are compared with a resonance counted as one more deflection or
//! force reading, which is conservative; the one chosen is then fitted again by feasible weighted least
//! squares, each log `f1` residual times `σ_act / σ_f1`, the two noise levels read off its own residuals,
//! until the weight settles. A resonance read to 1 % beside deflections and forces read to 5 % then
//! counts as the 25 readings it is worth, and the calibrated `f1` follows the measured ones.

use super::candidate::Candidate;

/// Floor of `σ_f1` (log): noise-free resonances do not pin the fit (the masses' floor, joint.rs).
const SIGMA_FLOOR: f64 = 1e-4;

/// Most reweighting rounds; they stop sooner once the weight moves by less than [`SETTLED`].
pub(super) const ROUNDS: usize = 4;

/// Relative change of the weight below which it has settled.
pub(super) const SETTLED: f64 = 0.01;

/// A fit's scored residuals split into its deflections and forces and its resonances: the sum of
/// squares of the first, their count, and the sum of squares of the last `resonances` (the log `f1`
/// residuals, read times `used` and returned without it); None with fewer than two resonances or
/// nothing beside them.
pub(super) fn split(residuals: &[f64], resonances: usize, used: f64) -> Option<Split> {
    let n_act = residuals.len().checked_sub(resonances)?;
    if n_act == 0 || resonances < 2 || used <= 0.0 {
        return None;
    }
    let sum_sq = |r: &[f64]| r.iter().map(|x| x * x).sum::<f64>();
    Some(Split {
        act: sum_sq(&residuals[..n_act]),
        n_act,
        f1: sum_sq(&residuals[n_act..]) / (used * used),
        n_f1: resonances,
    })
}

/// The sums of squares of one fit's deflections and forces and of its resonances (unweighted).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Split {
    pub(super) act: f64,
    pub(super) n_act: usize,
    pub(super) f1: f64,
    pub(super) n_f1: usize,
}

impl Split {
    /// The sum of squares with the resonances weighted by `w`.
    pub(super) fn weighted(&self, w: f64) -> f64 {
        self.act + w * w * self.f1
    }
}

/// The weight `σ_act / σ_f1` of the fits `splits`: each σ the smallest root mean square of its kind
/// among them (the model that fits it within its noise, as the masses' σ, joint.rs), `σ_f1` held above
/// [`SIGMA_FLOOR`]; None without a fit or where it is not a number.
pub(super) fn weight(splits: &[Split]) -> Option<f64> {
    let least = |ms: fn(&Split) -> f64| splits.iter().map(ms).fold(f64::INFINITY, f64::min);
    let act = least(|s| s.act / s.n_act as f64);
    let f1 = least(|s| s.f1 / s.n_f1 as f64).max(SIGMA_FLOOR * SIGMA_FLOOR);
    let w = (act / f1).sqrt();
    (w.is_finite() && w > 0.0).then_some(w)
}

/// `chosen` with its estimate from `refit` (the same effects on the weighted data): values, intervals,
/// carried mass parameters, model and fit; the scores it was chosen by stay.
pub(super) fn with_estimate(chosen: &Candidate, refit: Candidate) -> Candidate {
    Candidate {
        values: refit.values,
        std_errors: refit.std_errors,
        intervals: refit.intervals,
        correlation: refit.correlation,
        carried: refit.carried,
        model: refit.model,
        fit: refit.fit,
        ..chosen.clone()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_weight_is_the_ratio_of_the_two_noise_levels() {
        // Deflections and forces at ±0.05, resonances at ±0.01 (weighted by 2 when they were read).
        let mut r = vec![0.05, -0.05, 0.05, -0.05];
        r.extend([0.02, -0.02, 0.02]);
        let fit = split(&r, 3, 2.0).unwrap();
        assert_eq!((fit.n_act, fit.n_f1), (4, 3));
        assert!((fit.f1 - 3e-4).abs() < 1e-15, "{fit:?}");
        let w = weight(&[fit]).unwrap();
        assert!((w - 5.0).abs() < 1e-12, "{w}");
        assert!((fit.weighted(w) - 0.01 - 25.0 * 3e-4).abs() < 1e-15);
    }

    #[test]
    fn each_noise_level_is_that_of_the_fit_that_reads_it_best() {
        let a = split(&[0.05, -0.05, 0.03, -0.03], 2, 1.0).unwrap();
        let b = split(&[0.1, -0.1, 0.01, -0.01], 2, 1.0).unwrap();
        assert!((weight(&[a, b]).unwrap() - 5.0).abs() < 1e-12);
    }

    #[test]
    fn noise_free_resonances_are_held_at_the_floor() {
        let fit = split(&[0.05, -0.05, 0.0, 0.0], 2, 1.0).unwrap();
        assert!((weight(&[fit]).unwrap() - 0.05 / SIGMA_FLOOR).abs() < 1e-9);
    }

    #[test]
    fn too_few_resonances_give_no_weight() {
        assert_eq!(split(&[0.1, 0.2, 0.01], 1, 1.0), None);
        assert_eq!(split(&[0.01, 0.02], 2, 1.0), None);
        assert_eq!(weight(&[]), None);
    }
}
