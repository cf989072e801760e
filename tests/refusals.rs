//! Refusals name what the user wrote (the misspelt key, the field out of range, in short numbers), measured
//! values and failure data have physical ranges, names cannot break the files they go into, and the command
//! line's own errors stay one line.

use crate::common;
use common::*;
use std::process::Stdio;

/// The measured example with one cell of its first data row replaced.
fn measured_with(column: usize, value: &str) -> (tempfile::TempDir, String) {
    let text = std::fs::read_to_string(example("measured-thesis-like.csv")).unwrap();
    let mut done = false;
    let lines: Vec<String> = text
        .lines()
        .map(|l| {
            if done || l.starts_with('#') || l.starts_with("id,") {
                return l.to_string();
            }
            done = true;
            let mut cells: Vec<&str> = l.split(',').collect();
            cells[column] = value;
            cells.join(",")
        })
        .collect();
    let (dir, path) = write_temp("m.csv", &(lines.join("\n") + "\n"));
    (dir, path.to_str().unwrap().to_string())
}

#[test]
fn measured_values_outside_their_physical_range_are_refused() {
    // Columns: 8 mass_mg, 9 free_deflection_mm, 10 blocked_force_N.
    for (column, value, field, range) in [
        (9, "1e300", "free_deflection_mm", "[0.0001, 1000] mm"),
        (10, "1e-300", "blocked_force_N", "[1e-6, 1000] N"),
        (8, "1e12", "mass_mg", "[0.01, 10000000] mg"),
    ] {
        let (dir, csv) = measured_with(column, value);
        let out = dir.path().join("out");
        let o = run(&["calibrate", &csv, "-o", out.to_str().unwrap()]);
        let err = refused_in_one_line(&o);
        assert!(
            err.contains(&format!(
                "column {field} = {value}: outside the allowed range {range}"
            )),
            "{err}"
        );
        assert!(!out.exists(), "half-written output");
    }
}

#[test]
fn failure_data_spread_over_more_than_three_decades_is_refused() {
    let (_d, f) = write_temp("f.csv", "field\n1e-300\n1e300\n1\n");
    let err = refused_in_one_line(&run(&["weibull", f.to_str().unwrap()]));
    assert!(
        err.contains("f.csv: line 2, column field = 1e-300"),
        "{err}"
    );
    let (_d, f) = write_temp("f.csv", "field\n0.5\n900\n1000\n");
    let err = refused_in_one_line(&run(&["weibull", f.to_str().unwrap()]));
    assert!(
        err.contains("f.csv: column field = 0.5 to 1000: the values span a factor of 2000"),
        "{err}"
    );
    assert!(err.len() < 300, "{err}");
}

#[test]
fn a_huge_value_prints_short_and_the_right_field_is_blamed() {
    let spec = std::fs::read_to_string(example("optimize-thesis.toml")).unwrap();
    let spec = spec.replace("energy_mJ = 0.059", "energy_mJ = 1e300");
    let (_d, f) = write_temp("spec.toml", &spec);
    let err = refused_in_one_line(&run(&["optimize", f.to_str().unwrap()]));
    assert!(
        err.contains("requirement.energy_mJ = 1e300: outside the allowed range [1e-9, 1000000] mJ"),
        "{err}"
    );
}

#[test]
fn a_misspelt_key_is_named_with_a_did_you_mean() {
    let (_d, f) = write_temp(
        "d.toml",
        &design_c_with(&[("length_mm", "length_m = 42.2")]),
    );
    let err = refused_in_one_line(&run(&["predict", f.to_str().unwrap()]));
    assert!(
        err.contains("d.toml: geometry.length_m = 42.2: unknown key; did you mean `length_mm`?"),
        "{err}"
    );
}

#[test]
fn a_name_with_a_control_character_is_refused() {
    let (dir, f) = write_temp("d.toml", &design_c_with(&[("name", "name = \"C\\u0001\"")]));
    let out = dir.path().join("out");
    let err = refused_in_one_line(&cut_sheet(f.to_str().unwrap(), &out, &[]));
    assert!(
        err.contains("d.toml: name = \"C\\u{1}\": expected printable text"),
        "{err}"
    );
    assert!(!out.exists());
}

#[test]
fn command_line_errors_are_one_line() {
    let err = refused_in_one_line(&run(&[
        "cut-sheet",
        "examples/thesis-C.toml",
        "--kerf-mm",
        "-1",
    ]));
    assert!(err.contains("--flag=-1"), "{err}");
    let err = refused_in_one_line(&run(&["predict", "--no-such-flag"]));
    assert!(
        err.contains("unexpected argument '--no-such-flag' found;") && !err.contains("negative"),
        "{err}"
    );
    // A missing argument is named on the same line.
    let err = refused_in_one_line(&run(&["laminate", "--pzt-thickness-mm", "0.2"]));
    assert!(
        err.contains("the following required arguments were not provided: --layup <ANGLES>"),
        "{err}"
    );
}

#[test]
fn a_closed_stdout_ends_the_run_quietly() {
    let mut child = bin()
        .args(["sweep", "examples/sweep-table-3-2.toml"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let o = child.wait_with_output().unwrap();
    use std::os::unix::process::ExitStatusExt;
    assert!(
        o.status.success() || o.status.signal() == Some(13),
        "{:?}: {}",
        o.status,
        stderr(&o)
    );
    assert!(!stderr(&o).contains("panicked"), "{}", stderr(&o));
}

/// Cut thesis design C with the method-2 template's mold stock replaced by `stock`: the refusal, after
/// checking that nothing was written.
fn mold_stock_refusal(stock: &str) -> String {
    let dir = tempfile::tempdir().unwrap();
    let template = std::fs::read_to_string("templates/method-2.toml")
        .unwrap()
        .replace(
            "stock_thicknesses_mm = [0.05, 0.127, 0.25]",
            &format!("stock_thicknesses_mm = {stock}"),
        );
    std::fs::write(dir.path().join("tpl.toml"), template).unwrap();
    let design = dir.path().join("c.toml");
    std::fs::write(
        &design,
        design_c_with(&[("process", "process = \"tpl.toml\"")]),
    )
    .unwrap();
    let out = dir.path().join("out");
    let err = refused_in_one_line(&cut_sheet(design.to_str().unwrap(), &out, &[]));
    assert!(!out.exists(), "no half-written output");
    err
}

#[test]
fn a_mold_stock_with_no_film_under_a_plate_is_refused() {
    // Films all thicker than the 0.267 mm plate: no mold layer could hold or press a part. The template
    // is the file to change, and its field is named as the template spells it.
    let err = mold_stock_refusal("[5]");
    assert!(
        err.contains("tpl.toml: layers.mold.stock_thicknesses_mm = [5]: no stocked film is as thin as the 0.267 mm PZT plate"),
        "{err}"
    );
}

#[test]
fn a_film_thinner_than_any_sold_is_refused_with_a_short_bound() {
    // 1e-300 mm is positive, but no film is that thin, and its thickness would print with 300 digits.
    let err = mold_stock_refusal("[1e-300]");
    assert!(
        err.contains("tpl.toml: layers.mold.stock_thicknesses_mm[0] = 1e-300: outside the allowed range [0.001, 20] mm"),
        "{err}"
    );
    assert!(err.len() < 200, "{err}");
}

#[test]
fn a_huge_command_line_number_prints_short() {
    let err = refused_in_one_line(&run(&[
        "cut-sheet",
        "examples/thesis-C.toml",
        "--kerf-mm",
        "1e300",
    ]));
    assert!(
        err.contains("--kerf-mm \"1e300\": outside the allowed range [0, 2] mm"),
        "{err}"
    );
    let err = refused_in_one_line(&run(&[
        "laminate",
        "--layup",
        "0/90/0",
        "--pzt-thickness-mm",
        "1e300",
    ]));
    assert!(
        err.contains("--pzt-thickness-mm \"1e300\": outside the allowed range [0.05, 2] mm"),
        "{err}"
    );
}

/// A template beside a copy of thesis design C (method 1, with its Pyralux bond layers) that uses it,
/// with one template line replaced: `(dir, design path, template path)`.
fn method_1_with(old: &str, new: &str) -> (tempfile::TempDir, String, std::path::PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let template = std::fs::read_to_string("templates/method-1.toml").unwrap();
    assert!(template.contains(old), "the template holds {old:?}");
    let tpl = dir.path().join("tpl.toml");
    std::fs::write(&tpl, template.replace(old, new)).unwrap();
    let design = std::fs::read_to_string(example("thesis-C-method-1.toml"))
        .unwrap()
        .lines()
        .map(|l| {
            if l.starts_with("process") {
                "process = \"tpl.toml\"".to_string()
            } else {
                l.to_string()
            }
        })
        .collect::<Vec<_>>()
        .join("\n");
    let path = dir.path().join("d.toml");
    std::fs::write(&path, design + "\n").unwrap();
    (dir, path.to_str().unwrap().to_string(), tpl)
}

#[test]
fn an_unbounded_range_is_said_in_words() {
    let spec = std::fs::read_to_string(example("optimize-thesis.toml"))
        .unwrap()
        .replace("max_peak_pzt_strain = 0.0009", "max_peak_pzt_strain = -1");
    let (_d, f) = write_temp("spec.toml", &spec);
    let err = refused_in_one_line(&run(&["optimize", f.to_str().unwrap()]));
    assert!(
        err.contains(
            "spec.toml: constraints.max_peak_pzt_strain = -1: outside the allowed range: greater than 0"
        ),
        "{err}"
    );
    assert!(!err.contains("inf"), "{err}");
}

#[test]
fn weibull_prints_six_significant_digits_at_any_scale() {
    // Strains in plain units: a fixed six decimals would print every threshold as 0.000000.
    let (_d, f) = write_temp(
        "strain.csv",
        "strain\n1.1e-9\n1.3e-9\n1.2e-9\n1.25e-9\n1.15e-9\n1.05e-9\n",
    );
    let out = ok_stdout(&run(&["weibull", f.to_str().unwrap()]));
    assert!(!out.contains("0.000000"), "{out}");
    for line in out.lines().skip(1) {
        let number = line.split_whitespace().last().unwrap();
        let x: f64 = number.parse().unwrap_or_else(|_| panic!("{line}"));
        assert!(x > 1e-9 && x < 2e-9 || line.contains("shape"), "{line}");
        assert!(number.len() <= 12, "{line}");
    }
    // Stresses in Pa: no 19-digit numbers either.
    let (_d, f) = write_temp(
        "stress.csv",
        "stress_Pa\n1.1e11\n1.3e11\n1.2e11\n1.25e11\n1.15e11\n1.05e11\n",
    );
    let out = ok_stdout(&run(&["weibull", f.to_str().unwrap()]));
    for line in out.lines().skip(1) {
        assert!(
            line.split_whitespace().last().unwrap().len() <= 12,
            "{line}"
        );
    }
}

#[test]
fn a_tiny_modulus_blames_the_modulus() {
    let glass = |e1: &str| {
        design_c_with(&[("ply =", "ply = \"my-glass\"")])
            + &format!(
                "[materials.my-glass]\ne1_GPa = {e1}\ne2_GPa = 14\ng12_GPa = 5\nnu12 = 0.28\ndensity_kg_per_m3 = 1780\nply_thickness_mm = 0.1\n"
            )
    };
    let (_d, f) = write_temp("g.toml", &glass("1e-300"));
    let err = refused_in_one_line(&run(&["predict", f.to_str().unwrap()]));
    assert!(
        err.contains("g.toml: materials.my-glass.e1_GPa = 1e-300: outside the allowed range [0.001, 2000] GPa"),
        "{err}"
    );
    // In range, but too soft against E2 for a plane-stress stiffness: E1 is named, with its bound
    // ν12² E2 = 0.28² x 14 = 1.0976 GPa.
    let (_d, f) = write_temp("g.toml", &glass("0.5"));
    let err = refused_in_one_line(&run(&["predict", f.to_str().unwrap()]));
    assert!(
        err.contains("g.toml: materials.my-glass.e1_GPa = 0.5: with e2_GPa = 14 and nu12 = 0.28")
            && err.contains("e1_GPa must be greater than 1.0976"),
        "{err}"
    );
}

#[test]
fn a_voltage_cap_that_holds_the_energy_down_is_the_field_blamed() {
    for cap in ["1e-300", "5"] {
        let spec = std::fs::read_to_string(example("optimize-thesis.toml"))
            .unwrap()
            .replace("max_voltage_V = 300", &format!("max_voltage_V = {cap}"));
        let (dir, f) = write_temp("spec.toml", &spec);
        let best = dir.path().join("optimum");
        let err = refused_in_one_line(&run(&[
            "optimize",
            f.to_str().unwrap(),
            "-o",
            best.to_str().unwrap(),
        ]));
        assert!(
            err.contains(&format!(
                "spec.toml: drive.max_voltage_V = {cap}: infeasible"
            )),
            "{err}"
        );
        assert!(!err.contains("requirement.energy_mJ"), "{err}");
        assert!(!best.exists());
    }
}

#[test]
fn a_via_at_the_plate_end_is_refused_naming_the_template_field() {
    let (dir, design, _) = method_1_with("via_position = 0.25", "via_position = 0.999999");
    let out = dir.path().join("out");
    let err = refused_in_one_line(&cut_sheet(&design, &out, &[]));
    assert!(
        err.contains("tpl.toml: layers.pyralux.via_position = 0.999999: the 0.5 mm via"),
        "{err}"
    );
    assert!(err.contains("allowed range [0.01"), "{err}");
    assert!(!out.exists(), "no half-written output");
}

#[test]
fn pin_holes_through_the_panel_are_refused_naming_the_template_field() {
    let (dir, design, _) = method_1_with("pin_radius_mm = 0.79", "pin_radius_mm = 20");
    let out = dir.path().join("out");
    let err = refused_in_one_line(&cut_sheet(&design, &out, &[]));
    assert!(
        err.contains("tpl.toml: clamp.pin_radius_mm = 20:")
            && err.contains("allowed range (0.05, 2.9] mm"),
        "{err}"
    );
    assert!(!out.exists());
    // Inside the border but through the outline: 3 mm from the edge, a 2.95 mm hole leaves 0.05 mm.
    let (dir, design, _) = method_1_with("pin_radius_mm = 0.79", "pin_radius_mm = 2.95");
    let out = dir.path().join("out");
    let err = refused_in_one_line(&cut_sheet(&design, &out, &[]));
    assert!(
        err.contains("clamp.pin_radius_mm = 2.95: the pin holes, centred clamp.pin_inset_mm = 3 mm from the panel edges, would cut through the panel outline"),
        "{err}"
    );
    // The largest allowed radius is cut, and the panel label keeps clear of the pin.
    let (dir, design, _) = method_1_with("pin_radius_mm = 0.79", "pin_radius_mm = 2.9");
    let out = dir.path().join("out");
    ok_stdout(&cut_sheet(&design, &out, &[]));
}

#[test]
fn a_sheet_too_small_for_a_plate_names_the_sheet_field() {
    let (dir, design, _) = method_1_with("sheet_width_mm = 72.4", "sheet_width_mm = 1.5");
    let out = dir.path().join("out");
    let err = refused_in_one_line(&cut_sheet(&design, &out, &[]));
    assert!(
        err.contains("tpl.toml: layers.pzt.sheet_width_mm = 1.5: a ")
            && err.contains("PZT plate does not fit the sheet; it needs at least"),
        "{err}"
    );
    assert!(!err.contains("usable"), "{err}");
    assert!(!out.exists());
    // The width it names takes the plate.
    let need = err
        .split("it needs at least ")
        .nth(1)
        .and_then(|rest| rest.split(' ').next())
        .expect("a width in the refusal");
    let (_dir, design, _) =
        method_1_with("sheet_width_mm = 72.4", &format!("sheet_width_mm = {need}"));
    ok_stdout(&cut_sheet(&design, &out, &[]));
    // And it is the least hundredth that does: the plate's border and the snappable rest beside it.
    let less = need.parse::<f64>().expect("a number") - 0.01;
    let (_dir, design, _) = method_1_with(
        "sheet_width_mm = 72.4",
        &format!("sheet_width_mm = {less:.2}"),
    );
    let err = refused_in_one_line(&cut_sheet(&design, &dir.path().join("out-less"), &[]));
    assert!(err.contains("PZT plate does not fit the sheet"), "{err}");
}

#[test]
fn a_batch_sheet_too_small_names_the_batch_field() {
    let dir = tempfile::tempdir().unwrap();
    for f in [
        "thesis-A.toml",
        "thesis-B.toml",
        "thesis-C.toml",
        "thesis-1.toml",
    ] {
        std::fs::copy(example(f), dir.path().join(f)).unwrap();
    }
    let batch = std::fs::read_to_string(example("batch.toml")).unwrap();
    let line = batch
        .lines()
        .find(|l| l.starts_with("pzt = {"))
        .expect("the batch overrides the PZT sheet");
    let batch = batch.replace(line, "pzt = { width_mm = 3, height_mm = 72.4 }");
    let path = dir.path().join("b.toml");
    std::fs::write(&path, batch).unwrap();
    let out = dir.path().join("out");
    let err = refused_in_one_line(&run(&[
        "nest",
        path.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]));
    assert!(
        err.contains("b.toml: sheets.pzt.width_mm = 3: a ") && err.contains("it needs at least"),
        "{err}"
    );
    assert!(!out.exists());
}

#[test]
fn a_fit_that_cannot_run_names_the_measured_file() {
    // Two actuators: too few for the largest model.
    let text = std::fs::read_to_string(example("measured-thesis-like.csv")).unwrap();
    let few: Vec<&str> = text.lines().take(12).collect();
    let (dir, f) = write_temp("few.csv", &(few.join("\n") + "\n"));
    let out = dir.path().join("out");
    let err = refused_in_one_line(&run(&[
        "calibrate",
        f.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]));
    assert!(err.contains("few.csv: fit: 2 actuators"), "{err}");
    assert!(!out.exists());
}

#[test]
fn names_and_materials_are_escaped_in_markdown_and_stay_one_line_in_dxf() {
    // A template material holding a line break and DXF group codes, which would end a DXF early if
    // written as they are, is refused where it is read.
    let (bad, design, _) = method_1_with(
        "material = \"PTFE, non-porous\"",
        "material = \"PTFE|<b>\\n0\\nEOF\"",
    );
    let err = refused_in_one_line(&cut_sheet(&design, &bad.path().join("out"), &[]));
    assert!(
        err.contains("layers.mold.material = \"PTFE|<b>\\n0\\nEOF\": expected printable text"),
        "{err}"
    );
    // A name with Markdown's table, emphasis and HTML characters, and a material with the DXF's
    // group code and end marker on one line.
    let (dir, design, tpl) = method_1_with(
        "material = \"PTFE, non-porous\"",
        "material = \"PTFE|<b> 0 EOF\"",
    );
    let text = std::fs::read_to_string(&design)
        .unwrap()
        .replace("name = \"thesis-C-method-1\"", "name = \"C|*x*_<i>\"");
    assert!(text.contains("C|*x*_<i>"), "{text}");
    std::fs::write(&design, text).unwrap();
    assert!(std::fs::read_to_string(&tpl).unwrap().contains("EOF"));
    let out = dir.path().join("out");
    ok_stdout(&cut_sheet(&design, &out, &[]));
    let md = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(md.contains("# Cut sheet: C\\|\\*x\\*\\_\\<i\\> x "), "{md}");
    assert!(md.contains("| PTFE\\|\\<b\\> 0 EOF |"), "{md}");
    // Every table row keeps its column count.
    for table_row in md.lines().filter(|l| l.starts_with("| ")) {
        let cells = table_row.replace("\\|", "").matches('|').count();
        assert!(cells >= 3, "{table_row}");
    }
    // report.json keeps the name as written.
    assert_eq!(report_json(&out)["design"]["name"], "C|*x*_<i>");
    // Each DXF holds exactly one EOF and pairs every group code with one value line.
    for (name, bytes) in files(&out) {
        if !name.ends_with(".dxf") {
            continue;
        }
        let text = String::from_utf8(bytes).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len() % 2, 0, "{name}");
        let eofs = lines
            .chunks(2)
            .filter(|pair| pair[0].trim() == "0" && pair[1] == "EOF")
            .count();
        assert_eq!(eofs, 1, "{name}");
        assert_eq!(lines.last(), Some(&"EOF"), "{name}");
    }
}

#[test]
fn a_template_sheet_or_panel_too_small_names_the_template_and_its_field() {
    let dir = tempfile::tempdir().unwrap();
    let design = dir.path().join("d.toml");
    std::fs::write(
        &design,
        design_c_with(&[]).replace("process = \"method-2\"", "process = \"tpl.toml\""),
    )
    .unwrap();
    let template = shipped_template("method-2.toml");
    for (from, to, says) in [
        (
            "sheet_width_mm = 150.0\nsheet_height_mm = 150.0",
            "sheet_width_mm = 150.0\nsheet_height_mm = 5",
            "tpl.toml: layers.passive.sheet_height_mm = 5: the passive part of thesis-C",
        ),
        (
            "panel_height_mm = 100.0",
            "panel_height_mm = 5",
            "tpl.toml: clamp.panel_height_mm = 5: the actuator (5.20 x 43.90 mm with clearance) does not fit the clamp panel inside its 10 mm border; it needs at least 63.90 mm",
        ),
        (
            "sheet_width_mm = 150.0\nsheet_height_mm = 150.0",
            "sheet_width_mm = 150.0\nsheet_height_mm = 1e-300",
            "tpl.toml: layers.passive.sheet_height_mm = 1e-300: outside the allowed range [1, 2000] mm",
        ),
    ] {
        assert!(template.contains(from), "{from}");
        std::fs::write(dir.path().join("tpl.toml"), template.replace(from, to)).unwrap();
        let out = dir.path().join("out");
        let err = refused_in_one_line(&cut_sheet(design.to_str().unwrap(), &out, &[]));
        assert!(err.contains(says) && !err.contains("d.toml"), "{err}");
        assert!(err.len() < 400, "{err}");
        assert!(!out.exists());
    }
}

#[test]
fn control_characters_in_any_user_string_are_refused_and_never_printed_raw() {
    let effects = std::fs::read_to_string(example("effects-clamp-width.toml")).unwrap();
    let from = "parameter = \"c_w_rad_m_per_N_m\"";
    assert!(effects.contains(from));
    let (dir, f) = write_temp(
        "effects.toml",
        &effects.replace(from, "parameter = \"c_w\\u001b[31m\""),
    );
    let out = dir.path().join("out");
    let o = run(&[
        "calibrate",
        &example("measured-thesis-like.csv"),
        "--effects",
        f.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    let err = refused_in_one_line(&o);
    assert!(
        err.contains("effect[1].parameter = \"c_w\\u{1b}[31m\": expected printable text"),
        "{err}"
    );
    assert!(!stderr(&o).contains('\u{1b}'), "{err}");
    assert!(!out.exists());
    // The same in a template's free text (the pressure the book prints) and a part's name.
    let template = shipped_template("method-2.toml");
    let pressure = template
        .lines()
        .find(|l| l.starts_with("pressure = "))
        .expect("the template's pressure");
    let (dir, t) = write_temp(
        "tpl.toml",
        &template.replace(pressure, "pressure = \"hand\\tpress\""),
    );
    std::fs::write(
        dir.path().join("d.toml"),
        design_c_with(&[]).replace("process = \"method-2\"", "process = \"tpl.toml\""),
    )
    .unwrap();
    let out = dir.path().join("out");
    let err = refused_in_one_line(&cut_sheet(
        dir.path().join("d.toml").to_str().unwrap(),
        &out,
        &[],
    ));
    assert!(
        err.contains(&format!("{}: ", t.display()))
            && err.contains("pressure = \"hand\\tpress\": expected printable text"),
        "{err}"
    );
    assert!(!out.exists());
}
