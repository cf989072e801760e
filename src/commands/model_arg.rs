//! `--model`: a built-in model name or a `calibrated-model.toml` written by `calibrate`.

use crate::calibrate::model_file;
use actuator_model::model::{ModelChoice, ModelKind};
use anyhow::Context;
use std::path::Path;
use std::sync::Arc;

/// The built-in names, for help and errors.
pub const BUILT_IN: &str = "original, thesis-adjusted, euler-bernoulli";

/// Parse `--model`: `original`, `thesis-adjusted`, `euler-bernoulli`, or a calibrated-model file path.
pub fn parse_model(text: &str) -> anyhow::Result<ModelChoice> {
    let kind = match text {
        "original" => Some(ModelKind::Original),
        "thesis-adjusted" => Some(ModelKind::ThesisAdjusted),
        "euler-bernoulli" => Some(ModelKind::EulerBernoulli),
        _ => None,
    };
    if let Some(k) = kind {
        return Ok(ModelChoice::Kind(k));
    }
    let path = Path::new(text);
    if !path.exists() {
        anyhow::bail!(
            "--model {text:?}: expected one of {BUILT_IN}, or a calibrated-model.toml file"
        );
    }
    let model = model_file::load(path).with_context(|| format!("--model {text}"))?;
    Ok(ModelChoice::Calibrated(Arc::new(model)))
}
