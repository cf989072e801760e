//! `actuator-cam calibrate measured.csv` (issue 6): find the residual between measured actuators and the
//! model, trace it to a physical effect from a library, fit it, report the error before and after, and
//! write `calibrated-model.toml` for `predict`, `optimize` and `cut-sheet --model FILE`.
//!
//! Flow: [`csv`] validates the file into [`Measurement`]s → [`baseline`] error tables →
//! [`select`] (mass stage, then every subset of ≤ 2 effects with [`fit`]) → [`report`].

pub mod baseline;
pub mod csv;
pub mod fit;
pub mod library;
pub mod model_file;
pub mod report;
pub mod rounded;
pub mod select;
pub mod stats;
pub mod variables;

pub use self::csv::{Dataset, Measurement};
pub use select::{Selection, Settings, Verdict};

use actuator_model::empirical;
use actuator_model::{CalibratedModel, Effects, ModelError, Performance};
use baseline::{
    error_table, predict_all, residual_correlations, ErrorTable, ResidualCorrelation, RowError,
};

/// Everything `calibrate` computed.
#[derive(Debug, Clone)]
pub struct Calibration {
    /// The selection and its verdict.
    pub selection: Selection,
    /// The calibrated model as written to the TOML file.
    pub model: CalibratedModel,
    /// Original model.
    pub before: ErrorTable,
    /// Calibrated model.
    pub after: ErrorTable,
    /// Thesis' empirical corrections (eqs. 4.3-4.5) on the same data.
    pub thesis_adjusted: ErrorTable,
    /// Cross-validated RMSE of the log residuals (δ, F_b) of the original model.
    pub cv_rmse_before: f64,
    /// The same for the selected model.
    pub cv_rmse_after: f64,
    /// Residual correlations before.
    pub correlations_before: Vec<ResidualCorrelation>,
    /// Residual correlations after.
    pub correlations_after: Vec<ResidualCorrelation>,
    /// Original-model predictions per row.
    pub predictions_before: Vec<Performance>,
    /// Calibrated predictions per row.
    pub predictions_after: Vec<Performance>,
}

/// Predict one measured row with a calibrated model (the "after" predictions; `predict --model` must give
/// the same numbers).
pub fn predict_row(model: &CalibratedModel, m: &Measurement) -> Result<Performance, ModelError> {
    model.predict(&m.actuator())
}

/// Why a data set could not be calibrated.
#[derive(Debug, thiserror::Error)]
pub enum CalibrateError {
    /// The selection could not fit (too few actuators, a model error).
    #[error(transparent)]
    Model(#[from] ModelError),
    /// A row the original or calibrated model cannot predict.
    #[error(transparent)]
    Row(#[from] RowError),
}

/// Calibrate a validated data set.
pub fn calibrate(data: &Dataset, settings: &Settings) -> Result<Calibration, CalibrateError> {
    let selection = select::select(data, settings)?;
    let model = CalibratedModel {
        model: "calibrated".into(),
        verdict: selection.verdict.name().into(),
        selected_effects: selection
            .selected
            .iter()
            .map(|e| e.name().to_string())
            .collect(),
        effects: selection.model,
    };
    let original = Effects::default();
    let predictions_before = predict_all(data, |m| original.predict(&m.actuator()))?;
    let predictions_after = predict_all(data, |m| predict_row(&model, m))?;
    let thesis = predict_all(data, |m| {
        let p = original.predict(&m.actuator())?;
        Ok(empirical::adjust(&p, &m.planform, m.pzt_thickness))
    })?;
    Ok(Calibration {
        before: error_table(data, &predictions_before),
        after: error_table(data, &predictions_after),
        thesis_adjusted: error_table(data, &thesis),
        cv_rmse_before: selection.candidates[0].cv_rmse,
        cv_rmse_after: selection.candidates[selection.final_index].cv_rmse,
        correlations_before: residual_correlations(data, &predictions_before),
        correlations_after: residual_correlations(data, &predictions_after),
        selection,
        model,
        predictions_before,
        predictions_after,
    })
}
