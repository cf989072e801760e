//! The preview of the assembled actuator in the cut-sheet report.

use crate::cam::drawing::{Drawing, Operation, Shape};
use crate::pipeline::PartGeometry;
use cam_geometry::place_ring;

/// The assembled actuator: passive outline (green) under the PZT plate (red), with a 1 mm margin.
pub fn preview(g: &PartGeometry, name: &str) -> Drawing {
    let w = g.base_width_mm.max(g.tip_width_mm) + 2.0;
    let h = g.passive_length_mm() + 2.0;
    let origin = [w / 2.0, 1.0 + g.base_tab_mm];
    let mut d = Drawing::new(
        &format!("{name}: assembled actuator (green passive, red PZT)"),
        w,
        h,
    );
    d.add(
        Operation::Secondary,
        Shape::Polygon(place_ring(&g.passive_outline(), 0.0, origin)),
    );
    d.add(
        Operation::Cut,
        Shape::Polygon(place_ring(&g.pzt_outline(), 0.0, origin)),
    );
    d
}
