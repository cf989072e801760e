//! `actuator-cam cut-sheet` on the example designs: geometry against mass, files read back, score lines,
//! spacing, determinism and bad input.

use crate::common;
use actuator_cam::{
    build_layers, design_for_process, Design, Names, Operation, Packing, Shape, Template,
};
use cam_geometry::place_ring;
use common::*;
use geo::LineString;
use geo::{Distance, Euclidean, Intersects, Polygon};
use rand::{Rng, SeedableRng};
use std::path::Path;

const EXAMPLES: [&str; 7] = [
    "thesis-A.toml",
    "thesis-B.toml",
    "thesis-C.toml",
    "thesis-1.toml",
    "thesis-7.toml",
    "thesis-21.toml",
    "thesis-C-method-1.toml",
];

/// The four numbers of an SVG's `viewBox`: x, y, width, height (mm).
fn view_box(svg: &str) -> Vec<f64> {
    svg.split("viewBox=\"")
        .nth(1)
        .unwrap()
        .split('"')
        .next()
        .unwrap()
        .split_whitespace()
        .map(|t| t.parse().unwrap())
        .collect()
}

/// Paths of one Inkscape layer of an SVG, as point lists, plus whether each is closed. A tiny reader
/// independent of the writer: it understands the M/L/Z subset the writer uses for polygons and lines.
fn svg_paths(svg: &str, layer: &str) -> Vec<(Vec<[f64; 2]>, bool)> {
    let height = view_box(svg)[3];
    let Some(group) = svg.split(&format!("inkscape:label=\"{layer}\"")).nth(1) else {
        return vec![];
    };
    let group = group.split("</g>").next().unwrap();
    group
        .split(" d=\"")
        .skip(1)
        .filter_map(|rest| {
            let d = rest.split('"').next().unwrap();
            if d.contains('A') {
                return None; // circles (holes) are not part outlines
            }
            let closed = d.trim_end().ends_with('Z');
            let nums: Vec<f64> = d
                .replace(['M', 'L', 'Z', ','], " ")
                .split_whitespace()
                .map(|t| t.parse().unwrap())
                .collect();
            Some((
                nums.chunks(2).map(|c| [c[0], height - c[1]]).collect(),
                closed,
            ))
        })
        .collect()
}

/// The preview's passive outline and PZT plate at true size, and the scale the preview is drawn at
/// (its title states it: "drawn at 4:1").
fn preview_at_true_size(out: &Path) -> (Vec<[f64; 2]>, Vec<[f64; 2]>, f64) {
    let svg = std::fs::read_to_string(out.join("preview-actuator.svg")).unwrap();
    let scale: f64 = svg
        .split("drawn at ")
        .nth(1)
        .and_then(|t| t.split(':').next())
        .and_then(|t| t.parse().ok())
        .expect("the preview's title states its scale");
    let true_size = |layer: &str| -> Vec<[f64; 2]> {
        svg_paths(&svg, layer)[0]
            .0
            .iter()
            .map(|[x, y]| [x / scale, y / scale])
            .collect()
    };
    (
        true_size("preview passive part"),
        true_size("preview PZT plate"),
        scale,
    )
}

fn perimeter(ring: &[[f64; 2]]) -> f64 {
    let n = ring.len();
    (0..n)
        .map(|i| {
            ((ring[(i + 1) % n][0] - ring[i][0]).powi(2)
                + (ring[(i + 1) % n][1] - ring[i][1]).powi(2))
            .sqrt()
        })
        .sum()
}

/// A random valid design file (thesis ranges, CF plies, random process and tab).
fn random_design(rng: &mut impl Rng, i: usize) -> String {
    let layups = ["[0, 90, 0]", "[0, 0, 90, 0, 0]", "[0, 45, -45, 0]"];
    let field_or_voltage = if rng.gen_bool(0.5) {
        format!("field_V_per_mm = {:.1}", rng.gen_range(100.0..900.0))
    } else {
        format!("voltage_V = {:.1}", rng.gen_range(20.0..200.0))
    };
    format!(
        "name = \"rnd{i}\"\nquantity = {}\nprocess = \"{}\"\n[geometry]\nlength_mm = {:.4}\nextension_ratio = {:.4}\nbase_width_mm = {:.4}\nwidth_ratio = {:.4}\nbase_tab_mm = {:.3}\n[laminate]\npzt = \"PZT-5H\"\npzt_thickness_mm = {}\nply = \"CF-thesis\"\nlayup_deg = {}\n[drive]\nmode = \"{}\"\n{field_or_voltage}\n",
        rng.gen_range(1..8),
        ["method-1", "method-2"][rng.gen_range(0..2)],
        rng.gen_range(15.0..60.0),
        rng.gen_range(0.0..1.5),
        rng.gen_range(3.0..15.0),
        rng.gen_range(0.3..1.9),
        if rng.gen_bool(0.5) { 0.0 } else { rng.gen_range(0.5..4.0) },
        [0.127, 0.191, 0.267][rng.gen_range(0..3)],
        layups[rng.gen_range(0..3)],
        ["parallel", "series", "simultaneous", "alternating"][rng.gen_range(0..4)],
    )
}

/// The built-in method-2 template as shipped.
fn method_2() -> String {
    shipped_template("method-2.toml")
}

/// The built-in method-2 template with one text replaced (the replacement must apply).
fn method_2_with(from: &str, to: &str) -> String {
    let text = method_2();
    let changed = text.replace(from, to);
    assert_ne!(changed, text, "{from:?} is not in the template");
    changed
}

/// Write `template` as `dir/NAME` and design C using it (with more replaced lines) as `dir/d.toml`.
fn design_on_template(
    dir: &Path,
    name: &str,
    template: &str,
    replace: &[(&str, &str)],
) -> std::path::PathBuf {
    std::fs::write(dir.join(name), template).unwrap();
    let process = format!("process = \"{name}\"");
    let mut lines = vec![("process", process.as_str())];
    lines.extend_from_slice(replace);
    let path = dir.join("d.toml");
    std::fs::write(&path, design_c_with(&lines)).unwrap();
    path
}

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
        // The model bonds the whole plate; method 1's bond parts are inset from the plate edge
        // (docs/cam.md §1), which is the only mass the drawn parts lack.
        let row = |name: &str| layers.iter().find(|l| l["layer"] == name);
        let inset_mg = row("pyralux").map_or(0.0, |b| {
            let n = |l: &serde_json::Value, k: &str| l[k].as_f64().unwrap();
            let plate = n(row("pzt").unwrap(), "part_area_mm2");
            (plate - n(b, "part_area_mm2"))
                * n(b, "thickness_mm")
                * n(b, "density_kg_per_m3")
                * 1e-3
                * n(b, "parts_per_actuator")
        });
        assert!(
            ((geometry + inset_mg - model) / model).abs() < 1e-9,
            "{design}: geometry {geometry} mg + bond inset {inset_mg} mg vs model {model} mg"
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
fn pzt_score_lines_end_on_edges_and_parts_keep_their_spacing() {
    let dir = tempfile::tempdir().unwrap();
    for design in EXAMPLES {
        let out = dir.path().join(design);
        let o = cut_sheet(&example(design), &out, &["--quantity", "20"]);
        assert!(o.status.success(), "{design}: {}", stderr(&o));
        for (name, bytes) in files(&out) {
            if !name.ends_with(".svg") {
                continue;
            }
            let svg = String::from_utf8(bytes).unwrap();
            let vb = view_box(&svg);
            let (w, h) = (vb[2], vb[3]);
            if name.starts_with("pzt-") {
                let lines: Vec<[[f64; 2]; 2]> = svg_paths(&svg, "SCORE")
                    .into_iter()
                    .map(|(p, closed)| {
                        assert!(
                            !closed && p.len() == 2,
                            "{name}: score lines are straight open segments"
                        );
                        [p[0], p[1]]
                    })
                    .collect();
                assert!(!lines.is_empty());
                // The page is the sheet; an end on its edge runs past it by the overrun (tests/scoring.rs).
                let on_edge =
                    |p: [f64; 2]| p[0] < 1e-6 || p[1] < 1e-6 || p[0] > w - 1e-6 || p[1] > h - 1e-6;
                let on_line = |p: [f64; 2], l: &[[f64; 2]; 2]| {
                    let seg = geo::Line::new((l[0][0], l[0][1]), (l[1][0], l[1][1]));
                    Euclidean.distance(&geo::Point::new(p[0], p[1]), &seg) < 1e-6
                };
                for (i, l) in lines.iter().enumerate() {
                    for end in l {
                        assert!(
                            on_edge(*end)
                                || lines
                                    .iter()
                                    .enumerate()
                                    .any(|(j, m)| j != i && on_line(*end, m)),
                            "{name}: score line {i} ends in mid-air at {end:?}"
                        );
                    }
                }
            }
            if name.starts_with("passive-") || name.starts_with("pyralux-") {
                let gap = 0.5; // template spacing between cut paths (method-1 and method-2 both 0.5 mm)
                let parts: Vec<Polygon<f64>> = svg_paths(&svg, "CUT")
                    .into_iter()
                    .map(|(r, _)| polygon(&r))
                    .collect();
                for (i, a) in parts.iter().enumerate() {
                    for b in &parts[i + 1..] {
                        assert!(!a.intersects(b), "{name}: parts overlap");
                        assert!(
                            Euclidean.distance(a, b) >= gap - 1e-6,
                            "{name}: gap {}",
                            Euclidean.distance(a, b)
                        );
                    }
                }
            }
        }
    }
}

#[test]
fn two_runs_give_identical_bytes() {
    let dir = tempfile::tempdir().unwrap();
    for design in ["thesis-C.toml", "thesis-A.toml"] {
        let (a, b) = (
            dir.path().join(format!("a-{design}")),
            dir.path().join(format!("b-{design}")),
        );
        assert!(cut_sheet(&example(design), &a, &[]).status.success());
        assert!(cut_sheet(&example(design), &b, &[]).status.success());
        let (fa, fb) = (files(&a), files(&b));
        assert_eq!(fa.keys().collect::<Vec<_>>(), fb.keys().collect::<Vec<_>>());
        for (name, bytes) in &fa {
            assert!(bytes == &fb[name], "{name} differs between runs");
        }
    }
}

#[test]
fn outputs_have_the_layer_files_the_process_needs() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("m2");
    assert!(cut_sheet(&example("thesis-C.toml"), &out, &[])
        .status
        .success());
    let names: Vec<String> = sheet_files(&out).into_keys().collect();
    for want in [
        "pzt-1.svg",
        "pzt-1.dxf",
        "passive-1.svg",
        "mold-1-1.svg",
        "mold-1-1.dxf",
        "felt-1-1.svg",
        "teflon-cover-1-1.svg",
        "porous-teflon-1-1.svg",
        "bleeder-1-1.dxf",
        "report.json",
        "report.md",
        "preview-actuator.svg",
    ] {
        assert!(
            names.contains(&want.to_string()),
            "missing {want}: {names:?}"
        );
    }
    let method1 = design_c_with(&[("process", "process = \"method-1\"")]);
    let (_d, path) = write_temp("m1.toml", &method1);
    let out1 = dir.path().join("m1");
    let o = cut_sheet(path.to_str().unwrap(), &out1, &["--format", "svg"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let names: Vec<String> = sheet_files(&out1).into_keys().collect();
    assert!(
        names.contains(&"pyralux-1.svg".to_string()) && !names.iter().any(|n| n.ends_with(".dxf"))
    );
    let r = report_json(&out1);
    assert!(
        r["predicted"]["mass_breakdown_mg"]["bond"]
            .as_f64()
            .unwrap()
            > 0.0,
        "method 1 counts its Pyralux"
    );
    // The via is cut in every Pyralux part: as many circles as parts.
    let svg = std::fs::read_to_string(layer_file(&out1, "pyralux-1.svg")).unwrap();
    assert_eq!(svg.matches(" A").count() / 2, svg_paths(&svg, "CUT").len());
}

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

/// Entities of a DXF on `layer` (group code 8 names an entity's layer; the LAYER table uses code 2).
fn dxf_entities_on(dxf: &str, layer: &str) -> usize {
    let lines: Vec<&str> = dxf.lines().map(str::trim).collect();
    lines.windows(2).filter(|w| w == &["8", layer]).count()
}

/// Run cut-sheet on design C with `template` written as `dir/sub/t.toml`; the output directory.
fn run_on_template(dir: &Path, sub: &str, template: &str) -> std::path::PathBuf {
    let d = dir.join(sub);
    std::fs::create_dir_all(&d).unwrap();
    let design = design_on_template(&d, "t.toml", template, &[]);
    let out = d.join("out");
    let o = cut_sheet(design.to_str().unwrap(), &out, &[]);
    assert!(o.status.success(), "{sub}: {}", stderr(&o));
    out
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

#[test]
fn pzt_edge_margin_insets_the_plates_inside_the_passive_part() {
    // docs/cam.md §1: a clearance between plate edge and passive edge. With the template's margin m, every
    // corner of the plate (preview, kerf 0) lies inside the passive outline, exactly m from its edge.
    let dir = tempfile::tempdir().unwrap();
    let with_margin = |m: &str| {
        method_2_with(
            "passive_edge_margin_mm = 0.0",
            &format!("passive_edge_margin_mm = {m}"),
        )
    };
    let tab = [("base_tab_mm", "base_tab_mm = 1.0")];
    let design = design_on_template(dir.path(), "inset.toml", &with_margin("0.15"), &tab);
    let out = dir.path().join("out");
    let o = cut_sheet(design.to_str().unwrap(), &out, &["--kerf-mm", "0"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let (passive, plate, scale) = &preview_at_true_size(&out);
    let scale = *scale;
    assert_eq!(plate.len(), 4);
    let outer = polygon(passive);
    for corner in plate {
        let p = geo::Point::new(corner[0], corner[1]);
        assert!(outer.intersects(&p), "{corner:?} outside the passive part");
        let d = Euclidean.distance(&p, outer.exterior());
        assert!(
            (d - 0.15).abs() < 1e-6,
            "{corner:?} is {d} mm from the edge"
        );
    }
    let r = report_json(&out);
    let pzt_area = r["layers"][0]["part_area_mm2"].as_f64().unwrap();
    // The SVG holds 6 decimals: each corner within 5e-7 mm / scale, so the area within perimeter x 5e-7.
    let bound = perimeter(plate) * 5e-7 / scale;
    assert!(
        (pzt_area - area(plate)).abs() < bound,
        "{pzt_area} vs {} (bound {bound})",
        area(plate)
    );
    assert_eq!(r["pzt_edge_margin_mm"].as_f64(), Some(0.15));
    let geometry = r["mass_from_geometry_mg"].as_f64().unwrap();
    assert!(geometry < r["predicted"]["mass_mg"].as_f64().unwrap());
    assert!(std::fs::read_to_string(out.join("report.md"))
        .unwrap()
        .contains("insets the PZT plates 0.15 mm"));

    // A margin that eats the 1 mm tip of design C: refused, nothing written.
    let design = design_on_template(dir.path(), "inset.toml", &with_margin("0.5"), &tab);
    let out2 = dir.path().join("out2");
    let o = cut_sheet(design.to_str().unwrap(), &out2, &[]);
    let err = stderr(&o);
    assert!(!o.status.success());
    assert!(
        err.contains("d.toml") && err.contains("edge margin"),
        "{err}"
    );
    assert!(!out2.exists());
}

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
    // Without --force the folder is refused (tests/output_safety.rs); with it, the user's files stay.
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

#[test]
fn preview_uses_no_operation_colour_or_layer_name() {
    // The preview has no operation's layer name or colour: a PZT outline in red on a CUT layer, imported
    // by mistake, would be a cutting job.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = cut_sheet("examples/thesis-C.toml", &out, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let svg = std::fs::read_to_string(out.join("preview-actuator.svg")).unwrap();
    for name in ["CUT", "SCORE", "ENGRAVE", "SECONDARY", "REFERENCE"] {
        assert!(
            !svg.contains(&format!("label=\"{name}\"")),
            "{name} layer in {svg}"
        );
    }
    for colour in ["#FF0000", "#0000FF", "#000000", "#00FF00", "#808080"] {
        assert!(
            !svg.to_ascii_uppercase().contains(colour),
            "{colour} in {svg}"
        );
    }
    assert_eq!(svg.matches("<path").count(), 2, "{svg}");
    // Nothing in it is a line to follow, and it is not at true size: traced by mistake, no part fits.
    assert_eq!(svg.matches("stroke=\"none\"").count(), 2, "{svg}");
    assert!(!svg.contains("fill=\"none\""), "{svg}");
    let page_mm: f64 = svg
        .split("width=\"")
        .nth(1)
        .unwrap()
        .split("mm")
        .next()
        .unwrap()
        .parse()
        .unwrap();
    let r = report_json(&out);
    let base_w = r["design"]["base_width_mm"].as_f64().unwrap();
    assert!(
        page_mm > 3.0 * (base_w + 2.0),
        "page {page_mm} mm for a {base_w} mm wide actuator"
    );
}

#[test]
fn every_svg_states_how_far_its_shapes_run_off_the_page_and_dxf_extents_are_set() {
    // Kerf-offset clamp outlines of a 100 mm panel reach -0.05 ... 100.05 mm and score lines run past
    // the PZT sheet: the SVG page is the sheet, and its desc says how far shapes run past it, exactly;
    // a DXF's $EXTMIN and $EXTMAX must bound what it draws, not sit at (0, 0, 0).
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = cut_sheet("examples/thesis-C.toml", &out, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let mut checked = 0;
    for entry in std::fs::read_dir(&out).unwrap() {
        let path = entry.unwrap().path();
        let text = std::fs::read_to_string(&path).unwrap_or_default();
        match path.extension().and_then(|e| e.to_str()) {
            Some("svg") => {
                let vb = view_box(&text);
                let stated: f64 = match text.split("Shapes reach ").nth(1) {
                    Some(rest) => rest.split(' ').next().unwrap().parse().unwrap(),
                    None if path.to_string_lossy().contains("preview-") => continue,
                    None => {
                        assert!(text.contains("Every shape lies on the sheet."), "{path:?}");
                        0.0
                    }
                };
                let mut farthest = 0.0f64;
                for group in text.split(" d=\"").skip(1) {
                    let d = group.split('"').next().unwrap();
                    // Every end point of every command (arcs: their end points; the circles here are
                    // pin holes far inside the page).
                    let nums: Vec<f64> = d
                        .replace(['M', 'L', 'A', 'Z', ','], " ")
                        .split_whitespace()
                        .map(|t| t.parse().unwrap())
                        .collect();
                    let points: Vec<[f64; 2]> = if d.contains('A') {
                        vec![]
                    } else {
                        nums.chunks(2).map(|c| [c[0], c[1]]).collect()
                    };
                    for p in points {
                        let off = [
                            vb[0] - p[0],
                            p[0] - vb[0] - vb[2],
                            vb[1] - p[1],
                            p[1] - vb[1] - vb[3],
                        ]
                        .into_iter()
                        .fold(0.0f64, f64::max);
                        assert!(
                            off <= stated + 1e-6,
                            "{path:?}: {p:?} {off} mm off the page {vb:?}, {stated} mm stated"
                        );
                        farthest = farthest.max(off);
                    }
                }
                assert!(
                    (farthest - stated).abs() < 1e-6,
                    "{path:?}: {farthest} mm, {stated} stated"
                );
                checked += 1;
            }
            Some("dxf") => {
                let doc = dxf::Drawing::load_file(&path).unwrap();
                let (lo, hi) = (
                    &doc.header.minimum_drawing_extents,
                    &doc.header.maximum_drawing_extents,
                );
                assert!(
                    hi.x > lo.x && hi.y > lo.y,
                    "{path:?}: extents {lo:?} {hi:?}"
                );
                for e in doc.entities() {
                    if let dxf::entities::EntityType::LwPolyline(p) = &e.specific {
                        for v in &p.vertices {
                            assert!(
                                v.x >= lo.x && v.x <= hi.x && v.y >= lo.y && v.y <= hi.y,
                                "{path:?}: vertex ({}, {}) outside the extents",
                                v.x,
                                v.y
                            );
                        }
                    }
                }
                checked += 1;
            }
            _ => {}
        }
    }
    assert!(checked > 10, "only {checked} files checked");
}

/// The strips between the PZT sheet edges and the full-width score lines, and between neighbouring
/// full-width lines, are either nothing (a line on the edge) or at least the narrowest snappable strip,
/// 5 PZT thicknesses (docs/cam.md §4, "Snappable strips": a plain 0.3 mm edge margin would leave a
/// 0.3 - 0.03/2 = 0.285 mm root edge strip, which chips). Read back from the files, for every example.
#[test]
fn pzt_sheet_strips_between_full_width_score_lines_can_be_snapped() {
    let dir = tempfile::tempdir().unwrap();
    for design in EXAMPLES {
        let out = dir.path().join(design);
        let o = cut_sheet(&example(design), &out, &[]);
        assert!(o.status.success(), "{design}: {}", stderr(&o));
        let t = report_json(&out)["design"]["pzt_thickness_mm"]
            .as_f64()
            .unwrap();
        let min_strip = 5.0 * t;
        for (name, bytes) in files(&out) {
            if !(name.starts_with("pzt-") && name.ends_with(".svg")) {
                continue;
            }
            let svg = String::from_utf8(bytes).unwrap();
            let vb = view_box(&svg);
            let size = [vb[2], vb[3]];
            let lines = svg_paths(&svg, "SCORE");
            for axis in 0..2 {
                // Lines across the whole sheet, square to `axis`: their position on `axis`.
                let mut at: Vec<f64> = lines
                    .iter()
                    .filter(|(p, _)| {
                        let (a, b) = (p[0], p[p.len() - 1]);
                        (a[axis] - b[axis]).abs() < 1e-9
                            && (a[1 - axis] - b[1 - axis]).abs() > size[1 - axis] - 1e-6
                    })
                    .map(|(p, _)| p[0][axis])
                    .chain([0.0, size[axis]])
                    .collect();
                at.sort_by(f64::total_cmp);
                for pair in at.windows(2) {
                    let strip = pair[1] - pair[0];
                    assert!(
                        strip < 1e-6 || strip >= min_strip - 1e-6,
                        "{design} {name}: a {strip:.4} mm strip between {:.4} and {:.4} mm (axis {axis}), narrower than {min_strip:.3} mm",
                        pair[0],
                        pair[1]
                    );
                }
            }
        }
    }
}

// No engraved label lies on a face where a PZT plate is bonded (an engraved groove under a plate is a void
// in the bond line). Built through the library (not the binary: the test needs where each passive part was
// placed) for every example by both methods. The bonded zone is computed here from the design's planform
// alone (the passive part's whole PZT zone, `0 <= y <= l_p` from the root, full width: it holds the plate
// whatever the template's edge margin), placed where the build records each passive part; the labels are
// every open stroke drawn on the passive sheets.

/// Labels drawn on the passive sheets of `example` built by `method`, and how many of them cross
/// a bonded zone.
fn labels_on_bonded_zones(example: &str, method: &str) -> (usize, usize) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("examples")
        .join(example);
    let design = Design::load(&path).unwrap();
    let template = Template::resolve(method, &path).unwrap();
    let design = design_for_process(&design, &template).unwrap();
    let names = Names {
        title: design.name.clone(),
        file: example.into(),
        name_designs: false,
    };
    let built = build_layers(
        &[(&design, design.quantity)],
        &[],
        &template,
        &names,
        &Packing::Shelf,
    )
    .unwrap();
    let p = &design.planform;
    let (l_p, w0, tip) = (
        p.piezo_length() * 1e3,
        p.base_width * 1e3,
        p.tip_width() * 1e3,
    );
    let zone = [
        [-w0 / 2.0, 0.0],
        [w0 / 2.0, 0.0],
        [tip / 2.0, l_p],
        [-tip / 2.0, l_p],
    ];
    let (mut labels, mut crossing) = (0, 0);
    for sheet in built.sheets.iter().filter(|s| s.layer == "passive") {
        let drawing = &built
            .drawings
            .iter()
            .find(|d| d.stem == sheet.file_stem)
            .unwrap()
            .drawing;
        let zones: Vec<Polygon<f64>> = sheet
            .parts
            .iter()
            .map(|part| {
                let ring = place_ring(&zone, part.rotation_deg, part.offset);
                Polygon::new(ring.iter().map(|q| (q[0], q[1])).collect(), vec![])
            })
            .collect();
        for (_, shape) in drawing.items() {
            if let Shape::Polyline(stroke) = shape {
                labels += 1;
                let line: LineString<f64> = stroke.iter().map(|q| (q[0], q[1])).collect();
                if zones.iter().any(|z| z.intersects(&line)) {
                    crossing += 1;
                }
            }
        }
    }
    (labels, crossing)
}

#[test]
fn no_label_lies_in_a_bonded_zone_for_any_example_by_either_method() {
    for example in EXAMPLES {
        for method in ["method-1", "method-2"] {
            let (labels, crossing) = labels_on_bonded_zones(example, method);
            assert_eq!(
                crossing, 0,
                "{example} by {method}: {crossing} of {labels} label strokes lie in a bonded zone"
            );
            // Designs 1 and 7 have extensions wide enough for a label: they keep theirs.
            if example == "thesis-1.toml" || example == "thesis-7.toml" {
                assert!(labels > 0, "{example} by {method}: labels lost");
            }
        }
    }
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

/// The streamed writer gives the bytes the in-memory renderer gives (the library's `plan` + `render`), for a
/// quantity that spans several sheets of every layer (119: the last clamp panel is partly filled, so each
/// clamp layer has a run's file and the last panel's) and more files than the stream keeps in flight.
#[test]
fn streamed_files_equal_the_in_memory_render() {
    use actuator_cam::{
        plan_cut_sheet as plan, render_layer_files, CutSheetOptions, Design, Formats, Template,
    };
    use std::collections::BTreeMap;
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = cut_sheet(&example("thesis-C.toml"), &out, &["--quantity", "119"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let design = Design::load(&example_path("thesis-C.toml")).unwrap();
    let template = Template::resolve(&design.process, &design.source).unwrap();
    let opts = CutSheetOptions {
        formats: Formats {
            svg: true,
            dxf: true,
        },
        kerf_mm: None,
        quantity: Some(119),
        model: actuator_model::ModelKind::Original.into(),
        stroke_mm: 0.0254,
    };
    let sheet = plan(&design, &template, &opts).unwrap();
    let expected: BTreeMap<String, Vec<u8>> =
        render_layer_files(&sheet, opts.formats, opts.stroke_mm)
            .unwrap()
            .into_iter()
            .collect();
    let mut written = files(&out);
    written.remove(".actuator-cam-manifest");
    assert!(
        written.len() > 2 * actuator_cam::IN_FLIGHT,
        "{}",
        written.len()
    );
    assert_eq!(
        written.keys().collect::<Vec<_>>(),
        expected.keys().collect::<Vec<_>>()
    );
    for (name, bytes) in &expected {
        assert!(written[name] == *bytes, "{name} differs");
    }
}

/// Points of `shape`'s path: its vertices and 16 points along each segment (circles and arcs by their
/// bounds, which lie on them only at the axis points; guides are polygons and polylines).
fn path_points(shape: &Shape) -> Vec<[f64; 2]> {
    let ring = match shape {
        Shape::Polygon(r) | Shape::Polyline(r) => r.clone(),
        other => {
            let (lo, hi) = other.bounds();
            vec![lo, hi]
        }
    };
    let mut points = ring.clone();
    for w in ring.windows(2) {
        for k in 1..16 {
            let t = k as f64 / 16.0;
            points.push([
                w[0][0] + t * (w[1][0] - w[0][0]),
                w[0][1] + t * (w[1][1] - w[0][1]),
            ]);
        }
    }
    points
}

#[test]
fn nothing_that_is_never_run_crosses_a_cut_part() {
    // LightBurn ignores layer locks and no-plot flags: a REFERENCE-layer shape left on is cut, so a
    // bonded-zone outline across a passive part's extension would cut each actuator in two. A never-run
    // shape may surround parts (the PZT sheet edge) but no point of it lies inside a cut part.
    for example in EXAMPLES {
        for method in ["method-1", "method-2"] {
            let path = Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("examples")
                .join(example);
            let template = Template::resolve(method, &path).unwrap();
            let design = design_for_process(&Design::load(&path).unwrap(), &template).unwrap();
            let names = Names {
                title: design.name.clone(),
                file: example.into(),
                name_designs: false,
            };
            let built =
                build_layers(&[(&design, 2)], &[], &template, &names, &Packing::Shelf).unwrap();
            let mut guides = 0;
            for d in &built.drawings {
                guides += d.drawing.guides().len();
                let parts: Vec<Polygon<f64>> = d
                    .drawing
                    .shapes_of(Operation::Cut)
                    .filter_map(|s| match s {
                        Shape::Polygon(r) => Some(polygon(r)),
                        _ => None,
                    })
                    .collect();
                for never_run in d.drawing.shapes_of(Operation::Reference) {
                    for q in path_points(never_run) {
                        let p = geo::Point::new(q[0], q[1]);
                        for part in &parts {
                            let inside = part.intersects(&p)
                                && Euclidean.distance(&p, part.exterior()) > 1e-6;
                            assert!(
                                !inside,
                                "{example} by {method}, {}: a never-run line at {q:?} crosses a cut part",
                                d.stem
                            );
                        }
                    }
                }
            }
            // The bonded zones are still in the files, as data: one per labelled part.
            let labelled = labels_on_bonded_zones(example, method).0 > 0;
            assert!(
                !labelled || guides > 0,
                "{example} by {method}: no bonded-zone guide"
            );
        }
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
            // The model bonds the whole plate; method 1's bond parts are inset from its edge (docs/cam.md
            // §1): the inset strip is the only mass the drawing lacks, and the report's geometry mass is
            // the drawing's.
            let rows = r["layers"].as_array().unwrap();
            let row = |n: &str| rows.iter().find(|l| l["layer"] == n);
            let inset_mg = row("pyralux").map_or(0.0, |b| {
                let v = |l: &serde_json::Value, k: &str| l[k].as_f64().unwrap();
                (v(row("pzt").unwrap(), "part_area_mm2") - v(b, "part_area_mm2"))
                    * v(b, "thickness_mm")
                    * v(b, "density_kg_per_m3")
                    * v(b, "parts_per_actuator")
                    * 1e-3
            });
            assert!(
                ((drawn + inset_mg - model) / model).abs() < 1e-9,
                "{name} {label}: drawn {drawn} mg + bond inset {inset_mg} mg vs model {model} mg"
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

#[test]
fn each_pzt_sheet_has_a_snapping_order_picture_numbering_its_score_lines() {
    // Every example: one picture per PZT sheet, numbering each score line of the sheet's file once,
    // 1 to n, with nothing a laser follows (no stroke) and not at true size; the book names it.
    for design in ["thesis-C", "thesis-7", "thesis-C-method-1"] {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("out");
        let o = cut_sheet(&format!("examples/{design}.toml"), &out, &[]);
        assert!(o.status.success(), "{}", stderr(&o));
        let r = report_json(&out);
        let sheets = r["stock_list"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|s| s["material"].as_str().unwrap().starts_with("PZT"))
            .map(|s| s["sheets"].as_u64().unwrap())
            .sum::<u64>();
        assert!(sheets > 0);
        let book = r["build_book"].to_string();
        for n in 1..=sheets {
            let name = format!("preview-snap-order-pzt-{n}.svg");
            let guide = std::fs::read_to_string(out.join(&name)).unwrap();
            let pzt = std::fs::read_to_string(layer_file(&out, &format!("pzt-{n}.svg"))).unwrap();
            let lines = svg_paths(&pzt, "SCORE").len();
            assert!(lines > 0, "{design}: pzt-{n} has score lines");
            let numbers: Vec<usize> = guide
                .split("</text>")
                .filter_map(|t| t.rsplit('>').next().and_then(|n| n.parse().ok()))
                .collect();
            assert_eq!(numbers, (1..=lines).collect::<Vec<_>>(), "{design}: {name}");
            assert!(
                !guide.contains("stroke=\"#"),
                "{design}: {name} has a stroke"
            );
            assert!(guide.contains("drawn at 4:1") && guide.contains("not for cutting"));
            assert!(book.contains(&name), "{design}: the book names {name}");
        }
    }
}

/// The lines of an SVG's cut layer: what the laser cuts through.
fn cut_layer(svg: &str) -> &str {
    let start = svg.find("id=\"layer-cut\"").expect("a cut layer");
    let end = start + svg[start..].find("</g>").expect("the cut layer ends");
    &svg[start..end]
}

#[test]
fn identical_clamp_panels_share_one_file_cut_as_many_times() {
    // thesis-7 holds three actuators per panel: 20 of them fill panels 1-6 alike and leave two on
    // panel 7. Each clamp layer is one file for the run of six and one for the last panel, and the
    // stock list still counts a sheet per panel.
    let dir = tempfile::tempdir().unwrap();
    let (many, one) = (dir.path().join("many"), dir.path().join("one"));
    let o = cut_sheet(
        &example("thesis-7.toml"),
        &many,
        &["--quantity", "20", "--format", "svg"],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let o = cut_sheet(
        &example("thesis-7.toml"),
        &one,
        &["--quantity", "3", "--format", "svg"],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let names: Vec<String> = sheet_files(&many)
        .into_keys()
        .filter(|n| n.starts_with("mold-1-") || n.starts_with("felt-1-"))
        .collect();
    assert_eq!(
        names,
        [
            "felt-1-1to6.svg",
            "felt-1-7.svg",
            "mold-1-1to6.svg",
            "mold-1-7.svg"
        ]
    );
    let svg = |dir: &Path, name: &str| std::fs::read_to_string(layer_file(dir, name)).unwrap();
    let run = svg(&many, "mold-1-1to6.svg");
    assert!(run.contains("panels 1-6: cut 6 sheets"), "{run}");
    // The run's sheet cuts what one full panel cuts; the last panel cuts one cavity fewer.
    assert_eq!(cut_layer(&run), cut_layer(&svg(&one, "mold-1-1.svg")));
    assert_ne!(cut_layer(&run), cut_layer(&svg(&many, "mold-1-7.svg")));
    let report = report_json(&many);
    let felt: u64 = report["stock_list"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|s| s["material"] == "felt pad")
        .map(|s| s["sheets"].as_u64().unwrap())
        .sum();
    assert_eq!(felt, 14, "two felt pads on each of 7 panels");
    let book = std::fs::read_to_string(many.join("report.md")).unwrap();
    assert!(
        book.contains("`mold-1-1to6_ptfe-non-porous-0.127mm` (6 sheets)"),
        "the book says how many sheets a run's file cuts"
    );
}
