//! The stock label of a part sheet (PZT plates, passive parts, Pyralux, extra parts): the sheet's
//! name, material, thickness and size, drawn where no part is, so that a sheet off the bed still says
//! what it is (docs/cam.md §3 "Stock labels").
//!
//! The label is placed after the parts, in the largest-text place left free: the nester fills the
//! sheet first, and a label must never cost a part. A sheet with no room left carries none; its file
//! name, title and metadata still name the stock, and the report counts the sheets without a label.

use crate::drawing::decimal::fmt_mm;
use crate::drawing::label::{label_strokes, label_width};
use crate::drawing::model::{Drawing, Stock};
use cam_geometry::{Bounds, Point};

/// Label heights tried, largest first, mm: 1.5 mm reads at arm's length; 1 mm is the smallest the
/// ProtoLaser engraves legibly (the part labels' size).
const HEIGHTS_MM: [f64; 2] = [1.5, 1.0];

/// Clearance from the label's strokes to every drawn shape and to the sheet's unusable border, mm:
/// the engraved line's own width (about 0.1 mm) and as much again, so a label is never read as part
/// of an outline.
const CLEARANCE_MM: f64 = 0.2;

/// The texts a sheet's label may carry, longest first: name, material, thickness and size; then
/// name, the material's first word and thickness. Characters the stroke font lacks become spaces,
/// so a material's brackets do not come out as boxes.
fn texts(name: &str, stock: &Stock, width_mm: f64, height_mm: f64) -> [String; 2] {
    let clean: String = stock
        .material
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '.' {
                c
            } else {
                ' '
            }
        })
        .collect();
    let words: Vec<&str> = clean.split_whitespace().collect();
    let t = fmt_mm(stock.thickness_mm);
    [
        format!(
            "{name} {} {t}mm {}x{}mm",
            words.join(" "),
            fmt_mm(width_mm),
            fmt_mm(height_mm)
        ),
        format!("{name} {} {t}mm", words.first().copied().unwrap_or("")),
    ]
}

/// An axis-aligned box `(lo, hi)`.
pub type Box2 = (Point, Point);

fn overlaps(a: &Box2, b: &Box2) -> bool {
    a.0[0] < b.1[0] && b.0[0] < a.1[0] && a.0[1] < b.1[1] && b.0[1] < a.1[1]
}

/// The lowest-left-most free place, searched from the top of the sheet down, for a `w` x `h` box
/// within `lo..hi` that overlaps none of `taken`: the candidate corners are the usable area's own
/// and those just past each taken box (the places a free box can first touch), so the search is exact
/// for boxes and quadratic only in the shapes drawn.
fn free_place(taken: &[Box2], w: f64, h: f64, lo: Point, hi: Point) -> Option<Point> {
    let mut xs: Vec<f64> = std::iter::once(lo[0])
        .chain(taken.iter().map(|b| b.1[0]))
        .filter(|x| x + w <= hi[0])
        .collect();
    let mut ys: Vec<f64> = std::iter::once(hi[1] - h)
        .chain(taken.iter().map(|b| b.0[1] - h))
        .filter(|y| *y >= lo[1] && y + h <= hi[1])
        .collect();
    xs.sort_by(f64::total_cmp);
    xs.dedup();
    ys.sort_by(|a, b| b.total_cmp(a));
    ys.dedup();
    ys.iter().find_map(|&y| {
        xs.iter().find_map(|&x| {
            let candidate = ([x, y], [x + w, y + h]);
            (!taken.iter().any(|b| overlaps(b, &candidate))).then_some([x, y])
        })
    })
}

/// The bounding box of a placed part's outline, grown by the clearance: what a label keeps out of.
pub fn part_box(ring: &[Point]) -> Box2 {
    let b = Bounds::of(ring);
    (
        [b.min[0] - CLEARANCE_MM, b.min[1] - CLEARANCE_MM],
        [b.max[0] + CLEARANCE_MM, b.max[1] + CLEARANCE_MM],
    )
}

/// The strokes of the stock label of `drawing` (a part sheet named `name`, whose outer `margin_mm`
/// is unusable), placed clear of `parts` (each a [`part_box`]); `None` when no text fits anywhere.
/// The parts, not every stroke drawn: a part's own label and holes lie inside it, and a search over
/// their strokes would cost a large quantity seconds for nothing.
pub fn sheet_label(
    drawing: &Drawing,
    name: &str,
    margin_mm: f64,
    parts: &[Box2],
) -> Option<Vec<Vec<Point>>> {
    let stock = drawing.stock.as_ref()?;
    let inset = margin_mm + CLEARANCE_MM;
    let (lo, hi) = (
        [inset, inset],
        [drawing.width_mm - inset, drawing.height_mm - inset],
    );
    for height in HEIGHTS_MM {
        for text in texts(name, stock, drawing.width_mm, drawing.height_mm) {
            let w = label_width(&text, height);
            if let Some(at) = free_place(parts, w, height, lo, hi) {
                return Some(label_strokes(&text, at, height));
            }
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::drawing::model::Operation;

    fn stock() -> Stock {
        Stock {
            material: "PZT-5H (PZT sheet (Piezo Systems))".into(),
            thickness_mm: 0.267,
            kerf_mm: 0.0,
            fibre_axis: None,
        }
    }

    fn extent(strokes: &[Vec<Point>]) -> Box2 {
        let b = Bounds::of(&strokes.concat());
        (b.min, b.max)
    }

    #[test]
    fn the_label_names_the_stock_without_glyphs_the_font_lacks() {
        let [long, short] = texts("pzt-3", &stock(), 72.4, 72.4);
        assert_eq!(
            long,
            "pzt-3 PZT-5H PZT sheet Piezo Systems 0.267mm 72.4x72.4mm"
        );
        assert_eq!(short, "pzt-3 PZT-5H 0.267mm");
    }

    #[test]
    fn the_label_goes_where_no_part_is_and_inside_the_margin() {
        let d = Drawing::on_stock("s", 72.4, 72.4, stock());
        // Parts over the lower two thirds and a column up the right side.
        let parts = [
            part_box(&[[1.0, 1.0], [70.0, 1.0], [70.0, 48.0], [1.0, 48.0]]),
            part_box(&[[60.0, 48.0], [70.0, 48.0], [70.0, 71.0], [60.0, 71.0]]),
        ];
        let strokes = sheet_label(&d, "pzt-1", 0.3, &parts).expect("room above the parts");
        let (lo, hi) = extent(&strokes);
        assert!(lo[0] >= 0.5 - 1e-9 && lo[1] > 48.2 && hi[1] <= 72.4 - 0.5 + 1e-9);
        assert!(
            hi[0] < 60.0 - CLEARANCE_MM + 1e-9,
            "clear of the column: {hi:?}"
        );
    }

    #[test]
    fn a_full_sheet_carries_no_label_and_is_counted() {
        let mut d = Drawing::on_stock("s", 72.4, 72.4, stock());
        let parts = [part_box(&[
            [0.5, 0.5],
            [71.9, 0.5],
            [71.9, 71.9],
            [0.5, 71.9],
        ])];
        assert!(sheet_label(&d, "pzt-1", 0.3, &parts).is_none());
        // What the builders call: a full sheet is counted for the report and gets no strokes; a sheet
        // with room gets its label and is not counted.
        let mut drawn = super::super::jobs::Drawn::new(None);
        drawn.label_sheet(&mut d, "pzt-1", 0.3, &parts, Operation::Reference);
        assert_eq!((drawn.unlabelled_sheets, d.items().len()), (1, 0));
        drawn.label_sheet(&mut d, "pzt-2", 0.3, &[], Operation::Reference);
        assert_eq!(drawn.unlabelled_sheets, 1);
        assert!(!d.items().is_empty());
        assert!(d.items().iter().all(|(op, _)| *op == Operation::Reference));
    }

    #[test]
    fn a_narrow_strip_above_the_parts_holds_the_label() {
        let d = Drawing::on_stock("s", 72.4, 72.4, stock());
        let parts = [part_box(&[
            [0.5, 0.5],
            [71.9, 0.5],
            [71.9, 70.0],
            [0.5, 70.0],
        ])];
        // 1.7 mm left at the top between the part's clearance and the margin's: 1.5 mm text fits.
        let strokes = sheet_label(&d, "pzt-1", 0.3, &parts).expect("a strip of 1.7 mm");
        let (lo, hi) = extent(&strokes);
        assert!(
            lo[1] >= 70.2 - 1e-9 && hi[1] <= 71.9 + 1e-9,
            "{lo:?} {hi:?}"
        );
    }
}
