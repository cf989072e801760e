//! `cargo bench --bench optimize`: the optimizer's exhaustive stage on `examples/optimize-thesis.toml`,
//! and optimize for a wing on `examples/optimize-hawkmoth-wing.toml` (the thesis grid with the drive
//! objective), and the first with the nonlinear ceramic (docs/benchmarks.md). Prints the fastest wall-clock time of several runs, designs per second,
//! the process CPU time per run and the load average: on a shared machine the wall clock measures the
//! other jobs too, while designs per CPU-second times the number of idle cores is what the code does.

use actuator_cam::{
    exhaustive, optimize, optimize_flap, wing_load, DriveSpec, Objective, OptimizeSpec as Spec,
    Problem, SearchModel, Silent,
};
use actuator_model::{ModelChoice, ModelKind};
use std::path::Path;
use std::time::Instant;

/// Timed runs of the exhaustive stage after the first, whole optimisation.
const RUNS: usize = 5;

fn main() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/optimize-thesis.toml");
    let spec = Spec::from_file(&path).expect("the example spec reads");
    let model = SearchModel::from_kind(ModelKind::Original).expect("a search model");
    let problem =
        Problem::from_spec(&spec, model, Objective::MinMass).expect("the laminates solve");
    let start = Instant::now();
    let outcome = optimize(problem, &Silent).expect("the example is feasible");
    let whole = start.elapsed().as_secs_f64();
    let designs = outcome.grid.evaluated as f64;
    let cpu_before = process_cpu_seconds();
    let mut fastest = f64::INFINITY;
    for _ in 0..RUNS {
        let t = Instant::now();
        std::hint::black_box(exhaustive(&outcome.problem, &Silent));
        fastest = fastest.min(t.elapsed().as_secs_f64());
    }
    let cpu = match (cpu_before, process_cpu_seconds()) {
        (Some(a), Some(b)) if b > a => format!(
            "; CPU time {:.3} s per run = {:.0} million designs per CPU-second",
            (b - a) / RUNS as f64,
            designs * RUNS as f64 / (b - a) / 1e6
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
    println!(
        "optimize (examples/optimize-thesis.toml): exhaustive stage {} designs, fastest of {RUNS} runs {:.3} s = {:.0} million designs/s on {} threads{cpu}{load}; whole optimisation (first run) {:.3} s",
        outcome.grid.evaluated,
        fastest,
        designs / fastest / 1e6,
        rayon::current_num_threads(),
        whole
    );
    wing(&load);
    nonlinear(&spec, &load);
}

/// The whole optimisation with the nonlinear ceramic (docs/physics.md §18.3): one nonlinear solve per
/// shape and laminate of the grid, where the original model has a closed form. One run: it takes tens of
/// seconds.
fn nonlinear(spec: &Spec, load: &str) {
    let cpu_before = process_cpu_seconds();
    let t = Instant::now();
    let problem = Problem::from_spec(
        spec,
        SearchModel::from_kind(ModelKind::Nonlinear).expect("a search model"),
        Objective::MinMass,
    )
    .expect("the laminates solve");
    let outcome = optimize(problem, &Silent).expect("the example is feasible");
    let wall = t.elapsed().as_secs_f64();
    std::hint::black_box(&outcome);
    let cpu = match (cpu_before, process_cpu_seconds()) {
        (Some(a), Some(b)) if b > a => format!("; CPU time {:.1} s", b - a),
        _ => String::new(),
    };
    println!(
        "optimize --model nonlinear (examples/optimize-thesis.toml): whole optimisation {wall:.1} s on {} threads{cpu}{load}",
        rayon::current_num_threads()
    );
}

/// Optimize for a wing, the whole search (modes, requirement table, screen, exact stage), fastest of
/// three runs, with its CPU time.
fn wing(load: &str) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/optimize-hawkmoth-wing.toml");
    let spec = Spec::from_file(&path).expect("the example spec reads");
    let drive =
        DriveSpec::load(spec.flap.as_ref().expect("a flap requirement")).expect("drive file");
    let model = ModelChoice::Kind(ModelKind::Original);
    let wing = wing_load(&drive, &model).expect("a solved linkage");
    let mut fastest = f64::INFINITY;
    let mut points = 0;
    let cpu_before = process_cpu_seconds();
    for _ in 0..3 {
        let t = Instant::now();
        let problem = Problem::from_spec(
            &spec,
            SearchModel::from_kind(ModelKind::Original).expect("a search model"),
            Objective::MinMass,
        )
        .expect("the laminates solve");
        let outcome = optimize_flap(&spec, &problem, &wing, &model).expect("the wing is flapped");
        points = outcome.screened;
        fastest = fastest.min(t.elapsed().as_secs_f64());
    }
    let cpu = match (cpu_before, process_cpu_seconds()) {
        (Some(a), Some(b)) if b > a => format!("; CPU time {:.2} s per run", (b - a) / 3.0),
        _ => String::new(),
    };
    println!(
        "optimize for a wing (examples/optimize-hawkmoth-wing.toml): {points} laminate-shape-length points, fastest of 3 runs {fastest:.2} s on {} threads{cpu}{load}",
        rayon::current_num_threads()
    );
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
