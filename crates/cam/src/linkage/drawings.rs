//! The linkage layers as laser files on the clamp panel (docs/cam.md §7): each layer of the stack on a
//! sheet cut to the panel outline with the panel's pin holes, so the laminate registers on the same
//! pins as the actuator's clamp; then the release cut through the laminated stack. Kerf as for every
//! layer (docs/cam.md §4): the release outline is grown by kerf/2, slots, windows and holes shrunk by
//! kerf/2, so each comes out as drawn.

use super::pattern::{Rect, STACK};
use super::LinkageLaminate;
use crate::drawing::model::{file_stem, Drawing, FibreAxis, Shape, Stock};
use crate::input::InputError;
use crate::pipeline::{border_label, grid, grid_slots, panel_outline, pin_centres, SheetDrawing};
use crate::process::template::{ClampSpec, Template};
use crate::process::Feature;
use cam_geometry::offset::offset_ring;
use cam_geometry::Point;

/// Where each linkage sits on the panels: its pattern's origin, per panel.
pub fn layout(
    laminate: &LinkageLaminate,
    template: &Template,
    count: usize,
) -> Result<Vec<Vec<Point>>, InputError> {
    let c = &template.clamp;
    let p = &laminate.pattern;
    let over = p.overrun_mm;
    let spacing = laminate.process.spacing_mm;
    let cell_w = p.length_mm + 2.0 * over + spacing;
    let cell_h = p.strip_width_mm + 2.0 * over + spacing;
    let (cols, rows) = grid(c, cell_w, cell_h, spacing);
    if cols * rows == 0 {
        return Err(InputError::invalid(
            &template.source,
            "clamp.panel_width_mm",
            c.panel_width_mm,
            format!(
                "a panel that holds the {:.2} x {:.2} mm linkage with its overrun inside the {} mm border",
                p.length_mm + 2.0 * over,
                p.strip_width_mm + 2.0 * over,
                c.border_mm
            ),
        ));
    }
    let mut panels: Vec<Vec<Point>> = Vec::new();
    for (panel, col, row) in grid_slots(count, cols, rows) {
        if panel == panels.len() {
            panels.push(Vec::new());
        }
        let origin = [
            c.border_mm + col as f64 * cell_w + over,
            c.border_mm + row as f64 * cell_h + over + p.strip_width_mm / 2.0,
        ];
        panels.last_mut().expect("pushed above").push(origin);
    }
    Ok(panels)
}

fn offset(
    ring: &[Point],
    delta: f64,
    what: &str,
    template: &Template,
) -> Result<Vec<Point>, InputError> {
    offset_ring(ring, delta).map_err(|e| {
        InputError::invalid(
            &template.source,
            "linkage.kerf_mm",
            delta * 2.0,
            format!("a kerf the linkage's {what} survives: {e}"),
        )
    })
}

/// The layer files of `count` linkages, `linkage-N-<layer>-<panel>`, bottom to top, then the release.
pub fn linkage_drawings(
    laminate: &LinkageLaminate,
    template: &Template,
    count: usize,
    title: &str,
) -> Result<Vec<SheetDrawing>, InputError> {
    let panels = layout(laminate, template, count)?;
    draw_panels(
        laminate,
        template,
        &template.clamp,
        &panels,
        title,
        "linkage-",
    )
}

/// The layer files of linkages with their patterns' origins at `panels` (per panel) on panels of
/// `c`'s outline and pins, `<prefix>N-<layer>-<panel>`, bottom to top, then the release: the clamp
/// panels of `cut-sheet` and the one-linkage coupons of `nest` ([`super::coupon`]) alike.
pub(crate) fn draw_panels(
    laminate: &LinkageLaminate,
    template: &Template,
    c: &ClampSpec,
    panels: &[Vec<Point>],
    title: &str,
    prefix: &str,
) -> Result<Vec<SheetDrawing>, InputError> {
    let features = &template.features;
    let p = &laminate.pattern;
    let kerf = laminate.process.kerf_mm;
    let half = kerf / 2.0;
    let outline = offset(&panel_outline(c), half, "panel outline", template)?;
    let pin_radius = c.pin_radius_mm - half;
    if pin_radius <= 0.0 {
        return Err(InputError::invalid(
            &template.source,
            "clamp.pin_radius_mm",
            c.pin_radius_mm,
            format!("more than half the linkage kerf, {half} mm"),
        ));
    }
    let release = offset(&p.outline(), half, "release outline", template)?;
    let hole_radius = p.hole_diameter_mm / 2.0 - half;
    let levels = STACK.len() + 1;
    let mut drawings = Vec::new();
    for (n, origins) in panels.iter().enumerate() {
        let panel = n + 1;
        // The panel's stock on its top border, as a clamp panel engraves it: a sheet off the stack
        // says which layer and film it is.
        let label = |d: &mut Drawing, layer: &str, thickness_mm: Option<f64>| {
            for s in border_label(c, title, layer, thickness_mm, &panel.to_string()) {
                d.add(features.op(Feature::PanelLabel), Shape::Polyline(s));
            }
        };
        let pins = |d: &mut Drawing| {
            for centre in pin_centres(c) {
                d.add(
                    features.op(Feature::PinHole),
                    Shape::Circle {
                        center: centre,
                        radius: pin_radius,
                    },
                );
            }
        };
        for (k, (ply, name)) in STACK.iter().enumerate() {
            let sheet = match ply {
                super::pattern::Ply::Carbon => &laminate.process.carbon,
                super::pattern::Ply::Adhesive => &laminate.process.adhesive,
                super::pattern::Ply::Film => &laminate.process.film,
            };
            let mut d = Drawing::on_stock(
                &format!(
                    "{title} linkage layer {}/{levels} ({name}), panel {panel}",
                    k + 1
                ),
                c.panel_width_mm,
                c.panel_height_mm,
                Stock {
                    material: sheet.material.clone(),
                    thickness_mm: sheet.thickness_mm,
                    // The carbon's 0° fibres along the links, which run along x on the panel: the
                    // stiff direction of the links, as on the coupons the nester turns onto y.
                    fibre_axis: (*ply == super::pattern::Ply::Carbon).then_some(FibreAxis::X),
                },
            );
            d.add(
                features.op(Feature::PanelOutline),
                Shape::Polygon(outline.clone()),
            );
            pins(&mut d);
            let layer = format!("{prefix}{}-{name}", k + 1);
            label(&mut d, &layer, Some(sheet.thickness_mm));
            for origin in origins {
                for cut in p.cut_outs(*ply) {
                    let r: Rect = cut.moved(*origin).grown(-half);
                    d.add(
                        features.op(Feature::LinkageCutOut),
                        Shape::Polygon(r.ring()),
                    );
                }
            }
            drawings.push(SheetDrawing {
                stem: file_stem(
                    &format!("{prefix}{}-{name}-{panel}", k + 1),
                    d.stock.as_ref(),
                ),
                layer: format!("linkage-{name}"),
                drawing: d,
            });
        }
        let mut d = Drawing::on_stock(
            &format!("{title} linkage layer {levels}/{levels} (release cut through the laminated stack), panel {panel}"),
            c.panel_width_mm,
            c.panel_height_mm,
            Stock {
                material: "the laminated linkage stack".to_string(),
                thickness_mm: laminate.stack_thickness_mm(),
                fibre_axis: None,
            },
        );
        pins(&mut d);
        label(&mut d, &format!("{prefix}{levels}-release"), None);
        for origin in origins {
            d.add(
                features.op(Feature::LinkageHole),
                Shape::Circle {
                    center: [origin[0] + p.hole_centre[0], origin[1] + p.hole_centre[1]],
                    radius: hole_radius,
                },
            );
            d.add(
                features.op(Feature::LinkageRelease),
                Shape::Polygon(
                    release
                        .iter()
                        .map(|q| [q[0] + origin[0], q[1] + origin[1]])
                        .collect(),
                ),
            );
        }
        drawings.push(SheetDrawing {
            stem: file_stem(
                &format!("{prefix}{levels}-release-{panel}"),
                d.stock.as_ref(),
            ),
            layer: "linkage-release".to_string(),
            drawing: d,
        });
    }
    Ok(drawings)
}
