//! Nesting engine figures (docs/benchmarks.md): `cargo bench -p cam-nest --bench nest_engine`.
//!
//! * Passive parts of 60 actuators (4 designs x 15: a fixed mix and random mixes), 150 mm sheets,
//!   0.3 mm separation, rotations 0°/180°: the irregular nester against the bounding-box
//!   baseline, on sheets (plain utilisation and used-length utilisation, sheets used) and on a
//!   150 mm wide strip (strip-packing density). The batches are written to
//!   `target/nest-bench/batches.json`; `tools/nest_reference.py` nests them with an external
//!   strip packer and writes `target/nest-bench/reference.json`, which this bench then prints
//!   beside ours.
//! * 300 parts (10 designs x 30) on 150 mm sheets with the default settings (1000 iterations,
//!   2 workers): median wall time of 3 runs.
//!
//! `-- --quick` runs 3 random mixes instead of 8 and the 300-part job once;
//! `-- --export-only` only writes `batches.json`; `NEST_BENCH_SVG=1` also writes the layouts as
//! SVG; `NEST_BENCH_ITERATIONS=n` changes the budget of every run (to see what more search buys);
//! `NEST_BENCH_SEED=n` changes the seed (default 1); `NEST_BENCH_BATCH=name` runs one batch
//! (e.g. `random-2`); `NEST_STRIP_ONLY=1` runs only our nester on
//! the strips and prints the mean density, a quicker measure to repeat over several seeds (one
//! seed's figure of a batch moves by up to 3 points with any change of the random stream, the
//! mean of 9 batches by about 0.3).

use std::path::{Path, PathBuf};
use std::time::Instant;

use cam_nest::{
    nest, nest_bounding_boxes, verify, NestBin, NestError, NestItem, NestSettings, NestSolution,
};

/// The parts of the engine tests, one definition for both.
#[path = "../tests/fixtures/mod.rs"]
mod fixtures;
use fixtures::{random_designs, sixty_mixed, write_svg};

const SHEET_MM: f64 = 150.0;
const SEPARATION_MM: f64 = 0.3;

fn settings() -> NestSettings {
    fixtures::bench_settings(SEPARATION_MM)
}

fn part_area(items: &[NestItem]) -> f64 {
    items
        .iter()
        .map(|i| cam_geometry::area(&i.outline) * i.demand as f64)
        .sum()
}

/// A sheet long enough to be a strip for these parts.
fn strip(items: &[NestItem]) -> NestBin {
    NestBin {
        width_mm: SHEET_MM,
        height_mm: (3.0 * part_area(items) / SHEET_MM + 100.0).ceil(),
        stock: 1,
    }
}

fn sheets() -> NestBin {
    NestBin {
        width_mm: SHEET_MM,
        height_mm: SHEET_MM,
        stock: 100,
    }
}

/// Runs a nester, checks the result, returns it with the wall time.
fn timed(
    f: fn(&[NestItem], &NestBin, &NestSettings) -> Result<NestSolution, NestError>,
    items: &[NestItem],
    bin: &NestBin,
) -> (NestSolution, f64) {
    let started = Instant::now();
    let solution = f(items, bin, &settings()).expect("nest");
    let seconds = started.elapsed().as_secs_f64();
    verify(items, bin, &settings(), &solution, 1e-9).expect("layout verifies");
    (solution, seconds)
}

#[derive(Default)]
struct Row {
    sheets_nester: f64,
    sheets_baseline: f64,
    plain_nester: f64,
    plain_baseline: f64,
    used_nester: f64,
    used_baseline: f64,
    strip_nester: f64,
    strip_baseline: f64,
    reference: Option<f64>,
}

/// `target/nest-bench` of the workspace, where `tools/nest_reference.py` looks (cargo runs a
/// bench in its package's directory, `crates/nest`).
fn bench_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../target/nest-bench")
}

fn reference(name: &str) -> Option<f64> {
    let text = std::fs::read_to_string(bench_dir().join("reference.json")).ok()?;
    let json: serde_json::Value = serde_json::from_str(&text).ok()?;
    json.get(name)?.get("density")?.as_f64()
}

fn main() {
    let quick = std::env::args().any(|a| a == "--quick");
    let mut batches: Vec<(String, Vec<NestItem>)> = vec![("mixed-4x15".into(), sixty_mixed())];
    let randoms = if quick { 3 } else { 8 };
    batches.extend((1..=randoms).map(|s| (format!("random-{s}"), random_designs(s, 4, 15))));
    if let Ok(only) = std::env::var("NEST_BENCH_BATCH") {
        batches.retain(|(name, _)| *name == only);
    }

    let dir = bench_dir();
    let dir = dir.as_path();
    write_batches(dir, &batches);
    if std::env::args().any(|a| a == "--export-only") {
        return;
    }

    println!(
        "60 actuators (4 designs x 15), {SHEET_MM} mm sheets / {SHEET_MM} mm wide strip, {SEPARATION_MM} mm separation, {} iterations, 2 workers",
        settings().iterations
    );
    println!(
        "{:<12} {:>13} {:>17} {:>17} {:>24}",
        "batch", "sheets N/B", "plain % N/B", "used-len % N/B", "strip % N/B/ref"
    );
    let mut rows = Vec::new();
    let strip_only = std::env::var_os("NEST_STRIP_ONLY").is_some();
    if strip_only {
        let mut sum = 0.0;
        let mut secs = 0.0;
        for (name, items) in &batches {
            let long = strip(items);
            let (ns, t) = timed(nest, items, &long);
            let d = ns.used_length_utilization(&long, SEPARATION_MM) * 100.0;
            println!("{name:<12} strip {d:.1} {t:.2}s");
            sum += d;
            secs += t;
        }
        println!(
            "strip mean {:.2} total {secs:.1}s",
            sum / batches.len() as f64
        );
        return;
    }
    for (name, items) in &batches {
        let (n, _) = timed(nest, items, &sheets());
        let (b, _) = timed(nest_bounding_boxes, items, &sheets());
        let long = strip(items);
        let (ns, _) = timed(nest, items, &long);
        let (bs, _) = timed(nest_bounding_boxes, items, &long);
        if std::env::var_os("NEST_BENCH_SVG").is_some() {
            write_svg(&dir.join(format!("{name}-sheets.svg")), &n, &sheets());
            write_svg(&dir.join(format!("{name}-strip.svg")), &ns, &long);
        }
        let row = Row {
            sheets_nester: n.bins_used() as f64,
            sheets_baseline: b.bins_used() as f64,
            plain_nester: n.utilization() * 100.0,
            plain_baseline: b.utilization() * 100.0,
            used_nester: n.used_length_utilization(&sheets(), SEPARATION_MM) * 100.0,
            used_baseline: b.used_length_utilization(&sheets(), SEPARATION_MM) * 100.0,
            strip_nester: ns.used_length_utilization(&long, SEPARATION_MM) * 100.0,
            strip_baseline: bs.used_length_utilization(&long, SEPARATION_MM) * 100.0,
            reference: reference(name).map(|d| d * 100.0),
        };
        print_row(name, &row);
        rows.push(row);
    }
    let count = rows.len() as f64;
    let mean = |f: fn(&Row) -> f64| rows.iter().map(f).sum::<f64>() / count;
    let references: Vec<f64> = rows.iter().filter_map(|r| r.reference).collect();
    let mean_row = Row {
        sheets_nester: mean(|r| r.sheets_nester),
        sheets_baseline: mean(|r| r.sheets_baseline),
        plain_nester: mean(|r| r.plain_nester),
        plain_baseline: mean(|r| r.plain_baseline),
        used_nester: mean(|r| r.used_nester),
        used_baseline: mean(|r| r.used_baseline),
        strip_nester: mean(|r| r.strip_nester),
        strip_baseline: mean(|r| r.strip_baseline),
        reference: (references.len() == rows.len()).then(|| references.iter().sum::<f64>() / count),
    };
    print_row("mean", &mean_row);
    if references.len() != rows.len() {
        println!("(no reference column: run `python3 tools/nest_reference.py` after this bench, then the bench again)");
    }

    time_three_hundred_parts(quick);
}

/// Writes `batches` to `dir/batches.json`, the parts `tools/nest_reference.py` nests.
fn write_batches(dir: &Path, batches: &[(String, Vec<NestItem>)]) {
    let export: Vec<serde_json::Value> = batches
        .iter()
        .map(|(name, items)| {
            serde_json::json!({
                "name": name,
                "strip_width_mm": SHEET_MM,
                "separation_mm": SEPARATION_MM,
                "items": items,
            })
        })
        .collect();
    std::fs::create_dir_all(dir).expect("create target/nest-bench");
    std::fs::write(
        dir.join("batches.json"),
        serde_json::to_string_pretty(&export).expect("json"),
    )
    .expect("write batches.json");
}

/// The 300-part job (10 designs x 30) on sheets: the median wall time of 3 runs (1 with
/// `quick`), with the last run's figures.
fn time_three_hundred_parts(quick: bool) {
    let items = random_designs(2024, 10, 30);
    let runs = if quick { 1 } else { 3 };
    let mut times: Vec<f64> = Vec::new();
    let mut last = None;
    for _ in 0..runs {
        let (solution, seconds) = timed(nest, &items, &sheets());
        times.push(seconds);
        last = Some(solution);
    }
    times.sort_by(f64::total_cmp);
    let solution = last.expect("one run");
    println!(
        "300 parts (10 designs x 30), {} iterations, 2 workers: median {:.2} s of {runs} (min {:.2}, max {:.2}); {} sheets, plain {:.1} %, used-length {:.1} %",
        settings().iterations,
        times[times.len() / 2],
        times[0],
        times[times.len() - 1],
        solution.bins_used(),
        solution.utilization() * 100.0,
        solution.used_length_utilization(&sheets(), SEPARATION_MM) * 100.0,
    );
}

fn print_row(name: &str, r: &Row) {
    let reference = r
        .reference
        .map_or_else(|| "-".to_string(), |v| format!("{v:.1}"));
    println!(
        "{name:<12} {:>6.1}/{:<6.1} {:>8.1}/{:<8.1} {:>8.1}/{:<8.1} {:>8.1}/{:.1}/{reference}",
        r.sheets_nester,
        r.sheets_baseline,
        r.plain_nester,
        r.plain_baseline,
        r.used_nester,
        r.used_baseline,
        r.strip_nester,
        r.strip_baseline,
    );
}
