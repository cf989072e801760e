//! Parts nested with actuators: read back with their areas, cut along the sheet's fibres, on every ply at its
//! fibre angle, reported at their own base point, the same bytes twice.

use super::*;

#[test]
fn parts_from_a_dxf_and_an_svg_nest_with_actuators_and_read_back_with_their_areas() {
    // Kerf 0 on the prepreg: the cut paths are the drawn outlines, so the areas read back from the
    // files are the drawings' areas (closed forms above, within the flattening tolerance).
    let (dir, batch) = scratch(0.0, ITEMS, PARTS);
    let out = dir.path().join("out");
    nest_ok(&batch, &out, "60");
    let r = nest_report_json(&out);
    let parts = r["parts"].as_array().unwrap();
    assert_eq!(parts.len(), 2);
    assert_eq!(parts[0]["sheet"], "prepreg, layup 0/90/0");
    assert_eq!(parts[1]["sheet"], "prepreg, layup 0/0/90/0/0");
    // Every copy on a passive sheet of its layup.
    let sheets = r["sheets"].as_array().unwrap();
    let placed = |name: &str, layup: &str| -> usize {
        sheets
            .iter()
            .filter(|s| s["material"].as_str().unwrap().contains(layup))
            .flat_map(|s| s["parts"].as_array().unwrap())
            .filter(|p| p["design"] == name && p["part"] == "part")
            .count()
    };
    assert_eq!(placed("spar", "layup 0/90/0"), 5);
    assert_eq!(placed("flexure", "layup 0/0/90/0/0"), 4);
    let spar_tol = SPAR_ARCS_MM * TOLERANCE_MM + 1e-5;
    let flexure_tol = FLEXURE_ARCS_MM * TOLERANCE_MM + 1e-5;
    let (mut spars, mut flexures) = (0, 0);
    for s in sheets.iter().filter(|s| s["layer"] == "passive") {
        let stem = s["file_stem"].as_str().unwrap();
        let (w, h) = (
            s["width_mm"].as_f64().unwrap(),
            s["height_mm"].as_f64().unwrap(),
        );
        // DXF: material areas of the outlines, and the clearance between them.
        let rings = dxf_rings(&out.join(format!("{stem}.dxf")));
        let nets = net_areas(&rings);
        let areas: Vec<f64> = nets.iter().map(|(_, a)| *a).collect();
        spars += count_near(&areas, SPAR_AREA_MM2, spar_tol);
        flexures += count_near(&areas, FLEXURE_AREA_MM2, flexure_tol);
        let outers: Vec<&[[f64; 2]]> = nets.iter().map(|(i, _)| rings[*i].as_slice()).collect();
        assert_eq!(outers.len(), s["parts"].as_array().unwrap().len());
        // Kerf 0 and the template's 0.5 mm spacing: the outlines read back keep 0.5 mm apart and
        // from the sheet edge.
        let violations = clearance(&outers, w, h, Clearance::uniform(0.5), 1e-6);
        assert!(violations.is_empty(), "{stem}: {violations:?}");
        // SVG: the same outlines, read back from the other file.
        let svg = std::fs::read_to_string(out.join(format!("{stem}.svg"))).unwrap();
        let svg_rings: Vec<Vec<[f64; 2]>> = read_svg_polygons(&svg)
            .unwrap()
            .into_iter()
            .map(|(_, r)| r)
            .collect();
        let svg_areas: Vec<f64> = net_areas(&svg_rings).iter().map(|(_, a)| *a).collect();
        assert_eq!(
            count_near(&svg_areas, SPAR_AREA_MM2, spar_tol + 1e-4),
            count_near(&areas, SPAR_AREA_MM2, spar_tol),
            "{stem}"
        );
        assert_eq!(
            count_near(&svg_areas, FLEXURE_AREA_MM2, flexure_tol + 1e-4),
            count_near(&areas, FLEXURE_AREA_MM2, flexure_tol),
            "{stem}"
        );
    }
    assert_eq!((spars, flexures), (5, 4));
    // The markdown report lists them too.
    let md = std::fs::read_to_string(out.join("nest-report.md")).unwrap();
    assert!(md.contains("## Parts from drawings"));
    assert!(
        md.contains("| spar | 5 | prepreg, layup 0/90/0 | 90 | 0/180 |"),
        "{md}"
    );
}

#[test]
fn a_prepreg_part_is_cut_with_its_fibre_axis_along_the_sheets_fibres() {
    // The spar is drawn along x (60 x 4 mm). The sheet's 0° fibres run along its y axis, as the
    // actuators' passive parts lie. Declared with its fibres along its length (0° in the drawing),
    // every spar is cut standing along y; declared across (90°), lying along x. Rotations are the
    // default half turns, which keep the axis.
    for (axis, long_along_y) in [(0, true), (90, false)] {
        let parts = format!(
            "[[part]]\nfile = \"parts/spar.dxf\"\nquantity = 4\nlayup_deg = [0, 90, 0]\nfibre_axis_deg = {axis}\n"
        );
        let (dir, batch) = scratch(0.0, ITEMS, &parts);
        let out = dir.path().join("out");
        nest_ok(&batch, &out, "30");
        let r = nest_report_json(&out);
        assert_eq!(r["parts"][0]["fibre_axis_deg"], f64::from(axis));
        let boxes = spar_boxes(&out, &r);
        assert_eq!(boxes.len(), 4);
        // 60 mm of taper and the 1 mm radius of the round tip, 4 mm at the root.
        let expected = if long_along_y {
            [4.0, 61.0]
        } else {
            [61.0, 4.0]
        };
        for b in boxes {
            assert!(
                (b[0] - expected[0]).abs() < 0.01 && (b[1] - expected[1]).abs() < 0.01,
                "fibre axis {axis}°: a spar's box is {b:?} mm, expected {expected:?}"
            );
        }
    }
}

#[test]
fn a_prepreg_part_without_its_fibre_axis_is_refused_naming_the_field() {
    let (_dir, batch) = scratch(
        0.05,
        ITEMS,
        "[[part]]\nfile = \"parts/spar.dxf\"\nquantity = 1\nlayup_deg = [0, 90, 0]\n",
    );
    let err = refusal(&batch);
    assert!(err.contains("part[1].fibre_axis_deg"), "{err}");
    // On Pyralux (method 1) there are no fibres to declare.
    let dir = tempfile::tempdir().unwrap();
    std::fs::copy(
        example_path("thesis-C-method-1.toml"),
        dir.path().join("m1.toml"),
    )
    .unwrap();
    std::fs::write(dir.path().join("flexure.svg"), flexure_svg()).unwrap();
    let batch = dir.path().join("batch.toml");
    std::fs::write(
        &batch,
        "name = \"m1\"\n[[item]]\ndesign = \"m1.toml\"\nquantity = 2\n[[part]]\nfile = \"flexure.svg\"\nquantity = 1\nsheet = \"pyralux\"\nfibre_axis_deg = 0\n",
    )
    .unwrap();
    let err = refusal(&batch);
    assert!(
        err.contains("part[1].fibre_axis_deg") && err.contains("no fibres"),
        "{err}"
    );
}

#[test]
fn the_example_batches_with_parts_nest_and_are_deterministic() {
    // On sheets, and on a priced roll (the roll example: two layups, one strip each).
    for (name, rolls) in [("batch-with-parts.toml", 0), ("batch-roll.toml", 2)] {
        let dir = tempfile::tempdir().unwrap();
        let batch = example_path(name);
        let (a, b) = (dir.path().join("a"), dir.path().join("b"));
        for out in [&a, &b] {
            nest_ok(&batch, out, "40");
        }
        let (fa, fb) = (files(&a), files(&b));
        assert_eq!(fa.keys().collect::<Vec<_>>(), fb.keys().collect::<Vec<_>>());
        for (k, v) in &fa {
            if k.ends_with(".dxf") || k.ends_with(".svg") {
                assert_eq!(v, &fb[k], "{name}: {k} differs between two runs");
            }
        }
        let r = nest_report_json(&a);
        assert_eq!(r["parts"].as_array().unwrap().len(), 2, "{name}");
        let listed = r["rolls"].as_array().map_or(0, |v| v.len());
        assert_eq!(listed, rolls, "{name}");
    }
}

#[test]
fn prepreg_parts_cut_ply_by_ply_come_on_every_ply_at_its_fibre_angle() {
    // Spars (60 x 4 mm, drawn along x) on C's 0/90/0 and flexures (16 x 6 mm, along x) on A's
    // 0/0/90/0/0, both allowed 0/180 only. Kerf 0: the outlines read back are the drawn ones.
    let parts = "[[part]]\nfile = \"parts/spar.dxf\"\nquantity = 3\nlayup_deg = [0, 90, 0]\nfibre_axis_deg = 90\n\n\
                 [[part]]\nfile = \"parts/flexure.svg\"\nquantity = 2\nlayup_deg = [0, 0, 90, 0, 0]\nfibre_axis_deg = 90\n";
    let (dir, batch) = scratch_ply_by_ply(0.0, ITEMS, parts);
    let out = dir.path().join("out");
    nest_ok(&batch, &out, "40");
    let r = nest_report_json(&out);
    let rows = r["parts"].as_array().unwrap();
    assert_eq!(rows[0]["sheet"], "prepreg, layup 0/90/0, cut ply by ply");
    assert_eq!(rows[0]["pieces_per_part"], 3);
    assert_eq!(rows[1]["pieces_per_part"], 5);
    let spar_tol = SPAR_ARCS_MM * TOLERANCE_MM + 1e-5;
    let flexure_tol = FLEXURE_ARCS_MM * TOLERANCE_MM + 1e-5;
    // Per ply sheet of each layup (the material names the layup): spars and flexures read back
    // from the DXF, each with its long side along the sheet's x axis on a 0° ply (fibres along
    // the part) and along y on a 90° ply (fibres across it).
    let mut seen: Vec<(String, String, usize, usize)> = Vec::new();
    for s in r["sheets"].as_array().unwrap() {
        let layer = s["layer"].as_str().unwrap();
        if !layer.starts_with("passive-ply") {
            continue;
        }
        let across = layer.ends_with("-90deg");
        assert!(across || layer.ends_with("-0deg"), "{layer}");
        let stem = s["file_stem"].as_str().unwrap();
        let rings = dxf_rings(&out.join(format!("{stem}.dxf")));
        let nets = net_areas(&rings);
        let (mut spars, mut flexures) = (0, 0);
        for (i, a) in &nets {
            let [w, h] = box_size(&rings[*i]);
            let (long, short) = if across { (h, w) } else { (w, h) };
            if (a - SPAR_AREA_MM2).abs() <= spar_tol {
                spars += 1;
                assert!(
                    (long - 61.0).abs() < 1e-3 && (short - 4.0).abs() < 1e-3,
                    "{stem}: spar box {w} x {h}"
                );
            } else if (a - FLEXURE_AREA_MM2).abs() <= flexure_tol {
                flexures += 1;
                assert!(
                    (long - 16.0).abs() < 1e-3 && (short - 6.0).abs() < 1e-3,
                    "{stem}: flexure box {w} x {h}"
                );
            }
        }
        // Every outline read back is a part of the report, the clearance kept (kerf 0, 0.5 mm
        // spacing).
        let outers: Vec<&[[f64; 2]]> = nets.iter().map(|(i, _)| rings[*i].as_slice()).collect();
        assert_eq!(outers.len(), s["parts"].as_array().unwrap().len(), "{stem}");
        let (w, h) = (
            s["width_mm"].as_f64().unwrap(),
            s["height_mm"].as_f64().unwrap(),
        );
        let violations = clearance(&outers, w, h, Clearance::uniform(0.5), 1e-6);
        assert!(violations.is_empty(), "{stem}: {violations:?}");
        let listed = |name: &str| {
            s["parts"]
                .as_array()
                .unwrap()
                .iter()
                .filter(|p| p["design"] == name && p["part"] == "part")
                .count()
        };
        assert_eq!(
            (listed("spar"), listed("flexure")),
            (spars, flexures),
            "{stem}"
        );
        // Half turns only: the part's own rotations, on top of the ply's turn.
        for p in s["parts"].as_array().unwrap() {
            if p["part"] == "part" {
                let rot = p["rotation_deg"].as_f64().unwrap();
                assert!(rot == 0.0 || rot == 180.0, "{stem}: {rot}");
            }
        }
        seen.push((
            layer.to_string(),
            s["material"].as_str().unwrap().to_string(),
            spars,
            flexures,
        ));
    }
    // Each part on every ply of its layup, all its copies, and on no other sheet.
    let count = |layer: &str, layup: &str, which: usize| -> usize {
        seen.iter()
            .filter(|(l, m, _, _)| l == layer && m.contains(&format!("layup {layup}")))
            .map(|(_, _, s, f)| if which == 0 { *s } else { *f })
            .sum()
    };
    for layer in [
        "passive-ply1-0deg",
        "passive-ply2-90deg",
        "passive-ply3-0deg",
    ] {
        assert_eq!(count(layer, "0/90/0", 0), 3, "{layer}");
    }
    for layer in [
        "passive-ply1-0deg",
        "passive-ply2-0deg",
        "passive-ply3-90deg",
        "passive-ply4-0deg",
        "passive-ply5-0deg",
    ] {
        assert_eq!(count(layer, "0/0/90/0/0", 1), 2, "{layer}");
    }
    let total = |which: usize| -> usize {
        seen.iter()
            .map(|(_, _, s, f)| if which == 0 { *s } else { *f })
            .sum()
    };
    assert_eq!((total(0), total(1)), (3 * 3, 2 * 5));
}

#[test]
fn ply_by_ply_refuses_part_rotations_that_turn_the_fibres() {
    // PARTS lets the flexure take quarter turns: pieces of one ply could then come out with their
    // fibres turned and another ply's not.
    let (_dir, batch) = scratch_ply_by_ply(0.05, ITEMS, PARTS);
    let err = refusal(&batch);
    assert!(
        err.contains(&batch.display().to_string())
            && err.contains("part[2].rotations_deg = [0.0, 90.0, 180.0, 270.0]")
            && err.contains("all equal modulo 180 degrees"),
        "{err}"
    );
    // A part drawn across its fibres may say so: [90, 270] is one fibre direction.
    let sideways = PARTS.replace("[0, 90, 180, 270]", "[90, 270]");
    let (dir, batch) = scratch_ply_by_ply(0.05, ITEMS, &sideways);
    let out = dir.path().join("out");
    let o = run(&[
        "nest",
        batch.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--iterations",
        "20",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let r = nest_report_json(&out);
    for s in r["sheets"].as_array().unwrap() {
        for p in s["parts"].as_array().unwrap() {
            if p["design"] == "flexure" {
                let rot = p["rotation_deg"].as_f64().unwrap();
                assert!(rot == 90.0 || rot == 270.0, "{rot}");
            }
        }
    }
}

#[test]
fn an_extra_part_is_reported_at_its_own_base_point_on_the_sheet() {
    // A part reported at its drawing's origin would put flexures drawn away from it at y = -1.64 mm, off
    // the sheet. The base point is the centre of the part's bounding box: on the part's sheet, whatever
    // the drawing's origin, and at the centre of the placed outline.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = bin()
        .args(["nest", "examples/batch-with-parts.toml", "-o"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let r: serde_json::Value = nest_report_json(&out);
    let extra: Vec<String> = r["parts"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["name"].as_str().unwrap().to_string())
        .collect();
    assert!(!extra.is_empty());
    let mut seen = 0;
    for sheet in r["sheets"].as_array().unwrap() {
        let (w, h) = (
            sheet["width_mm"].as_f64().unwrap(),
            sheet["height_mm"].as_f64().unwrap(),
        );
        for p in sheet["parts"].as_array().unwrap() {
            if !extra.iter().any(|n| p["design"] == n.as_str()) {
                continue;
            }
            seen += 1;
            let (x, y) = (p["x_mm"].as_f64().unwrap(), p["y_mm"].as_f64().unwrap());
            assert!(
                (0.0..=w).contains(&x) && (0.0..=h).contains(&y),
                "{} at ({x}, {y}) is off its {w} x {h} mm sheet",
                p["design"]
            );
        }
    }
    assert!(seen > 0, "no extra part on any sheet");
}
