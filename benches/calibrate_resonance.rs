//! `cargo bench --bench calibrate_resonance`: what a measured first resonance costs `calibrate`. The
//! data of `examples/measured-thesis-like.csv` (24 actuators x 4 voltages, made again from its seed,
//! `tests/studies/calibrate_synthetic.rs::write_example`), without and with a `resonance_Hz` column (each
//! actuator's `f1` under the same hidden effects, 1 % seeded noise), each calibrated by the binary as a
//! child with the library alone and with `--effects examples/effects-held-root.toml`. For each: the
//! median wall clock and CPU time (the kernel's account of the child, `common/child.rs`) of
//! `CALIBRATE_RUNS` runs (default 3), and the verdict.
//! Target: with the resonance column, within twice the time without it. `CALIBRATE_RESONANCE_WRITE=FILE`
//! also writes the rows with the resonance column to FILE (to calibrate them with another binary).

#[path = "common/calibrate_child.rs"]
mod calibrate_child;
#[path = "common/child.rs"]
mod child;
#[path = "../tests/synthetic/mod.rs"]
mod synthetic;

use actuator_model::{EffectModel, Effects};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use synthetic::*;

/// The hidden effects of the example (`write_example`).
fn hidden() -> Effects {
    Effects {
        d31_scale: 0.8,
        dead_length: 2.5e-3,
        clamp_compliance: 0.4,
        ply_thickness_scale: 1.25,
        ..Effects::default()
    }
}

/// The example's rows, and the same rows with each actuator's first resonance on its first row.
fn example() -> (String, String) {
    let mut rng = ChaCha8Rng::seed_from_u64(2013);
    let designs: Vec<Design> = (0..24).map(|_| random_design(&mut rng)).collect();
    let csv = synthetic_csv(Truth::Library(hidden()), &designs, &mut rng);
    let physics = EffectModel {
        effects: hidden(),
        primitives: Vec::new(),
    };
    let with = with_first_row_columns(&csv, ",resonance_Hz", |id| {
        let f = resonance_of(&physics, &designs[id]);
        format!(",{:.4}", f * (0.01 * normal(&mut rng)).exp())
    });
    (csv, with)
}

fn main() {
    let runs: usize = std::env::var("CALIBRATE_RUNS")
        .ok()
        .and_then(|r| r.parse().ok())
        .unwrap_or(3)
        .max(1);
    println!("load average at start: {}", child::load());
    let (plain, resonant) = example();
    if let Ok(path) = std::env::var("CALIBRATE_RESONANCE_WRITE") {
        std::fs::write(&path, &resonant).expect("the rows write");
    }
    let dir = tempfile::tempdir().expect("temp dir");
    let binary = env!("CARGO_BIN_EXE_actuator-cam");
    let held_root = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/examples/effects-held-root.toml"
    );
    println!(
        "| data | --effects | runs | wall s, median | user + sys CPU s, median | peak RSS MB | verdict |"
    );
    println!("|---|---|---|---|---|---|---|");
    for (label, csv) in [
        ("24 x 4 rows", &plain),
        ("24 x 4 rows + resonance", &resonant),
    ] {
        let path = dir.path().join("rows.csv");
        std::fs::write(&path, csv).expect("the rows write");
        for effects in [None, Some(held_root)] {
            let (mut wall, mut cpu, mut peak, mut verdict) =
                (Vec::new(), Vec::new(), 0.0f64, String::new());
            for _ in 0..runs {
                // A fresh process each run: the beams one run solved do not serve the next.
                let args: Vec<&str> = effects.iter().flat_map(|e| ["--effects", e]).collect();
                let (u, v) = calibrate_child::calibrate(binary, &path, &args);
                wall.push(u.wall_s);
                cpu.push(u.user_s + u.sys_s);
                peak = peak.max(u.peak_mb);
                verdict = v;
            }
            wall.sort_by(f64::total_cmp);
            cpu.sort_by(f64::total_cmp);
            println!(
                "| {label} | {} | {runs} | {:.2} | {:.2} | {peak:.1} | {verdict} |",
                effects.map_or("-", |_| "held-root"),
                wall[runs / 2],
                cpu[runs / 2]
            );
        }
    }
    println!("load average at end: {}", child::load());
}
