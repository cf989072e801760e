//! `actuator-cam nest batch.toml -o out/`: a batch of designs nested on shared sheets and clamp panels.

use super::flags::{self, FormatFlag, JsonFlag, OutputDir, StrokeFlag};
use super::interrupt;
use actuator_cam::{
    limits, plan_nest_observed, render_drawings, Batch, NestObserver, NestOptions, Output,
    SvgOptions, TimeBudget, Unobserved,
};
use cam_nest::{NestProgress, NestSettings};
use clap::Args;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::cell::RefCell;
use std::io::IsTerminal;
use std::path::PathBuf;
use std::time::Instant;

/// The nester's progress as a bar on stderr: which job (cut layer) of how many, the iterations of
/// its budget (or under a time budget, the time), its sheets against their lower bound, the best
/// density so far and the time left.
struct Bar {
    bar: ProgressBar,
    /// `job 2/3 passive`, set when a layer starts.
    job: RefCell<String>,
    time: Option<TimeBudget>,
}

impl Bar {
    fn new(time: Option<TimeBudget>) -> Bar {
        Bar {
            time,
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
        if let Some(t) = self.time {
            // The whole nest's time: the bar fills as it runs out, whichever layer reports.
            let left = t.deadline.saturating_duration_since(Instant::now());
            let total = (t.seconds * 1000.0) as u64;
            self.bar.set_length(total.max(1));
            self.bar
                .set_position(total.saturating_sub(left.as_millis() as u64));
            self.bar.set_message(format!(
                "{}, {:.0} s left",
                progress_line(p),
                left.as_secs_f64()
            ));
            return;
        }
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
    #[arg(long, value_name = "N")]
    pub seed: Option<u64>,
    /// Optimiser budget of the irregular nester per job of 60+ parts, smaller jobs a share (overrides the batch file's; default 1000). Above 1000, anytime rounds after the base search; with --time, the most it may do.
    #[arg(long, value_name = "N", value_parser = flags::iterations)]
    pub iterations: Option<usize>,
    /// Wall-clock budget of the whole nest, e.g. `30s`, `2m`, `90` (seconds; overrides the batch file's `time_s`): the search improves until then. Machine-dependent: the report records the iterations each layer reached, which `--iterations` replays.
    #[arg(long, value_name = "TIME", value_parser = flags::time_s)]
    pub time: Option<f64>,
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
    let max = limits::MAX_ITERATIONS as usize;
    let batch = Batch::load(&args.batch)?;
    let inputs = || {
        std::iter::once(batch.source.clone())
            .chain(batch.items.iter().map(|i| i.design.source.clone()))
            .chain(batch.parts.iter().map(|p| p.part.file.clone()))
    };
    args.output.check_ahead("nest", inputs(), &[])?;
    let time_s = args.time.or(batch.time_s);
    let iterations = args.iterations.or(batch.iterations);
    // A time budget alone searches until its deadline: the iteration cap is the largest allowed.
    let iterations = match (iterations, time_s) {
        (Some(n), _) => n,
        (None, Some(_)) => max,
        (None, None) => NestSettings::default().iterations,
    };
    interrupt::search_started();
    let opts = NestOptions {
        seed: args.seed.unwrap_or(batch.seed),
        iterations,
        time: time_s.map(TimeBudget::from_now),
        interrupt: Some(&interrupt::SEARCH_STOP),
    };
    // A bar on a terminal only: piped or redirected, stderr stays empty (and --json's stdout is
    // the report alone either way).
    let bar = std::io::stderr().is_terminal().then(|| Bar::new(opts.time));
    let observer: &dyn NestObserver = match &bar {
        Some(b) => b,
        None => &Unobserved,
    };
    let planned = plan_nest_observed(&batch, &opts, observer);
    interrupt::search_finished();
    interrupt::pause_after_interrupted_search();
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
    files.extend(
        planned
            .snap_guides
            .into_iter()
            .map(|(name, svg)| (name, svg.into_bytes())),
    );
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
        .inputs(inputs())
        .folder("-o", args.output.required(), files)
        .write()?;
    // A time budget that the first layout alone overran is said, with how long the layer's search took.
    for b in &report.baseline {
        if let Some(t) = b.search.as_ref().and_then(|r| r.over_budget_s) {
            eprintln!(
                "nest: layer {}: the time budget was exceeded: placing every part once took {t:.1} s",
                b.layer
            );
        }
    }
    if interrupt::search_ended() {
        eprintln!("the search was interrupted: the files hold the best layout found by then (the report says how far each layer got)");
    }
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
        // The linkages' coupons are parts too: counted with the linkages, not as drawn parts.
        let coupons: usize = report.linkages.iter().map(|l| 5 * l.quantity).sum();
        let extra: usize = report.parts.iter().map(|p| p.quantity).sum::<usize>() - coupons;
        let linkages: usize = report.linkages.iter().map(|l| l.quantity).sum();
        let mut extra = if extra > 0 {
            format!(" and {extra} parts from drawings")
        } else {
            String::new()
        };
        if linkages > 0 {
            extra.push_str(&format!(" and {linkages} linkages ({coupons} coupons)"));
        }
        println!(
            "{}: {} actuators{extra}, {} files in {}; {} PZT sheet(s), {}; {} clamp panel(s)",
            report.name,
            report.actuators(),
            count,
            args.output.required().display(),
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
