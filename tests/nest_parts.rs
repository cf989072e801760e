//! Extra parts from DXF and SVG drawings nested with actuators, roll stock (`strip = true`) and the nest
//! progress: the layouts are checked again from the files written (areas read back against closed forms,
//! clearance between the outlines), every kind of bad drawing is refused in one line naming the file and the
//! entity.

use crate::common;
use actuator_cam::{
    plan_nest_observed as plan_observed, Batch, NestObserver, NestOptions, Planned,
    FLATTEN_TOLERANCE_MM as TOLERANCE_MM,
};
use cam_nest::{clearance, Clearance, NestProgress};
use common::svg_read::read_svg_polygons;
use common::*;
use geo::{Contains, Coord};
use std::cell::RefCell;
use std::f64::consts::PI;
use std::path::{Path, PathBuf};

// ---- The example drawings, generated here so that they are reproducible ----------------------

/// One DXF entity's group codes.
fn codes(pairs: &[(i32, String)]) -> String {
    pairs
        .iter()
        .map(|(c, v)| format!("{c:>3}\n{v}\n"))
        .collect()
}

/// A minimal R2000 DXF: header with `$INSUNITS` (none when `None`), then the entities.
pub(crate) fn dxf_text(insunits: Option<i32>, entities: &[String]) -> String {
    let mut header = vec![
        (0, "SECTION".to_string()),
        (2, "HEADER".into()),
        (9, "$ACADVER".into()),
        (1, "AC1015".into()),
    ];
    if let Some(u) = insunits {
        header.extend([(9, "$INSUNITS".to_string()), (70, u.to_string())]);
    }
    header.extend([
        (0, "ENDSEC".to_string()),
        (0, "SECTION".into()),
        (2, "ENTITIES".into()),
    ]);
    let mut text = codes(&header);
    for e in entities {
        text.push_str(e);
    }
    text + &codes(&[(0, "ENDSEC".into()), (0, "EOF".into())])
}

/// A LWPOLYLINE of `(x, y, bulge)` vertices.
pub(crate) fn lwpolyline(handle: &str, vertices: &[(f64, f64, f64)], closed: bool) -> String {
    let mut pairs = vec![
        (0, "LWPOLYLINE".to_string()),
        (5, handle.into()),
        (100, "AcDbEntity".into()),
        (8, "PARTS".into()),
        (100, "AcDbPolyline".into()),
        (90, vertices.len().to_string()),
        (70, if closed { "1" } else { "0" }.into()),
    ];
    for (x, y, b) in vertices {
        pairs.extend([(10, x.to_string()), (20, y.to_string())]);
        if *b != 0.0 {
            pairs.push((42, b.to_string()));
        }
    }
    codes(&pairs)
}

pub(crate) fn circle(handle: &str, c: [f64; 2], r: f64) -> String {
    codes(&[
        (0, "CIRCLE".into()),
        (5, handle.into()),
        (100, "AcDbEntity".into()),
        (8, "PARTS".into()),
        (100, "AcDbCircle".into()),
        (10, c[0].to_string()),
        (20, c[1].to_string()),
        (30, "0".into()),
        (40, r.to_string()),
    ])
}

fn line(handle: &str, a: [f64; 2], b: [f64; 2]) -> String {
    codes(&[
        (0, "LINE".into()),
        (5, handle.into()),
        (100, "AcDbEntity".into()),
        (8, "PARTS".into()),
        (100, "AcDbLine".into()),
        (10, a[0].to_string()),
        (20, a[1].to_string()),
        (30, "0".into()),
        (11, b[0].to_string()),
        (21, b[1].to_string()),
        (31, "0".into()),
    ])
}

fn arc(handle: &str, c: [f64; 2], r: f64, start_deg: f64, end_deg: f64) -> String {
    codes(&[
        (0, "ARC".into()),
        (5, handle.into()),
        (100, "AcDbEntity".into()),
        (8, "PARTS".into()),
        (100, "AcDbCircle".into()),
        (10, c[0].to_string()),
        (20, c[1].to_string()),
        (30, "0".into()),
        (40, r.to_string()),
        (100, "AcDbArc".into()),
        (50, start_deg.to_string()),
        (51, end_deg.to_string()),
    ])
}

fn text_entity(handle: &str) -> String {
    codes(&[
        (0, "TEXT".into()),
        (5, handle.into()),
        (100, "AcDbEntity".into()),
        (8, "NOTES".into()),
        (100, "AcDbText".into()),
        (10, "0".into()),
        (20, "0".into()),
        (30, "0".into()),
        (40, "2".into()),
        (1, "spar".into()),
    ])
}

/// The wing spar: 60 mm long, 4 mm wide at the root tapering to 2 mm, a round tip (a bulge of 1:
/// a half circle of radius 1), a 1.5 mm pin hole 4 mm from the root.
fn spar_dxf() -> String {
    dxf_text(
        Some(4),
        &[
            lwpolyline(
                "A1",
                &[
                    (0.0, -2.0, 0.0),
                    (60.0, -1.0, 1.0),
                    (60.0, 1.0, 0.0),
                    (0.0, 2.0, 0.0),
                ],
                true,
            ),
            circle("A2", [4.0, 0.0], 0.75),
        ],
    )
}

/// Closed form of the spar (independent of the importer): trapezoid 60 x (4 + 2) / 2, plus the half
/// disc of the tip, less the hole; and the length of its arcs (what flattening may lose).
const SPAR_AREA_MM2: f64 = 180.0 + PI / 2.0 - PI * 0.75 * 0.75;
const SPAR_ARCS_MM: f64 = PI + 2.0 * PI * 0.75;

/// The flexure: a 16 x 6 mm plate with 1 mm corner radii and a 6 x 1 mm slot with round ends,
/// drawn in a 20 x 10 mm page whose viewBox is in tenths of a millimetre, inside a group moved
/// by a transform.
fn flexure_svg() -> String {
    r#"<?xml version="1.0" encoding="UTF-8"?>
<svg xmlns="http://www.w3.org/2000/svg" width="20mm" height="10mm" viewBox="0 0 200 100">
  <title>flexure with a slot</title>
  <g id="flexure-part" transform="translate(20 20) scale(10)">
    <rect id="flexure" x="0" y="0" width="16" height="6" rx="1"/>
    <path id="slot" d="M 5 2.5 H 11 A 0.5 0.5 0 0 1 11 3.5 H 5 A 0.5 0.5 0 0 1 5 2.5 Z"/>
  </g>
</svg>
"#
    .to_string()
}

/// Closed form of the flexure: 16 x 6 less the four corners' (1 - π/4) r², less the slot
/// (6 x 1 plus a disc of 0.5).
const FLEXURE_AREA_MM2: f64 = 96.0 - (4.0 - PI) - (6.0 + PI * 0.25);
const FLEXURE_ARCS_MM: f64 = 2.0 * PI + PI;

#[test]
fn example_drawings_match_their_generator() {
    // EXAMPLES_UPDATE=1 writes them; otherwise the shipped files must be what this file makes.
    for (name, text) in [("spar.dxf", spar_dxf()), ("flexure.svg", flexure_svg())] {
        let path = example_path(&format!("parts/{name}"));
        if std::env::var_os("EXAMPLES_UPDATE").is_some() {
            std::fs::write(&path, &text).unwrap();
        }
        assert_eq!(
            std::fs::read_to_string(&path).unwrap(),
            text,
            "{name}: regenerate with EXAMPLES_UPDATE=1"
        );
    }
}

#[test]
fn imported_areas_match_the_closed_forms() {
    let spar = actuator_cam::import_parts(&example_path("parts/spar.dxf")).unwrap();
    assert_eq!(spar.len(), 1);
    assert_eq!(spar[0].holes.len(), 1);
    assert_eq!(spar[0].entity, "LWPOLYLINE handle A1");
    let err = (spar[0].area_mm2() - SPAR_AREA_MM2).abs();
    assert!(err <= SPAR_ARCS_MM * TOLERANCE_MM, "spar area off by {err}");
    let flexure = actuator_cam::import_parts(&example_path("parts/flexure.svg")).unwrap();
    assert_eq!(flexure.len(), 1);
    assert_eq!(flexure[0].holes.len(), 1);
    assert_eq!(flexure[0].entity, "<rect id=\"flexure\">");
    let err = (flexure[0].area_mm2() - FLEXURE_AREA_MM2).abs();
    assert!(
        err <= FLEXURE_ARCS_MM * TOLERANCE_MM,
        "flexure area off by {err}"
    );
    // The group's translate(20 20) in tenths of a mm and the y flip: 2 mm in, 10 - 2 mm down.
    let xs = flexure[0].outer.iter().map(|p| p[0]);
    let ys = flexure[0].outer.iter().map(|p| p[1]);
    assert!((xs.clone().fold(f64::INFINITY, f64::min) - 2.0).abs() < 1e-9);
    assert!((xs.fold(0.0, f64::max) - 18.0).abs() < 1e-9);
    assert!((ys.fold(0.0, f64::max) - 8.0).abs() < 1e-9);
}

#[test]
fn lines_and_arcs_chain_into_the_same_part_as_a_polyline_with_a_bulge() {
    // The spar drawn as LINE + ARC + LINE + LINE in scrambled order and direction.
    let text = dxf_text(
        Some(4),
        &[
            line("B1", [0.0, 2.0], [60.0, 1.0]),
            arc("B2", [60.0, 0.0], 1.0, -90.0, 90.0),
            line("B3", [0.0, -2.0], [0.0, 2.0]),
            line("B4", [60.0, -1.0], [0.0, -2.0]),
            circle("B5", [4.0, 0.0], 0.75),
            text_entity("B6"),
        ],
    );
    let (_dir, path) = write_temp("chained.dxf", &text);
    let parts = actuator_cam::import_parts(&path).unwrap();
    assert_eq!(parts.len(), 1);
    let err = (parts[0].area_mm2() - SPAR_AREA_MM2).abs();
    assert!(err <= SPAR_ARCS_MM * TOLERANCE_MM, "off by {err}");
}

// ---- Batches in a scratch folder ------------------------------------------------------------

/// A scratch folder with thesis C and A built by a method-2 template whose prepreg kerf is
/// `kerf_mm`, the example drawings, and `batch.toml` = the designs plus `tail`.
fn scratch(kerf_mm: f64, items: &str, tail: &str) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let template = shipped_template("method-2.toml");
    // The passive layer's kerf only: the [layers.passive] table's kerf_mm line.
    let mut out = String::new();
    let mut in_passive = false;
    for l in template.lines() {
        if l.starts_with('[') {
            in_passive = l.trim() == "[layers.passive]";
        }
        if in_passive && l.starts_with("kerf_mm") {
            out.push_str(&format!("kerf_mm = {kerf_mm}\n"));
        } else {
            out.push_str(l);
            out.push('\n');
        }
    }
    std::fs::write(d.join("process.toml"), out).unwrap();
    for name in ["thesis-C", "thesis-A"] {
        let text = std::fs::read_to_string(example_path(&format!("{name}.toml")))
            .unwrap()
            .replace(
                "process = \"method-2\"",
                &format!("process = \"{}\"", d.join("process.toml").display()),
            );
        std::fs::write(d.join(format!("{name}.toml")), text).unwrap();
    }
    std::fs::create_dir(d.join("parts")).unwrap();
    std::fs::write(d.join("parts/spar.dxf"), spar_dxf()).unwrap();
    std::fs::write(d.join("parts/flexure.svg"), flexure_svg()).unwrap();
    let batch = d.join("batch.toml");
    std::fs::write(
        &batch,
        format!("name = \"parts\"\nseed = 3\n{items}\n{tail}\n"),
    )
    .unwrap();
    (dir, batch)
}

const ITEMS: &str = "[[item]]\ndesign = \"thesis-C.toml\"\nquantity = 6\n\n[[item]]\ndesign = \"thesis-A.toml\"\nquantity = 3\n";

const PARTS: &str = "[[part]]\nfile = \"parts/spar.dxf\"\nquantity = 5\nlayup_deg = [0, 90, 0]\nfibre_axis_deg = 90\n\n[[part]]\nfile = \"parts/flexure.svg\"\nquantity = 4\nsheet = \"prepreg\"\nlayup_deg = [0, 0, 90, 0, 0]\nfibre_axis_deg = 90\nrotations_deg = [0, 90, 180, 270]\n";

/// Run `nest` on `batch` into a new folder beside it; it must be refused in one line with nothing
/// written. Returns the line.
fn refusal(batch: &Path) -> String {
    let out = batch.with_file_name("out");
    let o = run(&["nest", batch.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    assert!(!o.status.success());
    assert!(!out.exists(), "nothing is written");
    let err = stderr(&o);
    assert_eq!(err.trim_end().lines().count(), 1, "one line: {err}");
    err
}

/// Nest `batch` into `out` with an iteration budget, writing SVG and DXF; it must succeed.
fn nest_ok(batch: &Path, out: &Path, iterations: &str) -> std::process::Output {
    let o = run(&[
        "nest",
        batch.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--iterations",
        iterations,
        "--format",
        "svg,dxf",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    o
}

/// Closed rings of the DXF's LWPOLYLINEs on the cut layer.
fn dxf_rings(path: &Path) -> Vec<Vec<[f64; 2]>> {
    let drawing = dxf::Drawing::load_file(path).unwrap();
    drawing
        .entities()
        .filter_map(|e| match &e.specific {
            dxf::entities::EntityType::LwPolyline(p)
                if p.is_closed() && e.common.layer == "CUT" =>
            {
                Some(p.vertices.iter().map(|v| [v.x, v.y]).collect())
            }
            _ => None,
        })
        .collect()
}

/// Each outer ring (inside no other) with its material area: its area less the rings inside it.
fn net_areas(rings: &[Vec<[f64; 2]>]) -> Vec<(usize, f64)> {
    let polys: Vec<_> = rings.iter().map(|r| polygon(r)).collect();
    let inside = |i: usize, j: usize| {
        i != j
            && polys[j].contains(&Coord {
                x: rings[i][0][0],
                y: rings[i][0][1],
            })
    };
    (0..rings.len())
        .filter(|&i| (0..rings.len()).all(|j| !inside(i, j)))
        .map(|i| {
            let holes: f64 = (0..rings.len())
                .filter(|&k| inside(k, i))
                .map(|k| area(&rings[k]))
                .sum();
            (i, area(&rings[i]) - holes)
        })
        .collect()
}

fn count_near(areas: &[f64], target: f64, tol: f64) -> usize {
    areas.iter().filter(|a| (*a - target).abs() <= tol).count()
}

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

/// Width and height of the bounding box of the spar outlines (by area) on the passive sheets.
fn spar_boxes(out: &Path, r: &serde_json::Value) -> Vec<[f64; 2]> {
    let tol = SPAR_ARCS_MM * TOLERANCE_MM + 1e-5;
    let mut boxes = Vec::new();
    for s in r["sheets"].as_array().unwrap() {
        if s["layer"] != "passive" {
            continue;
        }
        let rings = dxf_rings(&out.join(format!("{}.dxf", s["file_stem"].as_str().unwrap())));
        for (i, a) in net_areas(&rings) {
            if (a - SPAR_AREA_MM2).abs() <= tol {
                boxes.push(box_size(&rings[i]));
            }
        }
    }
    boxes
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
fn a_roll_nests_one_strip_and_reports_its_used_length() {
    let tail = "[sheets]\nprepreg = { width_mm = 80, strip = true }\n";
    let (dir, batch) = scratch(0.05, ITEMS, &format!("{PARTS}\n{tail}"));
    let out = dir.path().join("out");
    let o = nest_ok(&batch, &out, "60");
    let r = nest_report_json(&out);
    let passive: Vec<&serde_json::Value> = r["sheets"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|s| s["layer"] == "passive")
        .collect();
    // One strip per layup, each the roll's width, as long as it was used.
    assert_eq!(passive.len(), 2);
    for (s, b) in passive.iter().zip(r["baseline"].as_array().unwrap()) {
        assert_eq!(s["roll"], true);
        assert_eq!(s["width_mm"], 80.0);
        let length = s["height_mm"].as_f64().unwrap();
        assert_eq!(b["strip_length_mm"].as_f64().unwrap(), length);
        // At least the part area over the width, at most the bounding-box baseline's length
        // plus the 0.1 mm rounding.
        let part_area: f64 = s["utilization"].as_f64().unwrap() * 80.0 * length;
        assert!(length >= part_area / 80.0);
        assert!(length <= b["baseline_strip_length_mm"].as_f64().unwrap() + 0.1);
        // The drawing is the used strip: the SVG page and the DXF extents.
        let stem = s["file_stem"].as_str().unwrap();
        let svg = std::fs::read_to_string(out.join(format!("{stem}.svg"))).unwrap();
        assert!(
            svg.contains(&format!("height=\"{}mm\"", actuator_cam::fmt_mm(length))),
            "{stem}: {}",
            &svg[..300.min(svg.len())]
        );
        let rings = dxf_rings(&out.join(format!("{stem}.dxf")));
        let top = rings.iter().flatten().map(|p| p[1]).fold(0.0, f64::max);
        assert!(
            top <= length && top > length - 5.0,
            "top {top}, length {length}"
        );
    }
    let md = std::fs::read_to_string(out.join("nest-report.md")).unwrap();
    assert!(md.contains("is a strip of roll stock 80 mm wide"), "{md}");
    assert!(stdout(&o).contains("mm of roll"), "{}", stdout(&o));
}

#[test]
fn a_priced_roll_reports_its_cost_beside_the_same_parts_on_cut_sheets() {
    // 80 mm roll at 47.5 per metre, compared with 80 x 60 mm sheets at 3.25 each.
    let tail = "[sheets]\nprepreg = { width_mm = 80, strip = true, price_per_m = 47.5, \
                compare_with = { width_mm = 80, height_mm = 60, price_per_sheet = 3.25 } }\n";
    let (dir, batch) = scratch(0.05, ITEMS, &format!("{PARTS}\n{tail}"));
    let out = dir.path().join("out");
    let o = nest_ok(&batch, &out, "40");
    let r = nest_report_json(&out);
    let sheets = r["sheets"].as_array().unwrap();
    let rolls = r["rolls"].as_array().unwrap();
    assert_eq!(rolls.len(), 2, "one strip per layup");
    // The summary line on stdout gives each roll's cost (its length times the batch's 47.5 per
    // metre, recomputed here) beside the sheets it is compared with and their cost (3.25 each).
    let line = stdout(&o);
    for roll in rolls {
        let length = roll["length_mm"].as_f64().unwrap();
        let n = roll["on_sheets"]["sheets"].as_u64().unwrap();
        let expected = format!(
            "passive roll {length:.1} mm at 47.50/m costs {:.2} (instead {n} sheet(s) of 80 x 60 mm, {:.2})",
            length / 1000.0 * 47.5,
            3.25 * n as f64
        );
        assert!(line.contains(&expected), "{expected:?} not in {line}");
    }
    let mut roll_total = 0.0;
    for roll in rolls {
        let stem = roll["file_stem"].as_str().unwrap();
        let sheet = sheets.iter().find(|s| s["file_stem"] == stem).unwrap();
        // The length priced is the strip as drawn: the sheet row and the SVG page.
        let length = roll["length_mm"].as_f64().unwrap();
        assert_eq!(sheet["height_mm"].as_f64().unwrap(), length);
        let svg = std::fs::read_to_string(out.join(format!("{stem}.svg"))).unwrap();
        assert!(svg.contains(&format!("height=\"{}mm\"", actuator_cam::fmt_mm(length))));
        assert_eq!(roll["width_mm"], 80.0);
        assert_eq!(roll["price_per_m"], 47.5);
        let cost = roll["cost"].as_f64().unwrap();
        assert!(
            (cost - length / 1000.0 * 47.5).abs() < 1e-12,
            "{cost} for {length} mm"
        );
        roll_total += cost;
        // The same parts on 80 x 60 mm sheets: at least their area's worth of sheets (part area
        // from the strip's utilisation), at most one sheet per part.
        let alt = &roll["on_sheets"];
        assert_eq!(
            (alt["width_mm"].as_f64(), alt["height_mm"].as_f64()),
            (Some(80.0), Some(60.0))
        );
        let n = alt["sheets"].as_u64().unwrap() as f64;
        let part_area = sheet["utilization"].as_f64().unwrap() * 80.0 * length;
        assert!(n >= (part_area / (80.0 * 60.0)).ceil(), "{n} sheets");
        assert!(n <= sheet["parts"].as_array().unwrap().len() as f64);
        assert_eq!(alt["cost"].as_f64().unwrap(), 3.25 * n);
        // The material the roll's strip is of, in the totals.
        let total = r["totals"]
            .as_array()
            .unwrap()
            .iter()
            .find(|t| t["material"] == roll["material"])
            .unwrap();
        assert_eq!(total["roll_length_mm"].as_f64().unwrap(), length);
        assert_eq!(total["cost"].as_f64().unwrap(), cost);
    }
    // Nothing else is priced: the batch's cost is the roll's.
    assert!((r["total_cost"].as_f64().unwrap() - roll_total).abs() < 1e-12);
    let md = std::fs::read_to_string(out.join("nest-report.md")).unwrap();
    assert!(md.contains("## Roll stock against cut sheets"), "{md}");
    let first = &rolls[0];
    assert!(
        md.contains(&format!(
            "| `{}` | {} | 80 | {:.1} | 47.50 | {:.2} | 80 x 60 mm: {} | {:.2} |",
            first["file_stem"].as_str().unwrap(),
            first["material"].as_str().unwrap(),
            first["length_mm"].as_f64().unwrap(),
            first["cost"].as_f64().unwrap(),
            first["on_sheets"]["sheets"],
            first["on_sheets"]["cost"].as_f64().unwrap()
        )),
        "{md}"
    );
}

#[test]
fn a_roll_without_compare_with_is_compared_with_the_template_sheet() {
    // The scratch template's prepreg sheet is 150 x 150 mm with no price: the sheets are counted,
    // their cost is unknown. An unpriced roll has no comparison and no cost.
    let tail = "[sheets]\nprepreg = { width_mm = 80, strip = true, price_per_m = 40 }\n";
    let (dir, batch) = scratch(0.05, ITEMS, &format!("{PARTS}\n{tail}"));
    let out = dir.path().join("out");
    nest_ok(&batch, &out, "20");
    let r = nest_report_json(&out);
    for roll in r["rolls"].as_array().unwrap() {
        let alt = &roll["on_sheets"];
        assert_eq!(
            (alt["width_mm"].as_f64(), alt["height_mm"].as_f64()),
            (Some(150.0), Some(150.0))
        );
        assert!(alt["sheets"].as_u64().unwrap() >= 1);
        assert!(alt["cost"].is_null() && alt["price_per_sheet"].is_null());
    }
    let tail = "[sheets]\nprepreg = { width_mm = 80, strip = true }\n";
    let (dir, batch) = scratch(0.05, ITEMS, &format!("{PARTS}\n{tail}"));
    let out = dir.path().join("out");
    nest_ok(&batch, &out, "20");
    let r = nest_report_json(&out);
    for roll in r["rolls"].as_array().unwrap() {
        assert!(
            roll["cost"].is_null() && roll["on_sheets"].is_null(),
            "{roll}"
        );
        assert!(roll["length_mm"].as_f64().unwrap() > 0.0);
    }
    assert!(r["total_cost"].is_null());
}

#[test]
fn bad_roll_prices_are_refused_in_one_line() {
    let cases = [
        (
            "prepreg = { width_mm = 80, strip = true, price_per_m = -1 }",
            "sheets.prepreg.price_per_m = -1: outside the allowed range [0, 1000000000] per m",
        ),
        (
            "prepreg = { width_mm = 80, strip = true, price_per_m = nan }",
            "sheets.prepreg.price_per_m = NaN: outside the allowed range [0, 1000000000] per m",
        ),
        (
            "prepreg = { width_mm = 80, strip = true, price_per_sheet = 3 }",
            "sheets.prepreg.price_per_sheet = (given): a roll (strip = true) is priced by its length: price_per_m",
        ),
        (
            "prepreg = { width_mm = 80, strip = true, compare_with = { width_mm = 80, height_mm = 60 } }",
            "sheets.prepreg.compare_with = (given): the sheet comparison is of costs: give the roll's price_per_m too",
        ),
        (
            "prepreg = { width_mm = 80, height_mm = 80, price_per_m = 3 }",
            "sheets.prepreg.price_per_m = (given): only roll stock (strip = true) is priced by the metre",
        ),
        (
            "prepreg = { width_mm = 80, strip = true, price_per_m = 3, compare_with = { width_mm = 80, height_mm = 0 } }",
            "sheets.prepreg.compare_with.height_mm = 0: outside the allowed range [1, 2000] mm",
        ),
        (
            "prepreg = { width_mm = 80, strip = true, price_per_m = 3, compare_with = { width_mm = 80, height_mm = 60, price_per_m = 2 } }",
            "sheets.prepreg.compare_with.price_per_m = 2: unknown key",
        ),
    ];
    for (line, want) in cases {
        let (_dir, batch) = scratch(0.05, ITEMS, &format!("[sheets]\n{line}\n"));
        let err = refusal(&batch);
        assert!(
            err.starts_with(&format!("error: {}: {want}", batch.display())),
            "{line}: {err}"
        );
    }
}

// ---- Ply-by-ply cutting ----------------------------------------------------------------------

/// [`scratch`] with the prepreg cut ply by ply, and 2 mm base tabs on the designs (room for the
/// actuators' registration holes).
fn scratch_ply_by_ply(kerf_mm: f64, items: &str, tail: &str) -> (tempfile::TempDir, PathBuf) {
    let (dir, batch) = scratch(kerf_mm, items, tail);
    let d = dir.path();
    let edit = |name: &str, from: &str, to: &str| {
        let text = std::fs::read_to_string(d.join(name)).unwrap();
        assert!(text.contains(from), "{name}: {from}");
        std::fs::write(d.join(name), text.replace(from, to)).unwrap();
    };
    edit(
        "process.toml",
        "passive_cut = \"stack\"",
        "passive_cut = \"ply-by-ply\"",
    );
    for name in ["thesis-C.toml", "thesis-A.toml"] {
        edit(name, "base_tab_mm = 0.0", "base_tab_mm = 2.0");
    }
    (dir, batch)
}

/// The box of a ring: width, height.
fn box_size(ring: &[[f64; 2]]) -> [f64; 2] {
    let (xs, ys) = (ring.iter().map(|p| p[0]), ring.iter().map(|p| p[1]));
    [
        xs.clone().fold(f64::MIN, f64::max) - xs.fold(f64::MAX, f64::min),
        ys.clone().fold(f64::MIN, f64::max) - ys.fold(f64::MAX, f64::min),
    ]
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

// ---- Progress ---------------------------------------------------------------------------------

#[derive(Default)]
struct Recorder {
    layers: RefCell<Vec<(usize, usize, String, usize)>>,
    reports: RefCell<Vec<(usize, NestProgress)>>,
}

impl NestObserver for Recorder {
    fn layer(&self, index: usize, count: usize, layer: &str, parts: usize) {
        self.layers
            .borrow_mut()
            .push((index, count, layer.to_string(), parts));
    }
    fn progress(&self, p: &NestProgress) {
        let layer = self.layers.borrow().len();
        self.reports.borrow_mut().push((layer, *p));
    }
}

/// An example batch planned (seed 1, `iterations`) with a recorder listening.
fn observed(example: &str, iterations: usize) -> (Planned, Recorder) {
    let batch = Batch::load(&example_path(example)).unwrap();
    let opts = NestOptions::budget(1, iterations);
    let recorder = Recorder::default();
    let planned = plan_observed(&batch, &opts, &recorder).unwrap();
    (planned, recorder)
}

#[test]
fn the_observer_sees_every_job_its_sheets_and_the_best_density() {
    let (planned, recorder) = observed("batch.toml", 100);
    let layers = recorder.layers.borrow();
    // The example batch has two layups: two passive layers, nested one after the other.
    assert_eq!(
        layers
            .iter()
            .map(|l| (l.0, l.1, l.2.as_str()))
            .collect::<Vec<_>>(),
        vec![(0, 2, "passive"), (1, 2, "passive")]
    );
    // Parts per job: one passive part per actuator of its layup (C, B: 16; A, 1: 8).
    assert_eq!(layers.iter().map(|l| l.3).collect::<Vec<_>>(), vec![16, 8]);
    let reports = recorder.reports.borrow();
    for job in 1..=2 {
        let mine: Vec<&NestProgress> = reports
            .iter()
            .filter(|(l, _)| *l == job)
            .map(|(_, p)| p)
            .collect();
        assert!(!mine.is_empty(), "job {job} reported nothing");
        for p in &mine {
            assert!(p.sheets >= p.sheets_lower_bound && p.sheets_lower_bound >= 1);
            assert!(p.best_density > 0.0 && p.best_density <= 1.0);
        }
        let last = mine.last().unwrap();
        assert!(last.finished);
        // The last report is the layout drawn: its density is the report's used-length one (to
        // 1e-6: the engine measures its snapshot on its own copy of the placed outlines).
        let row = &planned.report.baseline[job - 1];
        assert!(
            (last.best_density - row.used_length_utilization).abs() < 1e-6,
            "{last:?} {row:?}"
        );
        assert_eq!(last.sheets, row.sheets);
    }
}

#[test]
fn the_cost_comparison_nests_count_on_after_the_roll_jobs() {
    // examples/batch-roll.toml: two layups on a priced roll, each compared with cut sheets; the
    // comparison nests are jobs 3 and 4 of 4, not a second count from 1.
    let (planned, recorder) = observed("batch-roll.toml", 20);
    let layers = recorder.layers.borrow();
    let jobs: Vec<(usize, usize)> = layers.iter().map(|l| (l.0, l.1)).collect();
    assert_eq!(jobs, vec![(0, 2), (1, 2), (2, 4), (3, 4)]);
    assert_eq!(planned.report.rolls.len(), 2);
    for (l, roll) in layers[2..].iter().zip(&planned.report.rolls) {
        assert_eq!(
            l.2,
            format!("{} on 150 x 150 mm sheets instead of the roll", roll.layer)
        );
    }
    // Each comparison job reports its own nest, ending finished.
    let reports = recorder.reports.borrow();
    for job in 3..=4 {
        let last = reports.iter().rev().find(|(l, _)| *l == job).unwrap().1;
        assert!(last.finished, "{last:?}");
    }
}

#[test]
fn a_piped_run_prints_no_progress() {
    // The roll batch too: its cost comparison nests are jobs of the same (silent) run.
    for example in ["batch.toml", "batch-roll.toml"] {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("out");
        let o = run(&[
            "nest",
            example_path(example).to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--iterations",
            "30",
        ]);
        assert!(o.status.success(), "{example}: {}", stderr(&o));
        assert_eq!(
            stderr(&o),
            "",
            "{example}: stderr is not a terminal: nothing on it"
        );
    }
}

// ---- Bad drawings -----------------------------------------------------------------------------

/// Run a batch of thesis C with one extra part from `name` (text `drawing`), expect a refusal.
pub(crate) fn refused(name: &str, drawing: &str, part_extra: &str) -> String {
    let (dir, batch) = scratch(
        0.05,
        "[[item]]\ndesign = \"thesis-C.toml\"\nquantity = 2\n",
        &format!(
            "[[part]]\nfile = \"parts/{name}\"\nquantity = 1\nlayup_deg = [0, 90, 0]\nfibre_axis_deg = 90\n{part_extra}"
        ),
    );
    std::fs::write(dir.path().join("parts").join(name), drawing).unwrap();
    let err = refusal(&batch);
    let file = dir.path().join("parts").join(name);
    assert!(err.contains(&file.display().to_string()), "{err}");
    err
}

pub(crate) fn svg(width: &str, height: &str, view_box: &str, body: &str) -> String {
    format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{width}\" height=\"{height}\"{view_box}>{body}</svg>"
    )
}

#[test]
fn an_open_contour_is_refused_naming_its_entity() {
    let open = dxf_text(
        Some(4),
        &[lwpolyline(
            "2F",
            &[(0.0, 0.0, 0.0), (10.0, 0.0, 0.0), (10.0, 5.0, 0.0)],
            false,
        )],
    );
    let err = refused("open.dxf", &open, "");
    assert!(err.contains("LWPOLYLINE handle 2F: open contour"), "{err}");
    let open = svg(
        "20mm",
        "20mm",
        " viewBox=\"0 0 20 20\"",
        "<path id=\"wing\" d=\"M 1 1 L 10 1 L 10 8\"/>",
    );
    let err = refused("open.svg", &open, "");
    assert!(err.contains("<path id=\"wing\">: open contour"), "{err}");
}

#[test]
fn a_self_intersecting_contour_is_refused_naming_its_entity() {
    let bow_tie = dxf_text(
        Some(4),
        &[lwpolyline(
            "3A",
            &[
                (0.0, 0.0, 0.0),
                (10.0, 10.0, 0.0),
                (10.0, 0.0, 0.0),
                (0.0, 6.0, 0.0),
            ],
            true,
        )],
    );
    let err = refused("bow-tie.dxf", &bow_tie, "");
    assert!(
        err.contains("LWPOLYLINE handle 3A: self-intersecting contour"),
        "{err}"
    );
    let bow_tie = svg(
        "20mm",
        "20mm",
        " viewBox=\"0 0 20 20\"",
        "<polygon points=\"0,0 10,10 10,0 0,6\"/>",
    );
    let err = refused("bow-tie.svg", &bow_tie, "");
    assert!(
        err.contains("<polygon> #1 (no id): self-intersecting contour"),
        "{err}"
    );
    // A symmetric bow-tie: its two lobes cancel to a signed area of zero, yet its points do not lie
    // on one line, so it is a crossing, not a degenerate contour.
    let symmetric = svg(
        "20mm",
        "20mm",
        " viewBox=\"0 0 20 20\"",
        "<polygon id=\"tie\" points=\"0,0 10,10 10,0 0,10\"/>",
    );
    let err = refused("symmetric-bow-tie.svg", &symmetric, "");
    assert!(
        err.contains("<polygon id=\"tie\">: self-intersecting contour"),
        "{err}"
    );
    // Points on one line are still a zero-area contour.
    let flat = svg(
        "20mm",
        "20mm",
        " viewBox=\"0 0 20 20\"",
        "<polygon id=\"flat\" points=\"0,0 5,5 10,10\"/>",
    );
    let err = refused("flat.svg", &flat, "");
    assert!(err.contains("<polygon id=\"flat\">: zero area"), "{err}");
}

#[test]
fn missing_units_are_refused() {
    let square = lwpolyline(
        "10",
        &[
            (0.0, 0.0, 0.0),
            (5.0, 0.0, 0.0),
            (5.0, 5.0, 0.0),
            (0.0, 5.0, 0.0),
        ],
        true,
    );
    let err = refused(
        "unitless.dxf",
        &dxf_text(None, std::slice::from_ref(&square)),
        "",
    );
    assert!(
        err.contains("header $INSUNITS = 0 or missing (unitless)"),
        "{err}"
    );
    let err = refused(
        "unitless.svg",
        &svg(
            "20",
            "20mm",
            " viewBox=\"0 0 20 20\"",
            "<rect width=\"5\" height=\"5\"/>",
        ),
        "",
    );
    assert!(err.contains("<svg> width = \"20\" (no unit)"), "{err}");
    let err = refused(
        "no-viewbox.svg",
        &svg("20mm", "20mm", "", "<rect width=\"5\" height=\"5\"/>"),
        "",
    );
    assert!(err.contains("<svg> viewBox = missing"), "{err}");
}

#[test]
fn units_other_than_mm_are_refused() {
    let square = lwpolyline(
        "10",
        &[
            (0.0, 0.0, 0.0),
            (5.0, 0.0, 0.0),
            (5.0, 5.0, 0.0),
            (0.0, 5.0, 0.0),
        ],
        true,
    );
    let err = refused("inches.dxf", &dxf_text(Some(1), &[square]), "");
    assert!(
        err.contains("header $INSUNITS = 1 (Inches): parts must be drawn in millimetres"),
        "{err}"
    );
    let err = refused(
        "inches.svg",
        &svg(
            "2in",
            "2in",
            " viewBox=\"0 0 2 2\"",
            "<rect width=\"1\" height=\"1\"/>",
        ),
        "",
    );
    assert!(err.contains("<svg> width = \"2in\" (not mm)"), "{err}");
}

#[test]
fn a_part_the_nester_would_refuse_is_refused_by_the_batch_reader_naming_its_entity() {
    // 0.35 mm separation (kerf 0.05 + spacing 0.3) on an 80 mm roll: a 79.29 mm part leaves
    // 0.355 mm to each edge, more than the separation, but not the nester's working gap (its
    // model keeps 1 % more plus a margin of a few f32 steps, half that margin again of start
    // clearance, and 5 µm more to each edge for rounding, cam_nest::fits_empty_sheet).
    // The reader applies the nester's own check, so the refusal names the entity before any
    // nesting, rather than the nester refusing it later without the drawing's entity.
    let (dir, batch) = scratch(
        0.05,
        "[[item]]\ndesign = \"thesis-C.toml\"\nquantity = 2\n",
        "[[part]]\nfile = \"parts/bar.dxf\"\nquantity = 1\nlayup_deg = [0, 90, 0]\nfibre_axis_deg = 90\n\n\
         [sheets]\nprepreg = { width_mm = 80, strip = true }\nspacing_mm = 0.3\n",
    );
    let bar = |width: f64| {
        dxf_text(
            Some(4),
            &[lwpolyline(
                "5C",
                &[
                    (0.0, 0.0, 0.0),
                    (width, 0.0, 0.0),
                    (width, 3.0, 0.0),
                    (0.0, 3.0, 0.0),
                ],
                true,
            )],
        )
    };
    let file = dir.path().join("parts/bar.dxf");
    std::fs::write(&file, bar(79.29)).unwrap();
    let err = refusal(&batch);
    assert!(
        err.contains(&file.display().to_string())
            && err.contains("LWPOLYLINE handle 5C: part too large: 79.290 x 3.000 mm"),
        "{err}"
    );
    // 0.03 mm narrower fits the nester's gap too, and nests.
    std::fs::write(&file, bar(79.26)).unwrap();
    nest_ok(&batch, &dir.path().join("out"), "20");
}

#[test]
fn the_readers_size_check_is_the_nesters() {
    // Bars 79.20-79.35 mm long across an 80 mm strip and on 80 x 20 mm sheets, 0.35 mm apart:
    // cam_nest::fits_empty_sheet says yes exactly when the nester takes the bar.
    let settings = cam_nest::NestSettings {
        separation_mm: 0.35,
        seed: 1,
        iterations: 0,
        workers: 1,
    };
    let (mut yes, mut no) = (0, 0);
    for k in 0..=15 {
        let w = 79.20 + 0.01 * k as f64;
        let item = cam_nest::NestItem {
            outline: vec![[0.0, 0.0], [w, 0.0], [w, 3.0], [0.0, 3.0]],
            demand: 1,
            rotations_deg: vec![0.0, 180.0],
        };
        let items = [item.clone()];
        let strip = cam_nest::fits_empty_sheet(
            &item.outline,
            &item.rotations_deg,
            80.0,
            f64::INFINITY,
            0.35,
        );
        let nested = cam_nest::nest_strip(&items, 80.0, &settings, &|_| {});
        assert_eq!(strip.fits, nested.is_ok(), "{w} mm: {nested:?}");
        if let Err(e) = nested {
            assert!(
                matches!(e, cam_nest::NestError::PartLargerThanBin { .. }),
                "{e:?}"
            );
        }
        let sheet =
            cam_nest::fits_empty_sheet(&item.outline, &item.rotations_deg, 80.0, 20.0, 0.35);
        let bin = cam_nest::NestBin {
            width_mm: 80.0,
            height_mm: 20.0,
            stock: 1,
        };
        assert_eq!(
            sheet.fits,
            cam_nest::nest(&items, &bin, &settings).is_ok(),
            "{w} mm"
        );
        if strip.fits {
            yes += 1
        } else {
            no += 1
        }
    }
    assert!(
        yes > 0 && no > 0,
        "the range straddles the limit: {yes} fit, {no} do not"
    );
}

#[test]
fn on_a_long_strip_the_nesters_refusal_names_the_gap_it_needs() {
    // 200 squares of 70 mm make about 20 m of strip, where the nester's f32 margin is some
    // hundredths of a millimetre: a bar that one part's check lets through is refused, and the
    // edge gap the refusal gives is the one that takes it.
    let settings = cam_nest::NestSettings {
        separation_mm: 0.35,
        seed: 1,
        iterations: 0,
        workers: 1,
    };
    let square = cam_nest::NestItem {
        outline: vec![[0.0, 0.0], [70.0, 0.0], [70.0, 70.0], [0.0, 70.0]],
        demand: 200,
        rotations_deg: vec![0.0],
    };
    let bar = |w: f64| cam_nest::NestItem {
        outline: vec![[0.0, 0.0], [w, 0.0], [w, 3.0], [0.0, 3.0]],
        demand: 1,
        rotations_deg: vec![0.0],
    };
    let w = 79.27;
    let alone = cam_nest::fits_empty_sheet(&bar(w).outline, &[0.0], 80.0, f64::INFINITY, 0.35);
    assert!(alone.fits, "{alone:?}");
    let err = cam_nest::nest_strip(&[square.clone(), bar(w)], 80.0, &settings, &|_| {})
        .expect_err("the margin of 20 m of parts refuses the bar");
    let message = err.to_string();
    assert!(
        message.ends_with("does not fit the 80 mm wide strip"),
        "{message}"
    );
    let cam_nest::NestError::PartLargerThanBin {
        item, edge_gap_mm, ..
    } = err
    else {
        panic!("{err:?}")
    };
    assert_eq!(item, 1);
    assert!(
        edge_gap_mm > alone.edge_gap_mm && w + 2.0 * edge_gap_mm >= 80.0,
        "{edge_gap_mm} against {alone:?}"
    );
    // Narrower by what the refusal says is missing (and a micrometre), or by 0.4 or 0.8 mm more,
    // the bar is taken: its only room is a band at the top of the strip, which the
    // construction's sampled starts can miss.
    for k in 0..3 {
        let narrower = 80.0 - 2.0 * edge_gap_mm - 0.001 - 0.4 * k as f64;
        let items = [square.clone(), bar(narrower)];
        let strip = cam_nest::nest_strip(&items, 80.0, &settings, &|_| {})
            .unwrap_or_else(|e| panic!("{narrower} mm: {e}"));
        cam_nest::verify(&items, &strip.bin, &settings, &strip.solution, 1e-9)
            .unwrap_or_else(|v| panic!("{narrower} mm: {v:?}"));
    }
}

#[test]
fn a_part_too_large_for_the_sheet_is_refused_naming_its_entity() {
    // The example batch's prepreg sheets are the template's; a 500 mm spar fits none of them.
    let long = dxf_text(
        Some(4),
        &[lwpolyline(
            "4B",
            &[
                (0.0, 0.0, 0.0),
                (500.0, 0.0, 0.0),
                (500.0, 3.0, 0.0),
                (0.0, 3.0, 0.0),
            ],
            true,
        )],
    );
    let err = refused("long.dxf", &long, "");
    assert!(
        err.contains("LWPOLYLINE handle 4B: part too large: 500.000 x 3.000 mm"),
        "{err}"
    );
    let long = svg(
        "600mm",
        "20mm",
        " viewBox=\"0 0 600 20\"",
        "<rect id=\"beam\" width=\"500\" height=\"3\"/>",
    );
    let err = refused("long.svg", &long, "");
    assert!(err.contains("<rect id=\"beam\">: part too large"), "{err}");
}

#[test]
fn a_drawing_without_a_closed_contour_is_refused() {
    let err = refused("empty.dxf", &dxf_text(Some(4), &[text_entity("5C")]), "");
    assert!(err.contains("no closed contour"), "{err}");
    let err = refused(
        "empty.svg",
        &svg(
            "20mm",
            "20mm",
            " viewBox=\"0 0 20 20\"",
            "<text>spar</text>",
        ),
        "",
    );
    assert!(err.contains("no closed contour"), "{err}");
}

#[test]
fn unsupported_entities_and_crossing_contours_are_refused_naming_them() {
    let spline = dxf_text(
        Some(4),
        &[codes(&[
            (0, "SPLINE".into()),
            (5, "6D".into()),
            (100, "AcDbEntity".into()),
            (8, "0".into()),
            (100, "AcDbSpline".into()),
        ])],
    );
    let err = refused("spline.dxf", &spline, "");
    assert!(
        err.contains("SPLINE handle 6D: not a supported part entity"),
        "{err}"
    );
    let crossing = svg(
        "20mm",
        "20mm",
        " viewBox=\"0 0 20 20\"",
        "<rect id=\"a\" width=\"5\" height=\"5\"/><rect id=\"b\" x=\"3\" y=\"3\" width=\"5\" height=\"5\"/>",
    );
    let err = refused("crossing.svg", &crossing, "");
    assert!(
        err.contains("<rect id=\"b\">: crosses or touches <rect id=\"a\">"),
        "{err}"
    );
}

// ---- No panic on any drawing ------------------------------------------------------------------

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(128))]

    /// Path data of random commands and numbers (arcs with any radii and flags, curves, NaN-free
    /// but huge or tiny values): the importer returns parts or one error naming the file.
    #[test]
    fn random_svg_paths_never_panic(
        cmds in proptest::collection::vec(
            (proptest::sample::select(vec!["M", "L", "H", "V", "C", "S", "Q", "T", "A", "Z", "m", "l", "a", "c"]),
             proptest::collection::vec(-1e6f64..1e6, 0..8)),
            0..12),
    ) {
        let d: String = cmds
            .iter()
            .map(|(c, n)| {
                let nums: Vec<String> = n.iter().map(|x| format!("{x}")).collect();
                format!("{c} {} ", nums.join(" "))
            })
            .collect();
        let text = svg("20mm", "20mm", " viewBox=\"0 0 20 20\"", &format!("<path d=\"{d}\"/>"));
        let (_dir, path) = write_temp("random.svg", &text);
        if let Err(e) = actuator_cam::import_parts(&path) {
            let line = e.to_string();
            proptest::prop_assert!(line.starts_with(&path.display().to_string()));
            proptest::prop_assert_eq!(line.lines().count(), 1);
        }
    }

    /// Polylines of random vertices and bulges, open or closed, with circles of any radius.
    #[test]
    fn random_dxf_polylines_never_panic(
        vertices in proptest::collection::vec((-1e4f64..1e4, -1e4f64..1e4, -20f64..20.0), 0..10),
        closed in proptest::bool::ANY,
        r in -5f64..1e5,
    ) {
        let text = dxf_text(Some(4), &[lwpolyline("1", &vertices, closed), circle("2", [0.0, 0.0], r)]);
        let (_dir, path) = write_temp("random.dxf", &text);
        if let Err(e) = actuator_cam::import_parts(&path) {
            let line = e.to_string();
            proptest::prop_assert!(line.starts_with(&path.display().to_string()));
            proptest::prop_assert_eq!(line.lines().count(), 1);
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
