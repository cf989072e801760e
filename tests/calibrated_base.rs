//! A calibrated model's `base` (docs/calibration.md, "The model file"): a file on the nonlinear base
//! without effects is the nonlinear model, a file on the original base (or without `base`) the original
//! model, and a base or an effect the file cannot have is refused in one line.

use crate::common;
use common::*;
use std::path::{Path, PathBuf};

const HEAD: &str = "model = \"calibrated\"\nverdict = \"no-effect\"\nselected_effects = []\n";

/// A calibrated model file in `dir` with the `base` line and the `[effects]` body given.
fn model_file(dir: &Path, name: &str, base: &str, effects: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, format!("{base}\n{HEAD}[effects]\n{effects}")).unwrap();
    path
}

/// The JSON a command prints with `--model MODEL`, without the model's name (the one field that says
/// which model was asked for).
fn json_with(args: &[&str], model: &str) -> serde_json::Value {
    let mut args = args.to_vec();
    args.extend_from_slice(&["--model", model, "--json"]);
    let out = run(&args);
    let mut j: serde_json::Value = serde_json::from_slice(&out.stdout)
        .unwrap_or_else(|e| panic!("{args:?}: {e}: {}", stderr(&out)));
    j.as_object_mut().unwrap().remove("model");
    j
}

/// `predict thesis-C.toml --json` with a calibrated model of the `base` line and `[effects]` body given.
fn predict_c_with(base: &str, effects: &str) -> serde_json::Value {
    let dir = tempfile::tempdir().unwrap();
    let file = model_file(dir.path(), "m.toml", base, effects);
    let design = example("thesis-C.toml");
    json_with(&["predict", design.as_str()], file.to_str().unwrap())
}

#[test]
fn a_file_on_the_nonlinear_base_without_effects_predicts_as_the_nonlinear_model() {
    // docs/physics.md §18: the nonlinear ceramic of Jafferis, Smith & Wood 2015; the file adds nothing
    // to it, so every printed number, the resonance and the drive modes' table included, is the same.
    let dir = tempfile::tempdir().unwrap();
    let file = model_file(dir.path(), "nl.toml", "base = \"nonlinear\"", "");
    let file = file.to_str().unwrap();
    for design in ["thesis-C.toml", "thesis-B.toml", "thesis-21.toml"] {
        let design = example(design);
        let args = ["predict", design.as_str()];
        let nonlinear = json_with(&args, "nonlinear");
        assert_eq!(json_with(&args, file), nonlinear, "{design}");
        // Not the original model's numbers (the comparison above is not vacuous).
        assert_ne!(json_with(&args, "original"), nonlinear, "{design}");
    }
    // The drive's operating point is searched at the field the nonlinear model needs (§18.5), the
    // same for the file as for `--model nonlinear`.
    let drive = example("drive-hawkmoth.toml");
    let args = ["drive", drive.as_str()];
    assert_eq!(json_with(&args, file), json_with(&args, "nonlinear"));
}

/// True when two JSON trees have the same shape and their numbers agree to `1e-9` relative.
fn close(a: &serde_json::Value, b: &serde_json::Value) -> bool {
    use serde_json::Value::{Array, Number, Object};
    match (a, b) {
        (Number(x), Number(y)) => {
            let (x, y) = (x.as_f64().unwrap(), y.as_f64().unwrap());
            (x - y).abs() <= 1e-9 * x.abs().max(y.abs())
        }
        (Array(x), Array(y)) => x.len() == y.len() && x.iter().zip(y).all(|(x, y)| close(x, y)),
        (Object(x), Object(y)) => {
            x.len() == y.len() && x.iter().all(|(k, v)| y.get(k).is_some_and(|w| close(v, w)))
        }
        _ => a == b,
    }
}

#[test]
fn a_file_on_the_original_base_or_without_a_base_predicts_as_the_original_model() {
    // A file without `base` is on the original base: `base = "original"` changes no number. Null
    // effects are the original model (the effects' physics path against the section's, to rounding).
    let dead = "dead_length_m = 0.002\n";
    assert_eq!(
        predict_c_with("", dead),
        predict_c_with("base = \"original\"", dead)
    );
    let design = example("thesis-C.toml");
    let args = ["predict", design.as_str()];
    let original = json_with(&args, "original");
    let calibrated = predict_c_with("base = \"original\"", "");
    assert!(close(&calibrated, &original), "{calibrated}\n{original}");
    assert!(!close(&json_with(&args, "nonlinear"), &original));
}

#[test]
fn a_bad_base_and_an_effect_the_nonlinear_base_cannot_take_are_refused_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let design = example("thesis-C.toml");
    // The refusal of `file`, which must be one line naming it and then `rest`.
    let refused_naming = |file: &Path, rest: &str| {
        let err = refused_in_one_line(&run(&[
            "predict",
            design.as_str(),
            "--model",
            file.to_str().unwrap(),
        ]));
        let want = format!("--model \"{}\": {rest}", file.display());
        assert!(err.contains(&want), "{err}");
    };
    let bad = model_file(dir.path(), "bad.toml", "base = \"curved\"", "");
    refused_naming(
        &bad,
        "base = \"curved\": expected \"original\" or \"nonlinear\"",
    );
    // A dead length adds to the linear beam's compliance (docs/calibration.md §2): not approximated on
    // the nonlinear base.
    let dead = model_file(
        dir.path(),
        "dead.toml",
        "base = \"nonlinear\"",
        "dead_length_m = 0.002\n",
    );
    refused_naming(
        &dead,
        "effects.dead_length_m = 0.002: base = \"nonlinear\" takes the effects ply_thickness_scale and bond_thickness_m only",
    );
    // The same effect on the original base is taken.
    let on_original = model_file(dir.path(), "dead-o.toml", "", "dead_length_m = 0.002\n");
    assert!(run(&[
        "predict",
        design.as_str(),
        "--model",
        on_original.to_str().unwrap()
    ])
    .status
    .success());
}

#[test]
fn a_bond_layer_on_the_nonlinear_base_is_solved_into_its_laminate() {
    // The bond layer's mass is 2 ρ t A_pzt (docs/physics.md §4), whatever the ceramic; its stiffness
    // moves the nonlinear model's blocked force.
    let bare = predict_c_with("base = \"nonlinear\"", "");
    let bonded = predict_c_with("base = \"nonlinear\"", "bond_thickness_m = 2e-5\n");
    let get = |j: &serde_json::Value, k: &str| j[k].as_f64().unwrap();
    assert!(get(&bonded, "mass_mg") > get(&bare, "mass_mg"));
    let force = get(&bonded, "blocked_force_N") / get(&bare, "blocked_force_N");
    assert!((force - 1.0).abs() > 0.01, "{force}");
}

#[test]
fn the_optimizer_refuses_a_nonlinear_base_with_effects_in_one_line() {
    // Its nonlinear search takes the bare laminate; a bond layer would be dropped, so it is refused.
    let dir = tempfile::tempdir().unwrap();
    let file = model_file(
        dir.path(),
        "bond.toml",
        "base = \"nonlinear\"",
        "bond_thickness_m = 2e-5\n",
    );
    let out = dir.path().join("out");
    let err = refused_in_one_line(&run(&[
        "optimize",
        &example("optimize-thesis.toml"),
        "--model",
        file.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]));
    assert!(
        err.contains("base = \"nonlinear\" with fitted effects"),
        "{err}"
    );
    assert!(!out.exists());
}
