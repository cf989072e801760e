//! The jig the nested linkage coupons are stacked, cured and released on (docs/cam.md §7, "Nested with
//! the actuators"): a plate of the template's `[linkage] jig_material` with, for each linkage of the
//! batch, its coupon's four pin holes, into which the dowels are pressed, so that every coupon stack of
//! the batch cures in one clamp. A coupon's pins are its own
//! (a pin radius and the overrun in from its edges, [`super::coupon::Coupon::of`]), so each linkage
//! has a pattern of its own; the clamp's panel pins serve the panels of `cut-sheet` instead.
//!
//! The holes are cut to the dowel's diameter (drawn kerf/2 inside it), a line-to-line fit the dowel is
//! pressed into, where the coupons' holes are the clamp panel's, with the clearance the stacking step
//! states ([`crate::book::pin_fit_text`]). Each coupon's outline is engraved (where it lies, the chamfered
//! corner matching, and where the release file's origin goes), its name engraved under it.

use crate::drawing::label::{label_strokes, label_width};
use crate::drawing::model::{file_stem, Drawing, Shape, Stock};
use crate::pipeline::{panel_outline, pin_centres, SheetDrawing};
use crate::process::linkage::LinkageProcess;
use crate::process::template::ClampSpec;
use crate::process::{Feature, FeatureMap};
use cam_geometry::offset::offset_ring;
use cam_geometry::Point;

/// Height of the engraved names, mm.
const LABEL_MM: f64 = 1.5;

/// The pin pattern of a coupon: the spans between its pin centres along x and y, mm.
pub fn pin_pattern_mm(c: &ClampSpec) -> [f64; 2] {
    [
        c.panel_width_mm - 2.0 * c.pin_inset_mm,
        c.panel_height_mm - 2.0 * c.pin_inset_mm,
    ]
}

/// The radius of a jig hole as cut: the dowel's, or without a dowel diameter in the template the
/// coupon's pin hole (the largest dowel the coupons take), mm.
pub fn jig_hole_radius_mm(c: &ClampSpec) -> f64 {
    c.dowel_diameter_mm.map_or(c.pin_radius_mm, |d| d / 2.0)
}

/// The jig's engraved names of the `quantity` coupons `name`: `thesis-7 1`, `thesis-7 2`, ...
pub fn names_of(name: &str, quantity: usize) -> Vec<String> {
    (1..=quantity).map(|k| format!("{name} {k}")).collect()
}

/// The jig file `jig-1-linkage-coupons_<stock>`: the coupons `(name, coupon, quantity)`, each as many times as
/// its quantity, side by side `spacing_mm` apart and from the plate's edges, their names engraved below
/// them; `None` without coupons.
pub fn jig_drawing(
    coupons: &[(String, ClampSpec, usize)],
    process: &LinkageProcess,
    features: &FeatureMap,
    title: &str,
) -> Option<SheetDrawing> {
    let gap = process.spacing_mm;
    let half = process.kerf_mm / 2.0;
    let cells: Vec<(String, &ClampSpec, f64)> = coupons
        .iter()
        .flat_map(|(n, c, quantity)| {
            names_of(n, *quantity).into_iter().map(move |label| {
                let w = c.panel_width_mm.max(label_width(&label, LABEL_MM));
                (label, c, w)
            })
        })
        .collect();
    if cells.is_empty() {
        return None;
    }
    let tallest = cells
        .iter()
        .map(|(_, c, _)| c.panel_height_mm)
        .fold(0.0, f64::max);
    // To 0.1 mm above, a plate size one can order.
    let up = |x: f64| (x * 10.0).ceil() / 10.0;
    let width = up(gap + cells.iter().map(|(_, _, w)| w + gap).sum::<f64>());
    let height = up(gap + LABEL_MM + gap + tallest + gap);
    let mut d = Drawing::on_stock(
        &format!("{title} linkage coupon jig"),
        width,
        height,
        Stock {
            material: process.jig.material.clone(),
            thickness_mm: process.jig.thickness_mm,
            kerf_mm: process.kerf_mm,
            fibre_axis: None,
        },
    );
    let mut x = gap;
    for (label, c, cell) in &cells {
        let at = [x, gap + LABEL_MM + gap];
        let moved = |q: Point| [q[0] + at[0], q[1] + at[1]];
        d.add(
            features.op(Feature::PanelLabel),
            Shape::Polygon(panel_outline(c).into_iter().map(moved).collect()),
        );
        for centre in pin_centres(c) {
            d.add(
                features.op(Feature::PinHole),
                Shape::Circle {
                    center: moved(centre),
                    radius: jig_hole_radius_mm(c) - half,
                },
            );
        }
        for s in label_strokes(label, [x, gap], LABEL_MM) {
            d.add(features.op(Feature::PanelLabel), Shape::Polyline(s));
        }
        x += cell + gap;
    }
    // The plate's outline last, grown by half the kerf, so the plate comes out the page's size.
    let plate = [[0.0, 0.0], [width, 0.0], [width, height], [0.0, height]];
    let outline = offset_ring(&plate, half).ok()?;
    d.add(features.op(Feature::PanelOutline), Shape::Polygon(outline));
    Some(SheetDrawing {
        stem: file_stem("jig-1-linkage-coupons", d.stock.as_ref()),
        layer: "jig-linkage-coupons".to_string(),
        drawing: d,
    })
}

/// The build step that readies the jig `stem` for the `quantity` coupons `name` of `c` (a stack
/// `stack_mm` thick once laminated): the plate cut once for the batch, the dowels pressed into these
/// coupons' holes and standing no higher than the stack, so the clamp bears on the coupons.
pub fn jig_step(
    stem: &str,
    (name, quantity): (&str, usize),
    c: &ClampSpec,
    process: &LinkageProcess,
    stack_mm: f64,
) -> String {
    let dowel = match c.dowel_diameter_mm {
        Some(d) => format!("Ø{d} mm dowels (the template's `clamp.dowel_diameter_mm`)"),
        None => format!(
            "dowels of at most Ø{} mm (the template gives no `clamp.dowel_diameter_mm`)",
            2.0 * c.pin_radius_mm
        ),
    };
    let names = names_of(name, quantity);
    let [x, y] = pin_pattern_mm(c);
    format!(
        "The jig `{stem}` ({}, {} mm; cut it once for the batch, the laser set up for its stock on an offcut as for every stock): press {dowel} into the four holes of each coupon outline engraved `{}` to `{}` (pins {x:.3} x {y:.3} mm apart), cut to the dowel's Ø{} mm, a line-to-line press fit; each dowel square to the plate and standing at most {stack_mm:.3} mm above it, the laminated coupon's thickness, so the clamp bears on the coupons and never on a dowel.",
        process.jig.material,
        process.jig.thickness_mm,
        names[0],
        names[names.len() - 1],
        2.0 * jig_hole_radius_mm(c)
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linkage::coupon::Coupon;
    use crate::linkage::tests::hawkmoth;

    #[test]
    fn the_jig_holds_each_coupons_pins_at_the_dowel_size() {
        let (l, template) = hawkmoth();
        let c = Coupon::of(&l, &template).clamp;
        let process = &l.process;
        let jig = jig_drawing(
            &[
                ("a".to_string(), c.clone(), 1),
                ("b".to_string(), c.clone(), 1),
            ],
            process,
            &template.features,
            "t",
        )
        .unwrap();
        let circles: Vec<(Point, f64)> = jig
            .drawing
            .items()
            .iter()
            .filter_map(|(_, s)| match s {
                Shape::Circle { center, radius } => Some((*center, *radius)),
                _ => None,
            })
            .collect();
        assert_eq!(circles.len(), 8);
        // As cut (drawn radius and half the kerf) each hole is the template's Ø1.5 mm dowel.
        for (_, r) in &circles {
            assert!(
                (2.0 * (r + process.kerf_mm / 2.0) - 1.5).abs() < 1e-12,
                "{r}"
            );
        }
        // Each group of four is the coupon's own pin pattern, the coupon's holes' centres.
        let pins = pin_centres(&c);
        for group in circles.chunks(4) {
            let shift = [group[0].0[0] - pins[0][0], group[0].0[1] - pins[0][1]];
            for ((q, _), p) in group.iter().zip(&pins) {
                assert!((q[0] - p[0] - shift[0]).abs() < 1e-12);
                assert!((q[1] - p[1] - shift[1]).abs() < 1e-12);
            }
        }
        let [x, y] = pin_pattern_mm(&c);
        assert!((pins[2][0] - pins[0][0] - x).abs() < 1e-12);
        assert!((pins[2][1] - pins[0][1] - y).abs() < 1e-12);
        assert!(jig
            .stem
            .starts_with("jig-1-linkage-coupons_glass-polyimide-laminate-1.6mm"));
        assert!(jig_drawing(&[], process, &template.features, "t").is_none());
    }
}
