//! The clamp panel every clamp layer shares (docs/cam.md §2): outline with a chamfered orientation corner,
//! pin holes, fiducials, stacking-order windows, and the grid of actuator cavities.

use super::parts::PartGeometry;
use crate::drawing::label::{label_strokes, label_width};
use crate::process::template::ClampSpec;
use cam_geometry::Point;
use thiserror::Error;

/// Where the actuators sit on clamp panels.
#[derive(Debug, Clone, PartialEq)]
pub struct PanelLayout {
    /// Panel width, mm.
    pub width_mm: f64,
    /// Panel height, mm.
    pub height_mm: f64,
    /// Actuators per panel.
    pub capacity: usize,
    /// Per panel, the base position (origin of the part outlines) of each actuator it holds, with its
    /// global actuator index.
    pub panels: Vec<Vec<(usize, Point)>>,
}

/// The panel cannot hold even one actuator.
#[derive(Debug, Clone, PartialEq, Error)]
#[error("the actuator ({part_width_mm:.2} x {part_length_mm:.2} mm with clearance) does not fit the clamp panel inside its {border_mm} mm border")]
pub struct PanelTooSmall {
    part_width_mm: f64,
    part_length_mm: f64,
    width_mm: f64,
    height_mm: f64,
    border_mm: f64,
}

impl PanelTooSmall {
    /// The `[clamp]` key to change (`panel_width_mm` or `panel_height_mm`), its value and the least
    /// value that holds one actuator, mm (the other side as it is, if that one is wide enough).
    pub fn side_to_grow(&self) -> (&'static str, f64, f64) {
        let need_w = self.part_width_mm + 2.0 * self.border_mm;
        let need_h = self.part_length_mm + 2.0 * self.border_mm;
        if self.width_mm < need_w {
            ("panel_width_mm", self.width_mm, need_w)
        } else {
            ("panel_height_mm", self.height_mm, need_h)
        }
    }
}

/// Columns and rows of cells `cell_w` x `cell_h` (each holding a part and the `spacing` after it) inside a
/// panel's border: the grid both the actuators' cavities and the linkages are laid out on.
pub fn grid(spec: &ClampSpec, cell_w: f64, cell_h: f64, spacing: f64) -> (usize, usize) {
    let usable_w = spec.panel_width_mm - 2.0 * spec.border_mm + spacing;
    let usable_h = spec.panel_height_mm - 2.0 * spec.border_mm + spacing;
    (
        (usable_w / cell_w).floor().max(0.0) as usize,
        (usable_h / cell_h).floor().max(0.0) as usize,
    )
}

/// `count` parts filled into panels of `cols` x `rows` cells, row by row: for each part its panel
/// (0-based), column and row. `cols * rows` must not be zero.
pub fn grid_slots(
    count: usize,
    cols: usize,
    rows: usize,
) -> impl Iterator<Item = (usize, usize, usize)> {
    let capacity = cols * rows;
    (0..count).map(move |i| (i / capacity, i % capacity % cols, i % capacity / cols))
}

/// Actuators on a grid of cavities, row by row, as many panels as needed.
pub fn layout_panels(
    spec: &ClampSpec,
    parts: &PartGeometry,
    quantity: usize,
) -> Result<PanelLayout, PanelTooSmall> {
    let cell_w = parts.base_width_mm.max(parts.tip_width_mm)
        + 2.0 * spec.cavity_clearance_mm
        + spec.cavity_spacing_mm;
    let cell_h =
        parts.passive_length_mm() + 2.0 * spec.cavity_clearance_mm + spec.cavity_spacing_mm;
    let (cols, rows) = grid(spec, cell_w, cell_h, spec.cavity_spacing_mm);
    let capacity = cols * rows;
    if capacity == 0 {
        return Err(PanelTooSmall {
            part_width_mm: cell_w - spec.cavity_spacing_mm,
            part_length_mm: cell_h - spec.cavity_spacing_mm,
            width_mm: spec.panel_width_mm,
            height_mm: spec.panel_height_mm,
            border_mm: spec.border_mm,
        });
    }
    // Centre the grid in the panel.
    let x0 = (spec.panel_width_mm - (cols as f64 * cell_w - spec.cavity_spacing_mm)) / 2.0;
    let y0 = (spec.panel_height_mm - (rows as f64 * cell_h - spec.cavity_spacing_mm)) / 2.0;
    let mut panels: Vec<Vec<(usize, Point)>> = Vec::new();
    for (i, (panel, col, row)) in grid_slots(quantity, cols, rows).enumerate() {
        if panel == panels.len() {
            panels.push(Vec::new());
        }
        let base = [
            x0 + col as f64 * cell_w + (cell_w - spec.cavity_spacing_mm) / 2.0,
            y0 + row as f64 * cell_h + spec.cavity_clearance_mm + parts.base_tab_mm,
        ];
        panels.last_mut().expect("pushed above").push((i, base));
    }
    Ok(PanelLayout {
        width_mm: spec.panel_width_mm,
        height_mm: spec.panel_height_mm,
        capacity,
        panels,
    })
}

/// Panel outline with the top-left corner chamfered so no layer can go in flipped or turned (CCW).
pub fn panel_outline(spec: &ClampSpec) -> Vec<Point> {
    let (w, h) = (spec.panel_width_mm, spec.panel_height_mm);
    let c = (spec.pin_inset_mm * 2.0).min(w / 4.0).min(h / 4.0);
    vec![[0.0, 0.0], [w, 0.0], [w, h], [c, h], [0.0, h - c]]
}

/// Pin hole centres: three corners and a fourth moved off-symmetric, so the pins also key the panel.
pub fn pin_centres(spec: &ClampSpec) -> Vec<Point> {
    let (w, h, d) = (spec.panel_width_mm, spec.panel_height_mm, spec.pin_inset_mm);
    vec![[d, d], [w - d, d], [w - d, h - d], [d + 2.0 * d, h - d]]
}

/// Crosshair fiducials (two strokes each) in the border at mid-height of both sides, clear of the pins
/// (corners), the stacking windows (bottom edge) and the title (top edge).
pub fn fiducials(spec: &ClampSpec) -> Vec<Vec<Point>> {
    let (w, h, s) = (
        spec.panel_width_mm,
        spec.panel_height_mm,
        spec.fiducial_size_mm / 2.0,
    );
    let inset = (spec.border_mm / 2.0).max(s);
    let centres = [[inset, h / 2.0], [w - inset, h / 2.0]];
    centres
        .iter()
        .flat_map(|c| {
            vec![
                vec![[c[0] - s, c[1]], [c[0] + s, c[1]]],
                vec![[c[0], c[1] - s], [c[0], c[1] + s]],
            ]
        })
        .collect()
}

/// Lower-left corner of stacking window `k` (0-based stack position), along the bottom edge.
pub fn window_origin(spec: &ClampSpec, k: usize) -> Point {
    let x = 3.0 * spec.pin_inset_mm
        + spec.pin_radius_mm
        + 2.0
        + k as f64 * (spec.window_width_mm + 1.5);
    [x, (spec.border_mm - spec.window_height_mm) / 2.0]
}

/// The engraved label texts of a panel sheet (clamp or linkage), longest first:
/// `{title} {layer} {t}mm P{panel}`, the sheet's thickness with its layer since the layers of one stack
/// differ by film and a sheet off the stack must say which film it is; then without the thickness, then
/// without the title. `panel` is a number or a run (`1-6`).
fn border_texts(title: &str, layer: &str, thickness_mm: Option<f64>, panel: &str) -> [String; 4] {
    let t = thickness_mm.map_or(String::new(), |t| {
        format!(" {}mm", crate::drawing::decimal::fmt_mm(t))
    });
    [
        format!("{title} {layer}{t} P{panel}"),
        format!("{title} {layer} P{panel}"),
        format!("{layer}{t} P{panel}"),
        format!("{layer} P{panel}"),
    ]
}

/// The strokes of the label of panel `panel`'s sheet of `layer` ([`border_texts`], the first that
/// fits) on the top border of a panel of `spec`, engraved beside the fourth pin hole: at 30 % of the
/// border's height (at most 2.5 mm), starting 3 pin insets from the left edge and at least 1 mm clear
/// of the pin whatever its radius. Nothing when none fits.
pub fn border_label(
    spec: &ClampSpec,
    title: &str,
    layer: &str,
    thickness_mm: Option<f64>,
    panel: &str,
) -> Vec<Vec<Point>> {
    let texts = border_texts(title, layer, thickness_mm, panel);
    let th = (spec.border_mm * 0.3).min(2.5);
    let shift = (spec.pin_radius_mm + 1.0 - 2.0).max(0.0);
    let room = spec.panel_width_mm - 6.0 * spec.pin_inset_mm - shift;
    if th <= 0.0 {
        return Vec::new();
    }
    texts
        .iter()
        .find(|t| label_width(t, th) < room)
        .map_or_else(Vec::new, |t| {
            label_strokes(
                t,
                [
                    3.0 * spec.pin_inset_mm + 2.0 + shift,
                    spec.panel_height_mm - (spec.border_mm + th) / 2.0,
                ],
                th,
            )
        })
}

/// Rectangle ring.
pub fn rect(origin: Point, w: f64, h: f64) -> Vec<Point> {
    vec![
        origin,
        [origin[0] + w, origin[1]],
        [origin[0] + w, origin[1] + h],
        [origin[0], origin[1] + h],
    ]
}

/// Ends closer than this to the sheet edge lie on it, mm (the PZT planner puts them there exactly).
const ON_EDGE_MM: f64 = 1e-6;

/// Whether a score line's end `p` lies on the edge of a `width_mm` x `height_mm` sheet.
pub(crate) fn on_sheet_edge(p: Point, width_mm: f64, height_mm: f64) -> bool {
    p[0].abs() < ON_EDGE_MM
        || p[1].abs() < ON_EDGE_MM
        || (p[0] - width_mm).abs() < ON_EDGE_MM
        || (p[1] - height_mm).abs() < ON_EDGE_MM
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::process::template::Template;
    use std::path::Path;

    #[test]
    fn a_panel_label_names_its_film_thickness_then_falls_back_without_it() {
        assert_eq!(
            border_texts("C", "mold-4", Some(0.05), "1"),
            [
                "C mold-4 0.05mm P1",
                "C mold-4 P1",
                "mold-4 0.05mm P1",
                "mold-4 P1"
            ]
        );
        assert_eq!(
            border_texts("C", "mold-4", Some(0.05), "1-6")[0],
            "C mold-4 0.05mm P1-6"
        );
    }

    #[test]
    fn panels_hold_every_actuator_once_inside_the_border() {
        let spec = Template::resolve("method-2", Path::new("d.toml"))
            .unwrap()
            .clamp;
        let g = PartGeometry {
            piezo_length_mm: 23.0,
            extension_length_mm: 19.2,
            base_width_mm: 5.0,
            tip_width_mm: 1.0,
            base_tab_mm: 0.0,
            pzt_margin_mm: 0.0,
        };
        let layout = layout_panels(&spec, &g, 50).unwrap();
        let all: Vec<usize> = layout.panels.iter().flatten().map(|(i, _)| *i).collect();
        assert_eq!(all, (0..50).collect::<Vec<_>>());
        assert_eq!(layout.panels.len(), 50usize.div_ceil(layout.capacity));
        for (_, base) in layout.panels.iter().flatten() {
            assert!(
                base[0] - 2.5 >= spec.border_mm - 1e-9
                    && base[0] + 2.5 <= spec.panel_width_mm - spec.border_mm + 1e-9
            );
            assert!(
                base[1] + g.passive_length_mm() <= spec.panel_height_mm - spec.border_mm + 1e-9
            );
        }
        let huge = PartGeometry {
            piezo_length_mm: 200.0,
            ..g
        };
        assert!(layout_panels(&spec, &huge, 1).is_err());
    }
}
