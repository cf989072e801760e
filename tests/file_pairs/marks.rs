//! Marks: no engraving in a bonded face, and every sheet of bonded parts marks its bonded zones.

use super::*;

/// A ring as a `geo` polygon.
pub(super) fn polygon_of(ring: &[P]) -> Polygon<f64> {
    Polygon::new(
        LineString::from(ring.iter().map(|p| (p[0], p[1])).collect::<Vec<_>>()),
        vec![],
    )
}

/// Marks: what a file engraves, and what it scores where the score is not a PZT snap line.
pub(super) fn is_mark(s: &Shape, pzt_sheet: bool) -> bool {
    s.layer == "ENGRAVE" || (s.layer == "SCORE" && !pzt_sheet)
}

/// The first mark of `shapes` that touches a zone: `(mark, zone)` indices.
pub(super) fn mark_in_zone(
    shapes: &[Shape],
    zones: &[Vec<P>],
    pzt_sheet: bool,
) -> Option<(usize, usize)> {
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
pub(super) fn holds_bonded_parts(file: &str) -> bool {
    let stem = file.split('_').next().unwrap();
    // The PZT test coupon is scored on an offcut and holds no plate.
    if stem.starts_with("pzt-coupon-") {
        return false;
    }
    ["pzt-", "passive-", "pyralux-"]
        .iter()
        .any(|k| stem.starts_with(k))
        || (stem.starts_with("linkage-")
            && ["-carbon-", "-adhesive-", "-film-"]
                .iter()
                .any(|k| stem.contains(k)))
}

/// The plates a cut-sheet run's report places on PZT sheet `n`.
pub(super) fn plates_on(report: &serde_json::Value, n: &str) -> usize {
    let at = format!(": PZT sheet {n}");
    report["placement_map"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|line| line.as_str().unwrap().ends_with(&at))
        .count()
}

/// The closed through-cut contours of `shapes` that lie inside no other: the parts' outlines.
pub(super) fn outermost_cuts(shapes: &[Shape]) -> Vec<Polygon<f64>> {
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
