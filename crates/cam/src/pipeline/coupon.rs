//! The PZT test-score coupon: the score lines a production sheet has, on an offcut of the same
//! stock, run before any production sheet so that the laser setting is found on the offcut and not
//! on the first sheet of plates (docs/cam.md §4, "The test coupon"). It has the three kinds of line a
//! production sheet has: lines across the whole piece (ends run past its edges), a strip as narrow
//! as the template lets a production sheet leave, and a slanted line between two scored lines, which
//! breaks only once its strip is free.

use super::jobs::Drawn;
use super::panel::rect;
use super::score_lines::overrun;
use crate::drawing::model::{file_stem, Drawing, Shape, Stock};
use crate::process::template::SheetSpec;
use crate::process::{Feature, FeatureMap};
use cam_geometry::Point;

/// The least distance between the coupon's lines, mm: room to hold a strip in tweezers over the
/// snapping edge.
const BAND_MM: f64 = 5.0;

/// The coupon of `spec`'s PZT stock of `thickness_mm`: its size and score lines in break order.
pub(crate) fn coupon_lines(spec: &SheetSpec, thickness_mm: f64) -> (f64, f64, Vec<[Point; 2]>) {
    let strip = spec.min_snap_strip_thicknesses * thickness_mm + spec.kerf_mm / 2.0;
    let band = BAND_MM.max(2.0 * strip);
    let (w, h) = (4.0 * band, 3.0 * band);
    let lines = vec![
        [[0.0, band], [w, band]],
        [[0.0, 2.0 * band], [w, 2.0 * band]],
        // The narrowest strip a production sheet may leave at its edge.
        [[0.0, h - strip], [w, h - strip]],
        // A slanted line between two scored lines.
        [
            [w / 2.0 - 0.4 * band, band],
            [w / 2.0 + 0.4 * band, 2.0 * band],
        ],
    ];
    (w, h, lines)
}

/// Draw the test-score coupon of `stock` (one per PZT stock of the build) and record its file: the
/// coupon is cut from an offcut, so it adds no sheet to the stock list.
pub(crate) fn draw_coupon(
    spec: &SheetSpec,
    stock: &Stock,
    title: &str,
    features: &FeatureMap,
    drawn: &mut Drawn,
) {
    let n = drawn.next_number("pzt-coupon");
    let (w, h, lines) = coupon_lines(spec, stock.thickness_mm);
    let mut d = Drawing::on_stock(
        &format!("{title} PZT test-score coupon {n}: an offcut of this stock, scored before any production sheet"),
        w,
        h,
        stock.clone(),
    );
    for line in &lines {
        d.add(
            features.op(Feature::PztScoreLine),
            Shape::Polyline(overrun(*line, [[0.0, 0.0], [w, h]], spec.score_overrun_mm).to_vec()),
        );
    }
    d.add(
        features.op(Feature::PztSheetOutline),
        Shape::Polygon(rect([0.0, 0.0], w, h)),
    );
    let stem = format!("pzt-coupon-{n}");
    drawn.coupons.push((file_stem(&stem, Some(stock)), [w, h]));
    drawn.push_copies(stem, "pzt-coupon", d, 0);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_coupon_holds_the_narrowest_production_strip_and_a_slanted_line() {
        let spec =
            crate::process::template::Template::resolve("method-2", std::path::Path::new("d.toml"))
                .unwrap()
                .pzt;
        // 0.267 mm PZT, 5 thicknesses and half the 0.03 mm kerf: a 1.35 mm strip at the top edge.
        let (w, h, lines) = coupon_lines(&spec, 0.267);
        assert_eq!((w, h), (20.0, 15.0));
        let top = lines[2];
        assert!(
            (h - top[0][1] - (5.0 * 0.267 + 0.015)).abs() < 1e-12,
            "{top:?}"
        );
        // The slanted line ends on the two lines scored before it.
        let [a, b] = lines[3];
        assert!(a[1] == lines[0][0][1] && b[1] == lines[1][0][1] && a[0] != b[0]);
        // A thick sheet widens the coupon so every strip stays wider than the narrowest one.
        let (w, h, _) = coupon_lines(&spec, 1.0);
        assert!(h / 3.0 >= 2.0 * 5.0 && w > h, "{w} x {h}");
    }
}
