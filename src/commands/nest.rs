//! `actuator-cam nest batch.toml -o out/`: a batch of designs nested on shared sheets and clamp panels.

use super::flags::{FormatFlag, JsonFlag, OutputDir, StrokeFlag};
use crate::batch::{plan, Batch, NestOptions};
use crate::cam::svg::SvgOptions;
use crate::cutsheet::write::render_drawings;
use crate::output::Output;
use anyhow::bail;
use cam_nest::NestSettings;
use clap::Args;
use std::path::PathBuf;

/// Arguments of `nest`.
#[derive(Debug, Args)]
pub struct NestArgs {
    /// Batch file (designs relative to it).
    pub batch: PathBuf,
    /// `-o`.
    #[command(flatten)]
    pub output: OutputDir,
    /// `--format`.
    #[command(flatten)]
    pub format: FormatFlag,
    /// Seed of the nester (overrides the batch file's).
    #[arg(long)]
    pub seed: Option<u64>,
    /// Optimiser budget of the irregular nester per job of 60+ parts, smaller jobs a share (overrides the batch file's; default 1000).
    #[arg(long)]
    pub iterations: Option<usize>,
    /// `--json`: nest-report.json on standard output.
    #[command(flatten)]
    pub json: JsonFlag,
    /// `--stroke-mm`.
    #[command(flatten)]
    pub stroke: StrokeFlag,
}

/// Run `nest`.
pub fn run(args: &NestArgs) -> anyhow::Result<()> {
    let formats = args.format.formats();
    let max = crate::input::limits::MAX_ITERATIONS as usize;
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
            stroke_mm: args.stroke.stroke_mm,
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
    let count = files.len();
    Output::new("nest")
        .force(args.output.force.force)
        .inputs(
            std::iter::once(batch.source.clone())
                .chain(batch.items.iter().map(|i| i.design.source.clone())),
        )
        .folder("-o", &args.output.output, files)
        .write()?;
    if args.json.json {
        print!("{json}");
    } else {
        let passive: Vec<String> = report.baseline.iter().map(|b| b.summary()).collect();
        println!(
            "{}: {} actuators, {} files in {}; {} PZT sheet(s), {}; {} clamp panel(s)",
            report.name,
            report.actuators(),
            count,
            args.output.output.display(),
            report.sheets_of("pzt"),
            passive.join("; "),
            report.clamp_panels.len()
        );
    }
    Ok(())
}
