//! Every SVG/DXF pair every shipped example writes, read back with parsers of its own (roxmltree and
//! svgtypes for the SVG, the `dxf` crate for the DXF), not with the code that wrote them:
//! - one origin (docs/cam.md §3 "One origin"): the SVG page is the sheet its stock names, one user unit
//!   a millimetre from the page corner, the DXF's drawing limits the same sheet from (0, 0), both files
//!   state it, and every shape lies at the same place in both formats to 1 µm; a PZT sheet's drawn edge
//!   is the sheet, a clamp or linkage panel's outline is centred on it;
//! - cut order (docs/cam.md §3): in both formats every shape inside a closed through-cut contour comes
//!   before it, so holes, slots, windows and marks are cut while the part or panel is still held;
//! - marks (docs/cam.md §1 "Labels", §6 "Polarity"): no engraving lies in a bonded face, the zones each
//!   file marks as bonded (`<guide kind="bonded-zone">`), and every sheet whose parts are bonded marks
//!   them: each plate of a PZT sheet, each part of a passive, ply or Pyralux sheet, each linkage on the
//!   linkage's stack layers and each nested linkage coupon.

mod marks;
mod order;
mod origin;
mod read;
use order::*;
use origin::*;
use read::*;

use crate::common;
use common::*;
use geo::{Contains, Coord, Intersects, LineString, Polygon};
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

type P = [f64; 2];

/// 1 µm, in mm.
const TOL_MM: f64 = 1e-3;

/// One shape as a file gives it, in sheet coordinates (mm, y up, origin the sheet's lower-left corner):
/// the end points of its commands or vertices, whether it is closed, and the radius of its arcs.
#[derive(Clone, Debug)]
struct Shape {
    layer: String,
    points: Vec<P>,
    closed: bool,
    radius: Option<f64>,
    /// A circle's or arc's centre, where the file gives it (DXF).
    centre: Option<P>,
}

/// What one file pair says about itself.
struct Pair {
    name: String,
    svg_shapes: Vec<Shape>,
    dxf_shapes: Vec<Shape>,
    /// The bonded zones the SVG marks, sheet coordinates.
    zones: Vec<Vec<P>>,
    /// SVG page (mm), the stock's sheet (mm, metadata), the viewBox.
    page_mm: P,
    stock_mm: Option<P>,
    view_box: [f64; 4],
    /// DXF drawing limits.
    limits: [f64; 4],
    desc: Option<String>,
    dxf_comments: Vec<String>,
}

/// An example that writes no layer file, and why.
const NO_LAYER_FILES: [(&str, &str); 2] = [
    // `drive` checks a two-stage linkage's flexures, but `cut-sheet --drive` draws no layer of it.
    (
        "drive-robobee-jafferis2016-two-stage.toml",
        "a two-stage linkage",
    ),
    // A published transmission ratio has no link lengths to draw: `cut-sheet --drive` refuses it.
    (
        "drive-robobee-jafferis2016.toml",
        "a transmission given by its ratio",
    ),
];

/// The names of the files of `dir` that end in `ending`, sorted.
fn names_ending(dir: &Path, ending: &str) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(ending))
        .collect();
    names.sort();
    names
}

/// The commands of every example that writes layer files, as `(case, args)`; `{out}` is the case's
/// folder. Designs go through `cut-sheet`, drives with a drawn linkage through `cut-sheet --drive` (five
/// actuators, so a panel holds several linkages), batches through `nest`; optimisation, sweep and effect
/// files write no layer file. Every example is classified, so a new one is not left out unseen.
fn cases() -> Vec<(String, Vec<String>)> {
    let mut cases = Vec::new();
    for name in names_ending(&example_path(""), ".toml") {
        let stem = name.trim_end_matches(".toml").to_string();
        let text = std::fs::read_to_string(example_path(&name)).unwrap();
        let doc: toml::Table = toml::from_str(&text).unwrap();
        let path = format!("examples/{name}");
        if NO_LAYER_FILES.iter().any(|(n, _)| *n == name) {
            continue;
        }
        let command = if doc.contains_key("geometry") {
            format!("cut-sheet {path} -o {{out}}")
        } else if doc.contains_key("wing") {
            let design = doc["design"].as_str().unwrap();
            format!("cut-sheet examples/{design} --drive {path} --quantity 5 -o {{out}}")
        } else if doc.contains_key("item") {
            format!("nest {path} -o {{out}} --seed 1 --iterations 100")
        } else {
            assert!(
                ["factors", "effect", "search"]
                    .iter()
                    .any(|k| doc.contains_key(*k)),
                "{name}: an example of a kind this test does not know; say whether it writes layer files"
            );
            continue;
        };
        cases.push((stem, command.split(' ').map(String::from).collect()));
    }
    cases
}

/// The plies cut one by one (a template option no example ships): design C with a 2 mm base tab for
/// the registration holes, by method 2 with `passive_cut = "ply-by-ply"`, as CI cuts it.
fn ply_by_ply_case(dir: &Path) -> (String, Vec<String>) {
    let template = shipped_template("method-2.toml")
        .replace("passive_cut = \"stack\"", "passive_cut = \"ply-by-ply\"");
    let tpl = dir.join("ply-by-ply.toml");
    std::fs::write(&tpl, template).unwrap();
    let design = design_c_with(&[
        ("process", &format!("process = \"{}\"", tpl.display())),
        ("base_tab_mm", "base_tab_mm = 2.0"),
    ]);
    let path = dir.join("ply-by-ply-C.toml");
    std::fs::write(&path, design).unwrap();
    let args = ["cut-sheet", path.to_str().unwrap(), "-o", "{out}"];
    ("ply-by-ply-C".into(), args.map(String::from).to_vec())
}

/// Every case run once for the tests of this module: its folder of outputs.
fn outputs() -> &'static (tempfile::TempDir, Vec<PathBuf>) {
    static OUT: OnceLock<(tempfile::TempDir, Vec<PathBuf>)> = OnceLock::new();
    OUT.get_or_init(|| {
        let dir = tempfile::tempdir().unwrap();
        let mut all = cases();
        all.push(ply_by_ply_case(dir.path()));
        let mut folders = Vec::new();
        for (case, args) in all {
            let out = dir.path().join(&case);
            let args: Vec<String> = args
                .iter()
                .map(|a| a.replace("{out}", out.to_str().unwrap()))
                .collect();
            let refs: Vec<&str> = args.iter().map(String::as_str).collect();
            let o = run(&refs);
            assert!(o.status.success(), "{case}: {}", stderr(&o));
            folders.push(out);
        }
        (dir, folders)
    })
}

/// Every file pair of the outputs, read back.
fn pairs() -> &'static Vec<Pair> {
    static PAIRS: OnceLock<Vec<Pair>> = OnceLock::new();
    PAIRS.get_or_init(|| {
        let mut pairs = Vec::new();
        for folder in &outputs().1 {
            for dxf in names_ending(folder, ".dxf") {
                let stem = dxf.trim_end_matches(".dxf");
                let svg = folder.join(format!("{stem}.svg"));
                assert!(svg.exists(), "{dxf} has no SVG beside it");
                let case = folder.file_name().unwrap().to_string_lossy();
                pairs.push(read_pair(
                    &format!("{case}/{stem}"),
                    &svg,
                    &folder.join(&dxf),
                ));
            }
        }
        assert!(pairs.len() > 300, "only {} file pairs", pairs.len());
        pairs
    })
}

fn read_pair(name: &str, svg: &Path, dxf: &Path) -> Pair {
    let svg_text = std::fs::read_to_string(svg).unwrap();
    let s = read_svg(name, &svg_text);
    let d = read_dxf(name, dxf);
    Pair {
        name: name.to_string(),
        svg_shapes: s.shapes,
        dxf_shapes: d.0,
        zones: s.zones,
        page_mm: s.page_mm,
        stock_mm: s.stock_mm,
        view_box: s.view_box,
        limits: d.1,
        desc: s.desc,
        dxf_comments: d.2,
    }
}

/// What the SVG reader finds.
struct SvgRead {
    shapes: Vec<Shape>,
    zones: Vec<Vec<P>>,
    page_mm: P,
    stock_mm: Option<P>,
    view_box: [f64; 4],
    desc: Option<String>,
}
