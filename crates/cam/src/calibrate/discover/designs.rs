//! Designs whose measurement would best tell the leading candidates apart: among the corners of the
//! data's span ([`probes`]), those where the smallest disagreement between any two of the fitted
//! candidates, `max(|ln(δ_A/δ_B)|, |ln(F_A/F_B)|)`, is largest (a max-min criterion: one measurement
//! then separates all of them).

use crate::calibrate::csv::Dataset;
use crate::calibrate::rounded::six_digits;
use crate::calibrate::select::separating::{probes, DesignPoint};
use actuator_model::effects::Actuator;
use actuator_model::{ModelError, Performance};
use serde::Serialize;

/// What one candidate predicts at a design.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Prediction {
    /// Candidate name.
    pub candidate: String,
    /// Free deflection, mm.
    #[serde(serialize_with = "six_digits")]
    pub free_deflection_mm: f64,
    /// Blocked force, N.
    #[serde(rename = "blocked_force_N", serialize_with = "six_digits")]
    pub blocked_force_n: f64,
}

/// A design that separates the leading candidates.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DiscriminatingDesign {
    /// The design.
    #[serde(flatten)]
    pub design: DesignPoint,
    /// The smallest disagreement between two candidates, as a log ratio.
    #[serde(serialize_with = "six_digits")]
    pub separation_log: f64,
    /// Each candidate's prediction.
    pub predictions: Vec<Prediction>,
}

/// A named predictor.
pub type Predictor<'a> = (
    String,
    Box<dyn Fn(&Actuator) -> Result<Performance, ModelError> + Sync + 'a>,
);

/// Up to `count` designs in the data's span that separate the candidates most (needs two or more).
pub fn discriminate(
    data: &Dataset,
    candidates: &[Predictor],
    count: usize,
) -> Vec<DiscriminatingDesign> {
    if candidates.len() < 2 {
        return Vec::new();
    }
    let mut scored = Vec::new();
    'probe: for probe in probes(data) {
        let act = probe.actuator();
        let mut preds = Vec::with_capacity(candidates.len());
        for (_, f) in candidates {
            match f(&act) {
                Ok(p) if p.free_deflection > 0.0 && p.blocked_force > 0.0 => preds.push(p),
                _ => continue 'probe,
            }
        }
        let mut worst = f64::INFINITY;
        for (i, a) in preds.iter().enumerate() {
            for b in &preds[i + 1..] {
                let d = (a.free_deflection / b.free_deflection).ln().abs();
                let f = (a.blocked_force / b.blocked_force).ln().abs();
                worst = worst.min(d.max(f));
            }
        }
        scored.push((
            worst,
            DiscriminatingDesign {
                design: probe.design(),
                separation_log: worst,
                predictions: candidates
                    .iter()
                    .zip(&preds)
                    .map(|((name, _), p)| Prediction {
                        candidate: name.clone(),
                        free_deflection_mm: p.free_deflection * 1e3,
                        blocked_force_n: p.blocked_force,
                    })
                    .collect(),
            },
        ));
    }
    scored.sort_by(|a, b| b.0.total_cmp(&a.0));
    scored.into_iter().take(count).map(|(_, d)| d).collect()
}
