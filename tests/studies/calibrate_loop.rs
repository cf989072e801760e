//! The calibration loop in one step: on data that hide one primitive outside the library, `calibrate`
//! answers not-explained and writes `suggested-effects.toml`; calibrating again with that file declared
//! explains the data, with the hidden value inside the declared effect's 95 % interval.
//!
//! Every kind of primitive discovery can suggest is hidden once (a scale on a material, the clamp per
//! width, the held root, edge margins, the inactive surface layer and the three added masses), in 30
//! random actuators x 4 voltages with 5 % noise on δ and F_b and 1 % on the mass (`tests/synthetic`).
//! One case runs through the binary, the others through the library the binary calls.
//!
//! An added mass per bonded area has the mass shape of a thin bond layer, whose stiffness barely shows in
//! δ and F_b at this size, so the library's `bond-layer` may explain it on the first run (verdict
//! `explained`): that outcome is accepted for it. An inactive surface layer on plates of several
//! thicknesses is a thickness form the selection compares with the model it chose (docs/calibration.md
//! §3, "Thickness forms"): `explained` on the first run is accepted for it when the selection chose
//! `inactive-surface-layer` itself, with the estimate within 20 % as below.
//!
//! The estimate must lie within 20 % of the hidden value; whether the 95 % interval covers it is printed
//! (`--nocapture`) here and asserted over several seeds per primitive by
//! `the_intervals_cover_the_truth_at_their_stated_rate`.

use crate::common;
use crate::synthetic;

use actuator_cam::Declared;
use actuator_cam::EffectId;
use actuator_cam::{
    calibrate, parse_effects, parse_measured as parse, render_calibration, Calibration, Settings,
};
use actuator_model::primitives::{Primitive, Property, Target};
use rayon::prelude::*;
use std::path::Path;
use synthetic::*;

fn seed(k: u64) -> u64 {
    std::env::var("CALIBRATE_LOOP_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(29_311)
        + k
}

fn cases() -> Vec<(&'static str, Primitive, f64)> {
    vec![
        (
            "passive-E1-scale",
            Primitive::Scale {
                target: Target::Passive,
                property: Property::E1,
            },
            0.6,
        ),
        (
            "clamp-compliance-per-width",
            Primitive::ClampCompliancePerWidth,
            4e-3,
        ),
        ("rigid-root", Primitive::RigidRoot, 2e-3),
        ("edge-margin", Primitive::EdgeMargin, 0.3e-3),
        (
            "inactive-surface-layer",
            Primitive::InactiveSurfaceLayer,
            15e-6,
        ),
        ("added-mass", Primitive::AddedMass, 20e-6),
        ("added-mass-per-length", Primitive::AddedMassPerLength, 1e-4),
        ("added-mass-per-area", Primitive::AddedMassPerArea, 0.03),
    ]
}

/// The file calibrate writes as the next step, if any.
pub(crate) fn suggested(cal: &Calibration, data: &actuator_cam::Dataset) -> Option<String> {
    render_calibration(cal, data, "measured.csv")
        .unwrap()
        .into_iter()
        .find(|(name, _)| name == "suggested-effects.toml")
        .map(|(_, text)| text)
}

/// The settings that declare the effects of a `suggested-effects.toml` (`text`).
pub(crate) fn declaring(text: &str) -> Settings {
    let table: toml::Table = text.parse().unwrap();
    let declared: Vec<_> = parse_effects(Path::new("suggested-effects.toml"), &table)
        .unwrap()
        .into_iter()
        .flat_map(Declared::all)
        .collect();
    Settings {
        declared,
        ..Settings::default()
    }
}

/// A fitted value and its 95 % interval.
pub(super) type Fit = (f64, (f64, f64));

/// The value and interval of the declared effect `name` in the final model, if it was selected, in SI
/// (the primitive's own unit: the selection's thickness form is fitted in µm).
pub(super) fn declared_fit(cal: &Calibration, name: &str) -> Option<Fit> {
    let s = &cal.selection;
    let mass = s.final_mass_index.map(|i| &s.mass_candidates[i]);
    mass.into_iter()
        .chain([&s.candidates[s.final_index]])
        .flat_map(|c| c.effects.iter().zip(c.values.iter().zip(&c.intervals)))
        .find_map(|(id, (v, ci))| match id {
            EffectId::Declared(d) if id.name() == name => {
                let si = |x: f64| d.parameter().primitives[0].map.of(x).unwrap();
                Some((si(*v), (si(ci.0), si(ci.1))))
            }
            _ => None,
        })
}

/// One turn of the loop: first verdict, suggested file, second verdict, the fit of the effect and the
/// selected effects.
type Turn = (String, Option<String>, String, Option<Fit>, String);

/// One turn of the loop on a data set hiding `primitive` at `value`.
fn turn(primitive: Primitive, value: f64, k: u64) -> Turn {
    let csv = random_csv(Truth::Primitive(primitive, value), seed(k));
    let data = parse(&csv).unwrap();
    let first = calibrate(&data, &Settings::default()).unwrap();
    let v1 = first.selection.verdict.name().to_string();
    let name = actuator_cam::primitive_name(primitive);
    let Some(text) = suggested(&first, &data) else {
        // No next step: what the first run selected.
        let selected = first.model.selected_effects.join(", ");
        return (
            v1,
            None,
            String::new(),
            declared_fit(&first, &name),
            selected,
        );
    };
    let second = calibrate(&data, &declaring(&text)).unwrap();
    let fit = declared_fit(&second, &name);
    let selected = second.model.selected_effects.join(", ");
    (
        v1,
        Some(text),
        second.selection.verdict.name().to_string(),
        fit,
        selected,
    )
}

#[test]
#[ignore = "study"]
fn every_primitive_goes_round_the_loop_from_not_explained_to_explained() {
    // Each primitive on its own data set.
    let rows: Vec<_> = cases()
        .par_iter()
        .enumerate()
        .map(|(k, &(name, p, v))| (name, v, turn(p, v, 10 + k as u64)))
        .collect();
    let mut failures = Vec::new();
    for (name, value, (v1, text, v2, fit, selected)) in rows {
        let inside = fit.is_some_and(|(_, (lo, hi))| lo <= value && value <= hi);
        println!("{name}: {v1} -> {v2} ({selected}) fit {fit:?}, truth {value} inside: {inside}");
        if name == "added-mass-per-area" && v1 == "explained" {
            continue;
        }
        let close = fit.is_some_and(|(v, _)| (v / value - 1.0).abs() < 0.2);
        if name == "inactive-surface-layer" && v1 == "explained" {
            if !close || !selected.split(", ").any(|s| s == name) {
                failures.push(format!(
                    "{name}: explained on the first run as {selected}, fit {fit:?} against {value}"
                ));
            }
            continue;
        }
        if v1 != "not-explained" || text.is_none() || v2 != "explained" || !close {
            failures.push(format!(
                "{name}: {v1} -> {v2} ({selected}), fit {fit:?} against {value}\n{}",
                text.unwrap_or_default()
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// Interval coverage (docs/calibration.md §3, "The next step, written"): every primitive round the loop
/// on data sets from seeds the method was never adjusted on (`29_311 + 1000 + 8 j + case`); the 95 %
/// interval of the fitted effect must hold the hidden value at the stated rate, no more misses than
/// [`allowed_misses`] over all the intervals (a run that names no fit of the primitive, as a bond layer
/// explaining a mass per area, gives none). CI runs 2 seeds per primitive;
/// `ACTUATOR_CAM_FULL_STUDY=1` runs 10 and prints the table in docs/calibration.md (`--nocapture`).
#[test]
#[ignore = "study"]
fn the_intervals_cover_the_truth_at_their_stated_rate() {
    let seeds = if full_study() { 10 } else { 2 };
    let cases = cases();
    let jobs: Vec<(usize, u64)> = (0..seeds)
        .flat_map(|j| (0..cases.len()).map(move |c| (c, j)))
        .collect();
    let fits: Vec<(usize, Option<Fit>)> = jobs
        .par_iter()
        .map(|&(c, j)| {
            let (_, p, v) = cases[c];
            (c, turn(p, v, 1000 + 8 * j + c as u64).3)
        })
        .collect();
    let (mut n, mut misses) = (0, 0);
    println!("| hidden primitive | intervals | truth inside |\n|---|---|---|");
    for (c, &(name, _, value)) in cases.iter().enumerate() {
        let own: Vec<(f64, f64)> = fits
            .iter()
            .filter(|(k, _)| *k == c)
            .filter_map(|(_, f)| f.map(|(_, ci)| ci))
            .collect();
        let inside = own
            .iter()
            .filter(|(lo, hi)| *lo <= value && value <= *hi)
            .count();
        println!("| {name} | {} | {inside} |", own.len());
        n += own.len();
        misses += own.len() - inside;
    }
    let allowed = allowed_misses(n);
    println!(
        "{} of {n} intervals hold the truth; at most {allowed} misses allowed",
        n - misses
    );
    assert!(n >= 6 * seeds as usize, "only {n} intervals");
    assert!(
        misses <= allowed,
        "{misses} of {n} intervals miss the truth (at most {allowed})"
    );
}

#[test]
#[ignore = "study"]
fn allowed_misses_is_the_binomial_one_percent_point() {
    // P(X > 1 | n = 8, p = 0.05) = 0.057, P(X > 2) = 0.0058.
    assert_eq!(allowed_misses(8), 2);
    // n = 80: mean 4; P(X > 8) = 0.0184, P(X > 9) = 0.0065.
    assert_eq!(allowed_misses(80), 9);
}

/// Through the binary: the file is written with the reports, and `--effects` reads it back.
#[test]
#[ignore = "study"]
fn the_binary_writes_the_next_step_and_runs_it() {
    let dir = tempfile::tempdir().unwrap();
    let csv_path = dir.path().join("measured.csv");
    std::fs::write(
        &csv_path,
        random_csv(
            Truth::Primitive(Primitive::AddedMassPerLength, 1e-4),
            seed(1),
        ),
    )
    .unwrap();
    let first = dir.path().join("first");
    common::run_ok(&[
        "calibrate",
        csv_path.to_str().unwrap(),
        "-o",
        first.to_str().unwrap(),
    ]);
    let file = first.join("suggested-effects.toml");
    let text = std::fs::read_to_string(&file).unwrap();
    assert!(text.contains("name = \"added-mass-per-length\""), "{text}");
    assert!(text.contains("# rank 1 of the mass candidates"), "{text}");
    let second = dir.path().join("second");
    common::run_ok(&[
        "calibrate",
        csv_path.to_str().unwrap(),
        "--effects",
        file.to_str().unwrap(),
        "-o",
        second.to_str().unwrap(),
    ]);
    let report = common::report_json(&second);
    assert_eq!(report["verdict"], "explained", "{report}");
    assert!(!second.join("suggested-effects.toml").exists());
}

/// Writes `examples/measured-fillet.csv`, the mass worked example of docs/calibration.md §3: 30 random
/// actuators x 4 voltages (5 % noise on δ and F_b, 1 % on the mass) with a d31 loss (η = 0.85) and an
/// epoxy fillet along the PZT outline of 0.1 mg/mm, which no library effect carries.
/// `cargo test --release --test tests calibrate_loop::write_mass_example -- --ignored`
#[test]
#[ignore = "regenerates examples/measured-fillet.csv"]
fn write_mass_example() {
    let truth = Truth::Composed(
        actuator_model::Effects {
            d31_scale: 0.85,
            ..actuator_model::Effects::default()
        },
        actuator_model::primitives::Applied {
            primitive: Primitive::AddedMassPerLength,
            value: 1e-4,
        },
    );
    let csv = random_csv(truth, 2029);
    let text = format!(
        "# Synthetic measurements with a mass no layer carries (30 actuators x 4 voltages, 5% noise on\n\
         # deflection and force, 1% on mass). Generated by tests/studies/calibrate_loop.rs::write_mass_example:\n\
         # a d31 loss and an epoxy fillet along the PZT outline. See docs/calibration.md §3.\n{csv}"
    );
    std::fs::write(
        concat!(env!("CARGO_MANIFEST_DIR"), "/examples/measured-fillet.csv"),
        text,
    )
    .unwrap();
}
