//! `actuator-cam nest batch.toml -o out/`: a batch of designs nested on shared sheets and clamp panels.

use super::flags::{FormatFlag, JsonFlag, OutputDir, StrokeFlag};
use actuator_cam::batch::{plan_observed, Batch, NestOptions};
use actuator_cam::cam::svg::SvgOptions;
use actuator_cam::cutsheet::write::render_drawings;
use actuator_cam::output::Output;
use actuator_cam::pipeline::{NestObserver, Unobserved};
use anyhow::bail;
use cam_nest::{NestProgress, NestSettings};
use clap::Args;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::cell::RefCell;
use std::io::IsTerminal;
use std::path::PathBuf;

/// The nester's progress as a bar on stderr: which job (cut layer) of how many, the iterations of
/// its budget, its sheets against their lower bound and the best density so far.
struct Bar {
    bar: ProgressBar,
    /// `job 2/3 passive`, set when a layer starts.
    job: RefCell<String>,
}

impl Bar {
    fn new() -> Bar {
        Bar {
            bar: ProgressBar::with_draw_target(None, ProgressDrawTarget::stderr()).with_style(
                ProgressStyle::with_template("nest {prefix} {wide_bar} {msg}")
                    .unwrap_or_else(|_| ProgressStyle::default_bar()),
            ),
            job: RefCell::new(String::new()),
        }
    }
}

impl NestObserver for Bar {
    fn layer(&self, index: usize, count: usize, layer: &str, parts: usize) {
        let job = format!("job {}/{count} {layer} ({parts} parts)", index + 1);
        self.bar.set_prefix(job.clone());
        self.bar.set_position(0);
        self.bar.set_message("");
        *self.job.borrow_mut() = job;
    }

    fn progress(&self, p: &NestProgress) {
        self.bar.set_length(p.iterations_budget.max(1) as u64);
        self.bar.set_position(if p.finished {
            p.iterations_budget.max(1) as u64
        } else {
            p.iterations_done as u64
        });
        self.bar.set_message(progress_line(p));
    }
}

/// What the bar says about a job: sheets (and their lower bound) and the best density.
fn progress_line(p: &NestProgress) -> String {
    format!(
        "{} sheet(s) (at least {}), best density {:.1}%",
        p.sheets,
        p.sheets_lower_bound,
        p.best_density * 100.0
    )
}

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
    let max = actuator_cam::input::limits::MAX_ITERATIONS as usize;
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
    // A bar on a terminal only: piped or redirected, stderr stays empty (and --json's stdout is
    // the report alone either way).
    let bar = std::io::stderr().is_terminal().then(Bar::new);
    let observer: &dyn NestObserver = match &bar {
        Some(b) => b,
        None => &Unobserved,
    };
    let planned = plan_observed(&batch, &opts, observer);
    if let Some(b) = &bar {
        b.bar.finish_and_clear();
    }
    let planned = planned?;
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
                .chain(batch.items.iter().map(|i| i.design.source.clone()))
                .chain(batch.parts.iter().map(|p| p.part.file.clone())),
        )
        .folder("-o", &args.output.output, files)
        .write()?;
    if args.json.json {
        print!("{json}");
    } else {
        // Each layer's nest, then each priced roll's cost beside its cut sheets.
        let passive: Vec<String> = report
            .baseline
            .iter()
            .map(|b| b.summary())
            .chain(report.rolls.iter().filter_map(|r| r.summary()))
            .collect();
        let extra: usize = report.parts.iter().map(|p| p.quantity).sum();
        let extra = if extra > 0 {
            format!(" and {extra} parts from drawings")
        } else {
            String::new()
        };
        println!(
            "{}: {} actuators{extra}, {} files in {}; {} PZT sheet(s), {}; {} clamp panel(s)",
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_bar_names_sheets_their_bound_and_the_density() {
        let p = NestProgress {
            iterations_done: 40,
            iterations_budget: 100,
            sheets: 3,
            sheets_lower_bound: 2,
            best_density: 0.7834,
            finished: false,
        };
        assert_eq!(
            progress_line(&p),
            "3 sheet(s) (at least 2), best density 78.3%"
        );
    }
}
