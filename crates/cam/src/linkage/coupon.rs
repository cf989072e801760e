//! A linkage as `nest` cuts it (docs/cam.md §7, "Nested with the actuators"): each layer of one
//! linkage on a coupon, a small panel with the clamp panel's chamfered corner and four pins of the
//! panel's radius, so the five coupons of a linkage stack on the same pins as the panel layers do.
//! The coupons are parts: the nester places them on shared sheets (the carbon on prepreg, the film
//! and the adhesive on sheets of their own), turned so the links run along the sheet's y axis, the
//! prepreg's fibre direction, as an actuator's axis does. The laminated coupon is released on its
//! pins by the coupon's release file.
//!
//! The coupon's layer files are drawn by the one implementation of the panel layers
//! ([`super::drawings::draw_panels`]) with one linkage, so the cross-layer checks run on them as on
//! a panel, and the nested parts are those files' shapes before the kerf.

use super::drawings::draw_panels;
use super::pattern::{Ply, STACK};
use super::LinkageLaminate;
use crate::drawing::label::{label_strokes, label_width};
use crate::parts::ImportedPart;
use crate::pipeline::{panel_outline, pin_centres, SheetDrawing};
use crate::process::template::{ClampSpec, Template};
use cam_geometry::Point;
use std::path::Path;

/// The coupon of one linkage: its outline and pins, and where the pattern's origin sits on it.
#[derive(Debug, Clone, PartialEq)]
pub struct Coupon {
    /// The coupon as a panel: outline size, pin radius and inset.
    pub clamp: ClampSpec,
    /// The pattern's origin (the airframe tab's end, on the centre line), mm.
    pub origin: Point,
}

/// One layer of the coupon as a part to nest: outline and cut-outs (nominal, before the kerf) and
/// the pin holes, turned so the links run along +y and centred on the outline's bounding box.
#[derive(Debug, Clone, PartialEq)]
pub struct CouponPart {
    /// The layer's ply.
    pub ply: Ply,
    /// Stack positions (1-based) this part is cut for: two carbon, two adhesive, one film.
    pub layers: Vec<usize>,
    /// Outline and cut-outs.
    pub part: ImportedPart,
    /// Pin holes: centre and radius, mm.
    pub pins: Vec<(Point, f64)>,
    /// The linkage's release outline, where the layer is bonded to its neighbours, turned as the part.
    pub zone: Vec<Point>,
}

/// Room kept between an engraving and the coupon's edges, pins and cut-outs, mm: the engraved line's
/// own width and the frayed edge.
const LABEL_MARGIN_MM: f64 = 0.2;

/// Height of a coupon's engraving at most, mm.
const LABEL_HEIGHT_MM: f64 = 1.0;

impl Coupon {
    /// The coupon of `laminate` with the pins of `template`'s clamp panel: each pin hole a radius and
    /// `slot_overrun_mm` from the coupon's edges (room for the pin's head and for a viewer's bounding box
    /// of the hole's arcs) and `slot_overrun_mm` from the cut-outs, which run `slot_overrun_mm` past the
    /// linkage.
    pub fn of(laminate: &LinkageLaminate, template: &Template) -> Coupon {
        let p = &laminate.pattern;
        let over = p.overrun_mm;
        let r = template.clamp.pin_radius_mm;
        let inset = 2.0 * r + over;
        let border = inset + r + over;
        Coupon {
            clamp: ClampSpec {
                panel_width_mm: p.length_mm + 2.0 * over + 2.0 * border,
                panel_height_mm: p.strip_width_mm + 2.0 * over + 2.0 * border,
                border_mm: border,
                pin_radius_mm: r,
                pin_inset_mm: inset,
                ..template.clamp.clone()
            },
            origin: [border + over, border + over + p.strip_width_mm / 2.0],
        }
    }

    /// The coupon's layer files, `<prefix>N-<layer>-1`, bottom to top, then the release cut.
    pub fn drawings(
        &self,
        laminate: &LinkageLaminate,
        template: &Template,
        title: &str,
        prefix: &str,
    ) -> Result<Vec<SheetDrawing>, crate::input::InputError> {
        draw_panels(
            laminate,
            template,
            &self.clamp,
            &[vec![self.origin]],
            title,
            prefix,
        )
    }

    /// A quarter turn counter-clockwise about the coupon's centre: the links (+x) along +y, as the
    /// nested parts lie.
    fn turn(&self, q: Point) -> Point {
        let c = &self.clamp;
        let centre = [c.panel_width_mm / 2.0, c.panel_height_mm / 2.0];
        [-(q[1] - centre[1]), q[0] - centre[0]]
    }

    /// The engraving of `copies` nested coupons of `name` (`thesis-7 carbon 3`, else shorter), turned
    /// as the parts: in the border below the linkage, between the bottom pins, clear of the slots'
    /// overrun, the pins and the edge by [`LABEL_MARGIN_MM`]; off the bonded release outline, as a
    /// panel's label is. A copy whose text has no room carries none.
    pub fn labels(&self, name: &str, layer: &str, copies: usize) -> Vec<Vec<Vec<Point>>> {
        let c = &self.clamp;
        let m = LABEL_MARGIN_MM;
        let x0 = c.pin_inset_mm + c.pin_radius_mm + m;
        let room = c.panel_width_mm - 2.0 * x0;
        // The slots and windows start `overrun` below the linkage, at the border's top.
        let height = (c.border_mm - 2.0 * m).min(LABEL_HEIGHT_MM);
        (1..=copies)
            .map(|k| {
                [
                    format!("{name} {layer} {k}"),
                    format!("{name} {k}"),
                    k.to_string(),
                ]
                .iter()
                .find(|t| height > 0.0 && label_width(t, height) <= room)
                .map_or_else(Vec::new, |t| {
                    label_strokes(t, [x0, (c.border_mm - height) / 2.0], height)
                        .into_iter()
                        .map(|s| s.into_iter().map(|q| self.turn(q)).collect())
                        .collect()
                })
            })
            .collect()
    }

    /// The parts to nest: one per distinct layer (carbon, adhesive, film), in stack order of first use.
    /// `file` is the drive file the parts are reported with.
    pub fn parts(&self, laminate: &LinkageLaminate, file: &Path) -> Vec<CouponPart> {
        let c = &self.clamp;
        let turn = |q: Point| self.turn(q);
        let zone: Vec<Point> = laminate
            .pattern
            .outline()
            .iter()
            .map(|q| turn([q[0] + self.origin[0], q[1] + self.origin[1]]))
            .collect();
        let ring = |r: Vec<Point>| r.into_iter().map(turn).collect::<Vec<Point>>();
        let mut out: Vec<CouponPart> = Vec::new();
        for (k, (ply, name)) in STACK.iter().enumerate() {
            if let Some(part) = out.iter_mut().find(|p| p.ply == *ply) {
                part.layers.push(k + 1);
                continue;
            }
            let holes = laminate
                .pattern
                .cut_outs(*ply)
                .iter()
                .map(|r| ring(r.moved(self.origin).ring()))
                .collect();
            out.push(CouponPart {
                ply: *ply,
                layers: vec![k + 1],
                part: ImportedPart {
                    file: file.to_path_buf(),
                    entity: format!("linkage coupon, {name}"),
                    outer: ring(panel_outline(c)),
                    holes,
                },
                pins: pin_centres(c)
                    .into_iter()
                    .map(|q| (turn(q), c.pin_radius_mm))
                    .collect(),
                zone: zone.clone(),
            });
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linkage::tests::hawkmoth;
    use cam_geometry::signed_area;

    #[test]
    fn the_nested_parts_are_the_coupon_files_before_the_kerf() {
        let (l, template) = hawkmoth();
        let coupon = Coupon::of(&l, &template);
        let parts = coupon.parts(&l, Path::new("drive.toml"));
        assert_eq!(
            parts.iter().map(|p| p.layers.clone()).collect::<Vec<_>>(),
            vec![vec![1, 5], vec![2, 4], vec![3]]
        );
        let c = &coupon.clamp;
        let (w, h) = (c.panel_width_mm, c.panel_height_mm);
        for p in &parts {
            // The outline's area is the panel outline's; turned a quarter: its bounding box is h x w.
            let xs: Vec<f64> = p.part.outer.iter().map(|q| q[0]).collect();
            let ys: Vec<f64> = p.part.outer.iter().map(|q| q[1]).collect();
            let span = |v: &[f64]| {
                v.iter().cloned().fold(f64::NEG_INFINITY, f64::max)
                    - v.iter().cloned().fold(f64::INFINITY, f64::min)
            };
            assert!((span(&xs) - h).abs() < 1e-12 && (span(&ys) - w).abs() < 1e-12);
            assert!((signed_area(&p.part.outer) - signed_area(&panel_outline(c))).abs() < 1e-9);
            // Every cut-out and pin hole inside the outline, clear of its edge.
            for hole in &p.part.holes {
                for q in hole {
                    assert!(q[0].abs() < h / 2.0 && q[1].abs() < w / 2.0);
                }
            }
            assert_eq!(p.pins.len(), 4);
        }
        // Each copy's engraving lies in the coupon, off the bonded release outline and clear of the
        // pin holes by the margin.
        let labels = coupon.labels("thesis-7", "carbon", 6);
        assert_eq!(labels.len(), 6);
        let zone = &parts[0].zone;
        let (zx, zy) = (
            zone.iter().map(|q| q[0]).fold(f64::INFINITY, f64::min),
            zone.iter().map(|q| q[0]).fold(f64::NEG_INFINITY, f64::max),
        );
        for strokes in &labels {
            assert!(!strokes.is_empty());
            for q in strokes.iter().flatten() {
                assert!(q[0].abs() < h / 2.0 && q[1].abs() < w / 2.0, "{q:?}");
                // The links run along y, so the zone spans x from zx to zy across them.
                assert!(q[0] < zx || q[0] > zy, "{q:?} in the zone {zx}..{zy}");
                for (centre, r) in &parts[0].pins {
                    let d = ((q[0] - centre[0]).powi(2) + (q[1] - centre[1]).powi(2)).sqrt();
                    assert!(d >= r + LABEL_MARGIN_MM - 1e-9, "{q:?} {d}");
                }
            }
        }
        // The files of the coupon: five layers and the release, each with the four pins.
        let drawings = coupon.drawings(&l, &template, "t", "linkage-x-").unwrap();
        assert_eq!(drawings.len(), STACK.len() + 1);
        assert!(drawings[0].stem.starts_with("linkage-x-1-carbon-1_"));
        // The coupon's carbon, read back, gives the drive's θ_w(δ) at five points (eq. 2.5).
        let read = crate::linkage::checks::pivots_read_back(&drawings[0]);
        assert_eq!(read.len(), 1);
        let [o, b, a] = read[0];
        let back = actuator_model::transmission::Linkage::new(
            (a - b) * 1e-3,
            (b - o) * 1e-3,
            l.linkage.offset,
        )
        .unwrap();
        for x in [-1.0, -0.5, 0.0, 0.5, 1.0] {
            let x = x * 0.75e-3;
            let (drawn, solved) = (
                back.stroke_angle(x).unwrap(),
                l.linkage.stroke_angle(x).unwrap(),
            );
            assert!((drawn - solved).abs() < 1e-6, "{x}: {drawn} vs {solved}");
        }
    }
}
