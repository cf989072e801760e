use super::*;
use cam_nest::PlacedPart;

const SHEET: NestBin = NestBin {
    width_mm: 50.0,
    height_mm: 30.0,
    stock: 1,
};

fn square(item: usize, copy: usize, x: f64, y: f64, rotation_deg: f64) -> PlacedPart {
    PlacedPart {
        item,
        copy,
        rotation_deg,
        translation: [x, y],
        outline: vec![[x, y], [x + 10.0, y], [x + 10.0, y + 10.0], [x, y + 10.0]],
    }
}

fn layout(parts: Vec<PlacedPart>, score_lines: Vec<[Point; 2]>) -> NestedBin {
    NestedBin {
        index: 0,
        parts,
        utilization: 0.0,
        score_lines,
    }
}

/// Two squares in two cells of a vertical break, then a horizontal break on the left.
fn good() -> NestedBin {
    layout(
        vec![square(0, 0, 2.0, 2.0, 0.0), square(0, 1, 20.0, 2.0, 180.0)],
        vec![[[15.0, 0.0], [15.0, 30.0]], [[0.0, 20.0], [15.0, 20.0]]],
    )
}

#[test]
fn a_good_layout_passes() {
    verify_snappable(&good(), &SHEET).unwrap();
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
