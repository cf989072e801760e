//! The preview of the assembled actuator in the cut-sheet report.
//!
//! The preview is a picture, not a laser file. Laser software that is given it by mistake must not cut
//! an actuator-sized part from it, so it is everything a laser file is not: its layer names and colours
//! are none of an operation's, its shapes are filled and have no stroke (no vector path to follow), and
//! it is drawn at [`SCALE`]:1, so even a traced outline would come out four times too large.

use crate::drawing::model::{Drawing, Operation, Shape};
use crate::drawing::palette::Palette;
use crate::drawing::svg::{write_svg, LayerStyle};
use crate::pipeline::PartGeometry;
use cam_geometry::place_ring;

/// Layer label and colour of the passive outline in the preview.
const PASSIVE: (&str, &str) = ("preview passive part", "#8C6D46");
/// Layer label and colour of the PZT plate in the preview.
const PLATE: (&str, &str) = ("preview PZT plate", "#4F7FB0");
/// Fallbacks should a lab's palette use one of the colours above for an operation.
const SPARE: [&str; 2] = ["#6E8B3D", "#A05A7E"];
/// The preview's scale, drawing to actuator.
pub const SCALE: f64 = 4.0;

/// The assembled actuator at [`SCALE`]:1: passive outline under the PZT plate, with a 1 mm margin (at
/// true size). The drawing's operations are only keys for the two layers; [`preview_svg`] writes them.
pub fn preview(g: &PartGeometry, name: &str) -> Drawing {
    let w = g.base_width_mm.max(g.tip_width_mm) + 2.0;
    let h = g.passive_length_mm() + 2.0;
    let origin = [w / 2.0, 1.0 + g.base_tab_mm];
    let mut d = Drawing::new(
        &format!(
            "{name}: assembled actuator (brown passive, blue PZT) drawn at {SCALE}:1, a picture, not for cutting"
        ),
        SCALE * w,
        SCALE * h,
    );
    let scaled = |ring: &[[f64; 2]]| -> Vec<[f64; 2]> {
        place_ring(ring, 0.0, origin)
            .into_iter()
            .map(|[x, y]| [SCALE * x, SCALE * y])
            .collect()
    };
    d.add(
        Operation::Secondary,
        Shape::Polygon(scaled(&g.passive_outline())),
    );
    d.add(Operation::Cut, Shape::Polygon(scaled(&g.pzt_outline())));
    d
}

/// The preview as SVG, with layer names and colours no operation of `palette` uses.
pub fn preview_svg(drawing: &Drawing, stroke_mm: f64, palette: &Palette) -> String {
    let taken = |c: &str| Operation::ALL.iter().any(|op| palette.svg_colour(*op) == c);
    let pick = |(name, colour): (&str, &str), spare: &str| LayerStyle {
        name: name.to_string(),
        colour: if taken(colour) { spare } else { colour }.to_string(),
        filled: true,
    };
    write_svg(drawing, stroke_mm, |op| {
        if op == Operation::Cut {
            pick(PLATE, SPARE[1])
        } else {
            pick(PASSIVE, SPARE[0])
        }
    })
}
