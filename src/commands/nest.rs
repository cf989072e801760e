//! `actuator-cam nest batch.toml -o out/`: a batch of designs nested on shared sheets and clamp panels.

use super::formats::parse_formats;
use crate::batch::{plan, Batch, NestOptions};
use crate::cam::svg::SvgOptions;
use crate::cutsheet::write::{render_drawings, write_atomically};
use anyhow::bail;
use cam_nest::NestSettings;
use clap::Args;
use std::path::PathBuf;

/// Arguments of `nest`.
#[derive(Debug, Args)]
pub struct NestArgs {
    /// Batch file (designs relative to it).
    pub batch: PathBuf,
    /// Output directory (replaced as a whole when the run succeeds).
    #[arg(short, long, default_value = "out")]
    pub output: PathBuf,
    /// File formats, comma separated.
    #[arg(long, value_delimiter = ',', default_value = "svg,dxf")]
    pub format: Vec<String>,
    /// Seed of the nester (overrides the batch file's).
    #[arg(long)]
    pub seed: Option<u64>,
    /// Optimiser budget of the irregular nester per job of 60+ parts, smaller jobs a share (overrides the batch file's; default 1000).
    #[arg(long)]
    pub iterations: Option<usize>,
    /// Print nest-report.json to stdout instead of the summary line.
    #[arg(long)]
    pub json: bool,
    /// Hairline stroke width in the SVG files, mm.
    #[arg(long, default_value_t = 0.0254)]
    pub stroke_mm: f64,
}

/// Run `nest`.
pub fn run(args: &NestArgs) -> anyhow::Result<()> {
    let formats = parse_formats(&args.format)?;
    if !(args.stroke_mm.is_finite() && args.stroke_mm > 0.0 && args.stroke_mm <= 1.0) {
        bail!(
            "--stroke-mm = {}: outside the allowed range (0, 1] mm",
            args.stroke_mm
        );
    }
    let max = crate::batch::file::MAX_ITERATIONS as usize;
    if let Some(n) = args.iterations.filter(|n| *n > max) {
        bail!("--iterations = {n}: outside the allowed range [0, {max}]");
    }
    let batch = Batch::load(&args.batch)?;
    let opts = NestOptions {
        seed: args.seed.unwrap_or(batch.seed),
        iterations: args
            .iterations
            .or(batch.iterations)
            .unwrap_or(NestSettings::default().iterations),
    };
    let planned = plan(&batch, &opts)?;
    let mut files = render_drawings(
        &planned.drawings,
        formats,
        &SvgOptions {
            stroke_mm: args.stroke_mm,
            palette: batch.template.palette.clone(),
        },
    )?;
    let mut report = planned.report;
    report.files = files
        .iter()
        .map(|(n, _)| n.clone())
        .chain(["nest-report.json".into(), "nest-report.md".into()])
        .collect();
    let json = serde_json::to_string_pretty(&report)? + "\n";
    files.push(("nest-report.json".into(), json.clone().into_bytes()));
    files.push(("nest-report.md".into(), report.markdown().into_bytes()));
    write_atomically(&args.output, &files)?;
    if args.json {
        print!("{json}");
    } else {
        let passive: Vec<String> = report.baseline.iter().map(|b| b.summary()).collect();
        println!(
            "{}: {} actuators, {} files in {}; {} PZT sheet(s), {}; {} clamp panel(s)",
            report.name,
            report.actuators(),
            files.len(),
            args.output.display(),
            report.sheets_of("pzt"),
            passive.join("; "),
            report.clamp_panels.len()
        );
    }
    Ok(())
}
