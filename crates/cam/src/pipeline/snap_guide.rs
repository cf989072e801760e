//! The snapping order of a PZT sheet, as a picture beside its score file (docs/cam.md §4, "Snapping
//! order"). A slanted score line between two plates of a strip breaks cleanly only once the strip is
//! free, so the lines must be snapped in the order the planner scored them: the guide numbers each line
//! in that order. The numbers cannot go on the ceramic: a line inside a strip has a plate on either
//! side, and anything engraved on a plate is a flaw in it. So they go in a picture, which is, like the
//! actuator preview, everything a laser file is not: shapes filled with no stroke, colours of no
//! operation, drawn at [`SCALE`]:1, and titled as not for cutting. A line that reaches the sheet edge
//! has its number just past that end, off the sheet; a line inside the sheet has it at its middle.

use crate::drawing::decimal::fmt_mm;
use crate::drawing::svg::xml_escape;
use cam_geometry::Point;
use std::fmt::Write as _;

/// Drawing to sheet, as the actuator preview: a traced outline would come out four times too large.
pub const SCALE: f64 = 4.0;
/// Room around the sheet for the numbers of the lines that reach its edge, mm at true size.
const MARGIN_MM: f64 = 3.0;
/// Height of a number, mm at true size.
const DIGIT_MM: f64 = 1.2;

/// The file name of the guide of PZT sheet `stem` (`pzt-1`): a preview, as every picture's name starts.
pub fn file_name(stem: &str) -> String {
    format!("preview-snap-order-{stem}.svg")
}

/// The guide of one PZT sheet `width_mm` x `height_mm`: its plates (placed outlines), its score lines in
/// break order (the exact lines, without the drawn overrun), each numbered from 1.
pub fn snap_guide(
    title: &str,
    width_mm: f64,
    height_mm: f64,
    plates: &[Vec<Point>],
    lines: &[[Point; 2]],
) -> String {
    let (w, h) = (width_mm + 2.0 * MARGIN_MM, height_mm + 2.0 * MARGIN_MM);
    // Sheet coordinates (mm, y up) to page coordinates (scaled, y down).
    let page = |p: Point| -> (String, String) {
        (
            fmt_mm(SCALE * (p[0] + MARGIN_MM)),
            fmt_mm(SCALE * (height_mm + MARGIN_MM - p[1])),
        )
    };
    let path = |ring: &[Point]| -> String {
        let mut d = String::new();
        for (i, p) in ring.iter().enumerate() {
            let (x, y) = page(*p);
            let _ = write!(d, "{}{x} {y} ", if i == 0 { "M" } else { "L" });
        }
        d.push('Z');
        d
    };
    let mut s = String::new();
    let _ = writeln!(
        s,
        "<?xml version=\"1.0\" encoding=\"UTF-8\" standalone=\"no\"?>\n\
         <svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" width=\"{0}mm\" height=\"{1}mm\" viewBox=\"0 0 {0} {1}\">",
        fmt_mm(SCALE * w),
        fmt_mm(SCALE * h)
    );
    let _ = writeln!(
        s,
        "  <title>{}: snapping order, drawn at {SCALE}:1, a picture, not for cutting</title>",
        xml_escape(title)
    );
    let sheet = [
        [0.0, 0.0],
        [width_mm, 0.0],
        [width_mm, height_mm],
        [0.0, height_mm],
    ];
    let _ = writeln!(
        s,
        "  <path d=\"{}\" fill=\"#E8E4DA\" stroke=\"none\"/>",
        path(&sheet)
    );
    for plate in plates {
        let _ = writeln!(
            s,
            "  <path d=\"{}\" fill=\"#9DB7D5\" stroke=\"none\"/>",
            path(plate)
        );
    }
    // Each line as a thin filled band, 0.08 mm wide at true size: a picture has no stroked path.
    let half = 0.04;
    for [a, b] in lines {
        let length = (b[0] - a[0]).hypot(b[1] - a[1]);
        if length == 0.0 {
            continue;
        }
        let n = [
            -(b[1] - a[1]) / length * half,
            (b[0] - a[0]) / length * half,
        ];
        let band = [
            [a[0] + n[0], a[1] + n[1]],
            [b[0] + n[0], b[1] + n[1]],
            [b[0] - n[0], b[1] - n[1]],
            [a[0] - n[0], a[1] - n[1]],
        ];
        let _ = writeln!(
            s,
            "  <path d=\"{}\" fill=\"#5A4A78\" stroke=\"none\"/>",
            path(&band)
        );
    }
    for (k, line) in lines.iter().enumerate() {
        let at = number_position(*line, width_mm, height_mm);
        let (x, y) = page(at);
        let _ = writeln!(
            s,
            "  <circle cx=\"{x}\" cy=\"{y}\" r=\"{}\" fill=\"#FFFFFF\" stroke=\"none\"/>\
             <text x=\"{x}\" y=\"{y}\" font-family=\"sans-serif\" font-size=\"{}\" text-anchor=\"middle\" \
             dominant-baseline=\"central\" fill=\"#5A4A78\">{}</text>",
            fmt_mm(SCALE * DIGIT_MM * 0.75),
            fmt_mm(SCALE * DIGIT_MM),
            k + 1
        );
    }
    s.push_str("</svg>\n");
    s
}

/// Where a line's number goes: past the end on the sheet edge, off the sheet, if the line reaches the
/// edge; else at its middle.
fn number_position([a, b]: [Point; 2], width_mm: f64, height_mm: f64) -> Point {
    let on_edge = |p: Point| super::panel::on_sheet_edge(p, width_mm, height_mm);
    let length = (b[0] - a[0]).hypot(b[1] - a[1]);
    let away = |from: Point, to: Point| -> Point {
        let u = [(to[0] - from[0]) / length, (to[1] - from[1]) / length];
        let run = MARGIN_MM / 2.0;
        [to[0] + u[0] * run, to[1] + u[1] * run]
    };
    if length > 0.0 && on_edge(a) {
        away(b, a)
    } else if length > 0.0 && on_edge(b) {
        away(a, b)
    } else {
        [(a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_edge_line_is_numbered_off_the_sheet_an_inner_line_at_its_middle() {
        // A line across a 10 x 10 sheet: its number sits 1.5 mm past its start, left of the sheet.
        let p = number_position([[0.0, 4.0], [10.0, 4.0]], 10.0, 10.0);
        assert!((p[0] + MARGIN_MM / 2.0).abs() < 1e-12 && (p[1] - 4.0).abs() < 1e-12);
        // A line between two earlier lines: at its middle.
        assert_eq!(
            number_position([[2.0, 4.0], [3.0, 8.0]], 10.0, 10.0),
            [2.5, 6.0]
        );
    }

    #[test]
    fn the_guide_numbers_every_line_in_order_and_has_nothing_a_laser_follows() {
        let svg = snap_guide(
            "C",
            10.0,
            10.0,
            &[vec![[1.0, 1.0], [3.0, 1.0], [3.0, 3.0]]],
            &[[[0.0, 4.0], [10.0, 4.0]], [[2.0, 4.0], [3.0, 8.0]]],
        );
        assert!(svg.contains(">1</text>") && svg.contains(">2</text>"));
        assert!(!svg.contains(">3</text>"));
        assert!(svg.contains("not for cutting"));
        // No stroked shape: every path, circle and the page carry stroke="none".
        for tag in svg
            .split('<')
            .filter(|t| t.starts_with("path") || t.starts_with("circle"))
        {
            assert!(tag.contains("stroke=\"none\""), "{tag}");
        }
        // At 4:1: the page is (10 + 2 x 3) x 4 = 64 mm wide.
        assert!(svg.contains("width=\"64mm\""));
    }
}
