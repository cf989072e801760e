//! `actuator-cam cut-sheet` on the example designs: geometry against mass, files read back, score lines,
//! spacing, determinism and bad input.

mod clearance;
mod files;
mod mass;
mod pzt;
mod refusals;
mod template;

use crate::common;
use actuator_cam::{
    build_layers, design_for_process, Design, Names, Operation, Packing, Shape, Template,
};
use cam_geometry::place_ring;
use common::svg_read::{svg_paths, view_box};
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

/// The lines of an SVG's cut layer: what the laser cuts through.
fn cut_layer(svg: &str) -> &str {
    let start = svg.find("id=\"layer-cut\"").expect("a cut layer");
    let end = start + svg[start..].find("</g>").expect("the cut layer ends");
    &svg[start..end]
}
