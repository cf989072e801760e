//! `actuator-cam optimize`: the lightest actuator (or the highest energy density) that delivers a required
//! mechanical energy, as the thesis' `OptimizedActuator` (Lenzen 2013, §4.10), exact and fast.
//!
//! Two stages: an exhaustive grid over `(l_tot, w_0, l_r, w_r)` for every `(t_p, layup)` ([`search`]),
//! then a continuous refinement from the best grid cells of each laminate ([`refine`]). The laminate is
//! solved once per `(t_p, layup, field)`.

pub mod model;
pub mod pareto;
pub mod refine;
pub mod report;
pub mod search;
pub mod spec;

use crate::commands::model_arg::parse_model;
use actuator_model::ModelChoice;
use anyhow::{bail, Context};
use clap::Args;
use rayon::prelude::*;
use search::{Design, GridResult, Objective, Problem};
use spec::Spec;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Energy levels on the Pareto front.
pub const PARETO_LEVELS: usize = 40;

/// Grids above this many designs show a progress bar (on a terminal only).
const PROGRESS_ABOVE: u64 = 20_000_000;

/// `actuator-cam optimize`.
#[derive(Debug, Clone, Args)]
pub struct OptimizeArgs {
    /// Spec file: requirement, drive, search ranges, laminate, constraints (see examples/optimize-*.toml).
    pub spec: PathBuf,
    /// Model to optimise with: original, thesis-adjusted, or a calibrated-model.toml from `calibrate`.
    #[arg(long, default_value = "original")]
    pub model: String,
    /// What to optimise.
    #[arg(long, value_enum, default_value_t = Objective::MinMass)]
    pub objective: Objective,
    /// Write the winning design as a design.toml (cut-sheet reads it).
    #[arg(short = 'o', long = "output", value_name = "DESIGN_TOML")]
    pub output: Option<PathBuf>,
    /// Write the front of mass against delivered energy as CSV, and beside it an SVG plot.
    #[arg(long, value_name = "CSV")]
    pub pareto: Option<PathBuf>,
    /// Print the exhaustive stage's designs per second and the total time to stderr.
    #[arg(long)]
    pub bench: bool,
}

/// Everything one optimisation found.
#[derive(Debug, Clone)]
pub struct Outcome {
    /// The problem as solved.
    pub problem: Problem,
    /// Exhaustive stage.
    pub grid: GridResult,
    /// Refined best per laminate (`None`: it cannot reach the energy).
    pub refined: Vec<Option<Design>>,
    /// Most energetic design per laminate (`None`: no design meets the tip width).
    pub most_energy: Vec<Option<Design>>,
    /// The optimum.
    pub best: Design,
    /// Wall-clock time of the exhaustive stage, s (reported by `--bench` only: it varies run to run).
    pub grid_seconds: f64,
}

/// Why an optimisation has no answer.
#[derive(Debug, Clone, thiserror::Error)]
pub enum OptimizeError {
    /// No design in the ranges delivers the energy.
    #[error("infeasible: the most energy reachable in the search ranges is {most_energy_mj} mJ ({design}); lower the requirement or widen the ranges")]
    Infeasible {
        /// The most energy any design reaches, mJ.
        most_energy_mj: String,
        /// That design.
        design: String,
    },
}

/// Run both stages on a problem.
pub fn optimize(problem: Problem, progress: bool) -> Result<Outcome, OptimizeError> {
    let grid_start = Instant::now();
    let grid = search::exhaustive(&problem, progress);
    let grid_seconds = grid_start.elapsed().as_secs_f64();
    let per: Vec<(Option<Design>, Option<Design>)> = (0..problem.candidates.len())
        .into_par_iter()
        .map(|c| {
            let g = &grid.per_candidate[c];
            let most = g
                .most_energy
                .map(|seed| refine::most_energy(&problem, c, &seed));
            let mut seeds = g.seeds.clone();
            if let Some(m) = most.filter(|m| m.energy >= problem.energy) {
                if seeds.is_empty() {
                    seeds.push(m);
                }
            }
            (refine::refine(&problem, c, &seeds), most)
        })
        .collect();
    let (refined, most_energy): (Vec<_>, Vec<_>) = per.into_iter().unzip();
    let best = refined.iter().flatten().copied().reduce(|a, b| {
        if problem.compare(&b, &a).is_lt() {
            b
        } else {
            a
        }
    });
    match best {
        Some(best) => Ok(Outcome {
            problem,
            grid,
            refined,
            most_energy,
            best,
            grid_seconds,
        }),
        None => {
            let top = most_energy.iter().flatten().copied().reduce(|a, b| {
                if b.energy > a.energy {
                    b
                } else {
                    a
                }
            });
            Err(OptimizeError::Infeasible {
                most_energy_mj: top.map_or("0".into(), |d| format!("{:.6}", d.energy * 1e3)),
                design: top.map_or("no design meets the tip width".into(), |d| {
                    let c = &problem.candidates[d.candidate];
                    format!(
                        "t_p {} mm {}, l_tot {:.4} mm, l_r {:.4}, w_0 {:.4} mm, w_r {:.4}",
                        c.pzt_thickness * 1e3,
                        report::layup_label(&c.layup),
                        d.length * 1e3,
                        d.extension_ratio,
                        d.base_width * 1e3,
                        d.width_ratio
                    )
                }),
            })
        }
    }
}

/// The search model named on the command line: a built-in name or a `calibrated-model.toml`.
fn search_model(name: &str) -> anyhow::Result<model::SearchModel> {
    match parse_model(name)? {
        ModelChoice::Calibrated(m) => Ok(model::SearchModel::Calibrated(m)),
        ModelChoice::Kind(kind) => model::SearchModel::from_kind(kind).with_context(|| {
            format!(
                "--model {name}: the Euler-Bernoulli beam covers rectangles only and has no taper or extension to optimise; use original, thesis-adjusted or a calibrated-model.toml"
            )
        }),
    }
}

/// `actuator-cam optimize`.
pub fn run(args: &OptimizeArgs) -> anyhow::Result<()> {
    let start = Instant::now();
    let model = search_model(&args.model)?;
    let spec = Spec::from_file(&args.spec)?;
    let file = args.spec.display().to_string();
    let problem = Problem::from_spec(&spec, model, args.objective)
        .with_context(|| format!("{file}: the laminate cannot be solved"))?;
    let progress = problem.grid_size() > PROGRESS_ABOVE;
    let outcome = optimize(problem, progress).map_err(|e| match e {
        OptimizeError::Infeasible { .. } => {
            anyhow::anyhow!("{file}: requirement.energy_mJ = {}: {e}", spec.energy * 1e3)
        }
    })?;
    let total = start.elapsed().as_secs_f64();
    let best = outcome.best;
    let perf = outcome
        .problem
        .performance(&best)
        .with_context(|| format!("{file}: the optimum cannot be predicted"))?;
    if perf.energy < spec.energy * (1.0 - 1e-9) {
        bail!(
            "internal: the optimum delivers {} mJ < {} mJ",
            perf.energy * 1e3,
            spec.energy * 1e3
        );
    }
    print!("{}", report::text(&spec, &file, &outcome, &perf));
    if let Some(path) = &args.output {
        write(path, &report::design_toml(&spec, &outcome.problem, &best))?;
        println!("\nwrote {}", path.display());
    }
    if let Some(path) = &args.pareto {
        let most: Vec<Design> = outcome.most_energy.iter().flatten().copied().collect();
        let front = pareto::front(&outcome.problem, &most, PARETO_LEVELS);
        write(path, &pareto::to_csv(&outcome.problem, &front)?)?;
        let svg = path.with_extension("svg");
        write(&svg, &pareto::to_svg(&front, spec.energy, Some(&best)))?;
        println!(
            "wrote {} and {} ({} designs on the front)",
            path.display(),
            svg.display(),
            front.len()
        );
    }
    if args.bench {
        eprintln!("{}", bench(&outcome, total));
    }
    Ok(())
}

/// Runs of the exhaustive stage timed by `--bench`.
const BENCH_RUNS: usize = 5;

/// `--bench`: the exhaustive stage run [`BENCH_RUNS`] more times. Reports the fastest wall-clock run and the
/// process CPU time per run: on a shared machine the wall clock measures the other jobs too, while
/// designs per CPU-second times the number of idle cores is what the code does.
fn bench(outcome: &Outcome, total_seconds: f64) -> String {
    let designs = outcome.grid.evaluated as f64;
    let cpu_before = process_cpu_seconds();
    let mut fastest = outcome.grid_seconds;
    for _ in 0..BENCH_RUNS {
        let t = Instant::now();
        std::hint::black_box(search::exhaustive(&outcome.problem, false));
        fastest = fastest.min(t.elapsed().as_secs_f64());
    }
    let cpu = match (cpu_before, process_cpu_seconds()) {
        (Some(a), Some(b)) if b > a => format!(
            "; CPU time {:.3} s per run = {:.0} million designs per CPU-second",
            (b - a) / BENCH_RUNS as f64,
            designs * BENCH_RUNS as f64 / (b - a) / 1e6
        ),
        _ => String::new(),
    };
    let load = std::fs::read_to_string("/proc/loadavg")
        .ok()
        .and_then(|l| {
            l.split_whitespace()
                .next()
                .map(|s| format!("; load average {s}"))
        })
        .unwrap_or_default();
    format!(
        "bench: exhaustive stage {} designs, fastest of {} runs {:.3} s = {:.0} million designs/s on {} threads{cpu}{load}; whole optimisation (first run) {:.3} s",
        outcome.grid.evaluated,
        BENCH_RUNS + 1,
        fastest,
        designs / fastest / 1e6,
        rayon::current_num_threads(),
        total_seconds
    )
}

/// User + system CPU time of this process (all threads), s, from `/proc/self/stat` (Linux; USER_HZ = 100).
fn process_cpu_seconds() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // Fields after the parenthesised command name; utime and stime are fields 14 and 15.
    let rest = stat.rsplit_once(')')?.1;
    let fields: Vec<&str> = rest.split_whitespace().collect();
    let ticks: f64 = fields.get(11)?.parse::<f64>().ok()? + fields.get(12)?.parse::<f64>().ok()?;
    Some(ticks / 100.0)
}

fn write(path: &Path, text: &str) -> anyhow::Result<()> {
    std::fs::write(path, text).with_context(|| format!("cannot write {}", path.display()))
}
