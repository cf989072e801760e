//! One origin: the sheet corner at each file's origin and every shape at the same place in both formats.

use super::*;

pub(super) fn close(a: P, b: P) -> bool {
    (a[0] - b[0]).abs() <= TOL_MM && (a[1] - b[1]).abs() <= TOL_MM
}

pub(super) fn dist(a: P, b: P) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

/// The centre of a circle drawn through `points` that hold a diameter (an SVG circle's arc ends): the
/// middle of the first point and the point farthest from it.
pub(super) fn diameter_centre(points: &[P]) -> P {
    let a = points[0];
    let b = *points
        .iter()
        .max_by(|p, q| dist(**p, a).total_cmp(&dist(**q, a)))
        .unwrap();
    [(a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0]
}

/// Why the SVG shape `s` is not the DXF shape `d` at the same place, if it is not.
pub(super) fn mismatch(s: &Shape, d: &Shape) -> Option<String> {
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

/// The physical sheet where a file draws it: a PZT sheet's edge (the reference outline) is the sheet
/// exactly, and a panel's outline (a cut contour spanning most of the sheet) is centred on it.
pub(super) fn sheet_edges_where_drawn(p: &Pair, sheet: P) {
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

pub(super) fn bounds(points: &[P]) -> (P, P) {
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
