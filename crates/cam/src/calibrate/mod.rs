//! `actuator-cam calibrate measured.csv`: find the residual between measured actuators and the
//! model, trace it to a physical effect from a library, fit it, report the error before and after, and
//! write `calibrated-model.toml` for `predict`, `optimize` and `cut-sheet --model FILE`.
//!
//! Flow: [`csv`] validates the file into [`Measurement`]s → [`baseline`] error tables →
//! [`select`] (mass stage, then every subset of ≤ 2 effects with [`fit`]) → [`report`].

pub mod baseline;
pub mod broken;
pub mod csv;
pub mod discover;
pub mod effects_file;
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
use actuator_model::{
    CalibratedModel, DeclaredEffect, Effects, MeasuredLoss, ModelError, Performance,
};
use baseline::{
    error_table, predict_all, residual_correlations, ErrorTable, ResidualCorrelation, RowError,
};
use broken::BrokenActuator;
use library::{effect_names, EffectId};
use select::verdict::{decide, Grounds};

/// Everything `calibrate` computed.
#[derive(Debug, Clone)]
pub struct Calibration {
    /// The selection and its verdict.
    pub selection: Selection,
    /// What the residual looks like and what could cause it, when the selection's verdict is not
    /// explained (found on the data of the final fit).
    pub discovery: Option<discover::Discovery>,
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
    /// Actuators flagged as broken (excluded from the fit and the tables unless marked otherwise).
    pub broken: Vec<BrokenActuator>,
    /// With declared effects (`--effects`): the calibration the library alone gives on the same
    /// actuators, so the report shows the error of the original model, the library-only calibration and
    /// the calibration with the declared effects side by side.
    pub library_only: Option<LibraryOnly>,
    /// The loop's next step when the verdict is not-explained or ambiguous: discovery's leading
    /// candidates as effects to declare (`suggested-effects.toml`).
    pub suggestions: Vec<discover::suggest::Suggestion>,
}

/// The library-only calibration beside one with declared effects: what `calibrate` without `--effects`
/// gives on the same actuators.
#[derive(Debug, Clone)]
pub struct LibraryOnly {
    /// Its verdict (e.g. `not-explained` where the declared effect is what explains the data).
    pub verdict: Verdict,
    /// Its errors.
    pub table: ErrorTable,
    /// Its cross-validated RMSE of the log residuals (δ, F_b).
    pub cv_rmse: f64,
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

/// Calibrate a validated data set: select on every actuator, screen for broken ones against the shared
/// model, and if any are found select again without them (docs/calibration.md §3, "Broken actuators").
pub fn calibrate(data: &Dataset, settings: &Settings) -> Result<Calibration, CalibrateError> {
    let first = select::select(data, settings)?;
    let (selection, broken, kept) = screen_broken(data, settings, first)?;
    let fitted_subset;
    let fitted = match &kept {
        Some(keep) => {
            fitted_subset = broken::subset(data, keep);
            &fitted_subset
        }
        None => data,
    };
    let discovery = match selection.verdict {
        Verdict::NotExplained { .. } | Verdict::Ambiguous { .. } => {
            Some(discover::discover(fitted, &selection, settings)?)
        }
        _ => None,
    };
    // The mass ranking leads when the residual the verdict names is the mass.
    let mass_first = !selection.adequacy.passed
        && selection
            .adequacy
            .worst_variable
            .as_deref()
            .is_some_and(|v| v.contains("(mass residual"));
    let suggestions = discovery.as_ref().map_or_else(Vec::new, |d| {
        discover::suggest::suggestions(d, mass_first, settings.min_delta_aicc)
    });
    let model = calibrated_model(&selection, measured_loss(fitted));
    let original = Effects::default();
    let predictions_before = predict_all(data, |m| original.predict(&m.actuator()))?;
    let predictions_after = predict_all(data, |m| predict_row(&model, m))?;
    // The tables describe the actuators the model was fitted on.
    let (fit_before, fit_after) = if kept.is_some() {
        (
            predict_all(fitted, |m| original.predict(&m.actuator()))?,
            predict_all(fitted, |m| predict_row(&model, m))?,
        )
    } else {
        (predictions_before.clone(), predictions_after.clone())
    };
    let library_only = if settings.declared.is_empty() {
        None
    } else {
        Some(library_only(fitted, settings)?)
    };
    let thesis = predict_all(fitted, |m| {
        let p = original.predict(&m.actuator())?;
        Ok(empirical::adjust(&p, &m.planform, m.pzt_thickness))
    })?;
    Ok(Calibration {
        before: error_table(fitted, &fit_before),
        after: error_table(fitted, &fit_after),
        thesis_adjusted: error_table(fitted, &thesis),
        cv_rmse_before: selection.candidates[0].cv_rmse,
        cv_rmse_after: selection.candidates[selection.final_index].cv_rmse,
        correlations_before: residual_correlations(fitted, &fit_before),
        correlations_after: residual_correlations(fitted, &fit_after),
        selection,
        discovery,
        model,
        predictions_before,
        predictions_after,
        broken,
        library_only,
        suggestions,
    })
}

/// The loss factor of the actuators with a measured quality factor: `η = 1/Q` each, their mean and the
/// 95 % Student-t interval of the mean, held above the smallest η measured (a loss factor is positive)
/// and at most 1 (docs/calibration.md §3, "The resonance"). One actuator gives its own η with no spread
/// to widen it.
pub fn measured_loss(data: &Dataset) -> Option<MeasuredLoss> {
    let etas: Vec<f64> = (0..data.actuators())
        .filter_map(|g| data.rows[data.groups[g][0]].quality_factor)
        .map(|q| 1.0 / q)
        .collect();
    let n = etas.len();
    if n == 0 {
        return None;
    }
    let mean = etas.iter().sum::<f64>() / n as f64;
    let half = if n > 1 {
        let var = etas.iter().map(|e| (e - mean).powi(2)).sum::<f64>() / (n - 1) as f64;
        stats::t_quantile_two_sided(0.95, (n - 1) as f64) * (var / n as f64).sqrt()
    } else {
        0.0
    };
    let smallest = etas.iter().copied().fold(f64::INFINITY, f64::min);
    Some(MeasuredLoss {
        loss_factor: mean,
        interval: [(mean - half).max(smallest), (mean + half).min(1.0)],
        actuators: n,
    })
}

/// The model file's contents for a selection.
fn calibrated_model(selection: &Selection, loss: Option<MeasuredLoss>) -> CalibratedModel {
    CalibratedModel {
        model: "calibrated".into(),
        base: actuator_model::Base::Original,
        verdict: selection.verdict.name().into(),
        // A declared effect with several parameters is one name.
        selected_effects: effect_names(&selection.selected)
            .into_iter()
            .map(String::from)
            .collect(),
        effects: selection.model.effects,
        declared: declared_records(selection),
        loss,
    }
}

/// The selection without the declared effects, on the actuators the full one was fitted on.
fn library_only(fitted: &Dataset, settings: &Settings) -> Result<LibraryOnly, CalibrateError> {
    let library = Settings {
        declared: Vec::new(),
        ..settings.clone()
    };
    let selection = select::select(fitted, &library)?;
    let model = calibrated_model(&selection, measured_loss(fitted));
    let predictions = predict_all(fitted, |m| predict_row(&model, m))?;
    Ok(LibraryOnly {
        table: error_table(fitted, &predictions),
        cv_rmse: selection.candidates[selection.final_index].cv_rmse,
        verdict: selection.verdict,
    })
}

/// The declared effects of the final models (mass stage, then actuation) at their fitted values, in the
/// order their primitives were applied, so the file rebuilds `selection.model` exactly.
fn declared_records(selection: &Selection) -> Vec<DeclaredEffect> {
    let mass = selection
        .final_mass_index
        .map(|i| &selection.mass_candidates[i]);
    let actuation = &selection.candidates[selection.final_index];
    mass.into_iter()
        .chain([actuation])
        .flat_map(|c| c.effects.iter().zip(&c.values))
        .filter_map(|(id, &v)| match id {
            EffectId::Declared(d) => Some(d.record(v)),
            _ => None,
        })
        .collect()
}

/// The selection to report, the actuators flagged as broken, and which actuators the fit kept (None: all).
type Screened = (Selection, Vec<BrokenActuator>, Option<Vec<bool>>);

/// Rounds of screening: each excludes what the previous fit shows broken and selects again.
const SCREEN_ROUNDS: usize = 3;

/// Screen for broken actuators and select again without them. Returns the selection to report, the
/// flagged actuators, and which actuators were kept (None: all of them).
fn screen_broken(
    data: &Dataset,
    settings: &Settings,
    first: Selection,
) -> Result<Screened, CalibrateError> {
    let groups = data.actuators();
    let mut keep = vec![true; groups];
    let mut flagged: Vec<BrokenActuator> = Vec::new();
    let mut current: Option<Selection> = None;
    for _ in 0..SCREEN_ROUNDS {
        let sel = current.as_ref().unwrap_or(&first);
        let kept_index: Vec<usize> = (0..groups).filter(|&g| keep[g]).collect();
        let view;
        let on = if flagged.is_empty() {
            data
        } else {
            view = broken::subset(data, &keep);
            &view
        };
        // Against the model chosen before the thickness forms (`Selection::screening_index`).
        let model = if sel.screening_index == sel.final_index {
            &sel.model
        } else {
            &sel.candidates[sel.screening_index].model
        };
        let predictions = predict_all(on, |m| model.predict(&m.actuator()))?;
        let found = broken::screen(on, &predictions);
        if found.is_empty() {
            break;
        }
        for (g, b) in found {
            keep[kept_index[g]] = false;
            flagged.push(b);
        }
        if flagged.len() as f64 > broken::MAX_SHARE * groups as f64 {
            let note = format!(
                    "{} of {} actuators are off at every voltage against the rest: too many to be broken devices (more than {:.0} %), so none was excluded; a shared effect the model lacks is the likelier cause",
                flagged.len(),
                groups,
                100.0 * broken::MAX_SHARE
            );
            return Ok(keep_all(first, flagged, Some(note)));
        }
        match select::select(&broken::subset(data, &keep), settings) {
            Ok(sel) => current = Some(sel),
            Err(e) => {
                let (mut sel, flagged, _) = keep_all(first, flagged, None);
                sel.verdict = decide(Grounds::UnfittableWithoutBroken {
                    excluded: flagged.len(),
                    error: &e,
                });
                return Ok((sel, flagged, None));
            }
        }
    }
    let Some(mut sel) = current else {
        return Ok((first, flagged, None));
    };
    // An actuator set aside stays out whatever the rest shows: putting it back to change the verdict
    // would let one device fault decide what the others mean. A not-explained verdict on the rest says
    // which actuators were set aside and why, so a reader can judge whether they carry the effect.
    if let Verdict::NotExplained { variable } = &mut sel.verdict {
        variable.push_str(&set_aside(&flagged));
    }
    let names: Vec<&str> = flagged.iter().map(|b| b.id.as_str()).collect();
    sel.notes.push(format!(
        "{} of {} actuators excluded as broken ({}); the fit, the verdict and the error tables are on the other {}",
        flagged.len(),
        groups,
        names.join(", "),
        groups - flagged.len()
    ));
    Ok((sel, flagged, Some(keep)))
}

/// What a not-explained verdict on the rest adds: each actuator set aside with its likely cause.
fn set_aside(flagged: &[BrokenActuator]) -> String {
    let each: Vec<String> = flagged
        .iter()
        .map(|b| format!("{}: {}", b.id, b.likely_cause))
        .collect();
    format!(
        "; on the actuators left after setting aside as broken {}",
        each.join("; ")
    )
}

/// Report flagged actuators without excluding them.
fn keep_all(
    mut first: Selection,
    mut flagged: Vec<BrokenActuator>,
    note: Option<String>,
) -> Screened {
    for b in &mut flagged {
        b.excluded = false;
    }
    first.notes.extend(note);
    (first, flagged, None)
}
