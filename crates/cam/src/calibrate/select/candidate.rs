//! One fitted model of the selection: its effects, estimates, intervals and scores.

use crate::calibrate::fit::FitResult;
use crate::calibrate::library::{EffectId, Stage};
use actuator_model::EffectModel;

/// Role of a fitted model in the selection.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Role {
    /// The original model, nothing fitted.
    Original,
    /// A null model ({η} or {η, stiffness-scale}).
    Null,
    /// A model with library effects.
    Candidate,
}

/// One fitted model.
#[derive(Debug, Clone)]
pub struct Candidate {
    /// Which data it was fitted on.
    pub stage: Stage,
    /// Role in the selection.
    pub role: Role,
    /// Fitted effects, in parameter order (the carried mass effects not among them).
    pub effects: Vec<EffectId>,
    /// The mass model's parameters, fitted again with these effects on the masses, deflections and
    /// forces together (empty when the mass model was frozen: the mass stage, the original mass model,
    /// or a declared mass effect). `model` holds them.
    pub carried: Vec<CarriedValue>,
    /// Estimates in report units.
    pub values: Vec<f64>,
    /// Standard errors.
    pub std_errors: Vec<f64>,
    /// 95% intervals (t quantile times the covariance standard error).
    pub intervals: Vec<(f64, f64)>,
    /// Parameter correlation matrix.
    pub correlation: Vec<Vec<f64>>,
    /// Residual sum of squares (log residuals).
    pub rss: f64,
    /// Number of residuals.
    pub n: usize,
    /// AICc.
    pub aicc: f64,
    /// BIC.
    pub bic: f64,
    /// Grouped cross-validated RMSE of the log residuals.
    pub cv_rmse: f64,
    /// Passed every acceptance test.
    pub accepted: bool,
    /// Why it was not accepted (empty if accepted or a null model).
    pub note: String,
    /// The complete effects of this model (frozen mass effects included).
    pub model: EffectModel,
    /// Library effects the data cannot determine, with the reason (never selected).
    pub not_identifiable: Vec<(EffectId, String)>,
    /// The fit itself (residuals, Jacobian).
    pub fit: FitResult,
}

/// A mass parameter refitted beside an actuation model.
#[derive(Debug, Clone, PartialEq)]
pub struct CarriedValue {
    /// The mass effect.
    pub id: EffectId,
    /// Its estimate on all the data.
    pub value: f64,
    /// Standard error (from the joint fit's covariance).
    pub std_error: f64,
    /// 95% interval.
    pub interval: (f64, f64),
}

impl Candidate {
    /// Effects other than η and stiffness-scale.
    pub fn library_effects(&self) -> Vec<EffectId> {
        self.effects
            .iter()
            .filter(|e| !matches!(e, EffectId::D31Scale | EffectId::StiffnessScale))
            .cloned()
            .collect()
    }

    /// Display label like `{eta, dead-length}`.
    pub fn label(&self) -> String {
        if self.effects.is_empty() {
            return "original".into();
        }
        let names: Vec<&str> = self.effects.iter().map(|e| e.name()).collect();
        format!("{{{}}}", names.join(", "))
    }

    /// The 95% interval of parameter `k` excludes its null value.
    pub(super) fn excludes_null(&self, k: usize) -> bool {
        let null = self.effects[k].param().null;
        let (lo, hi) = self.intervals[k];
        lo.is_finite() && hi.is_finite() && (lo > null || hi < null)
    }
}
