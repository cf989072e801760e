//! The two readers, sharing no code with the writers: roxmltree and svgtypes for the SVG, the `dxf` crate for
//! the DXF, each file's shapes in sheet millimetres.

use super::*;

/// A length in mm (`72.4mm`); the files must give their page in mm.
pub(super) fn mm(name: &str, value: Option<&str>) -> f64 {
    let l: svgtypes::Length = value
        .unwrap_or_else(|| panic!("{name}: no page size"))
        .parse()
        .unwrap();
    assert_eq!(l.unit, svgtypes::LengthUnit::Mm, "{name}: page not in mm");
    l.number
}

pub(super) fn read_svg(name: &str, text: &str) -> SvgRead {
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
pub(super) fn element_shape(node: roxmltree::Node, to_sheet: &dyn Fn(f64, f64) -> P) -> Shape {
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
pub(super) fn path_shape(d: &str, to_sheet: &dyn Fn(f64, f64) -> P) -> Shape {
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
pub(super) fn read_dxf(name: &str, path: &Path) -> (Vec<Shape>, [f64; 4], Vec<String>) {
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
