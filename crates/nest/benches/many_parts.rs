//! Many small parts under a time budget (docs/benchmarks.md, "Nesting engine: many small parts
//! at a time budget"): `cargo bench -p cam-nest --bench many_parts`.
//!
//! 5,000 and 10,000 circles of 1 mm radius (32-gons, one design, 0.3 mm separation, 2 workers,
//! seed 1) on 300 mm square sheets, with a 5 s time budget and the iterations unbounded, as
//! `--time 5s` runs them. One line per batch: the wall and CPU time of the nesting (on a shared
//! machine the CPU time says what the wall time would be with the cores free), the wall time of
//! the verifier and of the bounding-box baseline (the app runs all three on a layer), the sheets
//! and parts placed, and the search's end ([`cam_nest::Reached`]). The deadline holds the
//! nesting to about the budget; a run whose first feasible layout alone takes longer says so
//! (`Reached::over_budget`).
//!
//! `NEST_PARTS=2000,5000` runs other batch sizes, `NEST_TIME_S=10` another budget, and
//! `NEST_ITERATIONS=1` an iteration budget instead of a time budget (the greedy fill and
//! little else).

use std::time::{Duration, Instant};

/// `cpu_seconds`, shared with the other benches.
#[path = "../tests/fixtures/mod.rs"]
mod fixtures;

use cam_nest::{
    nest_bounding_boxes, nest_until, verify, NestBin, NestItem, NestSettings, SearchLimit,
};

const RADIUS_MM: f64 = 1.0;
const CORNERS: usize = 32;
const SHEET_MM: f64 = 300.0;
const SEPARATION_MM: f64 = 0.3;

/// A circle of `RADIUS_MM` as a regular `CORNERS`-gon, counter-clockwise.
fn circle() -> Vec<[f64; 2]> {
    (0..CORNERS)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / CORNERS as f64;
            [RADIUS_MM * a.cos(), RADIUS_MM * a.sin()]
        })
        .collect()
}

fn env_usize(name: &str) -> Option<usize> {
    std::env::var(name).ok().and_then(|v| v.parse().ok())
}

fn main() {
    let batches: Vec<usize> = std::env::var("NEST_PARTS")
        .ok()
        .map(|v| v.split(',').filter_map(|n| n.trim().parse().ok()).collect())
        .unwrap_or_else(|| vec![5_000, 10_000]);
    let iterations = env_usize("NEST_ITERATIONS");
    let budget_s = env_usize("NEST_TIME_S").unwrap_or(5);
    match iterations {
        Some(n) => println!("iteration budget {n}, no deadline"),
        None => println!("time budget {budget_s} s, iterations unbounded"),
    }
    println!(
        "{:>7} {:>7} {:>7} {:>9} {:>10} {:>6} {:>7} {:>6} {:>11}",
        "parts",
        "nest s",
        "CPU s",
        "verify s",
        "baseline s",
        "sheets",
        "placed",
        "ended",
        "over budget"
    );
    for parts in batches {
        let items = vec![NestItem {
            outline: circle(),
            demand: parts,
            rotations_deg: vec![0.0],
        }];
        let bin = NestBin {
            width_mm: SHEET_MM,
            height_mm: SHEET_MM,
            stock: parts,
        };
        let settings = NestSettings {
            separation_mm: SEPARATION_MM,
            seed: 1,
            iterations: iterations.unwrap_or(usize::MAX),
            workers: 2,
        };
        let started = Instant::now();
        let cpu = fixtures::cpu_seconds();
        let limit = SearchLimit {
            deadline: iterations
                .is_none()
                .then(|| started + Duration::from_secs(budget_s as u64)),
            interrupt: None,
        };
        let (layout, reached) =
            nest_until(&items, &bin, &settings, &limit, &|_| {}).expect("the circles nest");
        let nest_s = started.elapsed().as_secs_f64();
        let cpu_s = fixtures::cpu_seconds() - cpu;
        let started = Instant::now();
        verify(&items, &bin, &settings, &layout, 1e-9).expect("the layout verifies");
        let verify_s = started.elapsed().as_secs_f64();
        let started = Instant::now();
        nest_bounding_boxes(&items, &bin, &settings).expect("the baseline packs");
        let baseline_s = started.elapsed().as_secs_f64();
        println!(
            "{parts:>7} {nest_s:>7.2} {cpu_s:>7.2} {verify_s:>9.2} {baseline_s:>10.2} {:>6} {:>7} {:>6} {:>11}",
            layout.bins_used(),
            layout.parts_placed(),
            format!("{:?}", reached.ended),
            reached
                .over_budget
                .map_or("no".to_string(), |d| format!("{:.2} s", d.as_secs_f64())),
        );
    }
}
