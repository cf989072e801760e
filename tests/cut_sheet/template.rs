//! Process templates: ply-by-ply cutting, operation colours, the features table and its refusals.

use super::*;

#[test]
fn ply_by_ply_template_turns_each_ply_and_registers_it() {
    // A user template (method 2 with ply-by-ply cutting) named by path from the design file.
    let dir = tempfile::tempdir().unwrap();
    let template = method_2_with("passive_cut = \"stack\"", "passive_cut = \"ply-by-ply\"");
    let design = design_on_template(
        dir.path(),
        "plies.toml",
        &template,
        &[("base_tab_mm", "base_tab_mm = 2.0")],
    );
    let out = dir.path().join("out");
    let o = cut_sheet(design.to_str().unwrap(), &out, &["--kerf-mm", "0"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let r = report_json(&out);
    let geometry = r["mass_from_geometry_mg"].as_f64().unwrap();
    let model = r["predicted"]["mass_mg"].as_f64().unwrap();
    assert!(
        ((geometry - model) / model).abs() < 1e-9,
        "{geometry} vs {model}"
    );
    for (i, angle) in [0, 90, 0].iter().enumerate() {
        let svg = std::fs::read_to_string(layer_file(
            &out,
            &format!("passive-ply{}-{angle}deg-1.svg", i + 1),
        ))
        .unwrap();
        let parts = svg_paths(&svg, "CUT");
        assert_eq!(parts.len(), 6);
        // Two registration holes (circles: two arcs each) per part.
        assert_eq!(svg.matches(" A").count(), 6 * 2 * 2);
        // The 90° ply's parts lie across the sheet: wider than tall.
        let (xs, ys): (Vec<f64>, Vec<f64>) = parts[0].0.iter().map(|p| (p[0], p[1])).unzip();
        let span = |v: &[f64]| {
            v.iter().cloned().fold(f64::MIN, f64::max) - v.iter().cloned().fold(f64::MAX, f64::min)
        };
        assert_eq!(span(&xs) > span(&ys), *angle == 90, "ply {i}");
    }
    // A design without a tab of its own gets the process's 1.5 mm ground tab, which holds the holes.
    let own = design_c_with(&[("process", "process = \"plies.toml\"")]);
    std::fs::write(dir.path().join("g.toml"), own).unwrap();
    let o = cut_sheet(
        dir.path().join("g.toml").to_str().unwrap(),
        &dir.path().join("out1"),
        &[],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        report_json(&dir.path().join("out1"))["ground_tab"]["length_mm"],
        1.5
    );
    // With no ground tab either there is no room for the holes: a clear error.
    let no_ground = template.replace("ground_tab_mm = 1.5\n", "ground_tab_mm = 0\n");
    assert!(no_ground.contains("ground_tab_mm = 0\n"));
    std::fs::write(dir.path().join("plies-no-ground.toml"), no_ground).unwrap();
    let no_tab = design_c_with(&[("process", "process = \"plies-no-ground.toml\"")]);
    std::fs::write(dir.path().join("e.toml"), no_tab).unwrap();
    let o = cut_sheet(
        dir.path().join("e.toml").to_str().unwrap(),
        &dir.path().join("out2"),
        &[],
    );
    assert!(
        !o.status.success() && stderr(&o).contains("geometry.base_tab_mm"),
        "{}",
        stderr(&o)
    );
    assert!(!dir.path().join("out2").exists());
}

#[test]
fn template_operation_colours_reach_both_file_formats() {
    // A lab whose laser maps magenta to "cut": the template says so, and SVG stroke and DXF layer follow.
    let dir = tempfile::tempdir().unwrap();
    let magenta = method_2_with(
        "cut = { colour = \"#FF0000\", aci = 1 }",
        "cut = { colour = \"#ff00ff\", aci = 6 }",
    );
    let design = design_on_template(dir.path(), "magenta.toml", &magenta, &[]);
    let out = dir.path().join("out");
    let o = cut_sheet(design.to_str().unwrap(), &out, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let svg = std::fs::read_to_string(layer_file(&out, "passive-1.svg")).unwrap();
    assert!(svg.contains("stroke=\"#FF00FF\""));
    assert!(!svg.contains("#FF0000"));
    let dxf = std::fs::read_to_string(layer_file(&out, "passive-1.dxf")).unwrap();
    let lines: Vec<&str> = dxf.lines().map(str::trim).collect();
    // The LAYER table entry: name CUT, then its colour (group code 62).
    let at = lines
        .windows(2)
        .position(|w| w == ["2", "CUT"])
        .expect("a CUT layer");
    let colour = lines[at..]
        .windows(2)
        .find(|w| w[0] == "62")
        .map(|w| w[1])
        .unwrap();
    assert_eq!(colour, "6");

    // Two operations sharing a colour could not be told apart by the laser software: refused.
    let clash = method_2_with(
        "engrave = { colour = \"#000000\", aci = 7 }",
        "engrave = { colour = \"#0000FF\", aci = 7 }",
    );
    let design = design_on_template(dir.path(), "magenta.toml", &clash, &[]);
    let out2 = dir.path().join("out2");
    let o = cut_sheet(design.to_str().unwrap(), &out2, &[]);
    let err = stderr(&o);
    assert!(!o.status.success());
    assert!(
        err.contains("magenta.toml")
            && err.contains("operations")
            && err.contains("share a colour"),
        "{err}"
    );
    assert!(!out2.exists());
}

#[test]
fn template_features_table_remaps_score_lines_into_the_cut_layer() {
    let dir = tempfile::tempdir().unwrap();
    let shipped = method_2();
    let base = run_on_template(dir.path(), "shipped", &shipped);
    let remapped = method_2_with("pzt-score-line = \"score\"", "pzt-score-line = \"cut\"");
    let cut = run_on_template(dir.path(), "remapped", &remapped);

    let svg0 = std::fs::read_to_string(layer_file(&base, "pzt-1.svg")).unwrap();
    let svg1 = std::fs::read_to_string(layer_file(&cut, "pzt-1.svg")).unwrap();
    let score0 = svg_paths(&svg0, "SCORE");
    assert!(!score0.is_empty(), "the shipped template scores the PZT");
    assert!(svg_paths(&svg1, "SCORE").is_empty(), "no score layer left");
    assert!(!svg1.contains("#0000FF"), "no blue (score) stroke left");
    // Remapped, every score line is an open straight path in the red cut layer, beside nothing else there.
    let cut1 = svg_paths(&svg1, "CUT");
    let open: Vec<_> = cut1
        .iter()
        .filter(|(p, closed)| !closed && p.len() == 2)
        .collect();
    assert_eq!(open.len(), score0.len());
    assert!(
        svg_paths(&svg0, "CUT").is_empty(),
        "the PZT sheet had no cuts"
    );
    let red = svg1.split("inkscape:label=\"CUT\"").nth(1).unwrap();
    let red = red.split("</g>").next().unwrap();
    assert!(red.contains("#FF0000") && !red.contains("#0000FF"));

    let dxf0 = std::fs::read_to_string(layer_file(&base, "pzt-1.dxf")).unwrap();
    let dxf1 = std::fs::read_to_string(layer_file(&cut, "pzt-1.dxf")).unwrap();
    assert_eq!(dxf_entities_on(&dxf1, "SCORE"), 0);
    assert_eq!(
        dxf_entities_on(&dxf1, "CUT"),
        dxf_entities_on(&dxf0, "SCORE") + dxf_entities_on(&dxf0, "CUT")
    );
    assert!(dxf_entities_on(&dxf0, "SCORE") > 0);
    // The other layers did not move.
    for (name, bytes) in files(&base) {
        if !name.starts_with("pzt-") && !name.starts_with("report") {
            assert_eq!(files(&cut)[&name], bytes, "{name} changed");
        }
    }
}

#[test]
fn template_without_features_table_gives_the_shipped_bytes() {
    // The [features] table of the shipped template spells out the defaults: dropping it changes nothing.
    let dir = tempfile::tempdir().unwrap();
    let shipped = method_2();
    let start = shipped.find("\n[features]\n").expect("a [features] table");
    let end = start + 1 + shipped[start + 1..].find("\n[").unwrap();
    let bare = format!("{}{}", &shipped[..start], &shipped[end..]);
    assert!(!bare.contains("[features]") && bare.contains("[cure]"));
    let a = sheet_files(&run_on_template(dir.path(), "shipped", &shipped));
    let b = sheet_files(&run_on_template(dir.path(), "bare", &bare));
    assert_eq!(a.keys().collect::<Vec<_>>(), b.keys().collect::<Vec<_>>());
    for (name, bytes) in &a {
        if name.ends_with(".svg") || name.ends_with(".dxf") {
            assert!(bytes == &b[name], "{name} differs without [features]");
        }
    }
    // And an explicit non-default differs (the comparison can fail).
    let moved = method_2_with("fiducial = \"engrave\"", "fiducial = \"score\"");
    let c = sheet_files(&run_on_template(dir.path(), "moved", &moved));
    assert!(c["mold-1-1.svg"] != a["mold-1-1.svg"]);
}

#[test]
fn bad_features_table_names_file_field_value_and_the_allowed() {
    let dir = tempfile::tempdir().unwrap();
    let cases = [
        (
            ("pzt-score-line = \"score\"", "pzt-score-lines = \"score\""),
            ["features.pzt-score-lines", "unknown key", "pzt-score-line,"],
        ),
        (
            ("pzt-score-line = \"score\"", "pzt-score-line = \"etch\""),
            [
                "features.pzt-score-line",
                "\"etch\"",
                "\"engrave\", \"score\", \"secondary\", \"cut\"",
            ],
        ),
        (
            ("part-outline = \"cut\"", "part-outline = \"engrave\""),
            [
                "features.part-outline",
                "\"engrave\"",
                "\"cut\", \"secondary\"",
            ],
        ),
        (
            ("part-label = \"engrave\"", "part-label = \"cut\""),
            [
                "features.part-label",
                "\"cut\"",
                "\"engrave\", \"score\", \"secondary\"",
            ],
        ),
    ];
    for (i, ((from, to), needles)) in cases.into_iter().enumerate() {
        let d = dir.path().join(format!("case{i}"));
        std::fs::create_dir_all(&d).unwrap();
        let design = design_on_template(&d, "lab.toml", &method_2_with(from, to), &[]);
        let out = d.join("out");
        let o = cut_sheet(design.to_str().unwrap(), &out, &[]);
        let err = stderr(&o);
        assert!(!o.status.success(), "case {i} accepted");
        assert!(err.contains("lab.toml"), "case {i}: {err}");
        for n in needles {
            assert!(err.contains(n), "case {i}: {n:?} not in {err}");
        }
        assert!(!out.exists(), "case {i} left {out:?}");
    }
}
