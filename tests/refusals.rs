//! Issue 31: refusals name what the user wrote (the misspelt key, the field out of range, in short
//! numbers), measured values and failure data have physical ranges, names cannot break the files they go
//! into, and the command line's own errors stay one line.

mod common;
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
    refused_in_one_line(&run(&["predict", "--no-such-flag"]));
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

#[test]
fn a_mold_stock_with_no_film_under_a_plate_is_refused() {
    // Films all thicker than the 0.267 mm plate: no mold layer could hold or press a part.
    let dir = tempfile::tempdir().unwrap();
    let template = std::fs::read_to_string("templates/method-2.toml")
        .unwrap()
        .replace(
            "stock_thicknesses_mm = [0.05, 0.127, 0.25]",
            "stock_thicknesses_mm = [5]",
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
    assert!(
        err.contains("[layers.mold] stock_thicknesses_mm = [5]: no stocked film is as thin as the 0.267 mm PZT plate"),
        "{err}"
    );
    assert!(!out.exists(), "no half-written output");
}
