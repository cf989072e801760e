use super::*;
use crate::layout::placement::Placement;

const SHEET: Sheet = Sheet {
    width_mm: 50.0,
    height_mm: 30.0,
};

fn square(item: usize, copy: usize, x: f64, y: f64, rotation_deg: f64) -> Placement {
    Placement {
        item,
        copy,
        rotation_deg,
        offset: [x, y],
        outline: vec![[x, y], [x + 10.0, y], [x + 10.0, y + 10.0], [x, y + 10.0]],
    }
}

fn layout(placements: Vec<Placement>, score_lines: Vec<[Point; 2]>) -> SheetLayout {
    SheetLayout {
        sheet_index: 0,
        placements,
        score_lines,
    }
}

fn upright(_: usize) -> Vec<f64> {
    vec![0.0, 180.0]
}

/// Two squares in two cells of a vertical break, then a horizontal break on the left.
fn good() -> SheetLayout {
    layout(
        vec![square(0, 0, 2.0, 2.0, 0.0), square(0, 1, 20.0, 2.0, 180.0)],
        vec![[[15.0, 0.0], [15.0, 30.0]], [[0.0, 20.0], [15.0, 20.0]]],
    )
}

#[test]
fn a_good_layout_passes() {
    verify_sheet(&good(), &SHEET, 1.0, &upright).unwrap();
    verify_snappable(&good(), &SHEET).unwrap();
}

#[test]
fn catches_overlap() {
    let l = layout(
        vec![square(0, 0, 2.0, 2.0, 0.0), square(0, 1, 7.0, 4.0, 0.0)],
        vec![],
    );
    let v = verify_sheet(&l, &SHEET, 1.0, &upright).unwrap_err();
    assert!(
        matches!(&v[..], [Violation::Overlap { area_mm2, .. }] if (area_mm2 - 40.0).abs() < 1e-9),
        "{v:?}"
    );
    assert_eq!(
        v[0].to_string(),
        "part 0 (item 0 copy 0) and part 1 (item 0 copy 1) overlap (40.000000 mm²)"
    );
}

#[test]
fn catches_part_outside_sheet() {
    let l = layout(vec![square(0, 0, 45.0, 2.0, 0.0)], vec![]);
    let v = verify_sheet(&l, &SHEET, 1.0, &upright).unwrap_err();
    assert!(matches!(&v[..], [Violation::OutsideSheet { .. }]), "{v:?}");
}

#[test]
fn catches_small_gaps() {
    let l = layout(
        vec![square(0, 0, 0.5, 2.0, 0.0), square(0, 1, 11.2, 2.0, 0.0)],
        vec![],
    );
    let v = verify_sheet(&l, &SHEET, 1.0, &upright).unwrap_err();
    assert_eq!(v.len(), 2, "{v:?}");
    assert!(
        matches!(v[0], Violation::EdgeGap { distance_mm, .. } if (distance_mm - 0.5).abs() < 1e-12)
    );
    assert!(
        matches!(v[1], Violation::Gap { distance_mm, .. } if (distance_mm - 0.7).abs() < 1e-12)
    );
    // The same layout passes a looser requirement.
    verify_sheet(&l, &SHEET, 0.5, &upright).unwrap();
}

#[test]
fn catches_forbidden_rotation() {
    let l = layout(vec![square(0, 0, 2.0, 2.0, 90.0)], vec![]);
    let v = verify_sheet(&l, &SHEET, 1.0, &upright).unwrap_err();
    assert!(
        matches!(
            &v[..],
            [Violation::ForbiddenRotation {
                rotation_deg: 90.0,
                ..
            }]
        ),
        "{v:?}"
    );
    // 360 is the same as 0.
    let l = layout(vec![square(0, 0, 2.0, 2.0, 360.0)], vec![]);
    verify_sheet(&l, &SHEET, 1.0, &upright).unwrap();
}

#[test]
fn catches_outline_that_does_not_match_its_rotation() {
    let nominal = |_: usize| vec![[0.0, 0.0], [10.0, 0.0], [10.0, 10.0], [0.0, 10.0]];
    let mut l = layout(vec![square(0, 0, 2.0, 2.0, 0.0)], vec![]);
    verify_outlines(&l, &nominal, 1e-9).unwrap();
    l.placements[0].rotation_deg = 90.0;
    let v = verify_outlines(&l, &nominal, 1e-9).unwrap_err();
    assert!(
        matches!(&v[..], [Violation::OutlineMismatch { .. }]),
        "{v:?}"
    );
    // Stated as a quarter turn with the matching offset, the same square agrees.
    l.placements[0].offset = [12.0, 2.0];
    verify_outlines(&l, &nominal, 1e-9).unwrap();
}

#[test]
fn catches_score_line_in_mid_air() {
    let mut l = good();
    l.score_lines[1] = [[0.0, 20.0], [12.0, 20.0]];
    let v = verify_snappable(&l, &SHEET).unwrap_err();
    assert!(
        matches!(v[0], Violation::ScoreLineMidAir { line: 1, x, y } if x == 12.0 && y == 20.0),
        "{v:?}"
    );
}

#[test]
fn catches_score_line_through_a_plate() {
    let mut l = good();
    l.score_lines.push([[0.0, 7.0], [15.0, 7.0]]);
    let v = verify_snappable(&l, &SHEET).unwrap_err();
    assert!(
        v.iter().any(
            |x| matches!(x, Violation::ScoreLineCrossesPlate { line: 2, part } if part.index == 0)
        ),
        "{v:?}"
    );
}

#[test]
fn catches_plates_sharing_a_cell() {
    let mut l = good();
    l.score_lines.clear();
    let v = verify_snappable(&l, &SHEET).unwrap_err();
    assert!(matches!(&v[..], [Violation::SharedCell { .. }]), "{v:?}");
}

#[test]
fn catches_pinwheel() {
    // Four lines around a square, each ending on the next: none can be snapped first.
    let pinwheel = layout(
        vec![],
        vec![
            [[20.0, 0.0], [20.0, 20.0]],
            [[50.0, 20.0], [10.0, 20.0]],
            [[10.0, 30.0], [10.0, 10.0]],
            [[0.0, 10.0], [20.0, 10.0]],
        ],
    );
    let v = verify_snappable(&pinwheel, &SHEET).unwrap_err();
    assert!(
        matches!(&v[..], [Violation::NotGuillotine { lines }] if lines.len() == 4),
        "{v:?}"
    );
    // Run one of them edge to edge and there is an order again.
    let mut ok = pinwheel;
    ok.score_lines[3] = [[0.0, 10.0], [50.0, 10.0]];
    verify_snappable(&ok, &SHEET).unwrap();
}

#[test]
fn catches_missing_and_doubled_copies() {
    let sheets = [good()];
    verify_copies(&sheets, &[2]).unwrap();
    let v = verify_copies(&sheets, &[3]).unwrap_err();
    assert_eq!(
        v[0].to_string(),
        "item 0: copies placed [0, 1], wanted each of 0..3 once"
    );
    let twice = [good(), good()];
    assert!(verify_copies(&twice, &[2]).is_err());
    verify_stock(&twice, 2).unwrap();
    assert_eq!(
        verify_stock(&twice, 1).unwrap_err()[0].to_string(),
        "the layout uses 2 sheets but the stock is 1"
    );
}

#[test]
fn catches_lines_listed_out_of_break_order() {
    let l = good();
    verify_break_order(&l, &SHEET).unwrap();
    let mut swapped = l;
    swapped.score_lines.reverse();
    // Still snappable in some order, but not in the order listed.
    verify_snappable(&swapped, &SHEET).unwrap();
    let v = verify_break_order(&swapped, &SHEET).unwrap_err();
    assert!(
        matches!(v[..], [Violation::OutOfOrder { line: 0, x, y }] if x == 15.0 && y == 20.0),
        "{v:?}"
    );
}

#[test]
fn the_layout_and_the_nest_verifier_reject_the_same_too_close_pair() {
    // Two squares 0.7 mm apart, 2 mm from every edge, where 1 mm is required.
    let l = layout(
        vec![square(0, 0, 2.0, 2.0, 0.0), square(0, 1, 12.7, 2.0, 0.0)],
        vec![],
    );
    let v = verify_sheet(&l, &SHEET, 1.0, &upright).unwrap_err();
    assert!(
        matches!(&v[..], [Violation::Gap { a, b, distance_mm, .. }]
            if a.index == 0 && b.index == 1 && (distance_mm - 0.7).abs() < 1e-12),
        "{v:?}"
    );
    assert_eq!(
        v[0].to_string(),
        "part 0 (item 0 copy 0) and part 1 (item 0 copy 1) are 0.700000 mm apart, less than the required 1.000000 mm"
    );

    let items = [cam_nest::NestItem {
        outline: vec![[0.0, 0.0], [10.0, 0.0], [10.0, 10.0], [0.0, 10.0]],
        demand: 2,
        rotations_deg: vec![0.0],
    }];
    let bin = cam_nest::NestBin {
        width_mm: SHEET.width_mm,
        height_mm: SHEET.height_mm,
        stock: 1,
    };
    let parts: Vec<cam_nest::PlacedPart> = l
        .placements
        .iter()
        .map(|p| cam_nest::PlacedPart {
            item: p.item,
            copy: p.copy,
            rotation_deg: p.rotation_deg,
            translation: p.offset,
            outline: p.outline.clone(),
        })
        .collect();
    let clearance = cam_nest::Clearance::uniform(1.0);
    let nest = cam_nest::verify_sheet(&items, &bin, clearance, 0, &parts, 1e-9);
    assert!(
        matches!(nest, Err(cam_nest::NestViolation::TooClose { a: 0, b: 1, distance_mm, .. })
            if (distance_mm - 0.7).abs() < 1e-12),
        "{nest:?}"
    );
    // Half a millimetre is kept, by both.
    verify_sheet(&l, &SHEET, 0.5, &upright).unwrap();
    let half = cam_nest::Clearance::uniform(0.5);
    assert_eq!(
        cam_nest::verify_sheet(&items, &bin, half, 0, &parts, 1e-9),
        Ok(())
    );
}
