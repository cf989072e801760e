//! Extra parts from DXF and SVG drawings nested with actuators, roll stock (`strip = true`) and the nest
//! progress: the layouts are checked again from the files written (areas read back against closed forms,
//! clearance between the outlines), every kind of bad drawing is refused in one line naming the file and the
//! entity.

mod drawings;
mod holes;
mod nesting;
mod progress;
mod refusals;
mod roll;

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

/// The passive sheets of a nest report.
fn passive_sheets(r: &serde_json::Value) -> Vec<&serde_json::Value> {
    r["sheets"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|s| s["layer"] == "passive")
        .collect()
}

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
