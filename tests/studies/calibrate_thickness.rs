//! A thickness trend seen: a piezoelectrically dead surface layer of the PZT costs a thin plate more than a
//! thick one, so when the PZT thickness varies, the selection must name the layer (`inactive-surface-layer`)
//! rather than take the loss for a uniform d31 scale (docs/calibration.md §3, "Thickness forms"), or the
//! other thickness form where the data call for it.
//!
//! Random designs (30 actuators on plates of 127, 191 and 267 µm, 4 voltages, 5 % noise on deflection and
//! force, 1 % on mass) with a dead layer of 5, 10 and 15 µm, generated two ways: by the test's own
//! approximation (a factor `1 - t_s/t_p` on δ and F_b, `tests/synthetic`) and by the model crate's
//! primitive (the layer in the CLT stack). The share is of seeds where `inactive-surface-layer` is
//! selected on the primitive's data, and a thickness form (`inactive-surface-layer` or
//! `d31-thickness-power`) on the approximation's: `1 - t_s/t_p` is not the CLT layer's shape, and the power
//! form may fit it better (the "power" column counts those).
//!
//! Seeds: `CALIBRATE_SEED_BASE=tuning` runs seeds 0-19 of the stream `seed * 7919 + 23`; the figures in
//! docs/calibration.md and the assertions use seeds 9000-9019 of `seed * 104_723 + 37`. The assertions:
//! the 10 and 15 µm layers selected in at least 16 of 20 seeds each way; the 5 µm layer is reported only
//! (its loss differs between the thinnest and the thickest plate by about 2 %, under the noise of one
//! actuator's mean).
//!
//! CI runs the 10 and 15 µm layers on the first 4 measuring seeds, each of which must select the layer
//! (16 of 20 scaled up to 4 of 4). `ACTUATOR_CAM_FULL_STUDY=1 cargo test --release --test
//! calibrate_thickness -- --nocapture` runs all 20 seeds and every layer and prints the table.

use crate::synthetic;

use actuator_cam::{calibrate, parse_measured as parse, Settings};
use actuator_model::primitives::Primitive;
use rayon::prelude::*;
use synthetic::*;

const NAME: &str = "inactive-surface-layer";

#[test]
#[ignore = "study"]
fn a_dead_surface_layer_is_selected_over_a_uniform_d31_scale() {
    let tuning = std::env::var("CALIBRATE_SEED_BASE").is_ok_and(|v| v == "tuning");
    let seeds: Vec<u64> = sample(if tuning {
        (0..20).map(|s| s * 7919 + 23).collect()
    } else {
        (9000..9020).map(|s| s * 104_723 + 37).collect()
    });
    // The 5 µm rows assert nothing: the full study prints them.
    let layers: &[f64] = if full_study() {
        &[5e-6, 10e-6, 15e-6]
    } else {
        &[10e-6, 15e-6]
    };
    let n = seeds.len();
    println!(
        "{:<34} {:>9} {:>6} {:>9} {:>13} {:>16}",
        "dead layer", "selected", "power", "explained", "not-explained", "median estimate"
    );
    let mut failures = Vec::new();
    for &t_s in layers {
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
                    let cal = calibrate(&data, &Settings::default()).unwrap();
                    let estimate = cal
                        .model
                        .declared
                        .iter()
                        .find(|d| d.name == NAME)
                        // The selection fits the layer in µm.
                        .map(|d| d.value * 1e-6);
                    (cal.model.verdict, cal.model.selected_effects, estimate)
                })
                .collect();
            // On the approximation's data either thickness form is the trend seen; on the model's own
            // layer, the layer.
            let forms: &[&str] = match truth {
                Truth::InactiveSurface(_) => &THICKNESS_FORMS,
                _ => &[NAME],
            };
            let selected = outcomes
                .iter()
                .filter(|o| o.1.iter().any(|e| forms.contains(&e.as_str())))
                .count();
            let power = outcomes
                .iter()
                .filter(|o| o.1.iter().any(|e| e == POWER))
                .count();
            let verdict = |v: &str| outcomes.iter().filter(|o| o.0 == v).count();
            let mut est: Vec<f64> = outcomes.iter().filter_map(|o| o.2).collect();
            est.sort_by(f64::total_cmp);
            let median = est
                .get(est.len() / 2)
                .map_or("-".into(), |v| format!("{:.1} um", v * 1e6));
            let label = format!("{:.0} um ({how})", t_s * 1e6);
            println!(
                "{label:<34} {selected:>6}/{n:<2} {power:>6} {:>9} {:>13} {median:>16}",
                verdict("explained"),
                verdict("not-explained")
            );
            if std::env::var("CALIBRATE_VERBOSE").is_ok() {
                for o in &outcomes {
                    println!("    {} {:?} {:?}", o.0, o.1, o.2);
                }
            }
            if t_s >= 10e-6 && selected < of_20(16, n) {
                failures.push(format!("{label}: selected {selected}/{n}"));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

const POWER: &str = "d31-thickness-power";

/// Verdict, selected effects, and the power form's exponent and interval when it is in the final model.
type PowerOutcome = (String, Vec<String>, Option<(f64, (f64, f64))>);

/// A d31 that follows a power of the plate thickness, `(t_p / 191 µm)^a`, hidden through the model crate's
/// primitive. With `a < 0` a thick plate loses more, which no dead layer can give: the power form must be
/// selected in at least 16 of 20 seeds (every one of the CI sample), and its exponent's 95 % interval
/// may miss the truth no more often than chance allows (`allowed_misses`). With `a > 0` the loss falls with the thickness as a dead layer's does, and the share where
/// the power form is named rather than the layer is printed, not asserted (docs/calibration.md §3).
///
/// Seeds 9100-9119 of the stream `seed * 104_723 + 41`, never looked at while choosing the margin
/// (`POWER_OVER_LAYER`, the selection's own rival margin of 2, fixed before the runs).
#[test]
#[ignore = "study"]
fn a_d31_power_of_the_plate_thickness_is_told_from_a_dead_layer() {
    let seeds: Vec<u64> = sample((9100..9120).map(|s| s * 104_723 + 41).collect());
    let n = seeds.len();
    println!(
        "{:<12} {:>9} {:>9} {:>9} {:>13} {:>16}",
        "exponent", "power", "covers", "layer", "not-explained", "median estimate"
    );
    let mut failures = Vec::new();
    for a in [-0.3, 0.3] {
        let truth = Truth::Primitive(Primitive::D31ThicknessPower, a);
        let outcomes: Vec<PowerOutcome> = seeds
            .par_iter()
            .map(|&s| {
                let data = parse(&random_csv(truth, s)).unwrap();
                let cal = calibrate(&data, &Settings::default()).unwrap();
                let c = &cal.selection.candidates[cal.selection.final_index];
                let fit = c
                    .effects
                    .iter()
                    .position(|e| e.name() == POWER)
                    .map(|k| (c.values[k], c.intervals[k]));
                (cal.model.verdict, cal.model.selected_effects, fit)
            })
            .collect();
        let power = outcomes.iter().filter(|o| o.2.is_some()).count();
        let covers = outcomes
            .iter()
            .filter_map(|o| o.2)
            .filter(|(_, (lo, hi))| *lo <= a && a <= *hi)
            .count();
        let layer = outcomes
            .iter()
            .filter(|o| o.1.iter().any(|e| e == NAME))
            .count();
        let not_explained = outcomes.iter().filter(|o| o.0 == "not-explained").count();
        let mut est: Vec<f64> = outcomes.iter().filter_map(|o| o.2.map(|f| f.0)).collect();
        est.sort_by(f64::total_cmp);
        let median = est
            .get(est.len() / 2)
            .map_or("-".into(), |v| format!("{v:.3}"));
        println!(
            "{a:<12} {power:>6}/{n:<2} {covers:>9} {layer:>9} {not_explained:>13} {median:>16}"
        );
        if std::env::var("CALIBRATE_VERBOSE").is_ok() {
            for o in &outcomes {
                println!("    {} {:?} {:?}", o.0, o.1, o.2);
            }
        }
        // Named in 16 of 20; the 95 % intervals miss no more often than chance allows.
        if a < 0.0 && (power < of_20(16, n) || power - covers > allowed_misses(power)) {
            failures.push(format!(
                "exponent {a}: power form {power}/{n}, interval holds the truth {covers}/{power}"
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
