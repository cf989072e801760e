//! Rows the final fit flags: large studentised residuals or Cook's distances.

use super::candidate::Candidate;
use super::observations::ActuationData;
use crate::calibrate::csv::Dataset;
use crate::calibrate::rounded::six_digits;
use serde::Serialize;

/// A flagged data row.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Outlier {
    /// Actuator id.
    pub id: String,
    /// File line.
    pub line: u64,
    /// `free_deflection` or `blocked_force`.
    pub output: &'static str,
    /// Studentised residual.
    #[serde(serialize_with = "six_digits")]
    pub studentised: f64,
    /// Cook's distance.
    #[serde(serialize_with = "six_digits")]
    pub cooks_distance: f64,
}

/// Rows whose studentised residual exceeds 3.5 or whose Cook's distance exceeds 1.
pub(super) fn outliers(data: &Dataset, act: &ActuationData, chosen: &Candidate) -> Vec<Outlier> {
    let fit = &chosen.fit;
    let p = chosen.values.len();
    let dof = (fit.n as f64 - p as f64).max(1.0);
    let sigma = (fit.rss / dof).sqrt();
    if sigma <= 0.0 {
        return Vec::new();
    }
    let leverage = fit.leverage();
    let labels = act.labels();
    let mut out = Vec::new();
    for ((&(i, output), &r), &h) in labels.iter().zip(&fit.residuals).zip(&leverage) {
        let h = h.clamp(0.0, 0.99);
        let t = r / (sigma * (1.0 - h).sqrt());
        let cooks = if p > 0 {
            t * t * h / (p as f64 * (1.0 - h))
        } else {
            0.0
        };
        if t.abs() > 3.5 || cooks > 1.0 {
            let row = &data.rows[act.obs[i].row];
            out.push(Outlier {
                id: row.id.clone(),
                line: row.line,
                output,
                studentised: t,
                cooks_distance: cooks,
            });
        }
    }
    out
}
