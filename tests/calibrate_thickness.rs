//! A thickness trend seen (issue 29 item 4): a piezoelectrically dead surface layer of the PZT costs a thin
//! plate more than a thick one, so when the PZT thickness varies, the selection must name the layer
//! (`inactive-surface-layer`) rather than take the loss for a uniform d31 scale (docs/calibration.md §3,
//! "Thickness forms").
//!
//! Random designs (30 actuators on plates of 127, 191 and 267 µm, 4 voltages, 5 % noise on deflection and
//! force, 1 % on mass) with a dead layer of 5, 10 and 15 µm, generated two ways: by the test's own
//! approximation (a factor `1 - t_s/t_p` on δ and F_b, `tests/synthetic`) and by the model crate's
//! primitive (the layer in the CLT stack). The share is of seeds where `inactive-surface-layer` is
//! selected.
//!
//! Seeds: `CALIBRATE_SEED_BASE=tuning` runs seeds 0-19 of the stream `seed * 7919 + 23`; the figures in
//! docs/calibration.md and the assertions use seeds 9000-9019 of `seed * 104_723 + 37`. The assertions:
//! the 10 and 15 µm layers selected in at least 16 of 20 seeds each way; the 5 µm layer is reported only
//! (its loss differs between the thinnest and the thickest plate by about 2 %, under the noise of one
//! actuator's mean).
//! `cargo test --release --test calibrate_thickness -- --nocapture` prints the table.

mod synthetic;

use actuator_cam::calibrate::{self, csv::parse, Settings};
use actuator_model::primitives::Primitive;
use rayon::prelude::*;
use synthetic::*;

const NAME: &str = "inactive-surface-layer";

#[test]
fn a_dead_surface_layer_is_selected_over_a_uniform_d31_scale() {
    let tuning = std::env::var("CALIBRATE_SEED_BASE").is_ok_and(|v| v == "tuning");
    let seeds: Vec<u64> = if tuning {
        (0..20).map(|s| s * 7919 + 23).collect()
    } else {
        (9000..9020).map(|s| s * 104_723 + 37).collect()
    };
    let n = seeds.len();
    println!(
        "{:<34} {:>9} {:>9} {:>13} {:>16}",
        "dead layer", "selected", "explained", "not-explained", "median estimate"
    );
    let mut failures = Vec::new();
    for t_s in [5e-6, 10e-6, 15e-6] {
        for (how, truth) in [
            ("approximation", Truth::InactiveSurface(t_s)),
            (
                "model primitive",
                Truth::Primitive(Primitive::InactiveSurfaceLayer, t_s),
            ),
        ] {
            let outcomes: Vec<(String, Vec<String>, Option<f64>)> = seeds
                .par_iter()
                .map(|&s| {
                    let data = parse(&random_csv(truth, s)).unwrap();
                    let cal = calibrate::calibrate(&data, &Settings::default()).unwrap();
                    let estimate = cal
                        .model
                        .declared
                        .iter()
                        .find(|d| d.name == NAME)
                        .map(|d| d.value);
                    (cal.model.verdict, cal.model.selected_effects, estimate)
                })
                .collect();
            let selected = outcomes
                .iter()
                .filter(|o| o.1.iter().any(|e| e == NAME))
                .count();
            let verdict = |v: &str| outcomes.iter().filter(|o| o.0 == v).count();
            let mut est: Vec<f64> = outcomes.iter().filter_map(|o| o.2).collect();
            est.sort_by(f64::total_cmp);
            let median = est
                .get(est.len() / 2)
                .map_or("-".into(), |v| format!("{:.1} um", v * 1e6));
            let label = format!("{:.0} um ({how})", t_s * 1e6);
            println!(
                "{label:<34} {selected:>6}/{n:<2} {:>9} {:>13} {median:>16}",
                verdict("explained"),
                verdict("not-explained")
            );
            if std::env::var("CALIBRATE_VERBOSE").is_ok() {
                for o in &outcomes {
                    println!("    {} {:?} {:?}", o.0, o.1, o.2);
                }
            }
            if t_s >= 10e-6 && selected * 20 < 16 * n {
                failures.push(format!("{label}: selected {selected}/{n}"));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
