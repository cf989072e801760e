//! Error tables (before and after): the thesis' k = model/measured mean and spread (eqs. 4.1, 4.2), RMSE
//! of log residuals, MAPE, max error, share within ±10% and ±20%, and how the residual follows each
//! design variable.

use super::csv::{Dataset, Measurement};
use super::rounded::{six_digits, six_digits_opt};
use super::stats;
use super::variables::design_variables;
use actuator_model::{ModelError, Performance};
use serde::Serialize;

/// Errors of one output.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct OutputErrors {
    /// Number of measured values.
    pub n: usize,
    /// Mean of k = model/measured (thesis eq. 4.1).
    #[serde(serialize_with = "six_digits")]
    pub k_mean: f64,
    /// Sample standard deviation of k (thesis eq. 4.2).
    #[serde(serialize_with = "six_digits")]
    pub k_std: f64,
    /// RMSE of ln(measured/model).
    #[serde(serialize_with = "six_digits")]
    pub rmse_log: f64,
    /// Mean absolute percentage error, %.
    #[serde(serialize_with = "six_digits")]
    pub mape: f64,
    /// Largest |model/measured - 1|, %.
    #[serde(serialize_with = "six_digits")]
    pub max_error: f64,
    /// Share of values within ±10%.
    #[serde(serialize_with = "six_digits")]
    pub within_10: f64,
    /// Share of values within ±20%.
    #[serde(serialize_with = "six_digits")]
    pub within_20: f64,
}

impl OutputErrors {
    fn from_pairs(pairs: &[(f64, f64)]) -> Option<Self> {
        if pairs.is_empty() {
            return None;
        }
        let n = pairs.len() as f64;
        let k: Vec<f64> = pairs.iter().map(|(model, meas)| model / meas).collect();
        let k_mean = k.iter().sum::<f64>() / n;
        let k_std = if pairs.len() > 1 {
            (k.iter().map(|x| (x - k_mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt()
        } else {
            0.0
        };
        let rel: Vec<f64> = k.iter().map(|x| (x - 1.0).abs()).collect();
        Some(OutputErrors {
            n: pairs.len(),
            k_mean,
            k_std,
            rmse_log: (k.iter().map(|x| x.ln().powi(2)).sum::<f64>() / n).sqrt(),
            mape: 100.0 * rel.iter().sum::<f64>() / n,
            max_error: 100.0 * rel.iter().copied().fold(0.0, f64::max),
            within_10: rel.iter().filter(|r| **r <= 0.1).count() as f64 / n,
            within_20: rel.iter().filter(|r| **r <= 0.2).count() as f64 / n,
        })
    }
}

/// Error table of one model on one data set.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ErrorTable {
    /// Mass (one value per actuator).
    pub mass: Option<OutputErrors>,
    /// Free deflection.
    pub free_deflection: Option<OutputErrors>,
    /// Blocked force.
    pub blocked_force: Option<OutputErrors>,
    /// Stiffness F_b/δ (rows with both).
    pub stiffness: Option<OutputErrors>,
    /// RMSE of all log residuals of deflection and force together.
    #[serde(serialize_with = "six_digits")]
    pub rmse_log_actuation: f64,
}

/// Correlation of the per-actuator mean residual with one design variable.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ResidualCorrelation {
    /// Variable.
    pub variable: String,
    /// r of the actuation residual ln(δ_meas/δ_model).
    #[serde(serialize_with = "six_digits_opt")]
    pub deflection: Option<f64>,
    /// r of the stiffness residual ln(k_meas/k_model).
    #[serde(serialize_with = "six_digits_opt")]
    pub stiffness: Option<f64>,
    /// r of the mass residual.
    #[serde(serialize_with = "six_digits_opt")]
    pub mass: Option<f64>,
}

/// A row the model cannot predict.
#[derive(Debug, thiserror::Error)]
#[error("line {line} (actuator {id}): {error}")]
pub struct RowError {
    /// File line.
    pub line: u64,
    /// Actuator id.
    pub id: String,
    /// Why (in the message, not a separate cause).
    pub error: ModelError,
}

/// Predictions of one model for every row.
pub fn predict_all<F>(data: &Dataset, predict: F) -> Result<Vec<Performance>, RowError>
where
    F: Fn(&Measurement) -> Result<Performance, ModelError>,
{
    data.rows
        .iter()
        .map(|m| {
            predict(m).map_err(|error| RowError {
                line: m.line,
                id: m.id.clone(),
                error,
            })
        })
        .collect()
}

/// The error table of predictions against the measurements.
pub fn error_table(data: &Dataset, predictions: &[Performance]) -> ErrorTable {
    let mut mass = Vec::new();
    for g in &data.groups {
        if let Some(m) = data.rows[g[0]].mass {
            mass.push((predictions[g[0]].mass, m));
        }
    }
    let (mut delta, mut force, mut stiff) = (Vec::new(), Vec::new(), Vec::new());
    for (m, p) in data.rows.iter().zip(predictions) {
        if m.voltage <= 0.0 {
            continue;
        }
        if let Some(d) = m.free_deflection {
            delta.push((p.free_deflection, d));
        }
        if let Some(f) = m.blocked_force {
            force.push((p.blocked_force, f));
        }
        if let (Some(d), Some(f)) = (m.free_deflection, m.blocked_force) {
            stiff.push((p.stiffness, f / d));
        }
    }
    let all: Vec<f64> = delta
        .iter()
        .chain(&force)
        .map(|(model, meas)| (meas / model).ln())
        .collect();
    ErrorTable {
        mass: OutputErrors::from_pairs(&mass),
        free_deflection: OutputErrors::from_pairs(&delta),
        blocked_force: OutputErrors::from_pairs(&force),
        stiffness: OutputErrors::from_pairs(&stiff),
        rmse_log_actuation: if all.is_empty() {
            0.0
        } else {
            (all.iter().map(|r| r * r).sum::<f64>() / all.len() as f64).sqrt()
        },
    }
}

/// Mean log residuals of one actuator, split into actuation, stiffness and mass parts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GroupResidual {
    /// Mean ln(δ_meas/δ_model).
    pub deflection: Option<f64>,
    /// Mean ln(k_meas/k_model), k = F_b/δ.
    pub stiffness: Option<f64>,
    /// ln(m_meas/m_model).
    pub mass: Option<f64>,
}

/// Per-actuator mean log residuals.
pub fn group_residuals(data: &Dataset, predictions: &[Performance]) -> Vec<GroupResidual> {
    data.groups
        .iter()
        .map(|g| {
            let (mut d, mut k) = (Vec::new(), Vec::new());
            for &i in g {
                let (m, p) = (&data.rows[i], &predictions[i]);
                if m.voltage <= 0.0 {
                    continue;
                }
                if let Some(dm) = m.free_deflection {
                    d.push((dm / p.free_deflection).ln());
                    if let Some(f) = m.blocked_force {
                        k.push((f / dm / p.stiffness).ln());
                    }
                }
            }
            let mean = |v: &[f64]| (!v.is_empty()).then(|| v.iter().sum::<f64>() / v.len() as f64);
            let mass = data.rows[g[0]]
                .mass
                .map(|m| (m / predictions[g[0]].mass).ln());
            GroupResidual {
                deflection: mean(&d),
                stiffness: mean(&k),
                mass,
            }
        })
        .collect()
}

/// Correlation of the residual parts with each design variable (thesis §4: residual vs l_r, w_0 t_p, …).
pub fn residual_correlations(
    data: &Dataset,
    predictions: &[Performance],
) -> Vec<ResidualCorrelation> {
    let res = group_residuals(data, predictions);
    let vars: Vec<_> = data
        .groups
        .iter()
        .map(|g| design_variables(&data.rows[g[0]]))
        .collect();
    let corr = |k: usize, pick: &dyn Fn(&GroupResidual) -> Option<f64>| {
        let (xs, ys): (Vec<f64>, Vec<f64>) = vars
            .iter()
            .zip(&res)
            .filter_map(|(v, r)| pick(r).map(|y| (v[k].1, y)))
            .unzip();
        stats::pearson(&xs, &ys)
    };
    (0..super::variables::COUNT)
        .map(|k| ResidualCorrelation {
            variable: vars.first().map(|v| v[k].0).unwrap_or("").to_string(),
            deflection: corr(k, &|r| r.deflection),
            stiffness: corr(k, &|r| r.stiffness),
            mass: corr(k, &|r| r.mass),
        })
        .collect()
}
