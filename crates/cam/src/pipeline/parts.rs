//! Nominal part outlines of one actuator, in mm: the actuator axis along +y, the base (clamped end)
//! centred on the origin, as the layout code expects.

use crate::design::Design;

use cam_geometry::Point;

/// Plan dimensions of one actuator, mm.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PartGeometry {
    /// PZT length l_p.
    pub piezo_length_mm: f64,
    /// Extension length l_ext.
    pub extension_length_mm: f64,
    /// Base width w_0.
    pub base_width_mm: f64,
    /// Tip width w_tip.
    pub tip_width_mm: f64,
    /// Passive-only tab behind the PZT.
    pub base_tab_mm: f64,
    /// How far the PZT plate's sides and tip end sit inside the passive part's edge (the template's
    /// PZT-to-CF edge margin, docs/cam.md §1: resin squeezed out at the CF edge cannot bridge the PZT
    /// electrodes). 0: the plate is the design's trapezoid.
    pub pzt_margin_mm: f64,
}

impl PartGeometry {
    /// From a validated design (SI → mm at the edge).
    pub fn of(design: &Design) -> Self {
        let p = &design.planform;
        PartGeometry {
            piezo_length_mm: p.piezo_length() * 1e3,
            extension_length_mm: p.extension_length() * 1e3,
            base_width_mm: p.base_width * 1e3,
            tip_width_mm: p.tip_width() * 1e3,
            base_tab_mm: p.base_tab * 1e3,
            pzt_margin_mm: 0.0,
        }
    }

    /// The same actuator with the PZT plate inset by `margin_mm` from the passive edge.
    pub fn with_pzt_margin(self, margin_mm: f64) -> Self {
        PartGeometry {
            pzt_margin_mm: margin_mm,
            ..self
        }
    }

    /// Length of the PZT plate: `l_p` less the margin at the tip end (the root stays on the clamp line).
    pub fn plate_length_mm(&self) -> f64 {
        self.piezo_length_mm - self.pzt_margin_mm
    }

    /// Width of the PZT plate at its root. Each side moves in by the margin measured square to the
    /// tapered edge, so by `margin · sqrt(1 + s²)` across, with `s` the side's slope `(w_tip - w_0)/(2 l_p)`.
    pub fn plate_base_width_mm(&self) -> f64 {
        let slope = (self.tip_width_mm - self.base_width_mm) / (2.0 * self.piezo_length_mm);
        self.base_width_mm - 2.0 * self.pzt_margin_mm * (1.0 + slope * slope).sqrt()
    }

    /// Width of the PZT plate at its tip end.
    pub fn plate_tip_width_mm(&self) -> f64 {
        self.plate_width_at_mm(self.plate_length_mm())
    }

    /// Width of the PZT plate at height y (the sides keep the design's taper).
    pub fn plate_width_at_mm(&self, y: f64) -> f64 {
        self.plate_base_width_mm()
            + (self.tip_width_mm - self.base_width_mm) * y / self.piezo_length_mm
    }

    /// Total passive length (tab + PZT + extension).
    pub fn passive_length_mm(&self) -> f64 {
        self.base_tab_mm + self.piezo_length_mm + self.extension_length_mm
    }

    /// The PZT plate: trapezoid from w_0 at y = 0 to w_tip at y = l_p (CCW), inset by the margin.
    pub fn pzt_outline(&self) -> Vec<Point> {
        let (b, t, l) = (
            self.plate_base_width_mm() / 2.0,
            self.plate_tip_width_mm() / 2.0,
            self.plate_length_mm(),
        );
        vec![[-b, 0.0], [b, 0.0], [t, l], [-t, l]]
    }

    /// The passive part: base tab (`l_tab x w_0`), trapezoid, extension (`l_ext x w_tip`), CCW. Corners
    /// that coincide (no tab, no extension) are left out so the ring has no zero-length edge.
    pub fn passive_outline(&self) -> Vec<Point> {
        let (b, t, l) = (
            self.base_width_mm / 2.0,
            self.tip_width_mm / 2.0,
            self.piezo_length_mm,
        );
        let tab = self.base_tab_mm;
        let end = l + self.extension_length_mm;
        let mut ring = Vec::with_capacity(8);
        if tab > 0.0 {
            ring.push([-b, -tab]);
            ring.push([b, -tab]);
        }
        ring.push([b, 0.0]);
        ring.push([t, l]);
        if self.extension_length_mm > 0.0 {
            ring.push([t, end]);
            ring.push([-t, end]);
        }
        ring.push([-t, l]);
        ring.push([-b, 0.0]);
        ring
    }

    /// Width of the passive part's tapered section at height y (0 ≤ y ≤ l_p).
    pub fn width_at_mm(&self, y: f64) -> f64 {
        self.base_width_mm + (self.tip_width_mm - self.base_width_mm) * y / self.piezo_length_mm
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use cam_geometry::signed_area;

    fn geometry(tab: f64, ext: f64) -> PartGeometry {
        PartGeometry {
            piezo_length_mm: 23.0,
            extension_length_mm: ext,
            base_width_mm: 5.0,
            tip_width_mm: 1.0,
            base_tab_mm: tab,
            pzt_margin_mm: 0.0,
        }
    }

    #[test]
    fn outline_areas_match_the_planform_formulas() {
        // Source: docs/physics.md §4, A_pzt = l_p w_nom, A_ext = l_ext w_tip, A_tab = l_tab w_0.
        for (tab, ext) in [(0.0, 0.0), (2.0, 0.0), (0.0, 19.0), (1.5, 19.0)] {
            let g = geometry(tab, ext);
            assert!((signed_area(&g.pzt_outline()) - 23.0 * 3.0).abs() < 1e-12);
            let want = 23.0 * 3.0 + ext * 1.0 + tab * 5.0;
            assert!(
                (signed_area(&g.passive_outline()) - want).abs() < 1e-12,
                "{tab} {ext}"
            );
        }
    }

    #[test]
    fn the_margin_insets_every_plate_edge_square_to_itself() {
        // Each inset side must lie `margin` from the passive side it follows (distance from a point to a
        // line), and the plate's tip end `margin` below the end of the taper.
        let g = geometry(1.0, 10.0).with_pzt_margin(0.2);
        let plate = g.pzt_outline();
        let (b, t, l) = (2.5, 0.5, 23.0);
        let distance = |p: [f64; 2]| {
            // Passive right side from (b, 0) to (t, l).
            let (dx, dy) = (t - b, l);
            ((p[0] - b) * dy - p[1] * dx).abs() / (dx * dx + dy * dy).sqrt()
        };
        assert!((distance(plate[1]) - 0.2).abs() < 1e-12);
        assert!((distance(plate[2]) - 0.2).abs() < 1e-12);
        assert!((plate[2][1] - (23.0 - 0.2)).abs() < 1e-12);
        assert!((g.plate_tip_width_mm() - 2.0 * plate[2][0]).abs() < 1e-12);
        // The passive part keeps the design's outline.
        assert_eq!(g.passive_outline(), geometry(1.0, 10.0).passive_outline());
        // No margin: the design's trapezoid exactly.
        assert_eq!(
            geometry(0.0, 0.0).pzt_outline(),
            vec![[-2.5, 0.0], [2.5, 0.0], [0.5, 23.0], [-0.5, 23.0]]
        );
    }
}
