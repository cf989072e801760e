use super::*;
use crate::layout::verify::{
    verify_break_order, verify_copies, verify_outlines, verify_sheet_edges, verify_snappable,
    Violation,
};
use cam_geometry::signed_area;
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

const PZT_SHEET: Sheet = Sheet {
    width_mm: 72.4,
    height_mm: 72.4,
};

/// Runs every verifier on a plate layout and checks the copies add up.
fn check_layout(
    items: &[PlateSpec],
    sheet: &Sheet,
    kerf: f64,
    margin: f64,
    sheets: &[SheetLayout],
) {
    let any_rotation = |_: usize| vec![0.0, 90.0, 180.0, 270.0];
    let nominal = |i: usize| plate_outline(&items[i]);
    for layout in sheets {
        verify_snappable(layout, sheet)
            .unwrap_or_else(|v| panic!("sheet {} not snappable: {v:?}", layout.sheet_index));
        verify_break_order(layout, sheet)
            .unwrap_or_else(|v| panic!("sheet {} break order: {v:?}", layout.sheet_index));
        verify_sheet_edges(layout, sheet, kerf - 1e-9, margin - 1e-9, &any_rotation)
            .unwrap_or_else(|v| panic!("sheet {} invalid: {v:?}", layout.sheet_index));
        verify_outlines(layout, &nominal, 1e-9)
            .unwrap_or_else(|v| panic!("sheet {} outlines: {v:?}", layout.sheet_index));
    }
    let counts: Vec<usize> = items.iter().map(|s| s.count).collect();
    verify_copies(sheets, &counts).unwrap();
}

#[test]
fn design_c_fills_a_pzt_sheet() {
    for (margin, expected) in [(0.5, 66), (0.0, 69)] {
        let items = [design_c(200)];
        let sheets = layout_plates(&items, &PZT_SHEET, 0.03, margin, None).unwrap();
        check_layout(&items, &PZT_SHEET, 0.03, margin, &sheets);
        let first = &sheets[0];
        let count = first.placements.len();
        assert!(count >= 66, "margin {margin}: {count} plates");
        assert_eq!(count, expected, "margin {margin}");
        let nominal_area = 3.0 * 42.2 / 1.833;
        for p in &first.placements {
            assert!((signed_area(&p.outline) - nominal_area).abs() < 1e-9);
        }
        let fill = count as f64 * nominal_area / (72.4 * 72.4);
        assert!(fill > 0.869, "margin {margin}: fill {fill}");
    }
}

#[test]
fn design_c_stock_limit() {
    let ok = layout_plates(&[design_c(66)], &PZT_SHEET, 0.03, 0.5, Some(1)).unwrap();
    assert_eq!(ok.len(), 1);
    let err = layout_plates(&[design_c(133)], &PZT_SHEET, 0.03, 0.5, Some(2)).unwrap_err();
    assert_eq!(err.to_string(), "needs 3 sheets but the stock is 2");
}

#[test]
fn design_c_score_lines_are_the_strip_pattern() {
    let sheets = layout_plates(&[design_c(66)], &PZT_SHEET, 0.03, 0.5, Some(1)).unwrap();
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
    let layout = &layout_plates(&[design_c(66)], &PZT_SHEET, 0.03, 0.5, Some(1)).unwrap()[0];
    let any = |_: usize| vec![0.0, 90.0, 180.0, 270.0];
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
    for p in &mut pushed.placements[1].outline {
        p[0] -= 0.02;
    }
    let v = verify_sheet_edges(&pushed, &PZT_SHEET, 0.03 - 1e-9, 0.5 - 1e-9, &any).unwrap_err();
    assert!(
        matches!(&v[..], [Violation::Gap { a, b, .. }] if a.index == 0 && b.index == 1),
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
    let sheets = layout_plates(&items, &PZT_SHEET, 0.03, 0.5, None).unwrap();
    check_layout(&items, &PZT_SHEET, 0.03, 0.5, &sheets);
    // 7 upright in one 50 mm strip, 2 lying in the 21.4 mm left above it.
    assert_eq!(sheets[0].placements.len(), 9);
    assert_eq!(sheets.len(), 3);
    let lines = &sheets[0].score_lines;
    assert!(lines
        .iter()
        .all(|l| l[0][0] == l[1][0] || l[0][1] == l[1][1]));
}

#[test]
fn mixed_items_share_a_sheet() {
    let items = [design_c(40), plate(15.0, 4.0, 2.0, 30)];
    let sheets = layout_plates(&items, &PZT_SHEET, 0.03, 0.5, None).unwrap();
    check_layout(&items, &PZT_SHEET, 0.03, 0.5, &sheets);
    assert_eq!(sheets.len(), 1, "40 C plates leave room for 30 small ones");
    // Same input, same output.
    assert_eq!(
        sheets,
        layout_plates(&items, &PZT_SHEET, 0.03, 0.5, None).unwrap()
    );
}

#[test]
fn too_large_plate_is_reported() {
    let items = [plate(80.0, 10.0, 10.0, 1)];
    let err = layout_plates(&items, &PZT_SHEET, 0.03, 0.5, None).unwrap_err();
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
        layout_plates(&[bad], &PZT_SHEET, 0.03, 0.5, None),
        Err(LayoutError::InvalidItem { item: 0, .. })
    ));
    assert!(matches!(
        layout_plates(&[design_c(1)], &PZT_SHEET, -0.1, 0.5, None),
        Err(LayoutError::InvalidParameter {
            name: "kerf_mm",
            ..
        })
    ));
}

#[test]
fn kerf_zero_plates_share_edges() {
    let items = [design_c(30)];
    let sheets = layout_plates(&items, &PZT_SHEET, 0.0, 0.0, None).unwrap();
    check_layout(&items, &PZT_SHEET, 0.0, 0.0, &sheets);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]
    #[test]
    fn random_trapezoids_verify(
        length in 5.0..60.0f64,
        base in 1.0..25.0f64,
        tip in 0.3..25.0f64,
        count in 1usize..40,
        kerf in 0.0..0.05f64,
        margin in 0.0..1.0f64,
        side in 20.0..100.0f64,
        second in proptest::option::of((5.0..30.0f64, 1.0..10.0f64, 0.3..10.0f64, 1usize..20)),
    ) {
        let sheet = Sheet { width_mm: side, height_mm: side * 0.8 };
        let mut items = vec![PlateSpec { length_mm: length, base_width_mm: base, tip_width_mm: tip, count }];
        if let Some((l, b, t, n)) = second {
            items.push(PlateSpec { length_mm: l, base_width_mm: b, tip_width_mm: t, count: n });
        }
        match layout_plates(&items, &sheet, kerf, margin, None) {
            Ok(sheets) => check_layout(&items, &sheet, kerf, margin, &sheets),
            Err(LayoutError::TooLarge { item, .. }) => {
                let s = &items[item];
                let room = |a: f64, b: f64| a <= side - 2.0 * margin + 1e-9 && b <= side * 0.8 - 2.0 * margin + 1e-9;
                let w = s.base_width_mm.max(s.tip_width_mm);
                prop_assert!(!room(w, s.length_mm) && !room(s.length_mm, w));
            }
            Err(e) => prop_assert!(false, "unexpected error {e}"),
        }
    }
}
