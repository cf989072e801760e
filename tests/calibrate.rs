//! `actuator-cam calibrate` end to end: the example data set, the files it writes, the round trip of the
//! calibrated model, and clear errors (non-zero exit, nothing written) on bad input.

use crate::common;
use actuator_cam::{
    calibrate, calibrated_model_toml, parse_calibrated_model, predict_row, read_measured, Settings,
};
use common::{example_path, run as cam, run_ok as cam_ok};
use std::path::{Path, PathBuf};

const HEADER: &str =
    "id,l_tot_mm,l_r,w0_mm,w_r,t_p_mm,layup,voltage_V,mass_mg,free_deflection_mm,blocked_force_N";

/// The example measured data set.
fn example() -> PathBuf {
    example_path("measured-thesis-like.csv")
}

/// `actuator-cam calibrate examples/measured-thesis-like.csv -o DIR`, which must succeed.
fn calibrate_example_into(dir: &Path) {
    cam_ok(&[
        "calibrate",
        example().to_str().unwrap(),
        "-o",
        dir.to_str().unwrap(),
    ]);
}

#[test]
fn example_is_explained_and_every_file_is_written() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let run = cam_ok(&[
        "calibrate",
        example().to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--json",
    ]);
    let report: serde_json::Value = serde_json::from_slice(&run.stdout).unwrap();
    assert_eq!(report["verdict"], "explained");
    let names: Vec<&str> = report["selected_effects"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| e["name"].as_str().unwrap())
        .collect();
    for hidden in [
        "ply-thickness",
        "d31-scale",
        "dead-length",
        "clamp-compliance",
    ] {
        assert!(names.contains(&hidden), "{hidden} not in {names:?}");
    }
    for e in report["selected_effects"].as_array().unwrap() {
        for (name, value) in e["parameters"].as_object().unwrap() {
            let iv = &e["intervals"][name];
            let v = value.as_f64().unwrap();
            assert!(iv[0].as_f64().unwrap() <= v && v <= iv[1].as_f64().unwrap());
        }
    }
    for c in report["candidates"].as_array().unwrap() {
        assert!(c["effects"].is_array() && c.get("aicc").is_some() && c.get("cv_rmse").is_some());
    }
    for when in ["before", "after"] {
        for output in ["mass", "free_deflection", "blocked_force"] {
            for key in ["k_mean", "k_std", "rmse_log", "mape"] {
                assert!(
                    report[when][output][key].is_number(),
                    "{when}.{output}.{key}"
                );
            }
        }
    }
    let before = report["before"]["blocked_force"]["rmse_log"]
        .as_f64()
        .unwrap();
    let after = report["after"]["blocked_force"]["rmse_log"]
        .as_f64()
        .unwrap();
    assert!(after * 3.0 < before, "force rmse_log {before} -> {after}");
    for file in [
        "calibrated-model.toml",
        "report.json",
        "report.md",
        "parity-before.svg",
        "parity-after.svg",
        "residuals-before.svg",
        "residuals-after.svg",
    ] {
        assert!(out.join(file).is_file(), "{file} missing");
    }
    // Deterministic: a second run writes the same bytes.
    let out2 = dir.path().join("out2");
    calibrate_example_into(&out2);
    for file in ["report.json", "calibrated-model.toml", "parity-after.svg"] {
        assert_eq!(
            std::fs::read(out.join(file)).unwrap(),
            std::fs::read(out2.join(file)).unwrap(),
            "{file} differs between runs"
        );
    }
}

/// Round trip through the file: the model read back from `calibrated-model.toml` predicts exactly the
/// "after" numbers. (The CLI form, `predict --model`, is `predict_cli_reproduces_after_predictions`.)
#[test]
fn calibrated_model_file_reproduces_the_after_predictions() {
    let data = read_measured(&example()).unwrap();
    let cal = calibrate(&data, &Settings::default()).unwrap();
    let text = calibrated_model_toml(&cal.model).unwrap();
    let back = parse_calibrated_model(&text).unwrap();
    assert_eq!(back, cal.model);
    for (m, after) in data.rows.iter().zip(&cal.predictions_after) {
        let p = predict_row(&back, m).unwrap();
        assert_eq!(p.free_deflection, after.free_deflection);
        assert_eq!(p.blocked_force, after.blocked_force);
        assert_eq!(p.mass, after.mass);
    }
    // The model crate's dispatcher gives the same numbers as predict_row.
    let choice = actuator_model::ModelChoice::Calibrated(std::sync::Arc::new(back));
    let m = &data.rows[0];
    assert_eq!(
        choice.predict(&m.actuator()).unwrap().blocked_force,
        cal.predictions_after[0].blocked_force
    );
}

/// CLI round trip: `predict DESIGN.toml --model calibrated-model.toml --json` must print the "after"
/// prediction.
#[test]
fn predict_cli_reproduces_after_predictions() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    calibrate_example_into(&out);
    let data = read_measured(&example()).unwrap();
    let cal = calibrate(&data, &Settings::default()).unwrap();
    let m = &data.rows[3];
    let design = common::design_of(m);
    let design_path = dir.path().join("design.toml");
    std::fs::write(&design_path, design).unwrap();
    let run = cam_ok(&[
        "predict",
        design_path.to_str().unwrap(),
        "--model",
        out.join("calibrated-model.toml").to_str().unwrap(),
        "--json",
    ]);
    let p: serde_json::Value = serde_json::from_slice(&run.stdout).unwrap();
    let after = &cal.predictions_after[3];
    let close = |a: f64, b: f64| ((a - b) / b).abs() < 1e-6;
    assert!(close(
        p["free_deflection_mm"].as_f64().unwrap(),
        after.free_deflection * 1e3
    ));
    assert!(close(
        p["blocked_force_N"].as_f64().unwrap(),
        after.blocked_force
    ));
    assert!(close(p["mass_mg"].as_f64().unwrap(), after.mass * 1e6));
}

/// Runs `calibrate` on `text`; asserts a non-zero exit, an error naming `needles`, and no output.
fn rejects(text: &str, needles: &[&str]) {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("measured.csv");
    std::fs::write(&input, text).unwrap();
    let out = dir.path().join("out");
    let run = cam(&[
        "calibrate",
        input.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    let stderr = common::refused_in_one_line(&run);
    for n in needles {
        assert!(stderr.contains(n), "`{n}` not in: {stderr}");
    }
    assert!(!out.exists(), "output written on error");
    let leftovers: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .filter(|n| n != "measured.csv")
        .collect();
    assert!(leftovers.is_empty(), "left behind: {leftovers:?}");
}

/// Eight good actuators, then `row` (line 26 of the file).
fn rejects_row(row: &str, needles: &[&str]) {
    rejects(&format!("{HEADER}\n{}{row}\n", good_rows(8)), needles);
}

fn good_rows(n: usize) -> String {
    let mut s = String::new();
    for i in 0..n {
        for v in [50.0, 100.0, 150.0] {
            s.push_str(&format!(
                "A{i},{},0.3,8,1.2,0.191,0/90/0,{v},{},{},{}\n",
                30 + i,
                400 + i,
                0.001 * v,
                0.0005 * v
            ));
        }
    }
    s
}

#[test]
fn missing_column_is_named() {
    let header = HEADER.replace(",blocked_force_N", "");
    let rows: String = good_rows(8)
        .lines()
        .map(|l| l.rsplit_once(',').unwrap().0.to_string() + "\n")
        .collect();
    rejects(
        &format!("{header}\n{rows}"),
        &["missing column", "blocked_force_N"],
    );
}

#[test]
fn non_numeric_cell_reports_line_and_column() {
    rejects_row(
        "A9,30,0.3,8,1.2,0.191,0/90/0,50,400,zero point one,0.02",
        &["line 26", "free_deflection_mm", "zero point one"],
    );
}

#[test]
fn negative_mass_is_rejected() {
    rejects_row(
        "A9,30,0.3,8,1.2,0.191,0/90/0,50,-400,0.1,0.02",
        &["mass_mg", "-400"],
    );
}

/// The CSV checks geometry against the design file's ranges; the error names file, line, column, value
/// and the allowed range on one line.
#[test]
fn geometry_outside_the_design_range_is_rejected() {
    rejects_row(
        "A9,1500,0.3,8,1.2,0.191,0/90/0,50,400,0.1,0.02",
        &["measured.csv: line 26, column l_tot_mm = 1500: outside the allowed range [1, 1000] mm"],
    );
    rejects_row(
        "A9,30,25,8,1.2,0.191,0/90/0,50,400,0.1,0.02",
        &["measured.csv: line 26, column l_r = 25: outside the allowed range [0, 20]"],
    );
    rejects_row(
        "A9,30,0.3,8,1.2,12,0/90/0,50,400,0.1,0.02",
        &["measured.csv: line 26, column t_p_mm = 12: outside the allowed range [0.05, 2] mm"],
    );
}

#[test]
fn unknown_layup_and_material_are_rejected() {
    rejects_row(
        "A9,30,0.3,8,1.2,0.191,[0/90]s,50,400,0.1,0.02",
        &["layup", "[0/90]s"],
    );
    let text = format!(
        "{HEADER},pzt\n{}",
        good_rows(8)
            .lines()
            .map(|l| format!("{l},PZT-9Z\n"))
            .collect::<String>()
    );
    rejects(&text, &["pzt", "PZT-9Z", "PZT-5H"]);
}

#[test]
fn fewer_actuators_than_parameters_is_rejected() {
    rejects(
        &format!("{HEADER}\n{}", good_rows(2)),
        &["actuators", "parameters"],
    );
}

/// The calibrated model feeds cut-sheet: its report carries the calibrated prediction, the same numbers
/// `predict --model FILE` prints.
#[test]
fn cut_sheet_takes_the_calibrated_model() {
    let dir = tempfile::tempdir().unwrap();
    let cal = dir.path().join("cal");
    calibrate_example_into(&cal);
    let model = cal.join("calibrated-model.toml");
    let design = example_path("thesis-C.toml");
    let out = dir.path().join("cut");
    cam_ok(&[
        "cut-sheet",
        design.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--model",
        model.to_str().unwrap(),
    ]);
    let report = common::report_json(&out);
    let predicted = cam_ok(&[
        "predict",
        design.to_str().unwrap(),
        "--model",
        model.to_str().unwrap(),
        "--json",
    ]);
    let p: serde_json::Value = serde_json::from_slice(&predicted.stdout).unwrap();
    assert_eq!(report["predicted"]["model"], "calibrated");
    assert_eq!(report["predicted"]["energy_mJ"], p["energy_mJ"]);
    let original = cam_ok(&["predict", design.to_str().unwrap(), "--json"]);
    let o: serde_json::Value = serde_json::from_slice(&original.stdout).unwrap();
    // The example data hides a lower d31 and a compliant clamp: the calibrated energy is lower.
    assert!(p["energy_mJ"].as_f64() < o["energy_mJ"].as_f64());
    let bad = cam(&[
        "predict",
        design.to_str().unwrap(),
        "--model",
        "no-such-model",
    ]);
    assert!(
        !bad.status.success()
            && String::from_utf8_lossy(&bad.stderr)
                .contains("original, thesis-adjusted, nonlinear, euler-bernoulli")
    );
}

/// The words a non-finite number prints as in Rust (`inf`, `-inf`, `NaN`) and elsewhere (`nan`,
/// `Infinity`), found as whole words in `text`.
fn non_finite_words(text: &str) -> Vec<&str> {
    text.split(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
        .filter(|w| matches!(*w, "inf" | "NaN" | "nan" | "Infinity"))
        .collect()
}

#[test]
fn resonances_the_model_cannot_reach_leave_no_inf_or_nan_in_any_file() {
    // Every actuator's first resonance at the top of the allowed range, 999999 Hz, a thousand times
    // what any of them can ring at: a resonance candidate is then fitted where its model cannot be
    // evaluated beside the optimum, and has no interval. Every file says so in words.
    let text = std::fs::read_to_string(example()).unwrap();
    let mut csv = String::new();
    let mut header = true;
    for line in text.lines() {
        csv.push_str(line);
        if !line.starts_with('#') {
            let weighed = line.split(',').nth(8).is_some_and(|m| !m.is_empty());
            csv.push_str(match (header, weighed) {
                (true, _) => ",resonance_Hz",
                (false, true) => ",999999",
                _ => ",",
            });
            header = false;
        }
        csv.push('\n');
    }
    let dir = tempfile::tempdir().unwrap();
    let rows = dir.path().join("rows.csv");
    std::fs::write(&rows, csv).unwrap();
    let out = dir.path().join("out");
    let run = cam_ok(&[
        "calibrate",
        rows.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    let mut files = vec![("stdout".to_string(), common::stdout(&run))];
    for entry in std::fs::read_dir(&out).unwrap() {
        let path = entry.unwrap().path();
        if let Ok(text) = std::fs::read_to_string(&path) {
            files.push((path.display().to_string(), text));
        }
    }
    assert!(files
        .iter()
        .any(|(name, _)| name.ends_with("suggested-effects.toml")));
    for (name, text) in &files {
        assert!(non_finite_words(text).is_empty(), "{name}:\n{text}");
    }
}
