//! `actuator-cam cut-sheet design.toml -o out/`: laser files, report and build checklist for one design.

use super::flags::{self, FormatFlag, ModelFlag, OutputDir, StrokeFlag};
use actuator_cam::{
    plan_and_put, plan_linkage, render_drawings, render_report, svg_options, transmission_of,
    CutSheetOptions, Design, LinkageSection, Output, Template,
};
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
    #[arg(long, value_name = "MM", value_parser = flags::kerf_mm)]
    pub kerf_mm: Option<f64>,
    /// Number of actuators (overrides the design's quantity).
    #[arg(long, value_name = "N", value_parser = flags::quantity)]
    pub quantity: Option<usize>,
    /// `--model` of the predicted performance.
    #[command(flatten)]
    pub model: ModelFlag,
    /// `--stroke-mm`.
    #[command(flatten)]
    pub stroke: StrokeFlag,
    /// Drive file whose linkage is cut with the actuator: its laminate layers and release cut
    /// (docs/cam.md §7); a design's own `[transmission]` is cut without it.
    #[arg(long, value_name = "FILE")]
    pub drive: Option<PathBuf>,
}

/// Run `cut-sheet`.
pub fn run(args: &CutSheetArgs) -> anyhow::Result<()> {
    let formats = args.format.formats();
    let design = Design::load(&args.design)?;
    let template = Template::resolve(&design.process, &design.source)?;
    let opts = CutSheetOptions {
        formats,
        kerf_mm: args.kerf_mm,
        quantity: args.quantity,
        model: args.model.model.clone(),
        stroke_mm: args.stroke.stroke_mm,
    };
    // The linkage is planned and checked before any file is written.
    let linkage = transmission_of(args.drive.as_deref(), &design)?
        .map(|(source, spec)| plan_linkage(&source, &spec, &design, &template, &opts))
        .transpose()?;
    // Checked against the output policy before any work; the files then go into its staging folder one
    // drawing at a time, so memory holds one sheet's drawing and the report, whatever the quantity.
    let mut folder = Output::new("cut-sheet")
        .force(args.output.force.force)
        .inputs(
            std::iter::once(design.source.clone())
                .chain(Template::file_of(&design.process, &design.source))
                .chain(args.drive.clone()),
        )
        .stream_folder("-o", args.output.required())?;
    let (mut sheet, mut layer_files) =
        plan_and_put(&design, &template, &opts, &mut |name, bytes| {
            folder.add(name, bytes).map_err(Into::into)
        })?;
    if let Some(l) = &linkage {
        let svg = svg_options(&sheet.palette, args.stroke.stroke_mm);
        for (name, bytes) in render_drawings(&l.drawings, formats, &svg)? {
            folder.add(&name, &bytes)?;
            layer_files.push(name);
        }
        sheet.report.linkage = Some(LinkageSection::new(l, &template));
        l.count_stock(&mut sheet.report.stock_list);
    }
    for (name, bytes) in render_report(&sheet, &layer_files, args.stroke.stroke_mm)? {
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
        args.output.required().display(),
        r.layers.iter().find(|l| l.layer == "pzt").map(|l| l.sheets).unwrap_or(0),
        r.clamp_panels,
        r.predicted.mass_mg,
        r.mass_from_geometry_mg,
        r.predicted.energy_mJ
    );
    if let Some(l) = &r.linkage {
        println!(
            "linkage: {} panel(s), {:.3} mg each, flexures {:.3} uN m/rad about the wing hinge{}",
            l.panels,
            l.laminate.mass_mg,
            l.laminate.flexure_stiffness_uNm_per_rad,
            if l.note.is_some() {
                " (see report.md: the drive file gives another transmission)"
            } else {
                ""
            }
        );
    }
    Ok(())
}
