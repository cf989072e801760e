//! Broken actuators: 1 to 3 of 30 actuators with a cracked plate (deflection and force 45 % low at every
//! voltage) must be named, excluded, and leave the verdict and the fitted parameters of the clean data
//! unchanged. Seeds 300-302 were not used while choosing the screen's thresholds.

use crate::synthetic;

use actuator_cam::{calibrate, parse_measured as parse, Calibration, Settings};
use actuator_model::Effects;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use synthetic::*;

fn run(csv: &str) -> Calibration {
    calibrate(&parse(csv).unwrap(), &Settings::default()).unwrap()
}

/// Selected effects with their estimate and interval, from the final models.
fn parameters(cal: &Calibration) -> Vec<(String, f64, (f64, f64))> {
    actuator_cam::selected_effects(cal)
        .into_iter()
        .map(|e| (e.name.to_string(), e.estimate, e.interval))
        .collect()
}

fn check(truth: Truth, seed: u64) {
    let csv = random_csv(truth, seed);
    let clean = run(&csv);
    assert!(
        clean.broken.is_empty(),
        "clean data flagged {:?}",
        clean.broken
    );
    let clean_params = parameters(&clean);
    // Which actuators break: drawn from the seed, not chosen.
    let mut pick = ChaCha8Rng::seed_from_u64(seed + 1000);
    let mut ids: Vec<usize> = Vec::new();
    while ids.len() < 3 {
        let i = rand::Rng::gen_range(&mut pick, 0..30);
        if !ids.contains(&i) {
            ids.push(i);
        }
    }
    for k in 1..=3 {
        let broken = run(&break_actuators(&csv, &ids[..k], 0.55));
        let mut named: Vec<String> = broken.broken.iter().map(|b| b.id.clone()).collect();
        let mut want: Vec<String> = ids[..k].iter().map(|i| format!("A{i}")).collect();
        named.sort();
        want.sort();
        assert_eq!(named, want, "seed {seed}, {k} broken");
        for b in &broken.broken {
            assert!(b.excluded, "{b:?}");
            assert!(
                b.likely_cause.starts_with("cracked plate or failed bond")
                    && b.likely_cause.ends_with("% low at every voltage"),
                "{}",
                b.likely_cause
            );
            for p in [b.deflection_percent, b.force_percent] {
                let p = p.unwrap();
                assert!((-55.0..-35.0).contains(&p), "{p}");
            }
        }
        assert_eq!(
            broken.model.verdict, clean.model.verdict,
            "seed {seed}, {k} broken"
        );
        assert_eq!(broken.model.selected_effects, clean.model.selected_effects);
        for ((name, v, _), (_, c, (lo, hi))) in parameters(&broken).iter().zip(&clean_params) {
            // Unchanged: within half the clean fit's 95% interval of the clean estimate.
            assert!(
                (v - c).abs() <= 0.5 * (hi - lo),
                "seed {seed}, {k} broken: {name} {v} vs clean {c} [{lo}, {hi}]"
            );
        }
        assert!(broken
            .selection
            .notes
            .iter()
            .any(|n| n.contains("excluded as broken")));
        assert_eq!(broken.after.free_deflection.unwrap().n, 4 * (30 - k));
    }
}

#[test]
#[ignore = "study"]
fn a_uniform_d31_loss_survives_up_to_three_cracked_actuators() {
    for seed in 300..302 {
        check(
            Truth::Library(Effects {
                d31_scale: 0.75,
                ..Effects::default()
            }),
            seed,
        );
    }
}

#[test]
#[ignore = "study"]
fn a_dead_length_with_a_compliant_clamp_survives_up_to_three_cracked_actuators() {
    check(
        Truth::Library(Effects {
            dead_length: 3e-3,
            clamp_compliance: 0.5,
            ..Effects::default()
        }),
        302,
    );
}

#[test]
#[ignore = "study"]
fn null_data_with_cracked_actuators_is_still_no_effect() {
    check(Truth::Library(Effects::default()), 303);
}

#[test]
#[ignore = "study"]
fn too_many_low_actuators_are_not_excluded_as_broken() {
    // 9 of 30 (30 %) low by 45 %: more than the 20 % that can be device faults; nothing is excluded.
    let csv = random_csv(Truth::Library(Effects::default()), 304);
    let ids: Vec<usize> = (0..30).step_by(3).take(9).collect();
    let cal = run(&break_actuators(&csv, &ids, 0.55));
    assert!(!cal.broken.is_empty());
    assert!(cal.broken.iter().all(|b| !b.excluded));
    assert!(cal
        .selection
        .notes
        .iter()
        .any(|n| n.contains("too many to be broken devices")));
    assert_eq!(cal.after.free_deflection.unwrap().n, 120);
}

#[test]
#[ignore = "study"]
fn the_report_names_the_broken_actuators_and_the_exclusion() {
    let truth = Truth::Library(Effects {
        d31_scale: 0.75,
        ..Effects::default()
    });
    let csv = break_actuators(&random_csv(truth, 305), &[4, 17], 0.55);
    let data = parse(&csv).unwrap();
    let cal = calibrate(&data, &Settings::default()).unwrap();
    let files = actuator_cam::render_calibration(&cal, &data, "measured.csv").unwrap();
    let text = |name: &str| files.iter().find(|(n, _)| n == name).unwrap().1.clone();
    let json: serde_json::Value = serde_json::from_str(&text("report.json")).unwrap();
    let broken = json["broken_actuators"].as_array().unwrap();
    let ids: Vec<&str> = broken.iter().map(|b| b["id"].as_str().unwrap()).collect();
    assert_eq!(ids, ["A4", "A17"]);
    assert!(broken.iter().all(|b| b["excluded"] == true));
    assert_eq!(json["verdict"], "explained");
    let md = text("report.md");
    assert!(md.contains("## Broken actuators"));
    assert!(md.contains("| A4 | "));
    assert!(md.contains("cracked plate or failed bond: deflection and force"));
    assert!(md.contains("2 of 30 actuators excluded as broken (A4, A17)"));
}

/// A cracked actuator among data with a width-dependent loss no library effect expresses (the selection
/// study's "outside: width loss" case): the rest is not explained, and the cracked actuator stays out
/// rather than being put back to change the verdict; the verdict names it and its likely cause.
#[test]
fn a_broken_actuator_stays_out_when_the_rest_is_not_explained() {
    let csv = break_actuators(&random_csv(Truth::WidthLoss(0.6), 306), &[11], 0.55);
    let cal = run(&csv);
    let ids: Vec<&str> = cal.broken.iter().map(|b| b.id.as_str()).collect();
    assert_eq!(ids, ["A11"]);
    assert!(cal.broken[0].excluded, "{:?}", cal.broken);
    assert_eq!(cal.model.verdict, "not-explained");
    let variable = format!("{:?}", cal.selection.verdict);
    assert!(
        variable.contains("setting aside as broken A11: cracked plate or failed bond"),
        "{variable}"
    );
    assert_eq!(cal.after.free_deflection.unwrap().n, 4 * 29);
}
