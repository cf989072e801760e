//! Geometry against the model: the drawn mass is the predicted mass, kerf grows every cut outline, the
//! bond parts sit where the template puts them.

use super::*;

#[test]
fn geometry_mass_equals_model_mass_and_svg_areas_read_back() {
    // Σ area x thickness x density of the nominal outlines equals the model's mass to 1e-9, and the outline
    // area read back from the written SVG (kerf 0) equals the nominal area to 1e-6.
    let dir = tempfile::tempdir().unwrap();
    let mut designs: Vec<String> = EXAMPLES.iter().map(|e| example(e)).collect();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
    for i in 0..12 {
        let path = dir.path().join(format!("rnd{i}.toml"));
        std::fs::write(&path, random_design(&mut rng, i)).unwrap();
        designs.push(path.to_string_lossy().into_owned());
    }
    for (i, design) in designs.iter().enumerate() {
        let out = dir.path().join(format!("out{i}"));
        let o = cut_sheet(design, &out, &["--kerf-mm", "0"]);
        assert!(o.status.success(), "{design}: {}", stderr(&o));
        let r = report_json(&out);
        let geometry = r["mass_from_geometry_mg"].as_f64().unwrap();
        let model = r["predicted"]["mass_mg"].as_f64().unwrap();
        let layers = r["layers"].as_array().unwrap();
        // Method 1's bond parts are inset from the plate edge (docs/cam.md §1), and the model's bond
        // mass is the parts as drawn: geometry and model are the same parts on every method.
        let bonded = layers.iter().any(|l| l["layer"] == "pyralux");
        let bond_mg = r["predicted"]["mass_breakdown_mg"]["bond"]
            .as_f64()
            .unwrap();
        assert_eq!(bonded, bond_mg > 0.0, "{design}");
        assert!(
            ((geometry - model) / model).abs() < 1e-9,
            "{design}: geometry {geometry} mg vs model {model} mg"
        );
        for l in layers {
            for key in [
                "layer",
                "material",
                "thickness_mm",
                "density_kg_per_m3",
                "part_area_mm2",
                "parts_per_actuator",
                "mass_per_actuator_mg",
                "sheets",
                "utilization",
            ] {
                assert!(l.get(key).is_some(), "{design}: layers[] lacks {key}");
            }
        }
        for (name, bytes) in files(&out) {
            let layer = name.split('-').next().unwrap();
            if !name.ends_with(".svg") || !(layer == "passive" || layer == "pyralux") {
                continue;
            }
            let row = layers
                .iter()
                .find(|l| name.starts_with(l["layer"].as_str().unwrap()))
                .unwrap();
            let nominal = row["part_area_mm2"].as_f64().unwrap();
            let svg = String::from_utf8(bytes).unwrap();
            let outlines = svg_paths(&svg, "CUT");
            assert!(!outlines.is_empty(), "{name}");
            for (ring, closed) in outlines {
                assert!(closed);
                assert!(
                    ((area(&ring) - nominal) / nominal).abs() < 1e-6,
                    "{name}: {} vs {nominal}",
                    area(&ring)
                );
            }
        }
    }
}

#[test]
fn kerf_grows_every_cut_outline_by_at_least_half_the_kerf() {
    // With kerf on, a part's cut path encloses its nominal outline grown by kerf/2: area >= A + P k/2
    // (Steiner: a convex offset adds P k/2 + π k²/4; mitre corners add more).
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let kerf = 0.1;
    let o = cut_sheet(&example("thesis-C.toml"), &out, &["--kerf-mm", "0.1"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let r = report_json(&out);
    let nominal = r["layers"]
        .as_array()
        .unwrap()
        .iter()
        .find(|l| l["layer"] == "passive")
        .unwrap()["part_area_mm2"]
        .as_f64()
        .unwrap();
    // The nominal perimeter from the design's own dimensions (trapezoid sides, base, extension sides, tip).
    let d = &r["design"];
    let f = |k: &str| d[k].as_f64().unwrap();
    let (l_p, w0, w_tip, l_ext) = (
        f("piezo_length_mm"),
        f("base_width_mm"),
        f("tip_width_mm"),
        f("extension_length_mm"),
    );
    let nominal_perimeter =
        w0 + w_tip + 2.0 * (l_p * l_p + (w0 - w_tip).powi(2) / 4.0).sqrt() + 2.0 * l_ext;
    let svg = std::fs::read_to_string(layer_file(&out, "passive-1.svg")).unwrap();
    let cuts = svg_paths(&svg, "CUT");
    assert_eq!(cuts.len(), 6);
    for (ring, _) in cuts {
        let grown = area(&ring);
        assert!(
            grown >= nominal + nominal_perimeter * kerf / 2.0 - 1e-9,
            "{grown} vs {nominal}"
        );
        // Upper bound: the mitred corners add at most (k/2)² x Σ tan(φ/2) over 6 corners, each < 1/tan(5.7°/2).
        assert!(
            grown <= nominal + nominal_perimeter * kerf / 2.0 + 6.0 * (kerf / 2.0).powi(2) * 20.1,
            "grew too much: {grown}"
        );
        assert!(perimeter(&ring) > nominal_perimeter);
    }
}

#[test]
fn method_1_bond_parts_sit_inside_the_plate_by_the_template_inset() {
    // A Pyralux part that is the plate outline exactly lets the adhesive squeeze out past the plate edge and
    // bridge the electrode to the carbon. Each part is the plate inset by `[layers.pyralux] inset_mm`: its
    // area is the plate's less perimeter x inset (to inset² terms), and no point of it comes nearer the
    // plate edge than the inset.
    let dir = tempfile::tempdir().unwrap();
    let method_1 = shipped_template("method-1.toml");
    let area_at = |inset: &str| -> (f64, f64, Vec<[f64; 2]>) {
        let t = method_1.replace("inset_mm = 0.15", &format!("inset_mm = {inset}"));
        assert!(t.contains(&format!("inset_mm = {inset}")));
        let out = run_on_template(dir.path(), &format!("inset-{inset}"), &t);
        let r = report_json(&out);
        let row = |layer: &str| {
            r["layers"]
                .as_array()
                .unwrap()
                .iter()
                .find(|l| l["layer"] == layer)
                .unwrap()["part_area_mm2"]
                .as_f64()
                .unwrap()
        };
        let ring = preview_at_true_size(&out).1;
        (row("pzt"), row("pyralux"), ring)
    };
    let (plate, flush, ring) = area_at("0.0");
    assert!((plate - flush).abs() < 1e-9, "{plate} vs {flush}");
    let (_, inset, _) = area_at("0.15");
    let expected = plate - perimeter(&ring) * 0.15;
    assert!(
        inset < plate && (inset - expected).abs() < 4.0 * 0.15 * 0.15 * 2.0,
        "bond part {inset} mm², plate {plate} mm², plate less perimeter x inset {expected} mm²"
    );
}

/// The model and the cut files hold the same layers. For every process (both shipped templates, and method 2
/// cut ply by ply) and with and without a bond the design declares, either the drawn areas times the areal
/// densities (Σ A t ρ over the layer rows, kerf 0) equal the predicted mass, or the run is refused naming
/// `laminate.bond` and writes nothing.
#[test]
fn a_declared_bond_is_cut_or_refused_and_the_drawn_mass_is_the_predicted_mass() {
    let dir = tempfile::tempdir().unwrap();
    let ply_by_ply = method_2_with("passive_cut = \"stack\"", "passive_cut = \"ply-by-ply\"");
    let processes: [(&str, String); 3] = [
        ("method-1.toml", shipped_template("method-1.toml")),
        ("method-2.toml", method_2()),
        ("plies.toml", ply_by_ply),
    ];
    // The bond method 1 cuts (Pyralux LF, 25 µm, 1100 kg/m³, as the library has it), one it does not
    // (50 µm), and none.
    let bonds: [(&str, Option<&str>); 3] = [
        ("none", None),
        (
            "pyralux-25um",
            Some("bond = \"Pyralux-LF\"\nbond_thickness_mm = 0.025"),
        ),
        (
            "pyralux-50um",
            Some("bond = \"Pyralux-LF\"\nbond_thickness_mm = 0.05"),
        ),
    ];
    let mut cut = 0;
    for (name, template) in &processes {
        for (label, bond) in &bonds {
            let case = dir.path().join(format!("{name}-{label}"));
            std::fs::create_dir(&case).unwrap();
            std::fs::write(case.join(name), template).unwrap();
            let process = format!("process = \"{name}\"");
            let layup = format!("layup_deg = [0, 90, 0]\n{}", bond.unwrap_or_default());
            let design = case.join("d.toml");
            std::fs::write(
                &design,
                design_c_with(&[
                    ("process", &process),
                    ("base_tab_mm", "base_tab_mm = 2.0"),
                    ("layup_deg", &layup),
                ]),
            )
            .unwrap();
            let out = case.join("out");
            let o = cut_sheet(design.to_str().unwrap(), &out, &["--kerf-mm", "0"]);
            let cuts_a_bond = name.starts_with("method-1");
            let matches = bond.is_none() || (cuts_a_bond && *label == "pyralux-25um");
            if !matches {
                let err = stderr(&o);
                assert!(!o.status.success(), "{name} {label}: accepted");
                assert_eq!(err.trim().lines().count(), 1, "{err}");
                assert!(
                    err.contains("d.toml: laminate.bond = \"Pyralux-LF\" ("),
                    "{name} {label}: {err}"
                );
                assert!(!out.exists(), "{name} {label}: half-written output");
                continue;
            }
            assert!(o.status.success(), "{name} {label}: {}", stderr(&o));
            let r = report_json(&out);
            let model = r["predicted"]["mass_mg"].as_f64().unwrap();
            // Σ A t ρ from the layer rows as drawn (mm² x mm x kg/m³ = 1e-3 mg), times the parts per
            // actuator.
            let drawn: f64 = r["layers"]
                .as_array()
                .unwrap()
                .iter()
                .map(|l| {
                    l["part_area_mm2"].as_f64().unwrap()
                        * l["thickness_mm"].as_f64().unwrap()
                        * l["density_kg_per_m3"].as_f64().unwrap()
                        * l["parts_per_actuator"].as_f64().unwrap()
                        * 1e-3
                })
                .sum();
            // Method 1's bond parts are inset from the plate's edge (docs/cam.md §1): the model's bond
            // mass is the parts as drawn, so the drawn mass is the model's on every method.
            assert!(
                ((drawn - model) / model).abs() < 1e-9,
                "{name} {label}: drawn {drawn} mg vs model {model} mg"
            );
            let geometry = r["mass_from_geometry_mg"].as_f64().unwrap();
            assert!(((geometry - drawn) / drawn).abs() < 1e-9, "{name} {label}");
            let bond_mg = r["predicted"]["mass_breakdown_mg"]["bond"]
                .as_f64()
                .unwrap();
            let has_bond_layer = r["layers"]
                .as_array()
                .unwrap()
                .iter()
                .any(|l| l["layer"] == "pyralux");
            assert_eq!(bond_mg > 0.0, has_bond_layer, "{name} {label}");
            cut += 1;
        }
    }
    // Method 1 with no bond and its own, method 2 and ply by ply with none.
    assert_eq!(cut, 4);
}

/// Every shipped design example (an `examples/*.toml` with `[geometry]`), cut by method 1 and by
/// method 2 alike (its `process` line set to each): the mass drawn from the geometry is the model's to
/// 1e-6 on every one, method 1's drawn Pyralux bond parts included.
#[test]
fn every_shipped_design_draws_its_model_mass_by_both_methods() {
    let dir = tempfile::tempdir().unwrap();
    let mut cases = 0;
    for entry in std::fs::read_dir(example_path("")).unwrap() {
        let path = entry.unwrap().path();
        let text = std::fs::read_to_string(&path).unwrap_or_default();
        let doc: toml::Table = toml::from_str(&text).unwrap_or_default();
        if !doc.contains_key("geometry") {
            continue;
        }
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        for method in ["method-1", "method-2"] {
            let lines: Vec<String> = text
                .lines()
                .map(|l| match l.starts_with("process = ") {
                    true => format!("process = \"{method}\""),
                    false => l.to_string(),
                })
                .collect();
            let design = dir.path().join(format!("{method}-{name}"));
            std::fs::write(&design, lines.join("\n")).unwrap();
            let out = dir.path().join(format!("{method}-{name}-out"));
            let o = cut_sheet(design.to_str().unwrap(), &out, &[]);
            assert!(o.status.success(), "{name} {method}: {}", stderr(&o));
            let r = report_json(&out);
            // Method 1 cuts the Pyralux bond parts, method 2 has none.
            let bonded = r["layers"]
                .as_array()
                .unwrap()
                .iter()
                .any(|l| l["layer"] == "pyralux");
            assert_eq!(bonded, method == "method-1", "{name} {method}");
            let geometry = r["mass_from_geometry_mg"].as_f64().unwrap();
            let model = r["predicted"]["mass_mg"].as_f64().unwrap();
            assert!(
                ((geometry - model) / model).abs() < 1e-6,
                "{name} {method}: geometry {geometry} mg vs model {model} mg"
            );
            cases += 1;
        }
    }
    // thesis-1, 7, 21, A, B, C, C-method-1 and robobee-jafferis2016-derated.
    assert_eq!(cases, 16);
}
