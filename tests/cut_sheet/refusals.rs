//! Bad input and folders: one line, non-zero, no output; `--force` keeps the user's files.

use super::*;

#[test]
fn bad_input_exits_non_zero_and_leaves_no_output() {
    let dir = tempfile::tempdir().unwrap();
    let cases: Vec<(String, Vec<&str>, &str)> = vec![
        (
            design_c_with(&[("width_ratio", "width_ratio = 2.5")]),
            vec![],
            "geometry.width_ratio",
        ),
        (
            design_c_with(&[("process", "process = \"method-9\"")]),
            vec![],
            "process",
        ),
        (
            // Tip (2 - 1.96) 5 / 1.96 = 0.102 mm: above the 0.1 mm any design needs, below two kerfs.
            design_c_with(&[("width_ratio", "width_ratio = 1.96")]),
            vec!["--kerf-mm", "0.1"],
            "narrower than twice the kerf",
        ),
        (
            design_c_with(&[("quantity", "quantity = 0")]),
            vec![],
            "quantity",
        ),
        (design_c_with(&[]), vec!["--quantity", "0"], "--quantity"),
        (
            design_c_with(&[("length_mm", "length_mm = 400")]),
            vec![],
            "layers.pzt.sheet_width_mm = 72.4: a 5.00 x 218.22 mm PZT plate does not fit the sheet",
        ),
    ];
    for (i, (text, extra, needle)) in cases.into_iter().enumerate() {
        let path = dir.path().join(format!("bad{i}.toml"));
        std::fs::write(&path, text).unwrap();
        let out = dir.path().join(format!("out{i}"));
        let o = cut_sheet(path.to_str().unwrap(), &out, &extra);
        assert!(!o.status.success(), "case {i} accepted");
        assert!(stderr(&o).contains(needle), "case {i}: {}", stderr(&o));
        assert!(!out.exists(), "case {i} left {out:?}");
    }
    // Unwritable output: the target is a file, or its parent is a file.
    let file = dir.path().join("plain-file");
    std::fs::write(&file, "x").unwrap();
    let o = cut_sheet(&example("thesis-C.toml"), &file, &[]);
    assert!(
        !o.status.success() && stderr(&o).contains("not a directory"),
        "{}",
        stderr(&o)
    );
    let o = cut_sheet(&example("thesis-C.toml"), &file.join("out"), &[]);
    assert!(
        !o.status.success() && stderr(&o).contains("a part of the path is a file, not a folder"),
        "{}",
        stderr(&o)
    );
    assert_eq!(std::fs::read_to_string(&file).unwrap(), "x");
    // Missing parents are created, like mkdir -p.
    let nested = dir.path().join("new/nested/out");
    assert!(cut_sheet(&example("thesis-C.toml"), &nested, &[])
        .status
        .success());
    assert!(nested.join("report.json").exists());
    // Nothing staged was left behind.
    let leftovers = staging_left(dir.path());
    assert!(leftovers.is_empty(), "{leftovers:?}");
}

/// `-o` into a folder that holds other work: the run replaces only the files it writes, so the design
/// file and the user's notes in that folder are kept.
#[test]
fn with_force_an_existing_output_folder_keeps_the_users_files() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("project");
    std::fs::create_dir_all(out.join("photos")).unwrap();
    let design = out.join("design.toml");
    std::fs::copy(example("thesis-C.toml"), &design).unwrap();
    std::fs::write(out.join("notes.txt"), "n").unwrap();
    std::fs::write(out.join("photos/coupon.txt"), "p").unwrap();
    std::fs::write(out.join("report.md"), "stale").unwrap();
    // Without --force the folder is refused (tests/output_safety/folders.rs); with it, the user's files stay.
    let o = cut_sheet(design.to_str().unwrap(), &out, &["--force"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(std::fs::read_to_string(out.join("notes.txt")).unwrap(), "n");
    assert_eq!(
        std::fs::read_to_string(out.join("photos/coupon.txt")).unwrap(),
        "p"
    );
    assert_eq!(
        std::fs::read_to_string(&design).unwrap(),
        std::fs::read_to_string(example("thesis-C.toml")).unwrap()
    );
    assert_ne!(
        std::fs::read_to_string(out.join("report.md")).unwrap(),
        "stale"
    );
    // The run wrote exactly what a fresh folder gets, on top of what was there.
    let fresh = dir.path().join("fresh");
    assert!(cut_sheet(design.to_str().unwrap(), &fresh, &[])
        .status
        .success());
    for (name, bytes) in files(&fresh) {
        assert!(
            std::fs::read(out.join(&name)).unwrap() == bytes,
            "{name} differs"
        );
    }
    let staged: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name() != "project" && e.file_name() != "fresh")
        .collect();
    assert!(staged.is_empty(), "{staged:?}");
}

/// A design whose features are narrower than two kerfs of its process is refused before anything is laid
/// out, in one line naming the design file and the design field the user wrote.
#[test]
fn features_too_small_for_the_kerf_name_the_design_field() {
    let dir = tempfile::tempdir().unwrap();
    // Design C's tip: (2 - 1.667) x 5 / 1.667 = 0.9988 mm, less than 2 x 0.6 mm.
    let out = dir.path().join("wide-kerf");
    let o = cut_sheet("examples/thesis-C.toml", &out, &["--kerf-mm", "0.6"]);
    let err = refused_in_one_line(&o);
    assert!(
        err.contains("thesis-C.toml: geometry.width_ratio = ")
            && err
                .contains("the tip width is 0.9988 mm, narrower than twice the kerf (2 x 0.6 mm)"),
        "{err}"
    );
    assert!(!out.exists());
    // A 0.05 mm base tab cannot be cut with a 0.05 mm kerf (it needs 0 or at least 0.1 mm).
    let text = design_c_with(&[("base_tab_mm", "base_tab_mm = 0.05")]);
    let (_d, design) = write_temp("tab.toml", &text);
    let out = dir.path().join("thin-tab");
    let o = cut_sheet(design.to_str().unwrap(), &out, &["--kerf-mm", "0.05"]);
    let err = refused_in_one_line(&o);
    assert!(
        err.contains("tab.toml: geometry.base_tab_mm = 0.05: a base tab must be 0 or at least twice the kerf (2 x 0.05 mm)"),
        "{err}"
    );
    assert!(!out.exists());
    // Two kerfs fit: the same design is cut.
    let out = dir.path().join("fits");
    let o = cut_sheet("examples/thesis-C.toml", &out, &["--kerf-mm", "0.49"]);
    assert!(o.status.success(), "{}", stderr(&o));
}

/// Nothing that is not a finite number reaches report.json. A calibrated model whose d31 scale is
/// positive, as the model allows, but absurd (1e300) would make the energy overflow. It is refused
/// when the model file is read, in one line naming the model file, its field, the value and the bounds
/// calibrate fits d31_scale in; nothing is written and no staging is left.
#[test]
fn a_model_file_value_outside_the_fit_bounds_is_refused_naming_the_file_and_field() {
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("calibrated-model.toml");
    std::fs::write(
        &model,
        "model = \"calibrated\"\nverdict = \"x\"\nselected_effects = []\n[effects]\nd31_scale = 1e300\n",
    )
    .unwrap();
    let out = dir.path().join("out");
    let o = cut_sheet(
        "examples/thesis-C.toml",
        &out,
        &["--model", model.to_str().unwrap()],
    );
    let err = refused_in_one_line(&o);
    // The flag, the file (once), the field, the value and what is allowed.
    let named = format!(
        "error: --model {:?}: effects.d31_scale = 1e300: outside the allowed range [0.05, 3]",
        model.display().to_string()
    );
    assert_eq!(err.trim_end(), named);
    // predict reads the model file the same way.
    let p = run(&[
        "predict",
        "examples/thesis-C.toml",
        "--model",
        model.to_str().unwrap(),
    ]);
    let perr = refused_in_one_line(&p);
    assert_eq!(perr.trim_end(), named);
    assert!(!out.exists());
    let staging = staging_left(dir.path());
    assert!(staging.is_empty(), "{staging:?}");
}
