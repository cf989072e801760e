//! Nominal part outlines of one actuator, in mm: the actuator axis along +y, the base (clamped end)
//! centred on the origin, as the layout code expects.

use crate::design::Design;

/// A point in mm.
pub type Point = [f64; 2];

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
        }
    }

    /// Total passive length (tab + PZT + extension).
    pub fn passive_length_mm(&self) -> f64 {
        self.base_tab_mm + self.piezo_length_mm + self.extension_length_mm
    }

    /// The PZT plate: trapezoid from w_0 at y = 0 to w_tip at y = l_p (CCW).
    pub fn pzt_outline(&self) -> Vec<Point> {
        let (b, t, l) = (
            self.base_width_mm / 2.0,
            self.tip_width_mm / 2.0,
            self.piezo_length_mm,
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

    /// Width of the PZT at height y (0 ≤ y ≤ l_p).
    pub fn width_at_mm(&self, y: f64) -> f64 {
        self.base_width_mm + (self.tip_width_mm - self.base_width_mm) * y / self.piezo_length_mm
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cam::drawing::polygon_area as ring_area;

    fn geometry(tab: f64, ext: f64) -> PartGeometry {
        PartGeometry {
            piezo_length_mm: 23.0,
            extension_length_mm: ext,
            base_width_mm: 5.0,
            tip_width_mm: 1.0,
            base_tab_mm: tab,
        }
    }

    #[test]
    fn outline_areas_match_the_planform_formulas() {
        // Source: MODEL-NOTES §4, A_pzt = l_p w_nom, A_ext = l_ext w_tip, A_tab = l_tab w_0.
        for (tab, ext) in [(0.0, 0.0), (2.0, 0.0), (0.0, 19.0), (1.5, 19.0)] {
            let g = geometry(tab, ext);
            assert!((ring_area(&g.pzt_outline()) - 23.0 * 3.0).abs() < 1e-12);
            let want = 23.0 * 3.0 + ext * 1.0 + tab * 5.0;
            assert!(
                (ring_area(&g.passive_outline()) - want).abs() < 1e-12,
                "{tab} {ext}"
            );
        }
    }

    #[test]
    fn half_turn_is_exact() {
        assert_eq!(
            crate::layout::place_point([1.0, 2.0], 180.0, [0.0, 0.0]),
            [-1.0, -2.0]
        );
    }
}
