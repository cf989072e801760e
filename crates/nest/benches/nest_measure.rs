//! The measuring set (README "Nesting engine: figures"): `cargo bench -p cam-nest --bench
//! nest_measure`, then `tools/nest_reference.py --measure` for sparrow beside it.
//!
//! 8 batches of actuator outlines the engine was never tuned on (`fixtures::measuring_set`,
//! seeds 7101-7108), each on a 150 mm wide strip (`nest_strip`), 0.3 mm separation, rotations
//! 0°/180°, the default settings (1000 iterations, 2 workers, seed 1). Prints our density and
//! wall time and writes them with the parts to `target/nest-bench/measure.json`; the reference
//! script nests the same parts with sparrow at 5 s and at our wall time of each batch and
//! prints the three side by side. `NEST_BENCH_SEED=n` changes our seed,
//! `NEST_BENCH_ITERATIONS=n` our budget (to compare at a shorter wall time).

use std::cell::Cell;
use std::path::Path;
use std::time::Instant;

use cam_nest::{nest_strip, verify, NestProgress};

#[path = "../tests/fixtures/mod.rs"]
mod fixtures;

const WIDTH_MM: f64 = 150.0;
const SEPARATION_MM: f64 = 0.3;

fn main() {
    let settings = fixtures::bench_settings(SEPARATION_MM);
    println!(
        "measuring set: {WIDTH_MM} mm strip, {SEPARATION_MM} mm separation, {} iterations, {} workers, seed {}",
        settings.iterations, settings.workers, settings.seed
    );
    println!(
        "{:<14} {:>6} {:>10} {:>8} {:>12}",
        "batch", "parts", "density %", "wall s", "iterations"
    );
    let mut export = Vec::new();
    let (mut density_sum, mut seconds_sum) = (0.0, 0.0);
    let batches = fixtures::measuring_set();
    for (name, items) in &batches {
        let started = Instant::now();
        let last: Cell<Option<NestProgress>> = Cell::new(None);
        let strip = nest_strip(items, WIDTH_MM, &settings, &|p| last.set(Some(*p))).expect("nest");
        // Iterations the search used of its budget (fewer when the stop rule ended it).
        let used = last.get().map_or_else(String::new, |p| {
            format!("{}/{}", p.iterations_done, p.iterations_budget)
        });
        let seconds = started.elapsed().as_secs_f64();
        verify(items, &strip.bin, &settings, &strip.solution, 1e-9).expect("layout verifies");
        let parts: usize = items.iter().map(|i| i.demand).sum();
        println!(
            "{name:<14} {parts:>6} {:>10.2} {seconds:>8.2} {used:>12}",
            strip.density * 100.0
        );
        density_sum += strip.density;
        seconds_sum += seconds;
        export.push(serde_json::json!({
            "name": name,
            "strip_width_mm": WIDTH_MM,
            "separation_mm": SEPARATION_MM,
            "items": items,
            "ours": { "density": strip.density, "seconds": seconds, "seed": settings.seed },
        }));
    }
    println!(
        "mean density {:.2} %, total wall {seconds_sum:.1} s",
        density_sum / batches.len() as f64 * 100.0
    );
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../target/nest-bench");
    std::fs::create_dir_all(&dir).expect("create target/nest-bench");
    std::fs::write(
        dir.join("measure.json"),
        serde_json::to_string_pretty(&export).expect("json"),
    )
    .expect("write measure.json");
}
