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
//! (`--nocapture`), not asserted: one data set per primitive measures coverage too coarsely.

mod common;
mod synthetic;

use actuator_cam::calibrate::library::Declared;
use actuator_cam::calibrate::library::EffectId;
use actuator_cam::calibrate::{self, csv::parse, effects_file, report, Calibration, Settings};
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
fn suggested(cal: &Calibration, data: &calibrate::Dataset) -> Option<String> {
    report::render(cal, data, "measured.csv")
        .unwrap()
        .into_iter()
        .find(|(name, _)| name == "suggested-effects.toml")
        .map(|(_, text)| text)
}

/// The value and interval of the declared effect `name` in the final model, if it was selected.
fn declared_fit(cal: &Calibration, name: &str) -> Option<(f64, (f64, f64))> {
    let s = &cal.selection;
    let mass = s.final_mass_index.map(|i| &s.mass_candidates[i]);
    mass.into_iter()
        .chain([&s.candidates[s.final_index]])
        .flat_map(|c| c.effects.iter().zip(c.values.iter().zip(&c.intervals)))
        .find(|(id, _)| matches!(id, EffectId::Declared(_)) && id.name() == name)
        .map(|(_, (v, ci))| (*v, *ci))
}

/// One turn of the loop: first verdict, suggested file, second verdict, the fit of the effect and the
/// selected effects.
type Turn = (
    String,
    Option<String>,
    String,
    Option<(f64, (f64, f64))>,
    String,
);

/// One turn of the loop on a data set hiding `primitive` at `value`.
fn turn(primitive: Primitive, value: f64, k: u64) -> Turn {
    let csv = random_csv(Truth::Primitive(primitive, value), seed(k));
    let data = parse(&csv).unwrap();
    let first = calibrate::calibrate(&data, &Settings::default()).unwrap();
    let v1 = first.selection.verdict.name().to_string();
    let name = actuator_cam::calibrate::discover::catalogue::name(primitive);
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
    let table: toml::Table = text.parse().unwrap();
    let declared: Vec<_> = effects_file::parse(Path::new("suggested-effects.toml"), &table)
        .unwrap()
        .into_iter()
        .flat_map(Declared::all)
        .collect();
    let settings = Settings {
        declared,
        ..Settings::default()
    };
    let second = calibrate::calibrate(&data, &settings).unwrap();
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

/// Through the binary: the file is written with the reports, and `--effects` reads it back.
#[test]
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
