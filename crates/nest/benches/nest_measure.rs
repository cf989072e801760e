//! The measuring set (README "Nesting engine: figures"): `cargo bench -p cam-nest --bench
//! nest_measure`, then `tools/nest_reference.py --measure` for sparrow beside it.
//!
//! 8 batches of actuator outlines the engine was never tuned on (`fixtures::measuring_set`,
//! seeds 7101-7108; `NEST_MEASURE_SEEDS=9100` for the fresh set 9101-9108, `=6100` for the
//! tuning copy 6101-6108), each on a 150 mm wide strip (`nest_strip`), 0.3 mm separation,
//! rotations 0°/180°, the default settings (1000 iterations, 2 workers, seed 1). Prints our
//! density, wall time and CPU time (user + system of the process, `getrusage`, so the CPU-to-wall
//! ratio shows how busy the two workers kept the two cores) and writes them with the parts to
//! `target/nest-bench/measure.json` (`measure-SEEDS.json` for another set); the reference script
//! nests the same parts with sparrow at 5 s and at our wall time of each batch and prints the
//! three side by side. `NEST_BENCH_SEED=n` changes our seed, `NEST_BENCH_ITERATIONS=n` our
//! budget (to compare at a shorter wall time).
//!
//! Then the sheet jobs of issue 15's time targets: the 60 actuators of `sixty_mixed` and 300
//! parts (10 designs x 30, seed 2024) on 150 x 150 mm sheets, wall and CPU time and used-length
//! utilisation. `NEST_MEASURE_SHEETS=0` skips them, `=only` runs only them.

use std::cell::Cell;
use std::path::Path;
use std::time::Instant;

use cam_nest::{nest, nest_strip, verify, NestBin, NestItem, NestProgress};

#[path = "../tests/fixtures/mod.rs"]
mod fixtures;

const WIDTH_MM: f64 = 150.0;
const SEPARATION_MM: f64 = 0.3;

/// User + system CPU seconds of this process so far.
fn cpu_seconds() -> f64 {
    // SAFETY: getrusage only writes the struct it is given.
    let usage = unsafe {
        let mut usage: libc::rusage = std::mem::zeroed();
        libc::getrusage(libc::RUSAGE_SELF, &mut usage);
        usage
    };
    let secs = |t: libc::timeval| t.tv_sec as f64 + t.tv_usec as f64 * 1e-6;
    secs(usage.ru_utime) + secs(usage.ru_stime)
}

/// Wall and CPU seconds of `f`.
fn timed<T>(f: impl FnOnce() -> T) -> (T, f64, f64) {
    let (wall, cpu) = (Instant::now(), cpu_seconds());
    let result = f();
    (result, wall.elapsed().as_secs_f64(), cpu_seconds() - cpu)
}

fn env(name: &str) -> Option<String> {
    std::env::var(name).ok()
}

fn main() {
    let settings = fixtures::bench_settings(SEPARATION_MM);
    let sheets = env("NEST_MEASURE_SHEETS");
    if sheets.as_deref() != Some("only") {
        strips(&settings);
    }
    if sheets.as_deref() != Some("0") {
        sheet_jobs(&settings);
    }
}

fn strips(settings: &cam_nest::NestSettings) {
    let base: u64 = env("NEST_MEASURE_SEEDS")
        .and_then(|v| v.parse().ok())
        .unwrap_or(7100);
    println!(
        "measuring set seeds {}-{}: {WIDTH_MM} mm strip, {SEPARATION_MM} mm separation, {} iterations, {} workers, seed {}",
        base + 1,
        base + 8,
        settings.iterations,
        settings.workers,
        settings.seed
    );
    println!(
        "{:<14} {:>6} {:>10} {:>8} {:>8} {:>6} {:>12}",
        "batch", "parts", "density %", "wall s", "cpu s", "cpu/w", "iterations"
    );
    let mut export = Vec::new();
    let (mut density_sum, mut seconds_sum, mut cpu_sum) = (0.0, 0.0, 0.0);
    let batches = fixtures::batches_from(base);
    for (name, items) in &batches {
        let last: Cell<Option<NestProgress>> = Cell::new(None);
        let (strip, seconds, cpu) =
            timed(|| nest_strip(items, WIDTH_MM, settings, &|p| last.set(Some(*p))).expect("nest"));
        // Iterations the search used of its budget (fewer when the stop rule ended it).
        let used = last.get().map_or_else(String::new, |p| {
            format!("{}/{}", p.iterations_done, p.iterations_budget)
        });
        verify(items, &strip.bin, settings, &strip.solution, 1e-9).expect("layout verifies");
        let parts: usize = items.iter().map(|i| i.demand).sum();
        println!(
            "{name:<14} {parts:>6} {:>10.2} {seconds:>8.2} {cpu:>8.2} {:>6.2} {used:>12}",
            strip.density * 100.0,
            cpu / seconds
        );
        density_sum += strip.density;
        seconds_sum += seconds;
        cpu_sum += cpu;
        export.push(serde_json::json!({
            "name": name,
            "strip_width_mm": WIDTH_MM,
            "separation_mm": SEPARATION_MM,
            "items": items,
            "ours": { "density": strip.density, "seconds": seconds, "cpu_seconds": cpu, "seed": settings.seed },
        }));
    }
    let n = batches.len() as f64;
    println!(
        "mean density {:.2} %, mean wall {:.2} s, mean cpu {:.2} s, cpu/wall {:.2}",
        density_sum / n * 100.0,
        seconds_sum / n,
        cpu_sum / n,
        cpu_sum / seconds_sum
    );
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../target/nest-bench");
    std::fs::create_dir_all(&dir).expect("create target/nest-bench");
    let file = if base == 7100 {
        "measure.json".to_string()
    } else {
        format!("measure-{base}.json")
    };
    std::fs::write(
        dir.join(file),
        serde_json::to_string_pretty(&export).expect("json"),
    )
    .expect("write measure json");
}

fn sheet_jobs(settings: &cam_nest::NestSettings) {
    let sheet = |items: &[NestItem]| NestBin {
        width_mm: WIDTH_MM,
        height_mm: WIDTH_MM,
        stock: items.iter().map(|i| i.demand).sum(),
    };
    println!(
        "sheet jobs: {WIDTH_MM} x {WIDTH_MM} mm sheets, {SEPARATION_MM} mm separation, {} iterations, {} workers, seed {}",
        settings.iterations, settings.workers, settings.seed
    );
    for (name, items) in [
        ("60 actuators (sixty_mixed)", fixtures::sixty_mixed()),
        (
            "300 parts (10 x 30)",
            fixtures::random_designs(2024, 10, 30),
        ),
    ] {
        let bin = sheet(&items);
        let (layout, seconds, cpu) = timed(|| nest(&items, &bin, settings).expect("nest"));
        verify(&items, &bin, settings, &layout, 1e-9).expect("layout verifies");
        println!(
            "{name:<28} wall {seconds:>6.2} s  cpu {cpu:>6.2} s  cpu/wall {:.2}  {} sheets  used-length {:.2} %",
            cpu / seconds,
            layout.bins_used(),
            layout.used_length_utilization(&bin, SEPARATION_MM) * 100.0
        );
    }
}
