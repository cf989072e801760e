//! The knobs of the selection (docs/calibration.md §3); the defaults are the documented procedure.

use crate::calibrate::library::Declared;

/// Knobs of the selection; the defaults are the documented procedure.
#[derive(Debug, Clone, PartialEq)]
pub struct Settings {
    /// Seed of the cross-validation folds.
    pub seed: u64,
    /// Folds of grouped cross-validation.
    pub folds: usize,
    /// Repeats of the K-fold split.
    pub repeats: usize,
    /// Largest number of effects (besides η) in one model.
    pub max_effects: usize,
    /// ΔAICc an added effect must gain over its parent.
    pub min_delta_aicc: f64,
    /// Family-wise level of the adequacy tests.
    pub alpha: f64,
    /// Smallest |η - 1| reported as a d31 scale: below it the change is immaterial to a design and a
    /// 5%-noise data set flags it by chance more often than the 1-in-10 the null case allows.
    pub min_relevant_d31_change: f64,
    /// Effects a lab declared (`--effects FILE`): candidates beside the library's, on the same terms.
    pub declared: Vec<Declared>,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            seed: 1,
            folds: 5,
            repeats: 2,
            max_effects: 2,
            min_delta_aicc: 4.0,
            alpha: 0.01,
            min_relevant_d31_change: 0.02,
            declared: Vec::new(),
        }
    }
}

/// Largest number of parameters a model can have: η + the allowed effects.
pub fn max_parameters(settings: &Settings) -> usize {
    1 + settings.max_effects
}
