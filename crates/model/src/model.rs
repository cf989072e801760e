//! Choice of model for a prediction: original lamination theory, the thesis' adjusted fits, or the
//! Euler-Bernoulli beam.

use crate::drive::Drive;
use crate::effects::{Actuator, CalibratedModel};
use crate::empirical;
use crate::error::ModelError;
use crate::euler_bernoulli::BeamBimorph;
use crate::laminate::Laminate;
use crate::performance::{evaluate, Performance};
use crate::planform::Planform;
use crate::section::Section;
use std::sync::Arc;

/// Which model predicts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ModelKind {
    /// Classical lamination theory with the tapered-beam compliance (thesis ch. 2, Wood 2005).
    Original,
    /// Original with the thesis' empirical corrections, eqs. 4.3-4.5 ([`crate::empirical`]).
    ThesisAdjusted,
    /// Euler-Bernoulli beam, eqs. 2.11-2.15; rectangular designs only.
    EulerBernoulli,
}

impl ModelKind {
    /// Command-line name.
    pub fn name(self) -> &'static str {
        match self {
            ModelKind::Original => "original",
            ModelKind::ThesisAdjusted => "thesis-adjusted",
            ModelKind::EulerBernoulli => "euler-bernoulli",
        }
    }
}

/// Predict one actuator with the chosen model.
pub fn predict(
    kind: ModelKind,
    laminate: &Laminate,
    planform: &Planform,
    drive: Drive,
) -> Result<Performance, ModelError> {
    let section = Section::new(laminate, drive)?;
    let original = evaluate(&section, planform);
    match kind {
        ModelKind::Original => Ok(original),
        ModelKind::ThesisAdjusted => Ok(empirical::adjust(
            &original,
            planform,
            section.pzt_thickness,
        )),
        ModelKind::EulerBernoulli => {
            if planform.extension_ratio != 0.0 || (planform.width_ratio - 1.0).abs() > 1e-12 {
                return Err(ModelError::OutOfRange {
                    name: "width_ratio/extension_ratio",
                    value: planform.width_ratio,
                    range: "the Euler-Bernoulli model covers rectangles only (w_r = 1, l_r = 0)",
                });
            }
            if drive.mode != crate::drive::DriveMode::Parallel
                && drive.mode != crate::drive::DriveMode::Series
            {
                return Err(ModelError::OutOfRange {
                    name: "drive mode",
                    value: f64::NAN,
                    range: "the Euler-Bernoulli model covers parallel and series drive",
                });
            }
            let beam = BeamBimorph::from_laminate(laminate, planform.length, planform.base_width)?;
            let r = beam.response(drive.field);
            Ok(original.with_outputs(r.free_deflection, r.blocked_force, original.mass_breakdown))
        }
    }
}

/// A model as the command line chooses it: one of the built-in kinds, or a calibrated model read from
/// `calibrated-model.toml` (`--model FILE`). [`ModelKind`] stays `Copy`; this carries the parameters.
#[derive(Debug, Clone)]
pub enum ModelChoice {
    /// A built-in model.
    Kind(ModelKind),
    /// The original model with calibrated physical effects ([`crate::effects`]).
    Calibrated(Arc<CalibratedModel>),
}

impl From<ModelKind> for ModelChoice {
    fn from(kind: ModelKind) -> Self {
        ModelChoice::Kind(kind)
    }
}

impl ModelChoice {
    /// Name for reports.
    pub fn name(&self) -> &'static str {
        match self {
            ModelChoice::Kind(k) => k.name(),
            ModelChoice::Calibrated(_) => "calibrated",
        }
    }

    /// Predict one actuator from its raw inputs (the calibrated effects change the stack itself, so they
    /// need the materials and thicknesses, not a finished laminate).
    pub fn predict(&self, a: &Actuator) -> Result<Performance, ModelError> {
        match self {
            ModelChoice::Kind(kind) => {
                let lam = Laminate::bimorph(
                    a.pzt,
                    a.pzt_thickness,
                    a.ply,
                    a.ply_thickness,
                    a.layup_deg,
                    None,
                )?;
                predict(*kind, &lam, &a.planform, a.drive)
            }
            ModelChoice::Calibrated(model) => model.predict(a),
        }
    }
}
