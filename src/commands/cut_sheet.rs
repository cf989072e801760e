//! `actuator-cam cut-sheet design.toml -o out/`: laser files, report and build checklist for one design.

use super::formats::parse_formats;
use super::model_arg::parse_model;
use crate::cutsheet::{plan, write, CutSheetOptions, Template};
use crate::design::Design;
use anyhow::bail;
use clap::Args;
use std::path::PathBuf;

/// Arguments of `cut-sheet`.
#[derive(Debug, Args)]
pub struct CutSheetArgs {
    /// Design file (design.toml).
    pub design: PathBuf,
    /// Output directory (replaced as a whole when the run succeeds).
    #[arg(short, long, default_value = "out")]
    pub output: PathBuf,
    /// File formats, comma separated.
    #[arg(long, value_delimiter = ',', default_value = "svg,dxf")]
    pub format: Vec<String>,
    /// Kerf for every layer, mm (overrides the template; calibrate it on a coupon).
    #[arg(long)]
    pub kerf_mm: Option<f64>,
    /// Number of actuators (overrides the design's quantity).
    #[arg(long)]
    pub quantity: Option<i64>,
    /// Model for the predicted performance: original, thesis-adjusted, euler-bernoulli, or a calibrated-model.toml.
    #[arg(long, default_value = "original")]
    pub model: String,
    /// Hairline stroke width in the SVG files, mm.
    #[arg(long, default_value_t = 0.0254)]
    pub stroke_mm: f64,
}

/// Run `cut-sheet`.
pub fn run(args: &CutSheetArgs) -> anyhow::Result<()> {
    let formats = parse_formats(&args.format)?;
    if let Some(k) = args.kerf_mm {
        if !(k.is_finite() && (0.0..=2.0).contains(&k)) {
            bail!("--kerf-mm = {k}: outside the allowed range [0, 2] mm");
        }
    }
    let quantity = match args.quantity {
        None => None,
        Some(q) if (1..=crate::input::limits::MAX_QUANTITY).contains(&q) => Some(q as usize),
        Some(q) => bail!(
            "--quantity = {q}: outside the allowed range [1, {}]",
            crate::input::limits::MAX_QUANTITY
        ),
    };
    if !(args.stroke_mm.is_finite() && args.stroke_mm > 0.0 && args.stroke_mm <= 1.0) {
        bail!(
            "--stroke-mm = {}: outside the allowed range (0, 1] mm",
            args.stroke_mm
        );
    }
    let design = Design::load(&args.design)?;
    let template = Template::resolve(&design.process, &design.source)?;
    let opts = CutSheetOptions {
        formats,
        kerf_mm: args.kerf_mm,
        quantity,
        model: parse_model(&args.model)?,
        stroke_mm: args.stroke_mm,
    };
    let sheet = plan(&design, &template, &opts)?;
    let files = write::render(&sheet, formats, args.stroke_mm)?;
    write::write_atomically(&args.output, &files)?;
    let r = &sheet.report;
    println!(
        "{} x {}: {} files in {} ({} PZT sheet(s), {} clamp panel(s)); mass {:.2} mg (geometry {:.2} mg), energy {:.4} mJ",
        r.design.name,
        r.quantity,
        files.len(),
        args.output.display(),
        r.layers.iter().find(|l| l.layer == "pzt").map(|l| l.sheets).unwrap_or(0),
        r.clamp_panels,
        r.predicted.mass_mg,
        r.mass_from_geometry_mg,
        r.predicted.energy_mJ
    );
    Ok(())
}
