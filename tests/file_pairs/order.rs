//! Cut order: whatever lies inside a closed through-cut contour is cut before it, in both formats.

use super::*;

/// The points that stand for a shape when asking what lies inside what: its vertices, and for a
/// circle or arc points round its circle (the DXF gives the centre; the SVG its end points, a
/// circle's diameter among them).
pub(super) fn sample(s: &Shape) -> Vec<P> {
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
pub(super) fn through_cut(s: &Shape) -> Option<Polygon<f64>> {
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
pub(super) fn cut_after_their_outline(shapes: &[Shape]) -> Vec<(usize, usize)> {
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

#[test]
fn every_file_states_its_cut_order_and_part_sheets_follow_a_short_path() {
    let (mut stated, mut toured) = (0, 0);
    for p in pairs() {
        let n = &p.name;
        // Both files state the order they are cut in.
        if let Some(desc) = &p.desc {
            assert!(
                desc.contains("Cut order: the file's order"),
                "{n}.svg: {desc:?}"
            );
            assert!(
                p.dxf_comments
                    .iter()
                    .any(|c| c.starts_with("Cut order: the file's order")),
                "{n}.dxf: {:?}",
                p.dxf_comments
            );
            stated += 1;
        }
        let stem = n.rsplit('/').next().unwrap_or(n);
        if !(stem.starts_with("passive") || stem.starts_with("pyralux")) {
            continue;
        }
        // The parts' outlines (the cut contours inside no other) in file order, each the nearest
        // of those left to the one before, from the sheet's corner: box centre to box centre.
        for (format, shapes) in [("svg", &p.svg_shapes), ("dxf", &p.dxf_shapes)] {
            let contours: Vec<Polygon<f64>> = shapes.iter().filter_map(through_cut).collect();
            let outer: Vec<P> = contours
                .iter()
                .enumerate()
                .filter(|(k, c)| {
                    let q = c.exterior().0[0];
                    !contours
                        .iter()
                        .enumerate()
                        .any(|(j, o)| j != *k && o.contains(&q))
                })
                .map(|(_, c)| {
                    let ring: Vec<P> = c.exterior().0.iter().map(|q| [q.x, q.y]).collect();
                    let (lo, hi) = bounds(&ring);
                    [(lo[0] + hi[0]) / 2.0, (lo[1] + hi[1]) / 2.0]
                })
                .collect();
            let mut at = [0.0, 0.0];
            for k in 0..outer.len() {
                let d = |c: &P| (c[0] - at[0]).hypot(c[1] - at[1]);
                let nearest = outer[k..].iter().map(d).fold(f64::INFINITY, f64::min);
                assert!(
                    d(&outer[k]) <= nearest + TOL_MM,
                    "{n}.{format}: part {k} is {} mm on, the nearest left {nearest} mm",
                    d(&outer[k])
                );
                at = outer[k];
            }
            toured += 1;
        }
    }
    assert!(
        stated > 300 && toured > 20,
        "{stated} files state, {toured} toured"
    );
}
