//! The files themselves: the layer files a process needs, identical bytes twice, streamed equal to
//! rendered, every page holding what is drawn, the preview uncuttable, shared clamp panel files.

use super::*;

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
