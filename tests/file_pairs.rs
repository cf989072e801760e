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
const NO_LAYER_FILES: [(&str, &str); 1] = [
    // Its flexures are a lumped stiffness the tool does not draw: `cut-sheet --drive` refuses it.
    ("drive-robobee.toml", "a lumped transmission"),
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

/// A length in mm (`72.4mm`); the files must give their page in mm.
fn mm(name: &str, value: Option<&str>) -> f64 {
    let l: svgtypes::Length = value
        .unwrap_or_else(|| panic!("{name}: no page size"))
        .parse()
        .unwrap();
    assert_eq!(l.unit, svgtypes::LengthUnit::Mm, "{name}: page not in mm");
    l.number
}

fn read_svg(name: &str, text: &str) -> SvgRead {
    let doc = roxmltree::Document::parse(text).unwrap_or_else(|e| panic!("{name}.svg: {e}"));
    let root = doc.root_element();
    let page_mm = [
        mm(name, root.attribute("width")),
        mm(name, root.attribute("height")),
    ];
    let vb: svgtypes::ViewBox = root.attribute("viewBox").unwrap().parse().unwrap();
    let view_box = [vb.x, vb.y, vb.w, vb.h];
    // User units to sheet coordinates: from the page's lower-left corner, y up.
    let to_sheet = |x: f64, y: f64| -> P {
        [
            (x - vb.x) * page_mm[0] / vb.w,
            page_mm[1] - (y - vb.y) * page_mm[1] / vb.h,
        ]
    };
    let mut shapes = Vec::new();
    let mut zones = Vec::new();
    let mut stock_mm = None;
    let mut desc = None;
    for node in root.descendants().filter(|n| n.is_element()) {
        assert!(
            node.attribute("transform").is_none(),
            "{name}.svg: a transform this reader does not apply"
        );
        let tag = node.tag_name().name();
        match tag {
            "desc" if node.parent() == Some(root) => desc = node.text().map(String::from),
            "stock" => {
                let n = |k| node.attribute(k).unwrap().parse::<f64>().unwrap();
                stock_mm = Some([n("width_mm"), n("height_mm")]);
            }
            "guide" if node.attribute("kind") == Some("bonded-zone") => {
                zones.push(path_shape(node.attribute("d").unwrap(), &to_sheet).points);
            }
            "path" | "rect" | "circle" | "line" | "polyline" | "polygon" => {
                let layer = node
                    .ancestors()
                    .find(|a| {
                        a.attribute(("http://www.inkscape.org/namespaces/inkscape", "groupmode"))
                            == Some("layer")
                    })
                    .and_then(|g| {
                        g.attribute(("http://www.inkscape.org/namespaces/inkscape", "label"))
                    })
                    .unwrap_or_else(|| panic!("{name}.svg: a {tag} outside every layer"))
                    .to_string();
                let mut shape = element_shape(node, &to_sheet);
                shape.layer = layer;
                shapes.push(shape);
            }
            _ => {}
        }
    }
    SvgRead {
        shapes,
        zones,
        page_mm,
        stock_mm,
        view_box,
        desc,
    }
}

/// A drawn element as a shape (layer left empty).
fn element_shape(node: roxmltree::Node, to_sheet: &dyn Fn(f64, f64) -> P) -> Shape {
    let n = |k: &str| node.attribute(k).map_or(0.0, |v| v.parse::<f64>().unwrap());
    let points_of = |k: &str| -> Vec<P> {
        svgtypes::PointsParser::from(node.attribute(k).unwrap())
            .map(|(x, y)| to_sheet(x, y))
            .collect()
    };
    let poly = |points: Vec<P>, closed: bool| Shape {
        layer: String::new(),
        points,
        closed,
        radius: None,
        centre: None,
    };
    match node.tag_name().name() {
        "path" => path_shape(node.attribute("d").unwrap(), to_sheet),
        "rect" => {
            let (x, y, w, h) = (n("x"), n("y"), n("width"), n("height"));
            poly(
                vec![
                    to_sheet(x, y),
                    to_sheet(x + w, y),
                    to_sheet(x + w, y + h),
                    to_sheet(x, y + h),
                ],
                true,
            )
        }
        "line" => poly(
            vec![to_sheet(n("x1"), n("y1")), to_sheet(n("x2"), n("y2"))],
            false,
        ),
        "polyline" => poly(points_of("points"), false),
        "polygon" => poly(points_of("points"), true),
        _ => {
            // A circle: its four axis points, and its centre and radius, scaled as the page is.
            let (cx, cy, r) = (n("cx"), n("cy"), n("r"));
            let c = to_sheet(cx, cy);
            let edge = to_sheet(cx + r, cy);
            let radius = edge[0] - c[0];
            Shape {
                layer: String::new(),
                points: vec![
                    edge,
                    to_sheet(cx, cy - r),
                    to_sheet(cx - r, cy),
                    to_sheet(cx, cy + r),
                ],
                closed: true,
                radius: Some(radius),
                centre: Some(c),
            }
        }
    }
}

/// A path's end points (absolute or relative commands), closed when it ends in Z; arcs give their
/// radius (scaled as the page is).
fn path_shape(d: &str, to_sheet: &dyn Fn(f64, f64) -> P) -> Shape {
    use svgtypes::PathSegment as S;
    let mut at = [0.0, 0.0];
    let mut points = Vec::new();
    let mut closed = false;
    let mut radius = None;
    for seg in svgtypes::PathParser::from(d) {
        let seg = seg.unwrap_or_else(|e| panic!("path {d:?}: {e}"));
        assert!(!closed, "path {d:?}: commands after Z");
        let end = |abs: bool, x: f64, y: f64| if abs { [x, y] } else { [at[0] + x, at[1] + y] };
        let next = match seg {
            S::MoveTo { abs, x, y } => end(abs, x, y),
            S::LineTo { abs, x, y } => end(abs, x, y),
            S::HorizontalLineTo { abs, x } => end(abs, x, if abs { at[1] } else { 0.0 }),
            S::VerticalLineTo { abs, y } => end(abs, if abs { at[0] } else { 0.0 }, y),
            S::EllipticalArc {
                abs, rx, ry, x, y, ..
            } => {
                assert!((rx - ry).abs() < 1e-9, "path {d:?}: an elliptical arc");
                radius = Some(rx);
                end(abs, x, y)
            }
            S::ClosePath { .. } => {
                closed = true;
                continue;
            }
            other => panic!("path {d:?}: {other:?}, which laser files do not use"),
        };
        at = next;
        points.push(to_sheet(at[0], at[1]));
    }
    // The radius in sheet units: the page's scale.
    let scale = {
        let (a, b) = (to_sheet(0.0, 0.0), to_sheet(1.0, 0.0));
        b[0] - a[0]
    };
    Shape {
        layer: String::new(),
        points,
        closed,
        radius: radius.map(|r| r * scale),
        centre: None,
    }
}

/// The DXF's shapes, drawing limits and comments.
fn read_dxf(name: &str, path: &Path) -> (Vec<Shape>, [f64; 4], Vec<String>) {
    use dxf::entities::EntityType as E;
    let doc = dxf::Drawing::load_file(path).unwrap_or_else(|e| panic!("{name}.dxf: {e}"));
    let on = |c: f64, r: f64, deg: f64, cy: f64| -> P {
        let a = deg.to_radians();
        [c + r * a.cos(), cy + r * a.sin()]
    };
    let shapes = doc
        .entities()
        .map(|e| {
            let (points, closed, radius, centre) = match &e.specific {
                E::LwPolyline(p) => (
                    p.vertices.iter().map(|v| [v.x, v.y]).collect(),
                    p.is_closed(),
                    None,
                    None,
                ),
                E::Circle(c) => (
                    vec![on(c.center.x, c.radius, 0.0, c.center.y)],
                    true,
                    Some(c.radius),
                    Some([c.center.x, c.center.y]),
                ),
                E::Arc(a) => (
                    vec![
                        on(a.center.x, a.radius, a.start_angle, a.center.y),
                        on(a.center.x, a.radius, a.end_angle, a.center.y),
                    ],
                    false,
                    Some(a.radius),
                    Some([a.center.x, a.center.y]),
                ),
                other => panic!("{name}.dxf: {other:?}, which laser files do not use"),
            };
            Shape {
                layer: e.common.layer.clone(),
                points,
                closed,
                radius,
                centre,
            }
        })
        .collect();
    let h = &doc.header;
    let limits = [
        h.minimum_drawing_limits.x,
        h.minimum_drawing_limits.y,
        h.maximum_drawing_limits.x,
        h.maximum_drawing_limits.y,
    ];
    let text = std::fs::read_to_string(path).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    let comments = lines
        .windows(2)
        .filter(|w| w[0].trim() == "999")
        .map(|w| w[1].to_string())
        .collect();
    (shapes, limits, comments)
}

fn close(a: P, b: P) -> bool {
    (a[0] - b[0]).abs() <= TOL_MM && (a[1] - b[1]).abs() <= TOL_MM
}

fn dist(a: P, b: P) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

/// The centre of a circle drawn through `points` that hold a diameter (an SVG circle's arc ends): the
/// middle of the first point and the point farthest from it.
fn diameter_centre(points: &[P]) -> P {
    let a = points[0];
    let b = *points
        .iter()
        .max_by(|p, q| dist(**p, a).total_cmp(&dist(**q, a)))
        .unwrap();
    [(a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0]
}

/// Why the SVG shape `s` is not the DXF shape `d` at the same place, if it is not.
fn mismatch(s: &Shape, d: &Shape) -> Option<String> {
    if s.layer != d.layer || s.closed != d.closed || s.radius.is_some() != d.radius.is_some() {
        return Some(format!(
            "layer {} / {}, closed {} / {}, arcs {} / {}",
            s.layer,
            d.layer,
            s.closed,
            d.closed,
            s.radius.is_some(),
            d.radius.is_some()
        ));
    }
    match (s.radius, d.radius, d.centre) {
        (Some(rs), Some(rd), Some(c)) => {
            // A circle or arc: same radius, every SVG end point on the DXF's circle, the SVG's farthest
            // pair of points (a diameter, for a circle) centred on the DXF's centre, and an arc's ends
            // where the DXF's angles put them.
            if (rs - rd).abs() > TOL_MM {
                return Some(format!("radius {rs} / {rd}"));
            }
            if let Some(p) = s.points.iter().find(|p| (dist(**p, c) - rd).abs() > TOL_MM) {
                return Some(format!("{p:?} is not on the circle about {c:?} r {rd}"));
            }
            if s.closed {
                let mid = diameter_centre(&s.points);
                (!close(mid, c)).then(|| format!("circle about {mid:?} / {c:?}"))
            } else {
                let (first, last) = (s.points[0], *s.points.last().unwrap());
                (!close(first, d.points[0]) || !close(last, d.points[1]))
                    .then(|| format!("arc from {first:?} to {last:?} / {:?}", d.points))
            }
        }
        _ => {
            if s.points.len() != d.points.len() {
                return Some(format!("{} / {} vertices", s.points.len(), d.points.len()));
            }
            s.points
                .iter()
                .zip(&d.points)
                .find(|(a, b)| !close(**a, **b))
                .map(|(a, b)| format!("vertex {a:?} / {b:?}"))
        }
    }
}

#[test]
fn every_file_pair_has_the_sheet_corner_at_its_origin_and_the_same_shapes_at_the_same_places() {
    let mut checked = 0;
    for p in pairs() {
        let n = &p.name;
        let stock = p
            .stock_mm
            .unwrap_or_else(|| panic!("{n}.svg: no stock sheet"));
        // The page is the sheet, one user unit a millimetre from the page's corner.
        assert!(
            close(p.page_mm, stock),
            "{n}.svg: page {:?}, sheet {stock:?}",
            p.page_mm
        );
        let at_sheet = |box4: [f64; 4]| {
            close([box4[0], box4[1]], [0.0, 0.0]) && close([box4[2], box4[3]], stock)
        };
        assert!(
            at_sheet(p.view_box),
            "{n}.svg: viewBox {:?}, sheet {stock:?}",
            p.view_box
        );
        // The DXF's drawing limits are the same sheet from its origin.
        assert!(
            at_sheet(p.limits),
            "{n}.dxf: $LIMMIN/$LIMMAX {:?}, sheet {stock:?}",
            p.limits
        );
        // Both files say so.
        let desc = p.desc.as_deref().unwrap_or_default();
        assert!(
            desc.contains("lower-left corner is the sheet's lower-left corner"),
            "{n}.svg: desc {desc:?}"
        );
        assert!(
            p.dxf_comments
                .iter()
                .any(|c| c.starts_with("origin: (0, 0) is the sheet's lower-left corner")),
            "{n}.dxf: comments {:?}",
            p.dxf_comments
        );
        // The same shapes in the same order at the same places.
        assert_eq!(
            p.svg_shapes.len(),
            p.dxf_shapes.len(),
            "{n}: shapes in SVG / DXF"
        );
        for (k, (s, d)) in p.svg_shapes.iter().zip(&p.dxf_shapes).enumerate() {
            if let Some(why) = mismatch(s, d) {
                panic!("{n}: shape {k} differs between SVG and DXF: {why}");
            }
        }
        sheet_edges_where_drawn(p, stock);
        checked += 1;
    }
    assert!(checked > 300, "{checked} pairs");
}

/// The physical sheet where a file draws it: a PZT sheet's edge (the reference outline) is the sheet
/// exactly, and a panel's outline (a cut contour spanning most of the sheet) is centred on it.
fn sheet_edges_where_drawn(p: &Pair, sheet: P) {
    for (format, shapes) in [("svg", &p.svg_shapes), ("dxf", &p.dxf_shapes)] {
        for s in shapes.iter().filter(|s| s.closed && s.radius.is_none()) {
            let (lo, hi) = bounds(&s.points);
            let spans = hi[0] - lo[0] > 0.9 * sheet[0] && hi[1] - lo[1] > 0.9 * sheet[1];
            if s.layer == "REFERENCE" && p.name.contains("/pzt-") {
                assert!(
                    close(lo, [0.0, 0.0]) && close(hi, sheet),
                    "{}.{format}: sheet edge {lo:?}-{hi:?}, sheet {sheet:?}",
                    p.name
                );
            } else if spans && s.layer == "CUT" {
                let centre = [(lo[0] + hi[0]) / 2.0, (lo[1] + hi[1]) / 2.0];
                assert!(
                    close(centre, [sheet[0] / 2.0, sheet[1] / 2.0]),
                    "{}.{format}: panel outline {lo:?}-{hi:?} off the {sheet:?} sheet's centre",
                    p.name
                );
            }
        }
    }
}

fn bounds(points: &[P]) -> (P, P) {
    points.iter().fold(
        ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]),
        |(lo, hi), p| {
            (
                [lo[0].min(p[0]), lo[1].min(p[1])],
                [hi[0].max(p[0]), hi[1].max(p[1])],
            )
        },
    )
}

/// The points that stand for a shape when asking what lies inside what: its vertices, and for a
/// circle or arc points round its circle (the DXF gives the centre; the SVG its end points, a
/// circle's diameter among them).
fn sample(s: &Shape) -> Vec<P> {
    match (s.radius, s.centre) {
        (Some(r), Some(c)) => (0..16)
            .map(|k| {
                let a = k as f64 * std::f64::consts::PI / 8.0;
                [c[0] + r * a.cos(), c[1] + r * a.sin()]
            })
            .collect(),
        _ => s.points.clone(),
    }
}

/// A closed through-cut contour as a polygon (circles by 16 points), if `s` is one.
fn through_cut(s: &Shape) -> Option<Polygon<f64>> {
    if !s.closed || !(s.layer == "CUT" || s.layer == "SECONDARY") {
        return None;
    }
    let ring = match (s.radius, s.centre) {
        (Some(_), None) => {
            // An SVG circle, which gives its end points only.
            sample(&Shape {
                centre: Some(diameter_centre(&s.points)),
                ..s.clone()
            })
        }
        _ => sample(s),
    };
    Some(Polygon::new(
        LineString::from(ring.iter().map(|p| (p[0], p[1])).collect::<Vec<_>>()),
        vec![],
    ))
}

/// The shapes of `shapes` that lie inside a closed through-cut contour drawn before them: `(inner,
/// contour)` indices. A cut contour frees what it surrounds, so what lies inside must be cut first.
fn cut_after_their_outline(shapes: &[Shape]) -> Vec<(usize, usize)> {
    let boxes: Vec<(P, P)> = shapes.iter().map(|s| bounds(&sample(s))).collect();
    let mut late = Vec::new();
    for (k, outer) in shapes.iter().enumerate() {
        let Some(poly) = through_cut(outer) else {
            continue;
        };
        let (lo, hi) = boxes[k];
        for (j, inner) in shapes.iter().enumerate().skip(k + 1) {
            let (a, b) = boxes[j];
            let within = a[0] >= lo[0] && a[1] >= lo[1] && b[0] <= hi[0] && b[1] <= hi[1];
            if inner.layer == "REFERENCE" || !within {
                continue;
            }
            let sampled = match (inner.radius, inner.centre) {
                (Some(_), None) => inner.points.clone(),
                _ => sample(inner),
            };
            if sampled
                .iter()
                .all(|p| poly.contains(&Coord { x: p[0], y: p[1] }))
            {
                late.push((j, k));
            }
        }
    }
    late
}

#[test]
fn every_file_cuts_what_lies_inside_a_contour_before_the_contour() {
    let mut contours = 0;
    for p in pairs() {
        for (format, shapes) in [("svg", &p.svg_shapes), ("dxf", &p.dxf_shapes)] {
            contours += shapes.iter().filter(|s| through_cut(s).is_some()).count();
            let late = cut_after_their_outline(shapes);
            assert!(
                late.is_empty(),
                "{}.{format}: {} shape(s) cut after the contour around them, the first shape {} ({} layer) after contour {}",
                p.name,
                late.len(),
                late[0].0,
                shapes[late[0].0].layer,
                late[0].1
            );
        }
    }
    assert!(contours > 1000, "{contours} contours");
}

#[test]
fn the_order_check_finds_an_outline_cut_before_its_hole() {
    // The check above on a part whose hole comes after its outline, and on the same part in cut order.
    let shape = |layer: &str, points: Vec<P>| Shape {
        layer: layer.into(),
        points,
        closed: true,
        radius: None,
        centre: None,
    };
    let outline = shape(
        "CUT",
        vec![[0.0, 0.0], [10.0, 0.0], [10.0, 5.0], [0.0, 5.0]],
    );
    let hole = Shape {
        radius: Some(0.5),
        centre: Some([2.0, 2.0]),
        ..shape("CUT", vec![[2.5, 2.0]])
    };
    let label = Shape {
        closed: false,
        ..shape("ENGRAVE", vec![[5.0, 2.0], [7.0, 2.0]])
    };
    assert_eq!(
        cut_after_their_outline(&[outline.clone(), hole.clone(), label.clone()]),
        [(1, 0), (2, 0)]
    );
    assert!(cut_after_their_outline(&[label, hole, outline]).is_empty());
}

/// A ring as a `geo` polygon.
fn polygon_of(ring: &[P]) -> Polygon<f64> {
    Polygon::new(
        LineString::from(ring.iter().map(|p| (p[0], p[1])).collect::<Vec<_>>()),
        vec![],
    )
}

/// Marks: what a file engraves, and what it scores where the score is not a PZT snap line.
fn is_mark(s: &Shape, pzt_sheet: bool) -> bool {
    s.layer == "ENGRAVE" || (s.layer == "SCORE" && !pzt_sheet)
}

/// The first mark of `shapes` that touches a zone: `(mark, zone)` indices.
fn mark_in_zone(shapes: &[Shape], zones: &[Vec<P>], pzt_sheet: bool) -> Option<(usize, usize)> {
    let polys: Vec<Polygon<f64>> = zones.iter().map(|z| polygon_of(z)).collect();
    for (k, s) in shapes.iter().enumerate() {
        if !is_mark(s, pzt_sheet) {
            continue;
        }
        let line = LineString::from(sample(s).iter().map(|p| (p[0], p[1])).collect::<Vec<_>>());
        if let Some(z) = polys.iter().position(|z| z.intersects(&line)) {
            return Some((k, z));
        }
    }
    None
}

/// Whether a file's sheet holds parts that are bonded in their stack, from its name: PZT plates,
/// passive parts and plies, Pyralux bond parts, the linkage's stack layers (`linkage-1-carbon-1_…`) and
/// the nested linkage coupons (`linkage-carbon-1_…`); not the clamp sheets, the release cut or extra
/// parts' sheets.
fn holds_bonded_parts(file: &str) -> bool {
    let stem = file.split('_').next().unwrap();
    ["pzt-", "passive-", "pyralux-"]
        .iter()
        .any(|k| stem.starts_with(k))
        || (stem.starts_with("linkage-")
            && ["-carbon-", "-adhesive-", "-film-"]
                .iter()
                .any(|k| stem.contains(k)))
}

/// The plates a cut-sheet run's report places on PZT sheet `n`.
fn plates_on(report: &serde_json::Value, n: &str) -> usize {
    let at = format!(": PZT sheet {n}");
    report["placement_map"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|line| line.as_str().unwrap().ends_with(&at))
        .count()
}

#[test]
fn no_file_engraves_a_mark_in_a_bonded_face_and_bonded_parts_are_marked_so() {
    let mut zones = 0;
    for p in pairs() {
        let (case, file) = p.name.split_once('/').unwrap();
        let pzt_sheet = file.starts_with("pzt-");
        for (format, shapes) in [("svg", &p.svg_shapes), ("dxf", &p.dxf_shapes)] {
            if let Some((k, z)) = mark_in_zone(shapes, &p.zones, pzt_sheet) {
                panic!("{}.{format}: mark {k} lies in bonded zone {z}", p.name);
            }
        }
        zones += p.zones.len();
        if !holds_bonded_parts(file) {
            assert!(
                p.zones.is_empty(),
                "{}: zones on a sheet of unbonded parts",
                p.name
            );
            continue;
        }
        assert!(!p.zones.is_empty(), "{}: no bonded zone", p.name);
        let report = outputs().0.path().join(case).join("report.json");
        if pzt_sheet && report.exists() {
            // A cut-sheet run: one zone per plate its report places on the sheet.
            let r: serde_json::Value =
                serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
            let n = file.trim_start_matches("pzt-").split('_').next().unwrap();
            assert_eq!(p.zones.len(), plates_on(&r, n), "{}: zones", p.name);
        }
        let stem = file.split('_').next().unwrap();
        let coupon_sheet = ["carbon", "adhesive", "film"].iter().any(|ply| {
            stem.strip_prefix(&format!("linkage-{ply}-"))
                .is_some_and(|n| n.parse::<usize>().is_ok())
        });
        if stem.starts_with("passive-") || stem.starts_with("pyralux-") || coupon_sheet {
            // A sheet of cut parts: every part's outline (a closed cut contour inside no other)
            // holds exactly one zone.
            let outlines: Vec<Polygon<f64>> = outermost_cuts(&p.svg_shapes);
            for (k, o) in outlines.iter().enumerate() {
                let held = p
                    .zones
                    .iter()
                    .filter(|z| z.iter().all(|q| o.contains(&Coord { x: q[0], y: q[1] })))
                    .count();
                let extra_part = held == 0 && case.starts_with("batch");
                assert!(
                    held == 1 || extra_part,
                    "{}: outline {k} holds {held} bonded zones",
                    p.name
                );
            }
        }
    }
    assert!(zones > 300, "{zones} zones");
}

/// The closed through-cut contours of `shapes` that lie inside no other: the parts' outlines.
fn outermost_cuts(shapes: &[Shape]) -> Vec<Polygon<f64>> {
    let cuts: Vec<(Polygon<f64>, &Shape)> = shapes
        .iter()
        .filter_map(|s| through_cut(s).map(|poly| (poly, s)))
        .collect();
    cuts.iter()
        .enumerate()
        .filter(|(k, (_, s))| {
            !cuts.iter().enumerate().any(|(j, (other, _))| {
                j != *k
                    && s.points
                        .iter()
                        .all(|q| other.contains(&Coord { x: q[0], y: q[1] }))
            })
        })
        .map(|(_, (poly, _))| poly.clone())
        .collect()
}

#[test]
fn the_mark_check_finds_a_label_on_a_plate() {
    let plate = vec![[0.0, 0.0], [5.0, 0.0], [4.0, 20.0], [1.0, 20.0]];
    let stroke = |y: f64| Shape {
        layer: "ENGRAVE".into(),
        points: vec![[2.0, y], [3.0, y]],
        closed: false,
        radius: None,
        centre: None,
    };
    let zones = [plate];
    assert_eq!(mark_in_zone(&[stroke(10.0)], &zones, false), Some((0, 0)));
    assert_eq!(mark_in_zone(&[stroke(21.0)], &zones, false), None);
    // A PZT sheet's score lines bound its plates; they are not marks.
    let score = Shape {
        layer: "SCORE".into(),
        ..stroke(10.0)
    };
    assert_eq!(
        mark_in_zone(std::slice::from_ref(&score), &zones, true),
        None
    );
    assert_eq!(mark_in_zone(&[score], &zones, false), Some((0, 0)));
}
