//! `cut-sheet`: turn one design into laser-cut layer drawings, a build checklist and a report with the
//! predicted mass and performance beside the geometry's own mass.

pub mod clamp;
pub mod cut;
pub mod features;
pub mod jobs;
pub mod panel;
pub mod parts;
pub mod pzt;
pub mod report;
pub mod sheets;
pub mod template;
pub mod write;

pub use report::{LayerRow, Report};
pub use template::Template;

use crate::cam::drawing::Drawing;
use crate::cam::palette::Palette;
use crate::design::Design;
use crate::prediction::Prediction;
use actuator_model::model::ModelChoice;
use actuator_model::Material;
use thiserror::Error;

/// Which file formats to write.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Formats {
    /// SVG files.
    pub svg: bool,
    /// DXF files.
    pub dxf: bool,
}

/// Settings of one cut-sheet run (after the command line is parsed).
#[derive(Debug, Clone)]
pub struct CutSheetOptions {
    /// File formats.
    pub formats: Formats,
    /// Kerf for every layer, overriding the template, mm.
    pub kerf_mm: Option<f64>,
    /// Quantity overriding the design's.
    pub quantity: Option<usize>,
    /// Model for the predicted performance.
    pub model: ModelChoice,
    /// Hairline stroke width, mm.
    pub stroke_mm: f64,
}

/// A cut-sheet problem the user can fix.
#[derive(Debug, Error)]
pub enum CutSheetError {
    /// A feature vanishes or is thinner than the kerf.
    #[error("{file}: {what}")]
    Geometry {
        /// Design file.
        file: String,
        /// What is wrong, with the numbers.
        what: String,
    },
    /// The model refused the design.
    #[error("{file}: {0}", file = .1)]
    Model(actuator_model::ModelError, String),
    /// A drawing could not be serialised.
    #[error("{0}")]
    Output(String),
}

/// One named drawing (a layer on one sheet or panel).
#[derive(Debug, Clone)]
pub struct SheetDrawing {
    /// File stem: `pzt-1`, `mold-2-1`, …
    pub stem: String,
    /// Layer name the report groups it under.
    pub layer: String,
    /// The geometry.
    pub drawing: Drawing,
}

/// Everything a cut-sheet run produces, in memory, before anything is written.
#[derive(Debug, Clone)]
pub struct CutSheet {
    /// Drawings, in file order.
    pub drawings: Vec<SheetDrawing>,
    /// The report.
    pub report: Report,
    /// Preview of the assembled actuator.
    pub preview: Drawing,
    /// Operation colours of the process template.
    pub palette: Palette,
}

/// The design as the process builds it: method 1 adds its Pyralux bond layers to the stack so the
/// prediction's mass and stiffness include them.
pub fn design_for_process(design: &Design, template: &Template) -> Result<Design, CutSheetError> {
    let mut d = design.clone();
    if let (Some(b), None) = (&template.bond, &design.bond) {
        let mut m = Material::builtin(&b.bond_material).ok_or_else(|| CutSheetError::Geometry {
            file: design.source.display().to_string(),
            what: format!(
                "template {}: bond material {:?} is not in the library",
                template.name, b.bond_material
            ),
        })?;
        m.density = b.density_kg_per_m3;
        d.bond = Some((m, b.thickness_mm * 1e-3));
    }
    Ok(d)
}

/// Plan all drawings and the report for a design (no I/O).
pub fn plan(
    design: &Design,
    template: &Template,
    opts: &CutSheetOptions,
) -> Result<CutSheet, CutSheetError> {
    let mut template = template.clone();
    if let Some(k) = opts.kerf_mm {
        template.override_kerf(k);
    }
    let mut design = design_for_process(design, &template)?;
    if let Some(q) = opts.quantity {
        design.quantity = q;
    }
    let file = design.source.display().to_string();
    let prediction = Prediction::with_model(&design, &opts.model)
        .map_err(|e| CutSheetError::Model(e, file.clone()))?;
    let built = sheets::build(&design, &template)?;
    let report = report::Report::new(&design, &template, prediction, &built);
    Ok(CutSheet {
        drawings: built.drawings,
        report,
        preview: built.preview,
        palette: template.palette.clone(),
    })
}
