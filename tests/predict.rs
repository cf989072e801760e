//! `actuator-cam predict` on the example designs: reference numbers and input errors.

use crate::common;
use common::*;
use proptest::prelude::*;

fn predict_json(file: &str, extra: &[&str]) -> serde_json::Value {
    let mut args = vec!["predict", file, "--json"];
    args.extend_from_slice(extra);
    let out = run(&args);
    assert!(out.status.success(), "{}", stderr(&out));
    serde_json::from_slice(&out.stdout).unwrap()
}

#[test]
#[allow(clippy::approx_constant)] // 0.5236 mm is design 21's deflection, not π/6
fn reference_predictions_of_the_example_designs() {
    // Source: docs/physics.md §9 (independent derivation), within 0.1%.
    let rows = [
        ("A", 0.7371, 456.00, 168.07, 1704.56),
        ("B", 0.8120, 341.37, 138.59, 933.23),
        ("C", 0.6443, 180.56, 58.16, 310.35),
        ("1", 0.5471, 353.50, 96.70, 1119.15),
        ("7", 0.5776, 682.41, 197.07, 1343.45),
        ("21", 0.5236, 446.55, 116.90, 1074.67),
    ];
    for (name, d_mm, f_mn, u_uj, m_mg) in rows {
        let j = predict_json(&example(&format!("thesis-{name}.toml")), &[]);
        let close = |key: &str, scale: f64, want: f64| {
            let got = j[key].as_f64().unwrap() * scale;
            assert!(
                ((got - want) / want).abs() < 1e-3,
                "{name} {key}: {got} vs {want}"
            );
        };
        close("free_deflection_mm", 1.0, d_mm);
        close("blocked_force_N", 1e3, f_mn);
        close("energy_mJ", 1e3, u_uj);
        close("mass_mg", 1.0, m_mg);
        for key in [
            "name",
            "model",
            "energy_density_J_per_kg",
            "stiffness_N_per_m",
            "field_V_per_mm",
            "voltage_V",
            "survival",
            "peak_pzt_strain",
            "base_stress_MPa",
            "capacitance_nF",
            "mass_breakdown_mg",
        ] {
            assert!(!j[key].is_null(), "{name}: {key} missing");
        }
        let b = &j["mass_breakdown_mg"];
        let sum = b["pzt"].as_f64().unwrap()
            + b["passive"].as_f64().unwrap()
            + b["bond"].as_f64().unwrap();
        assert!((sum - j["mass_mg"].as_f64().unwrap()).abs() < 1e-9);
    }
}

#[test]
fn models_are_selectable_and_euler_bernoulli_refuses_tapers() {
    let adjusted = predict_json(&example("thesis-C.toml"), &["--model", "thesis-adjusted"]);
    assert_eq!(adjusted["model"], "thesis-adjusted");
    let original = predict_json(&example("thesis-C.toml"), &[]);
    assert!(adjusted["free_deflection_mm"].as_f64() < original["free_deflection_mm"].as_f64());
    let eb = predict_json(&example("thesis-B.toml"), &["--model", "euler-bernoulli"]);
    // Thesis Table 4.1: EB and CLT free deflection agree closely (here within 1%).
    let ratio = eb["free_deflection_mm"].as_f64().unwrap()
        / original_b()["free_deflection_mm"].as_f64().unwrap();
    assert!((ratio - 1.0).abs() < 0.01, "{ratio}");
    let out = run(&[
        "predict",
        &example("thesis-C.toml"),
        "--model",
        "euler-bernoulli",
    ]);
    assert!(!out.status.success());
    assert!(stderr(&out).contains("rectangles only"), "{}", stderr(&out));
}

#[test]
fn resonance_and_modal_mass_of_a_rectangle_are_the_cantilevers() {
    // Design B is a rectangle without extension or tab: a uniform cantilever, whose lumped tip mass
    // k/ω1² is 3/1.87510⁴ of its mass (β1 L = 1.87510, e.g. Rao, Vibration of Continuous Systems) and
    // whose resonance is √(k/m)/2π with k = F_b/δ. Under every built-in model.
    for model in ["original", "thesis-adjusted", "euler-bernoulli"] {
        let j = predict_json(&example("thesis-B.toml"), &["--model", model]);
        let number = |key: &str| j[key].as_f64().unwrap();
        let want_mg = 3.0 / 1.875_104_068_7f64.powi(4) * number("mass_mg");
        let m = number("modal_mass_mg");
        assert!(
            (m / want_mg - 1.0).abs() < 1e-6,
            "{model}: {m} vs {want_mg}"
        );
        let k = number("stiffness_N_per_m");
        let f = (k / (m * 1e-6)).sqrt() / (2.0 * std::f64::consts::PI);
        assert!((number("resonance_Hz") / f - 1.0).abs() < 1e-9, "{model}");
    }
    // A tapered design with an extension: positive and finite, and the table prints both.
    let c = predict_json(&example("thesis-C.toml"), &[]);
    assert!(c["resonance_Hz"].as_f64().unwrap() > 0.0);
    let out = run(&["predict", &example("thesis-C.toml")]);
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(
        text.contains("resonance") && text.contains("modal mass"),
        "{text}"
    );
}

fn original_b() -> serde_json::Value {
    predict_json(&example("thesis-B.toml"), &[])
}

#[test]
fn voltage_or_field_give_the_same_prediction() {
    // 800 V/mm on 0.267 mm plates in parallel is 213.6 V.
    let text = design_c_with(&[("field_V_per_mm", "voltage_V = 213.6")]);
    let (_d, path) = write_temp("v.toml", &text);
    let by_voltage = predict_json(path.to_str().unwrap(), &[]);
    let by_field = predict_json(&example("thesis-C.toml"), &[]);
    assert!(
        (by_voltage["energy_mJ"].as_f64().unwrap() / by_field["energy_mJ"].as_f64().unwrap() - 1.0)
            .abs()
            < 1e-9
    );
}

/// Run predict on a design text; return (success, stderr).
fn predict_text(text: &str) -> (bool, String) {
    let (_d, path) = write_temp("design.toml", text);
    let out = run(&["predict", path.to_str().unwrap()]);
    (out.status.success(), stderr(&out))
}

#[test]
fn bad_input_gives_one_clear_line_naming_file_field_value_and_range() {
    let cases: Vec<(String, &[&str])> = vec![
        (
            design_c_with(&[("width_ratio", "width_ratio = 2.5")]),
            &["design.toml", "geometry.width_ratio", "2.5", "[0.25, 2)"],
        ),
        (
            design_c_with(&[("length_mm", "length_mm = -42.2")]),
            &["geometry.length_mm", "-42.2", "[1, 1000] mm"],
        ),
        (
            design_c_with(&[("length_mm", "length_mm = 0")]),
            &["geometry.length_mm", "0", "[1, 1000] mm"],
        ),
        (
            design_c_with(&[("pzt_thickness_mm", "pzt_thickness_mm = 0")]),
            &["laminate.pzt_thickness_mm", "0", "[0.05, 2] mm"],
        ),
        (
            design_c_with(&[("base_width_mm", "base_width_mm = nan")]),
            &["geometry.base_width_mm", "NaN", "allowed range"],
        ),
        (
            design_c_with(&[("extension_ratio", "")]),
            &["geometry.extension_ratio", "missing", "[0, 20]"],
        ),
        (
            design_c_with(&[("base_tab_mm", "base_tab_mn = 1.0")]),
            &["geometry.base_tab_mn", "unknown key"],
        ),
        (
            design_c_with(&[("ply =", "ply = \"unobtainium\"")]),
            &[
                "laminate.ply",
                "unobtainium",
                "unknown material",
                "CF-thesis",
            ],
        ),
        (
            design_c_with(&[("field_V_per_mm", "field_V_per_mm = 800\nvoltage_V = 200")]),
            &["drive", "exactly one of field_V_per_mm and voltage_V"],
        ),
        (
            design_c_with(&[("layup_deg", "layup_deg = [0, nan, 0]")]),
            &["laminate.layup_deg[1]", "NaN", "[-180, 180] deg"],
        ),
        (
            design_c_with(&[("layup_deg", "layup_deg = [0, inf, 0]")]),
            &["laminate.layup_deg[1]", "inf"],
        ),
        (
            design_c_with(&[("mode", "mode = \"diagonal\"")]),
            &["drive.mode", "diagonal", "parallel"],
        ),
        (
            design_c_with(&[("quantity", "quantity = 0")]),
            &["quantity", "0", "[1, 100000]"],
        ),
        (
            "name = \"x\"\n[geometry\n".to_string(),
            &["line", "not valid TOML"],
        ),
    ];
    for (text, needles) in cases {
        let (ok, err) = predict_text(&text);
        assert!(!ok, "accepted: {text}");
        assert_eq!(err.trim_end().lines().count(), 1, "one line: {err}");
        for n in needles {
            assert!(err.contains(n), "{err:?} lacks {n:?}");
        }
        assert!(!err.contains("panicked"), "{err}");
    }
    let out = run(&["predict", "examples/no-such-file.toml"]);
    assert!(!out.status.success() && stderr(&out).contains("no-such-file.toml"));
}

/// Values that would give NaN (`null` in `--json`) or absurd numbers with exit 0 if the ranges let them
/// in. Each is refused in one line naming the field the user wrote and its value in short form, and
/// nothing reaches standard output.
#[test]
fn absurd_values_are_refused_naming_the_field() {
    let cases = [
        (
            ("length_mm", "length_mm = 1e-300"),
            "design.toml: geometry.length_mm = 1e-300: outside the allowed range [1, 1000] mm",
        ),
        (
            ("width_ratio", "width_ratio = 1e-300"),
            "design.toml: geometry.width_ratio = 1e-300: outside the allowed range [0.25, 2)",
        ),
        (
            ("pzt_thickness_mm", "pzt_thickness_mm = 1e-300"),
            "design.toml: laminate.pzt_thickness_mm = 1e-300: outside the allowed range [0.05, 2] mm",
        ),
        // Shorter than the 0.03 mm kerf of the PZT layer.
        (
            ("length_mm", "length_mm = 0.01"),
            "design.toml: geometry.length_mm = 0.01: outside the allowed range [1, 1000] mm",
        ),
        // Printed short, not as 301 digits.
        (
            ("length_mm", "length_mm = 1e300"),
            "design.toml: geometry.length_mm = 1e300: outside the allowed range [1, 1000] mm",
        ),
        // In range, but the PZT plate l_tot / (1 + l_r) = 2 / 21 mm is not a plate.
        (
            ("length_mm", "length_mm = 2\nextension_ratio = 20"),
            "design.toml: geometry.length_mm = length_mm = 2, extension_ratio = 20, base_width_mm = 5, width_ratio = 1.667: \
             the PZT plate length_mm / (1 + extension_ratio) = 0.0952381 mm is shorter than 1 mm",
        ),
        // In range, but the tip (2 - 1.99) 5 / 1.99 = 0.025 mm is narrower than any laser cut.
        (
            ("width_ratio", "width_ratio = 1.99"),
            "design.toml: geometry.width_ratio = length_mm = 42.2, extension_ratio = 0.833, base_width_mm = 5, \
             width_ratio = 1.99: the tip width (2 - width_ratio) base_width_mm / width_ratio = 0.0251256 mm is \
             narrower than 0.1 mm; lower width_ratio or widen the base",
        ),
        // 300 V on 0.05 mm plates in parallel is 6000 V/mm, twice the highest allowed field.
        (
            ("field_V_per_mm", "voltage_V = 300"),
            "design.toml: drive.voltage_V = 300: with laminate.pzt_thickness_mm = 0.05 gives a plate field of \
             6000 V/mm, outside the allowed range (0, 3000] V/mm",
        ),
    ];
    for ((key, line), want) in cases {
        let mut text = design_c_with(&[(key, line)]);
        if key == "length_mm" && line.contains("extension_ratio") {
            text = text.replace("extension_ratio = 0.833\n", "");
        }
        if line.starts_with("voltage_V") {
            text = text.replace("pzt_thickness_mm = 0.267", "pzt_thickness_mm = 0.05");
        }
        let (_d, path) = write_temp("design.toml", &text);
        for json in [false, true] {
            let mut args = vec!["predict", path.to_str().unwrap()];
            if json {
                args.push("--json");
            }
            let out = run(&args);
            let err = stderr(&out);
            let err = err.trim_end();
            assert!(!out.status.success(), "{line}: accepted");
            assert_eq!(err.lines().count(), 1, "{err}");
            assert!(err.ends_with(want), "{line}:\n got {err}\nwant {want}");
            assert!(out.stdout.is_empty(), "{line}: printed {}", stdout(&out));
        }
        // cut-sheet refuses the same way and writes nothing.
        let o = path.with_file_name("out");
        let out = run(&[
            "cut-sheet",
            path.to_str().unwrap(),
            "-o",
            o.to_str().unwrap(),
        ]);
        assert!(!out.status.success(), "{line}: cut-sheet accepted");
        assert!(stderr(&out).trim_end().ends_with(want), "{}", stderr(&out));
        assert!(!o.exists());
    }
}

#[test]
fn user_materials_are_read_from_the_file() {
    let text = design_c_with(&[("ply =", "ply = \"my-glass\"")])
        + "[materials.my-glass]\ne1_GPa = 55\ne2_GPa = 14\ng12_GPa = 5\nnu12 = 0.28\ndensity_kg_per_m3 = 1780\nply_thickness_mm = 0.1\n";
    let (_d, path) = write_temp("glass.toml", &text);
    let j = predict_json(path.to_str().unwrap(), &[]);
    let c = predict_json(&example("thesis-C.toml"), &[]);
    // Glass is far more compliant than carbon: more deflection per field (thinner effective core).
    assert!(
        j["mass_breakdown_mg"]["passive"].as_f64() > c["mass_breakdown_mg"]["passive"].as_f64()
    );
    let bad = design_c_with(&[("ply =", "ply = \"g\"")])
        + "[materials.g]\ne1_GPa = 55\nnu12 = 0.28\ndensity = 1780\n";
    let (ok, err) = predict_text(&bad);
    assert!(
        !ok && err.contains("materials.g.density_kg_per_m3"),
        "{err}"
    );
}

#[test]
fn laminate_and_weibull_commands() {
    let out = run(&["laminate", "--layup", "0/90/0", "--json"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let j: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    // Source: 3 plies of 61.8 µm at 1390 kg/m³ = 0.1854 mm and 257.7 g/m².
    assert!((j["thickness_mm"].as_f64().unwrap() - 0.1854).abs() < 1e-12);
    assert!((j["areal_mass_g_per_m2"].as_f64().unwrap() - 257.706).abs() < 1e-9);
    let bad = run(&["laminate", "--layup", "0/x/0"]);
    assert!(!bad.status.success() && stderr(&bad).contains("\"x\""));

    let (_d, path) = write_temp(
        "f.csv",
        "field_V_per_mm\n# comment\n850\n900\n910\n870\n930\n",
    );
    let out = run(&["weibull", path.to_str().unwrap()]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(stdout(&out).contains("90.0% survive up to"));
    let (_d2, bad_csv) = write_temp("g.csv", "field\n850\nabc\n");
    let out = run(&["weibull", bad_csv.to_str().unwrap()]);
    assert!(
        !out.status.success()
            && stderr(&out).contains("g.csv: line 3, column field = \"abc\": expected a number"),
        "{}",
        stderr(&out)
    );
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, .. ProptestConfig::default() })]
    /// No panic on any number in any field: the binary either predicts or says what is wrong.
    #[test]
    fn random_numbers_in_every_field_never_panic(
        values in proptest::collection::vec(prop_oneof![
            any::<f64>(),
            -10.0f64..100.0,
            Just(f64::NAN),
            Just(f64::INFINITY),
            Just(0.0),
        ], 9)
    ) {
        let fmt = |x: f64| if x.is_nan() { "nan".to_string() } else if x.is_infinite() { if x > 0.0 { "inf".into() } else { "-inf".into() } } else { format!("{x:?}") };
        let text = design_c_with(&[
            ("length_mm", &format!("length_mm = {}", fmt(values[0]))),
            ("extension_ratio", &format!("extension_ratio = {}", fmt(values[1]))),
            ("base_width_mm", &format!("base_width_mm = {}", fmt(values[2]))),
            ("width_ratio", &format!("width_ratio = {}", fmt(values[3]))),
            ("base_tab_mm", &format!("base_tab_mm = {}", fmt(values[4]))),
            ("pzt_thickness_mm", &format!("pzt_thickness_mm = {}", fmt(values[5]))),
            ("layup_deg", &format!("layup_deg = [{}, 90, 0]", fmt(values[6]))),
            ("field_V_per_mm", &format!("field_V_per_mm = {}", fmt(values[7]))),
            ("quantity", &format!("quantity = {}", fmt(values[8]))),
        ]);
        let (ok, err) = predict_text(&text);
        prop_assert!(!err.contains("panicked"), "{}", err);
        if !ok {
            prop_assert_eq!(err.trim_end().lines().count(), 1, "{}", err);
            prop_assert!(err.starts_with("error: "), "{}", err);
        }
    }
}

#[test]
fn method_1_design_predicts_its_pyralux_bond_layers_as_cut_sheet_does() {
    // The process named in the design file is part of the actuator: method 1 bonds each PZT plate
    // with a Pyralux layer (templates/method-1.toml: 0.025 mm, 1100 kg/m³), method 2 with none.
    let m1 = predict_json(&example("thesis-C-method-1.toml"), &[]);
    let m2 = predict_json(&example("thesis-C.toml"), &[]);
    let mb = |v: &serde_json::Value, k: &str| v["mass_breakdown_mg"][k].as_f64().unwrap();
    assert_eq!(mb(&m1, "pzt"), mb(&m2, "pzt"));
    assert_eq!(mb(&m1, "passive"), mb(&m2, "passive"));
    assert_eq!(mb(&m2, "bond"), 0.0);
    // Closed form: two bond layers of the PZT trapezoid, l_p · w_nom with l_p = l_tot / (1 + l_r),
    // w_nom = w_0 / w_r (design C: 42.2 mm, l_r 0.833, w_0 5 mm, w_r 1.667).
    let plate_area_mm2 = 42.2 / 1.833 * (5.0 / 1.667);
    let bond_mg = 2.0 * plate_area_mm2 * 0.025 * 1100.0 * 1e-6 * 1e3;
    assert!(
        (mb(&m1, "bond") / bond_mg - 1.0).abs() < 1e-9,
        "{}",
        mb(&m1, "bond")
    );
    // A stiffer stack: the bond layers carry no piezo load, so deflection falls.
    assert!(m1["free_deflection_mm"].as_f64() < m2["free_deflection_mm"].as_f64());
    // cut-sheet reports the same prediction for the same file.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let run_out = run(&[
        "cut-sheet",
        &example("thesis-C-method-1.toml"),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(run_out.status.success(), "{}", stderr(&run_out));
    let report: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("report.json")).unwrap()).unwrap();
    // Less the ground tab cut-sheet adds to a design without a tab, and states with its mass; its
    // bond mass is the Pyralux parts as drawn, inset from the plate (the pyralux layer row), where
    // predict, knowing no process's inset, bonds the whole plate.
    let tab_mg = report["ground_tab"]["mass_mg"].as_f64().unwrap();
    let cut = report["predicted"]["mass_mg"].as_f64().unwrap();
    let drawn_bond = report["layers"]
        .as_array()
        .unwrap()
        .iter()
        .find(|l| l["layer"] == "pyralux")
        .unwrap()["mass_per_actuator_mg"]
        .as_f64()
        .unwrap();
    assert_eq!(
        report["predicted"]["mass_breakdown_mg"]["bond"].as_f64(),
        Some(drawn_bond)
    );
    assert!(drawn_bond < mb(&m1, "bond"));
    assert!(
        (cut - tab_mg - (m1["mass_mg"].as_f64().unwrap() - mb(&m1, "bond") + drawn_bond)).abs()
            < 1e-9,
        "{cut} - {tab_mg} against {}",
        m1["mass_mg"]
    );
    assert_eq!(
        report["predicted"]["blocked_force_N"],
        m1["blocked_force_N"]
    );
}

/// The biased drive (docs/physics.md §2.1): the signal bends the stack as parallel drive at the same
/// field does, the bias only adds the same field along both plates' poling, so the deflection is
/// parallel's and the plates see `E_b/2 + E` along and nothing against their poling; its bias is
/// required, held to at most twice the signal's reach, and refused on any other mode.
#[test]
fn the_biased_drive_bends_as_parallel_and_keeps_the_plates_along_their_poling() {
    let text = std::fs::read_to_string(example_path("thesis-C.toml")).unwrap();
    let with = |drive: &str| {
        text.replace(
            "[drive]\nmode = \"parallel\"\nfield_V_per_mm = 800",
            &format!("[drive]\n{drive}"),
        )
    };
    assert!(text.contains("[drive]\nmode = \"parallel\"\nfield_V_per_mm = 800"));
    let (_d1, biased) = write_temp(
        "biased.toml",
        &with("mode = \"biased\"\nvoltage_V = 80\nbias_V = 200"),
    );
    let (_d2, parallel) = write_temp(
        "parallel.toml",
        &with("mode = \"parallel\"\nvoltage_V = 80"),
    );
    let b = predict_json(biased.to_str().unwrap(), &[]);
    let p = predict_json(parallel.to_str().unwrap(), &[]);
    let free = |v: &serde_json::Value| v["free_deflection_mm"].as_f64().unwrap();
    assert!((free(&b) / free(&p) - 1.0).abs() < 1e-12);
    // 0.267 mm plates: signal 80 V is 299.6 V/mm, bias 200 V 749.1 V/mm; along 674.2, against 0.
    let row = b["modes"]
        .as_array()
        .unwrap()
        .iter()
        .find(|m| m["mode"] == "biased")
        .unwrap();
    let along = row["along_V_per_mm"].as_f64().unwrap();
    assert!((along - (100.0 + 80.0) / 0.267).abs() < 1e-6, "{row}");
    assert_eq!(row["against_V_per_mm"].as_f64().unwrap(), 0.0);
    assert_eq!(row["bias_V"].as_f64().unwrap(), 200.0);
    // The same signal in parallel puts 299.6 V/mm against a plate's poling, just within PZT-5H's 300.
    let par = &p["modes"].as_array().unwrap()[0];
    assert!(
        (par["depolarization_margin_V_per_mm"].as_f64().unwrap() - (300.0 - 80.0 / 0.267)).abs()
            < 1e-6
    );
    for (drive, field, allowed) in [
        (
            "mode = \"biased\"\nvoltage_V = 80",
            "drive",
            "bias_V_per_mm or bias_V",
        ),
        (
            "mode = \"biased\"\nvoltage_V = 120\nbias_V = 200",
            "drive.voltage_V",
            "at most half the bias (100 V)",
        ),
        (
            "mode = \"parallel\"\nvoltage_V = 80\nbias_V = 200",
            "drive.bias_V",
            "only mode = \"biased\" takes a bias",
        ),
    ] {
        let (_d, path) = write_temp("bad.toml", &with(drive));
        let err = refused_in_one_line(&run(&["predict", path.to_str().unwrap()]));
        assert!(
            err.contains(field) && err.contains(allowed),
            "{drive}: {err}"
        );
    }
}

/// A user PZT's depolarization field is a material property (docs/physics.md §2.1): it sets the margin
/// `predict` reports against the poling, and a value outside (0, 3000] V/mm is refused naming the key.
#[test]
fn a_user_pzts_depolarization_field_sets_the_margin_and_is_range_checked() {
    let text = std::fs::read_to_string(example_path("thesis-C.toml"))
        .unwrap()
        .replace("pzt = \"PZT-5H\"", "pzt = \"hard\"");
    let with = |field: &str| {
        format!(
            "{text}\n[materials.hard]\ne1_GPa = 62\nnu12 = 0.31\ndensity_kg_per_m3 = 7800\n\
             d31_pm_per_V = -320\nrelative_permittivity = 3800\n{field}"
        )
    };
    let (_d, path) = write_temp("hard.toml", &with("depolarization_field_V_per_mm = 900"));
    let p = predict_json(path.to_str().unwrap(), &[]);
    let parallel = &p["modes"].as_array().unwrap()[0];
    // Parallel at 800 V/mm: 900 - 800 against the poling, and the failure fit binds (832.5 < 900).
    assert_eq!(
        parallel["depolarization_margin_V_per_mm"].as_f64().unwrap(),
        100.0
    );
    assert_eq!(parallel["binds"], "failure");
    // Without the key a piezoelectric material takes PZT-5H's 300 V/mm.
    let (_d, path) = write_temp("default.toml", &with(""));
    let p = predict_json(path.to_str().unwrap(), &[]);
    assert_eq!(
        p["modes"][0]["depolarization_margin_V_per_mm"]
            .as_f64()
            .unwrap(),
        -500.0
    );
    let (_d, path) = write_temp("bad.toml", &with("depolarization_field_V_per_mm = 0"));
    let err = refused_in_one_line(&run(&["predict", path.to_str().unwrap()]));
    assert!(
        err.contains("materials.hard.depolarization_field_V_per_mm = 0"),
        "{err}"
    );
}

#[test]
fn the_nonlinear_model_predicts_thesis_c_from_the_papers_constants() {
    // Source: docs/physics.md §18.6, the nonlinear ceramic of Jafferis, Smith & Wood 2015 at its
    // published constants (the model's own output, pinned to 0.1 %), against the original model.
    let original = predict_json(&example("thesis-C.toml"), &[]);
    let nl = predict_json(&example("thesis-C.toml"), &["--model", "nonlinear"]);
    assert_eq!(nl["model"], "nonlinear");
    let get = |j: &serde_json::Value, key: &str| j[key].as_f64().unwrap();
    for (key, want) in [
        ("free_deflection_mm", 1.2234),
        ("blocked_force_N", 0.24724),
        ("energy_mJ", 0.1512),
        ("stiffness_N_per_m", 202.1),
    ] {
        let got = get(&nl, key);
        assert!((got / want - 1.0).abs() < 1e-3, "{key}: {got} vs {want}");
    }
    // The mass is the laminate's, whatever the ceramic's law.
    assert_eq!(get(&nl, "mass_mg"), get(&original, "mass_mg"));
    // The blocked force grows by the coefficient's ratio at 800 V/mm, f31 = 27.4 against E |d31| =
    // 19.84 Pa·m/V (eq. 18.1); the deflection by more, the plate in tension being softer (38.5 GPa).
    let force = get(&nl, "blocked_force_N") / get(&original, "blocked_force_N");
    assert!((force - 27.4 / 19.84).abs() < 0.02, "{force}");
    let deflection = get(&nl, "free_deflection_mm") / get(&original, "free_deflection_mm");
    assert!(deflection > force + 0.3, "{deflection}");
    // A softer actuator resonates lower.
    assert!(get(&nl, "resonance_Hz") < get(&original, "resonance_Hz"));
}

#[test]
fn the_nonlinear_model_refuses_a_pzt_its_fit_does_not_describe() {
    // docs/physics.md §18.1: the fit of Jafferis et al. 2015 is PZT-5H's; a PZT-5A design is refused in
    // one line naming the file, not given PZT-5H's law.
    let text = std::fs::read_to_string(example("thesis-C.toml"))
        .unwrap()
        .replacen("pzt = \"PZT-5H\"", "pzt = \"PZT-5A\"", 1);
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("c-5a.toml");
    std::fs::write(&file, text).unwrap();
    let o = run(&["predict", file.to_str().unwrap(), "--model", "nonlinear"]);
    let err = refused_in_one_line(&o);
    assert!(err.contains("c-5a.toml") && err.contains("PZT-5H"), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    // The original model takes it.
    assert!(run(&["predict", file.to_str().unwrap()]).status.success());
}
