//! The verdict of a calibration (docs/calibration.md §3) and the one place that decides it: from the
//! selection's final model, or, when the actuators left after excluding the broken ones cannot be
//! fitted, that too little data is left.

use super::adequacy::Adequacy;
use crate::calibrate::library::{effect_names, EffectId};
use actuator_model::ModelError;

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

/// What a verdict is decided on.
pub(crate) enum Grounds<'a> {
    /// A selection's final model.
    Fitted {
        /// Its adequacy tests.
        adequacy: &'a Adequacy,
        /// The effects selected (mass stage first).
        selected: &'a [EffectId],
        /// The effect sets the data cannot tell from the selected ones.
        contenders: Vec<Vec<String>>,
        /// The selected parameters whose final interval holds their null value, described.
        holding_null: Vec<String>,
        /// Why the fitted model is refused for contradicting a measured quantity (`touches.rs`).
        contradicts: Option<String>,
    },
    /// The actuators left after excluding `excluded` broken ones could not be fitted.
    UnfittableWithoutBroken {
        /// How many actuators were flagged as broken.
        excluded: usize,
        /// Why the rest could not be fitted.
        error: &'a ModelError,
    },
}

/// The verdict on its grounds. A final model that fails its adequacy tests is not explained, whatever
/// else holds: a residual that follows a variable is not one any contender explains; a model that makes a
/// measured quantity follow a variable though the original model fits it is refused first, named by
/// what the original model's residual touches. A selected effect
/// whose final interval holds its null value is not one the data support (the acceptance rule,
/// docs/calibration.md §3), so the model with it explains nothing either. An adequate model
/// with rivals the data cannot tell apart is ambiguous, naming the selected set first; otherwise it is
/// explained, or no effect when nothing was selected.
pub(crate) fn decide(grounds: Grounds) -> Verdict {
    match grounds {
        Grounds::Fitted {
            contradicts: Some(why),
            ..
        } => Verdict::NotExplained { variable: why },
        Grounds::Fitted { adequacy, .. } if !adequacy.passed => Verdict::NotExplained {
            variable: adequacy
                .worst_variable
                .clone()
                .unwrap_or_else(|| "(lack of fit, no single variable)".into()),
        },
        Grounds::Fitted { holding_null, .. } if !holding_null.is_empty() => Verdict::NotExplained {
            variable: format!(
                "no effect the data support: the final fit's 95 % interval of {}",
                holding_null.join(", and of ")
            ),
        },
        Grounds::Fitted {
            selected,
            contenders,
            ..
        } if !contenders.is_empty() => {
            let mut all = vec![effect_names(selected)
                .into_iter()
                .map(String::from)
                .collect()];
            all.extend(contenders);
            Verdict::Ambiguous { contenders: all }
        }
        Grounds::Fitted { selected: [], .. } => Verdict::NoEffect,
        Grounds::Fitted { .. } => Verdict::Explained,
        Grounds::UnfittableWithoutBroken { excluded, error } => Verdict::InsufficientData {
            reason: format!(
                "without the {excluded} broken actuator(s) the rest cannot be fitted: {error}"
            ),
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn adequate() -> Adequacy {
        Adequacy {
            lack_of_fit: None,
            correlations: Vec::new(),
            passed: true,
            worst_variable: None,
            resonance: None,
        }
    }

    #[test]
    fn an_adequate_fit_whose_effect_holds_its_null_is_not_explained() {
        // The acceptance rule (docs/calibration.md §3, step 4) on the final fit: a null data set that two
        // effects would "explain" while both their intervals hold their null.
        let adequacy = adequate();
        let selected = [EffectId::DeadLength, EffectId::ClampCompliance];
        let grounds = |holding_null: Vec<String>| Grounds::Fitted {
            adequacy: &adequacy,
            selected: &selected,
            contenders: Vec::new(),
            holding_null,
            contradicts: None,
        };
        assert_eq!(decide(grounds(Vec::new())), Verdict::Explained);
        let Verdict::NotExplained { variable } = decide(grounds(vec![
            "dead-length (dead_length_mm [-0.1, 0.9]) holds its null 0".into(),
        ])) else {
            panic!("not refused");
        };
        assert!(
            variable.starts_with("no effect the data support"),
            "{variable}"
        );
        assert!(
            variable.contains("dead-length (dead_length_mm"),
            "{variable}"
        );
    }
}
