//! `cut-sheet`: turn one design into laser-cut layer drawings, a build checklist and a report with the
//! predicted mass and performance beside the geometry's own mass.

mod layers;
pub mod linkage;
mod preview;
pub mod report;
pub mod stream;
pub mod write;

pub use crate::pipeline::{BuildError, SheetDrawing};
pub use crate::process::{template, Template};
pub use report::Report;

use crate::design::Design;
use crate::drawing::model::Drawing;
use crate::drawing::palette::Palette;
use crate::input::{short_number, InputError};
use crate::pipeline::{build_into, DrawingSink, Names, Packing};
use crate::prediction::Prediction;
use actuator_model::model::ModelChoice;
use actuator_model::Material;

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

/// Everything a cut-sheet run produces, in memory, before anything is written.
#[derive(Debug, Clone)]
pub struct CutSheet {
    /// Drawings, in file order.
    pub drawings: Vec<SheetDrawing>,
    /// The report.
    pub report: Report,
    /// Preview of the assembled actuator.
    pub preview: Drawing,
    /// The snapping-order picture of each PZT sheet, (file name, SVG).
    pub snap_guides: Vec<(String, String)>,
    /// Operation colours of the process template.
    pub palette: Palette,
}

/// The design as the process builds it: method 1 adds its Pyralux bond layers to the stack so the
/// prediction's mass and stiffness include them. The model and the cut files must hold the same
/// layers, so a bond the design declares is refused when the process cuts none (method 2 co-cures
/// its prepreg: the bond would be mass no file cuts), or cuts one of another thickness or density.
pub fn design_for_process(design: &Design, template: &Template) -> Result<Design, BuildError> {
    if let Some((m, t)) = &design.bond {
        let refuse = |why: String| {
            BuildError::Input(InputError::invalid(
                &design.source,
                "laminate.bond",
                format!("{:?} ({} mm)", m.name, short_number(t * 1e3)),
                why,
            ))
        };
        match &template.bond {
            None => {
                return Err(refuse(format!(
                    "process {:?} ({}) cuts no bond layer, so the predicted mass would count a layer \
                     no file cuts; remove laminate.bond, or use a process with a [layers.pyralux] table",
                    template.name,
                    template.source.display()
                )))
            }
            Some(b)
                if (b.thickness_mm - t * 1e3).abs() > 1e-9
                    || (b.density_kg_per_m3 - m.density).abs() > 1e-9 =>
            {
                return Err(refuse(format!(
                    "process {:?} ({}) cuts its own bond layer, {} mm at {} kg/m^3; remove \
                     laminate.bond (the process adds its layer) or match it",
                    template.name,
                    template.source.display(),
                    short_number(b.thickness_mm),
                    short_number(b.density_kg_per_m3)
                )))
            }
            Some(_) => {}
        }
    }
    let mut d = design.clone();
    if let (Some(b), None) = (&template.bond, &design.bond) {
        let mut m = Material::builtin(&b.bond_material).ok_or_else(|| BuildError::Geometry {
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

/// The design with the ground tab the process gives a design that has no base tab
/// ([`Template::ground_tab_mm`], docs/cam.md §6 "Ground access"): the ground wire needs bare carbon,
/// and a design without a tab exposes only the 0.2-0.3 mm of the laminate's edge. Returns the tab
/// added, mm, if one was. The tab is clamped and carries no PZT, so it changes the mass alone.
pub fn with_ground_tab(design: Design, template: &Template) -> (Design, Option<f64>) {
    if design.planform.base_tab > 0.0 || template.ground_tab_mm <= 0.0 {
        return (design, None);
    }
    let mut d = design;
    d.planform.base_tab = template.ground_tab_mm * 1e-3;
    (d, Some(template.ground_tab_mm))
}

/// Plan all drawings and the report for a design (no I/O).
pub fn plan(
    design: &Design,
    template: &Template,
    opts: &CutSheetOptions,
) -> Result<CutSheet, BuildError> {
    plan_into(design, template, opts, None)
}

/// [`plan`], handing each drawing to `sink` as soon as it is made (file order) instead of keeping it,
/// so that a large quantity holds one sheet's drawing at a time; the returned [`CutSheet::drawings`]
/// is then empty.
pub fn plan_into<'s>(
    design: &Design,
    template: &Template,
    opts: &CutSheetOptions,
    sink: Option<&'s mut DrawingSink<'s>>,
) -> Result<CutSheet, BuildError> {
    let template = process_template(template, opts);
    let (mut design, ground_tab_mm) =
        with_ground_tab(design_for_process(design, &template)?, &template);
    if let Some(q) = opts.quantity {
        design.quantity = q;
    }
    // Every feature against the kerf, naming the design field, before anything is laid out.
    design.check_cut(widest_kerf_mm(&template), template.pzt_edge_margin_mm)?;
    let file = design.source.display().to_string();
    let prediction = Prediction::with_model(&design, &opts.model)
        .map_err(|e| BuildError::Model(e, file.clone()))?;
    prediction.ensure_finite(&design)?;
    let ground_tab = match ground_tab_mm {
        Some(length_mm) => {
            let mut bare = design.clone();
            bare.planform.base_tab = 0.0;
            let without = Prediction::with_model(&bare, &opts.model)
                .map_err(|e| BuildError::Model(e, file.clone()))?;
            Some(report::GroundTab {
                length_mm,
                mass_mg: prediction.mass_mg - without.mass_mg,
            })
        }
        None => None,
    };
    // A batch of one: the same pipeline as `nest`, with the shelf packer for the cut-through layers.
    let names = Names {
        title: design.name.clone(),
        file,
        name_designs: false,
    };
    let built = build_into(
        &[(&design, design.quantity)],
        &[],
        &template,
        &names,
        &Packing::Shelf,
        sink,
    )?;
    let rows = layers::layer_rows(&design, &template, &built);
    let prediction = match built.drawn_bond_mg(0) {
        Some(bond_mg) => prediction.with_drawn_bond(bond_mg),
        None => prediction,
    };
    let report = Report::new(&design, &template, prediction, rows, &built, ground_tab);
    report.ensure_finite(&design)?;
    Ok(CutSheet {
        preview: preview::preview(&built.geometry[0], &design.name),
        drawings: built.drawings,
        snap_guides: built.snap_guides,
        report,
        palette: template.palette.clone(),
    })
}

/// The widest kerf of the layers whose parts follow the design's outline (PZT, passive, Pyralux), mm.
fn widest_kerf_mm(template: &Template) -> f64 {
    [template.pzt.kerf_mm, template.passive.kerf_mm]
        .into_iter()
        .chain(template.bond.as_ref().map(|b| b.sheet.kerf_mm))
        .fold(0.0, f64::max)
}

/// The template as a cut-sheet run uses it: `--kerf-mm` applied, and no PZT stock limit (one design is
/// laid out whatever the stock: stock limits are a batch's concern).
pub fn process_template(template: &Template, opts: &CutSheetOptions) -> Template {
    let mut template = template.clone();
    if let Some(k) = opts.kerf_mm {
        template.override_kerf(k);
    }
    template.pzt.stock = None;
    template
}
