//! `actuator-cam cut-sheet design.toml -o out/`: laser files, report and build checklist for one design.

use super::flags::{FormatFlag, ModelFlag, OutputDir, StrokeFlag};
use actuator_cam::cutsheet::stream::plan_and_put;
use actuator_cam::cutsheet::{write, CutSheetOptions, Template};
use actuator_cam::design::Design;
use actuator_cam::output::Output;
use anyhow::bail;
use clap::Args;
use std::path::PathBuf;

/// Arguments of `cut-sheet`.
#[derive(Debug, Args)]
pub struct CutSheetArgs {
    /// Design file (design.toml).
    pub design: PathBuf,
    /// `-o`.
    #[command(flatten)]
    pub output: OutputDir,
    /// `--format`.
    #[command(flatten)]
    pub format: FormatFlag,
    /// Kerf for every layer, mm (overrides the template; calibrate it on a coupon).
    #[arg(long)]
    pub kerf_mm: Option<f64>,
    /// Number of actuators (overrides the design's quantity).
    #[arg(long)]
    pub quantity: Option<i64>,
    /// `--model` of the predicted performance.
    #[command(flatten)]
    pub model: ModelFlag,
    /// `--stroke-mm`.
    #[command(flatten)]
    pub stroke: StrokeFlag,
}

/// Run `cut-sheet`.
pub fn run(args: &CutSheetArgs) -> anyhow::Result<()> {
    let formats = args.format.formats();
    if let Some(k) = args.kerf_mm {
        if !(k.is_finite() && (0.0..=2.0).contains(&k)) {
            bail!("--kerf-mm = {k}: outside the allowed range [0, 2] mm");
        }
    }
    let quantity = match args.quantity {
        None => None,
        Some(q) if (1..=actuator_cam::input::limits::MAX_QUANTITY).contains(&q) => Some(q as usize),
        Some(q) => bail!(
            "--quantity = {q}: outside the allowed range [1, {}]",
            actuator_cam::input::limits::MAX_QUANTITY
        ),
    };
    let design = Design::load(&args.design)?;
    let template = Template::resolve(&design.process, &design.source)?;
    let opts = CutSheetOptions {
        formats,
        kerf_mm: args.kerf_mm,
        quantity,
        model: args.model.model.clone(),
        stroke_mm: args.stroke.stroke_mm,
    };
    // Checked against the output policy before any work; the files then go into its staging folder one
    // drawing at a time, so memory holds one sheet's drawing and the report, whatever the quantity.
    let mut folder = Output::new("cut-sheet")
        .force(args.output.force.force)
        .inputs(
            std::iter::once(design.source.clone())
                .chain(Template::file_of(&design.process, &design.source)),
        )
        .stream_folder("-o", &args.output.output)?;
    let (sheet, layer_files) = plan_and_put(&design, &template, &opts, &mut |name, bytes| {
        folder.add(name, bytes).map_err(Into::into)
    })?;
    for (name, bytes) in write::render_report(&sheet, &layer_files, args.stroke.stroke_mm)? {
        folder.add(&name, &bytes)?;
    }
    let count = folder.len();
    folder.finish()?;
    let r = &sheet.report;
    println!(
        "{} x {}: {} files in {} ({} PZT sheet(s), {} clamp panel(s)); mass {:.2} mg (geometry {:.2} mg), energy {:.4} mJ",
        r.design.name,
        r.quantity,
        count,
        args.output.output.display(),
        r.layers.iter().find(|l| l.layer == "pzt").map(|l| l.sheets).unwrap_or(0),
        r.clamp_panels,
        r.predicted.mass_mg,
        r.mass_from_geometry_mg,
        r.predicted.energy_mJ
    );
    Ok(())
}
