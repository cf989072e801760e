use super::*;
use crate::layout::verify::{verify_break_order, verify_offcuts, verify_snappable, Violation};
use cam_geometry::signed_area;
use cam_nest::{verify_copies, verify_sheet, Clearance, NestItem};
use proptest::prelude::*;

fn plate(length_mm: f64, base_width_mm: f64, tip_width_mm: f64, count: usize) -> PlateSpec {
    PlateSpec {
        length_mm,
        base_width_mm,
        tip_width_mm,
        count,
    }
}

/// Thesis design C: l_p = 42.2 mm / 1.833, base 5.0 mm, tip 1.0 mm.
fn design_c(count: usize) -> PlateSpec {
    PlateSpec {
        length_mm: 42.2 / 1.833,
        base_width_mm: 5.0,
        tip_width_mm: 1.0,
        count,
    }
}

const PZT_SHEET: NestBin = NestBin {
    width_mm: 72.4,
    height_mm: 72.4,
    stock: usize::MAX,
};

/// [`layout_plates`] on `sheet` with at most `stock` sheets (any number when `None`), as sheets.
fn plates_on(
    items: &[PlateSpec],
    sheet: &NestBin,
    kerf: f64,
    margin: f64,
    strip: f64,
    stock: Option<usize>,
) -> Result<Vec<NestedBin>, LayoutError> {
    let sheet = NestBin {
        stock: stock.unwrap_or(usize::MAX),
        ..*sheet
    };
    layout_plates(items, &sheet, kerf, margin, strip).map(|s| s.bins)
}

/// Runs every verifier on a plate layout and checks the copies add up.
fn check_layout(
    items: &[PlateSpec],
    sheet: &NestBin,
    kerf: f64,
    margin: f64,
    sheets: &[NestedBin],
) {
    let nested: Vec<NestItem> = items
        .iter()
        .map(|p| NestItem {
            outline: plate_outline(p),
            demand: p.count,
            rotations_deg: vec![0.0, 90.0, 180.0, 270.0],
        })
        .collect();
    let clearance = Clearance {
        between_parts_mm: (kerf - 1e-9).max(0.0),
        to_edge_mm: (margin - 1e-9).max(0.0),
    };
    for layout in sheets {
        verify_snappable(layout, sheet)
            .unwrap_or_else(|v| panic!("sheet {} not snappable: {v:?}", layout.index));
        verify_break_order(layout, sheet)
            .unwrap_or_else(|v| panic!("sheet {} break order: {v:?}", layout.index));
        verify_sheet(&nested, sheet, clearance, layout.index, &layout.parts, 1e-9)
            .unwrap_or_else(|v| panic!("sheet {} invalid: {v}", layout.index));
    }
    verify_copies(&nested, sheets).unwrap();
}

#[test]
fn design_c_fills_a_pzt_sheet() {
    for (margin, expected) in [(0.5, 66), (0.0, 69)] {
        let items = [design_c(200)];
        let sheets = plates_on(&items, &PZT_SHEET, 0.03, margin, 0.0, None).unwrap();
        check_layout(&items, &PZT_SHEET, 0.03, margin, &sheets);
        let first = &sheets[0];
        let count = first.parts.len();
        assert!(count >= 66, "margin {margin}: {count} plates");
        assert_eq!(count, expected, "margin {margin}");
        let nominal_area = 3.0 * 42.2 / 1.833;
        for p in &first.parts {
            assert!((signed_area(&p.outline) - nominal_area).abs() < 1e-9);
        }
        let fill = count as f64 * nominal_area / (72.4 * 72.4);
        assert!(fill > 0.869, "margin {margin}: fill {fill}");
    }
}

#[test]
fn design_c_stock_limit() {
    let ok = plates_on(&[design_c(66)], &PZT_SHEET, 0.03, 0.5, 0.0, Some(1)).unwrap();
    assert_eq!(ok.len(), 1);
    let err = plates_on(&[design_c(133)], &PZT_SHEET, 0.03, 0.5, 0.0, Some(2)).unwrap_err();
    assert_eq!(err.to_string(), "needs 3 sheets but the stock is 2");
}

#[test]
fn design_c_score_lines_are_the_strip_pattern() {
    let sheets = plates_on(&[design_c(66)], &PZT_SHEET, 0.03, 0.5, 0.0, Some(1)).unwrap();
    let lines = &sheets[0].score_lines;
    let horizontal = lines.iter().filter(|l| l[0][1] == l[1][1]).count();
    // Bottom trim, two strip boundaries, top trim first; then 23 slanted lines in each of
    // 3 strips.
    assert_eq!(horizontal, 4);
    assert!(lines[..4].iter().all(|l| l[0][1] == l[1][1]));
    assert_eq!(lines.len(), 4 + 3 * 23);
    for l in lines.iter().filter(|l| l[0][1] == l[1][1]) {
        assert_eq!(
            (l[0][0], l[1][0]),
            (0.0, 72.4),
            "strip boundaries run edge to edge"
        );
    }
}

#[test]
fn verifier_catches_a_tampered_design_c_sheet() {
    let layout = &plates_on(&[design_c(66)], &PZT_SHEET, 0.03, 0.5, 0.0, Some(1)).unwrap()[0];
    // Drop a slanted line between two neighbours: they now share a cell.
    let mut missing = layout.clone();
    let slanted = missing
        .score_lines
        .iter()
        .rposition(|l| l[0][0] != l[1][0] && l[0][1] != l[1][1])
        .unwrap();
    missing.score_lines.remove(slanted - 1);
    let v = verify_snappable(&missing, &PZT_SHEET).unwrap_err();
    assert!(matches!(&v[..], [Violation::SharedCell { .. }]), "{v:?}");
    // Push one plate 0.02 mm towards its neighbour: below the kerf, and across a score line.
    let mut pushed = layout.clone();
    for p in &mut pushed.parts[1].outline {
        p[0] -= 0.02;
    }
    pushed.parts[1].translation[0] -= 0.02;
    let item = NestItem {
        outline: plate_outline(&design_c(66)),
        demand: 66,
        rotations_deg: vec![0.0, 90.0, 180.0, 270.0],
    };
    let clearance = Clearance {
        between_parts_mm: 0.03 - 1e-9,
        to_edge_mm: 0.5 - 1e-9,
    };
    let v = verify_sheet(&[item], &PZT_SHEET, clearance, 0, &pushed.parts, 1e-9);
    assert!(
        matches!(v, Err(cam_nest::NestViolation::TooClose { a: 0, b: 1, .. })),
        "{v:?}"
    );
    let v = verify_snappable(&pushed, &PZT_SHEET).unwrap_err();
    assert!(
        v.iter()
            .any(|x| matches!(x, Violation::ScoreLineCrossesPlate { part, .. } if part.index == 1)),
        "{v:?}"
    );
}

#[test]
fn rectangular_plates() {
    let items = [plate(50.0, 10.0, 10.0, 20)];
    let sheets = plates_on(&items, &PZT_SHEET, 0.03, 0.5, 0.0, None).unwrap();
    check_layout(&items, &PZT_SHEET, 0.03, 0.5, &sheets);
    // 7 upright in one 50 mm strip, 2 lying in the 21.4 mm left above it.
    assert_eq!(sheets[0].parts.len(), 9);
    assert_eq!(sheets.len(), 3);
    let lines = &sheets[0].score_lines;
    assert!(lines
        .iter()
        .all(|l| l[0][0] == l[1][0] || l[0][1] == l[1][1]));
}

#[test]
fn mixed_items_share_a_sheet() {
    let items = [design_c(40), plate(15.0, 4.0, 2.0, 30)];
    let sheets = plates_on(&items, &PZT_SHEET, 0.03, 0.5, 0.0, None).unwrap();
    check_layout(&items, &PZT_SHEET, 0.03, 0.5, &sheets);
    assert_eq!(sheets.len(), 1, "40 C plates leave room for 30 small ones");
    // Same input, same output.
    assert_eq!(
        sheets,
        plates_on(&items, &PZT_SHEET, 0.03, 0.5, 0.0, None).unwrap()
    );
}

#[test]
fn too_large_plate_is_reported() {
    let items = [plate(80.0, 10.0, 10.0, 1)];
    let err = plates_on(&items, &PZT_SHEET, 0.03, 0.5, 0.0, None).unwrap_err();
    assert!(matches!(err, LayoutError::TooLarge { item: 0, .. }));
    assert!(err
        .to_string()
        .starts_with("item 0 is larger than the sheet: 10.0 x 80.0 mm on a 72.4 x 72.4 mm sheet"));
}

#[test]
fn invalid_input_is_reported() {
    let mut bad = design_c(1);
    bad.tip_width_mm = 0.0;
    assert!(matches!(
        plates_on(&[bad], &PZT_SHEET, 0.03, 0.5, 0.0, None),
        Err(LayoutError::InvalidItem { item: 0, .. })
    ));
    assert!(matches!(
        plates_on(&[design_c(1)], &PZT_SHEET, -0.1, 0.5, 0.0, None),
        Err(LayoutError::InvalidParameter {
            name: "kerf_mm",
            ..
        })
    ));
}

#[test]
fn kerf_zero_plates_share_edges() {
    // Edges of two placed plates that coincide end to end (in either direction), within 1e-9 mm.
    let shared_edges = |sheet: &NestedBin| {
        let edges = |ring: &[Point]| -> Vec<(Point, Point)> {
            (0..ring.len())
                .map(|k| (ring[k], ring[(k + 1) % ring.len()]))
                .collect()
        };
        let same = |p: Point, q: Point| (p[0] - q[0]).abs() < 1e-9 && (p[1] - q[1]).abs() < 1e-9;
        let mut count = 0;
        for (i, a) in sheet.parts.iter().enumerate() {
            for b in &sheet.parts[i + 1..] {
                for (a0, a1) in edges(&a.outline) {
                    for (b0, b1) in edges(&b.outline) {
                        if (same(a0, b1) && same(a1, b0)) || (same(a0, b0) && same(a1, b1)) {
                            count += 1;
                        }
                    }
                }
            }
        }
        count
    };
    let items = [design_c(30)];
    let sheets = plates_on(&items, &PZT_SHEET, 0.0, 0.0, 0.0, None).unwrap();
    check_layout(&items, &PZT_SHEET, 0.0, 0.0, &sheets);
    // Turned neighbours in a strip share their slanted edge: at least one per plate but the first
    // of each strip (30 plates of design C fill at most a few strips).
    let shared = shared_edges(&sheets[0]);
    assert!(shared >= sheets[0].parts.len() - 4, "{shared} shared edges");
    // With a kerf between them, no two plates share an edge.
    let kerfed = plates_on(&items, &PZT_SHEET, 0.03, 0.0, 0.0, None).unwrap();
    assert_eq!(shared_edges(&kerfed[0]), 0);
}

/// 5 thicknesses of design C's 0.267 mm PZT: the shipped templates' narrowest snappable strip
/// (docs/cam.md §4, "Snappable strips").
const C_STRIP: f64 = 5.0 * 0.267;

#[test]
fn the_root_edge_sliver_of_the_old_layout_is_caught_and_gone() {
    // Without the rule, a 0.3 mm margin leaves 0.3 - 0.015 = 0.285 mm between the sheet edge and
    // the plates' root score line, about one PZT thickness: the offcut check must name it.
    let old = &plates_on(&[design_c(68)], &PZT_SHEET, 0.03, 0.3, 0.0, None).unwrap()[0];
    let v = verify_offcuts(old, &PZT_SHEET, C_STRIP).unwrap_err();
    assert!(
        v.iter()
            .any(|x| matches!(x, Violation::NarrowOffcut { width_mm, .. }
            if (width_mm - 0.285).abs() < 1e-6)),
        "{v:?}"
    );
    // With it, every offcut is at least the strip and the sheet still takes 2 strips of plates.
    let items = [design_c(68)];
    let sheets = plates_on(&items, &PZT_SHEET, 0.03, 0.3, C_STRIP, None).unwrap();
    check_layout(&items, &PZT_SHEET, 0.03, 0.3, &sheets);
    for layout in &sheets {
        verify_offcuts(layout, &PZT_SHEET, C_STRIP).unwrap();
    }
    // The trim strip along the root edge: the first full-width line is kerf/2 + strip from the edge
    // (margin 0.3 < 0.015 + 1.335), so the plates sit 1.35 mm in.
    let lowest = sheets[0]
        .parts
        .iter()
        .flat_map(|p| p.outline.iter().map(|q| q[1]))
        .fold(f64::INFINITY, f64::min);
    assert!((lowest - (0.015 + C_STRIP)).abs() < 1e-9, "{lowest}");
    let plates = sheets[0].parts.len();
    assert!(plates >= 60, "{plates} plates on the first sheet");
}

#[test]
fn offcut_check_measures_strips_wedges_and_triangles() {
    // A 10 x 10 sheet, one line 0.4 from the bottom edge: a 0.4 mm strip, no plate in it.
    let sheet = NestBin {
        width_mm: 10.0,
        height_mm: 10.0,
        stock: usize::MAX,
    };
    let mut layout = NestedBin {
        index: 0,
        parts: vec![],
        utilization: 0.0,
        score_lines: vec![[[0.0, 0.4], [10.0, 0.4]]],
    };
    let width = |l: &NestedBin, min: f64| match verify_offcuts(l, &sheet, min) {
        Ok(()) => None,
        Err(v) => v.iter().find_map(|x| match x {
            Violation::NarrowOffcut { width_mm, .. } => Some(*width_mm),
            _ => None,
        }),
    };
    assert!((width(&layout, 0.5).unwrap() - 0.4).abs() < 1e-12);
    assert_eq!(width(&layout, 0.4), None);
    // A slanted line from (1, 0) to (2, 10): the wedge left of it is 1 mm wide at the bottom along
    // x, so 1 * cos(atan(0.1)) = 0.995 mm square to the line.
    layout.score_lines = vec![[[1.0, 0.0], [2.0, 10.0]]];
    let cos = 1.0 / (1.0f64 + 0.01).sqrt();
    assert!((width(&layout, 2.0).unwrap() - cos).abs() < 1e-12);
    // A line from (0, 9) to (3, 10) cuts a triangle off the top-left corner: its height over the
    // line from the corner (0, 10) is 3 / sqrt(10).
    layout.score_lines = vec![[[0.0, 9.0], [3.0, 10.0]]];
    assert!((width(&layout, 2.0).unwrap() - 3.0 / 10f64.sqrt()).abs() < 1e-12);
    // A piece holding a plate is not an offcut, however narrow.
    layout.score_lines = vec![[[0.0, 0.4], [10.0, 0.4]]];
    layout.parts = vec![cam_nest::PlacedPart::at(
        0,
        0,
        &[[0.0, 0.0], [1.0, 0.0], [1.0, 0.3], [0.0, 0.3]],
        0.0,
        [2.0, 0.05],
    )];
    assert_eq!(width(&layout, 0.5), None);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]
    #[test]
    fn random_trapezoids_verify_and_leave_no_sliver(
        length in 5.0..60.0f64,
        base in 1.0..25.0f64,
        tip in 0.3..25.0f64,
        count in 1usize..40,
        kerf in 0.0..0.05f64,
        margin in 0.0..1.0f64,
        strip in prop_oneof![Just(0.0), 0.25..2.5f64],
        side in 20.0..100.0f64,
        second in proptest::option::of((5.0..30.0f64, 1.0..10.0f64, 0.3..10.0f64, 1usize..20)),
    ) {
        let sheet = NestBin { width_mm: side, height_mm: side * 0.8, stock: usize::MAX };
        let mut items = vec![PlateSpec { length_mm: length, base_width_mm: base, tip_width_mm: tip, count }];
        if let Some((l, b, t, n)) = second {
            items.push(PlateSpec { length_mm: l, base_width_mm: b, tip_width_mm: t, count: n });
        }
        match plates_on(&items, &sheet, kerf, margin, strip, None) {
            Ok(sheets) => {
                check_layout(&items, &sheet, kerf, margin, &sheets);
                for layout in &sheets {
                    verify_offcuts(layout, &sheet, strip)
                        .unwrap_or_else(|v| panic!("sheet {}: {v:?}", layout.index));
                }
            }
            Err(LayoutError::TooLarge { item, .. }) => {
                // Across the strip the plate needs its length inside the edge clearance; along it,
                // its width plus at most `strip sec θ + kerf/2 sec θ + |b - t|/2 + kerf/2 |m|` at each
                // end for a snappable wedge (the run end's offcut clearance bound).
                let s = &items[item];
                let edge = if margin <= kerf / 2.0 { margin } else { margin.max(kerf / 2.0 + strip) };
                let w = s.base_width_mm.max(s.tip_width_mm);
                let slope = (s.base_width_mm - s.tip_width_mm).abs() / (2.0 * s.length_mm);
                let sec = (1.0 + slope * slope).sqrt();
                // Without the rule (strip 0) a run needs only the edge clearance.
                let end = if strip == 0.0 { edge } else { edge.max((strip + kerf / 2.0) * sec + 2.0 * slope * s.length_mm / 2.0 + kerf / 2.0 * slope) };
                let fits = |along: f64, across: f64, u: f64, v: f64| {
                    along + 2.0 * end <= u + 1e-9 && across + 2.0 * edge <= v + 1e-9
                };
                prop_assert!(!fits(w, s.length_mm, side, side * 0.8) && !fits(w, s.length_mm, side * 0.8, side));
            }
            Err(e) => prop_assert!(false, "unexpected error {e}"),
        }
    }
}
