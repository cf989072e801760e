//! The linkage layers as laser files on the clamp panel (docs/cam.md §7): each layer of the stack on a
//! sheet cut to the panel outline with the panel's pin holes, so the laminate registers on the same
//! pins as the actuator's clamp; then the release cut through the laminated stack. Kerf as for every
//! layer (docs/cam.md §4): the release outline is grown by kerf/2, slots, windows and holes shrunk by
//! kerf/2, so each comes out as drawn.

use super::pattern::{Ply, Rect, STACK};
use super::LinkageLaminate;
use crate::drawing::model::{file_stem, Drawing, FibreAxis, Operation, Shape, Stock};
use crate::input::InputError;
use crate::pipeline::{border_label, grid, grid_slots, panel_outline, pin_centres, SheetDrawing};
use crate::process::template::{ClampSpec, Template};
use crate::process::{Feature, FeatureMap};
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
    let half = laminate.process.kerf_mm / 2.0;
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
    let p = &laminate.pattern;
    let drawer = PanelDrawer {
        laminate,
        features: &template.features,
        c,
        title,
        prefix,
        half,
        outline,
        pin_radius,
        release: offset(&p.outline(), half, "release outline", template)?,
        hole_radius: p.hole_diameter_mm / 2.0 - half,
        levels: STACK.len() + 1,
    };
    let mut drawings = Vec::new();
    for (n, origins) in panels.iter().enumerate() {
        let panel = n + 1;
        for (k, (ply, name)) in STACK.iter().enumerate() {
            drawings.push(drawer.stack_layer(panel, origins, k, *ply, name));
        }
        drawings.push(drawer.release_cut(panel, origins));
    }
    Ok(drawings)
}

/// What every linkage panel drawing of one laminate shares: the panel, the names, and the shapes
/// with the kerf already applied.
struct PanelDrawer<'a> {
    laminate: &'a LinkageLaminate,
    features: &'a FeatureMap,
    c: &'a ClampSpec,
    title: &'a str,
    prefix: &'a str,
    /// Half the kerf, mm.
    half: f64,
    /// The panel outline, grown by kerf/2.
    outline: Vec<Point>,
    /// The pin holes' radius, kerf/2 off.
    pin_radius: f64,
    /// One linkage's release outline, grown by kerf/2.
    release: Vec<Point>,
    /// The linkage's hole radius, kerf/2 off.
    hole_radius: f64,
    /// Stack layers and the release cut.
    levels: usize,
}

impl PanelDrawer<'_> {
    /// The panel's stock on its top border, as a clamp panel engraves it: a sheet off the stack
    /// says which layer and film it is.
    fn label(&self, d: &mut Drawing, panel: usize, layer: &str, thickness_mm: Option<f64>) {
        for s in border_label(self.c, self.title, layer, thickness_mm, &panel.to_string()) {
            d.add(self.features.op(Feature::PanelLabel), Shape::Polyline(s));
        }
    }

    /// The release outline of the linkage at `origin`.
    fn released_at(&self, origin: Point) -> Vec<Point> {
        self.release
            .iter()
            .map(|q| [q[0] + origin[0], q[1] + origin[1]])
            .collect()
    }

    /// The panel's pin holes.
    fn pins(&self, d: &mut Drawing, op: Operation) {
        for centre in pin_centres(self.c) {
            d.add(
                op,
                Shape::Circle {
                    center: centre,
                    radius: self.pin_radius,
                },
            );
        }
    }

    /// Stack layer `k` (`ply`, `name`) of panel `panel`, whose linkages sit at `origins`.
    fn stack_layer(
        &self,
        panel: usize,
        origins: &[Point],
        k: usize,
        ply: Ply,
        name: &str,
    ) -> SheetDrawing {
        let (c, features, prefix, levels) = (self.c, self.features, self.prefix, self.levels);
        let process = &self.laminate.process;
        let sheet = match ply {
            Ply::Carbon => &process.carbon,
            Ply::Adhesive => &process.adhesive,
            Ply::Film => &process.film,
        };
        let mut d = Drawing::on_stock(
            &format!(
                "{} linkage layer {}/{levels} ({name}), panel {panel}",
                self.title,
                k + 1
            ),
            c.panel_width_mm,
            c.panel_height_mm,
            Stock {
                material: sheet.material.clone(),
                thickness_mm: sheet.thickness_mm,
                kerf_mm: process.kerf_mm,
                // The carbon's 0° fibres along the links, which run along x on the panel: the
                // stiff direction of the links, as on the coupons the nester turns onto y.
                fibre_axis: (ply == Ply::Carbon).then_some(FibreAxis::X),
            },
        );
        self.pins(&mut d, self.features.op(Feature::PinHole));
        let layer = format!("{prefix}{}-{name}", k + 1);
        self.label(&mut d, panel, &layer, Some(sheet.thickness_mm));
        for origin in origins {
            // Each stack layer is laminated to its neighbours over the linkage (its release outline):
            // a bonded face, where nothing may be engraved. The border around is cut away.
            d.add_guide("bonded-zone", self.released_at(*origin));
            for cut in self.laminate.pattern.cut_outs(ply) {
                let r: Rect = cut.moved(*origin).grown(-self.half);
                d.add(
                    features.op(Feature::LinkageCutOut),
                    Shape::Polygon(r.ring()),
                );
            }
        }
        // The outline last: cut first, it would free the panel (a 7.6 µm film among them) before its
        // slots and pin holes, which then cut a sheet that moves.
        d.add(
            features.op(Feature::PanelOutline),
            Shape::Polygon(self.outline.clone()),
        );
        SheetDrawing {
            stem: file_stem(
                &format!("{prefix}{}-{name}-{panel}", k + 1),
                d.stock.as_ref(),
            ),
            layer: format!("linkage-{name}"),
            drawing: d,
        }
    }

    /// The release cut through the laminated stack of panel `panel`, whose linkages sit at
    /// `origins`: each linkage's hole and outline.
    fn release_cut(&self, panel: usize, origins: &[Point]) -> SheetDrawing {
        let (c, features, prefix, levels) = (self.c, self.features, self.prefix, self.levels);
        let p = &self.laminate.pattern;
        let mut d = Drawing::on_stock(
            &format!(
                "{} linkage layer {levels}/{levels} (release cut through the laminated stack), panel {panel}",
                self.title
            ),
            c.panel_width_mm,
            c.panel_height_mm,
            Stock {
                material: "the laminated linkage stack".to_string(),
                thickness_mm: self.laminate.stack_thickness_mm(),
                kerf_mm: self.laminate.process.kerf_mm,
                fibre_axis: None,
            },
        );
        // The stack sits on the steel dowels through its pin holes while the release cut runs: the
        // holes are drawn as a guide the laser never runs, or the beam would land on the dowels.
        self.pins(&mut d, Operation::Reference);
        // No label: the release runs on the laminated stack, whose top layer carries its own label
        // where this one would go, and an engraving there would burn over it.
        for origin in origins {
            d.add(
                features.op(Feature::LinkageHole),
                Shape::Circle {
                    center: [origin[0] + p.hole_centre[0], origin[1] + p.hole_centre[1]],
                    radius: self.hole_radius,
                },
            );
            d.add(
                features.op(Feature::LinkageRelease),
                Shape::Polygon(self.released_at(*origin)),
            );
        }
        SheetDrawing {
            stem: file_stem(
                &format!("{prefix}{levels}-release-{panel}"),
                d.stock.as_ref(),
            ),
            layer: "linkage-release".to_string(),
            drawing: d,
        }
    }
}
