//! Report of a calibration: `report.json` (keys as in docs/calibration.md §4) and `report.md` from
//! one tree of serde structs ([`tree::Report`]), the SVG parity and residual plots, and the model file,
//! all rendered in memory.

pub mod fitted;
pub mod markdown;
pub mod plots;
pub mod suggested;
pub mod tree;

pub use tree::Report;

use super::csv::Dataset;
use super::model_file::{self, ModelFileError};
use super::Calibration;
use plots::{parity_svg, residual_svg};
use tree::{selected_effects, Errors, LibraryOnlyErrors, VerdictDetail};

/// A report that could not be rendered.
#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    /// report.json.
    #[error(transparent)]
    Json(#[from] serde_json::Error),
    /// The model file.
    #[error(transparent)]
    ModelFile(#[from] ModelFileError),
}

/// Short terminal summary: verdict, fitted parameters, error tables.
pub fn summary(cal: &Calibration) -> String {
    let s = &cal.selection;
    let table = |table, cv| Errors {
        table,
        cv_rmse: cv,
        residual_correlations: None,
    };
    let mut out = markdown::summary(
        s.verdict.name(),
        &VerdictDetail::new(&s.verdict),
        &selected_effects(cal),
        [
            &table(&cal.before, Some(cal.cv_rmse_before)),
            &table(&cal.after, Some(cal.cv_rmse_after)),
            &table(&cal.thesis_adjusted, None),
        ],
        LibraryOnlyErrors::new(cal).as_ref(),
    );
    if let Some(d) = &cal.discovery {
        out.push_str(&markdown::discovery_line(d));
    }
    out
}

/// Every output file, name and text.
pub fn render(
    cal: &Calibration,
    data: &Dataset,
    source: &str,
) -> Result<Vec<(String, String)>, ReportError> {
    let report = Report::new(cal, data, source);
    let mut files = vec![
        (
            model_file::FILE_NAME.into(),
            model_file::to_toml(&cal.model)?,
        ),
        ("report.json".into(), report.to_json()?),
        ("report.md".into(), markdown::markdown(&report)),
        (
            "parity-before.svg".into(),
            parity_svg(data, &cal.predictions_before, "original"),
        ),
        (
            "parity-after.svg".into(),
            parity_svg(data, &cal.predictions_after, "calibrated"),
        ),
        (
            "residuals-before.svg".into(),
            residual_svg(data, &cal.predictions_before, "original"),
        ),
        (
            "residuals-after.svg".into(),
            residual_svg(data, &cal.predictions_after, "calibrated"),
        ),
    ];
    if let Some(text) = suggested::render(cal, source) {
        files.push((suggested::FILE_NAME.into(), text));
    }
    Ok(files)
}
