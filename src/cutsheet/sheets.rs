//! Layer drawings for one design: PZT score sheets, passive and Pyralux cut sheets, clamp-panel layers.

use super::panel::{fiducials, layout_panels, panel_outline, pin_centres, rect, window_origin};
use super::parts::{PartGeometry, Point};
use super::report::LayerRow;
use super::template::{PassiveCut, SheetSpec, Template};
use super::{CutSheetError, SheetDrawing};
use crate::cam::drawing::polygon_area as ring_area;
use crate::cam::drawing::{Drawing, Operation, Shape};
use crate::cam::kerf::offset_ring;
use crate::cam::label::{label_strokes, label_width};
use crate::design::Design;
use crate::layout::{
    layout_parts, layout_plates, verify_break_order, verify_copies, verify_outlines, verify_sheet,
    verify_sheet_edges, verify_snappable, PartSpec, PlateSpec, Sheet, SheetLayout,
};
use crate::layout::{place_point, place_ring as place};

/// Diameter of the ply registration holes (ply-by-ply cutting), mm: a 0.5 mm pin.
pub const REGISTRATION_HOLE_MM: f64 = 0.5;

/// Everything `build` makes.
#[derive(Debug, Clone)]
pub struct Built {
    /// Drawings in file order.
    pub drawings: Vec<SheetDrawing>,
    /// Assembled actuator preview.
    pub preview: Drawing,
    /// Per-layer totals.
    pub layers: Vec<LayerRow>,
    /// Clamp stack, bottom to top, with the mold layers numbered.
    pub stack: Vec<String>,
    /// Clamp panels used.
    pub panels: usize,
    /// Which clamp panel holds each actuator, and which PZT sheet holds each plate.
    pub placement_map: Vec<String>,
}

fn geometry_error(design: &Design, what: String) -> CutSheetError {
    CutSheetError::Geometry {
        file: design.source.display().to_string(),
        what,
    }
}

/// Offset a ring by `delta` mm (outer contours +kerf/2, holes and cavities -kerf/2), naming the feature
/// when it vanishes.
fn kerfed(
    design: &Design,
    ring: &[Point],
    delta: f64,
    feature: &str,
) -> Result<Vec<Point>, CutSheetError> {
    if delta == 0.0 {
        return Ok(ring.to_vec());
    }
    offset_ring(ring, delta).map_err(|e| geometry_error(design, format!("{feature}: {e}")))
}

fn layout_error(design: &Design, layer: &str, e: impl std::fmt::Display) -> CutSheetError {
    geometry_error(design, format!("{layer} layout: {e}"))
}

fn sheet_of(spec: &SheetSpec) -> Sheet {
    Sheet {
        width_mm: spec.width_mm,
        height_mm: spec.height_mm,
    }
}

/// Build every layer of `design.quantity` actuators.
pub fn build(design: &Design, template: &Template) -> Result<Built, CutSheetError> {
    let g = PartGeometry::of(design);
    let widest_kerf = [template.pzt.kerf_mm, template.passive.kerf_mm]
        .into_iter()
        .fold(0.0, f64::max);
    if g.tip_width_mm < 2.0 * widest_kerf {
        return Err(geometry_error(
            design,
            format!(
                "geometry: tip width {:.4} mm is narrower than twice the kerf (2 x {} mm): the tip would be cut away",
                g.tip_width_mm, widest_kerf
            ),
        ));
    }
    let mut built = Built {
        drawings: Vec::new(),
        preview: preview(&g, &design.name),
        layers: Vec::new(),
        stack: Vec::new(),
        panels: 0,
        placement_map: Vec::new(),
    };
    pzt_sheets(design, template, &g, &mut built)?;
    passive_sheets(design, template, &g, &mut built)?;
    if template.bond.is_some() {
        pyralux_sheets(design, template, &g, &mut built)?;
    }
    clamp_layers(design, template, &g, &mut built)?;
    Ok(built)
}

fn utilization(area_each: f64, parts: usize, sheets: usize, sheet: &Sheet) -> Option<f64> {
    (sheets > 0)
        .then(|| area_each * parts as f64 / (sheets as f64 * sheet.width_mm * sheet.height_mm))
}

fn pzt_sheets(
    design: &Design,
    template: &Template,
    g: &PartGeometry,
    built: &mut Built,
) -> Result<(), CutSheetError> {
    let spec = &template.pzt;
    let sheet = sheet_of(spec);
    let plates = 2 * design.quantity;
    let item = PlateSpec {
        length_mm: g.piezo_length_mm,
        base_width_mm: g.base_width_mm,
        tip_width_mm: g.tip_width_mm,
        count: plates,
    };
    let layouts = layout_plates(&[item], &sheet, spec.kerf_mm, spec.edge_margin_mm, None)
        .map_err(|e| layout_error(design, "pzt", e))?;
    // Check the layout independently of the code that made it before anything is drawn.
    let fail = |v: Vec<crate::layout::Violation>| {
        layout_error(design, "pzt (verifier)", format_violations(&v))
    };
    verify_copies(&layouts, &[plates]).map_err(fail)?;
    let nominal = g.pzt_outline();
    for layout in &layouts {
        verify_snappable(layout, &sheet).map_err(fail)?;
        verify_break_order(layout, &sheet).map_err(fail)?;
        verify_outlines(layout, &|_| nominal.clone(), 1e-9).map_err(fail)?;
        // PZT is in-plane isotropic: strips may run either way, so any quarter turn is allowed.
        verify_sheet_edges(
            layout,
            &sheet,
            (spec.kerf_mm - 1e-9).max(0.0),
            (spec.edge_margin_mm - 1e-9).max(0.0),
            &|_| vec![0.0, 90.0, 180.0, 270.0],
        )
        .map_err(fail)?;
        let n = layout.sheet_index + 1;
        let mut d = Drawing::new(
            &format!("{} PZT plates, sheet {n}: score, then snap", design.name),
            sheet.width_mm,
            sheet.height_mm,
        );
        for line in &layout.score_lines {
            d.add(Operation::Score, Shape::Polyline(vec![line[0], line[1]]));
        }
        // The sheet edge as a green alignment reference (not a cut).
        d.add(
            Operation::Secondary,
            Shape::Polygon(rect([0.0, 0.0], sheet.width_mm, sheet.height_mm)),
        );
        for p in &layout.placements {
            built.placement_map.push(format!(
                "actuator {} plate {}: PZT sheet {n}",
                p.copy / 2 + 1,
                p.copy % 2 + 1
            ));
        }
        built.drawings.push(SheetDrawing {
            stem: format!("pzt-{n}"),
            layer: "pzt".into(),
            drawing: d,
        });
    }
    built.layers.push(LayerRow::new(LayerRow {
        layer: "pzt".into(),
        material: format!("{} ({})", design.pzt.name, spec.material),
        thickness_mm: design.pzt_thickness * 1e3,
        density_kg_per_m3: design.pzt.density,
        part_area_mm2: ring_area(&g.pzt_outline()),
        parts_per_actuator: 2,
        sheets: layouts.len(),
        utilization: utilization(ring_area(&g.pzt_outline()), plates, layouts.len(), &sheet),
        mass_per_actuator_mg: 0.0,
    }));
    Ok(())
}

/// A label along the part axis from `y_start`, if it fits inside the trapezoid with a margin.
fn axis_label(g: &PartGeometry, text: &str, height: f64, margin: f64) -> Option<Vec<Vec<Point>>> {
    if height <= 0.0 {
        return None;
    }
    let width = label_width(text, height);
    let y_start = 0.1 * g.piezo_length_mm;
    let y_end = y_start + width;
    let narrowest = g
        .width_at_mm(y_start)
        .min(g.width_at_mm(y_end.min(g.piezo_length_mm)));
    if y_end > 0.9 * g.piezo_length_mm || narrowest < height + 2.0 * margin {
        return None;
    }
    // Text runs along +x from the origin; turn it 90° so it reads along the axis, centred on it.
    Some(
        label_strokes(text, [0.0, 0.0], height)
            .into_iter()
            .map(|s| place(&s, 90.0, [height / 2.0, y_start]))
            .collect(),
    )
}

#[allow(clippy::too_many_arguments)]
fn cut_part_sheets(
    design: &Design,
    layer: &str,
    spec: &SheetSpec,
    outline: &[Point],
    count: usize,
    holes: &[(Point, f64)],
    label: &dyn Fn(usize) -> Option<Vec<Vec<Point>>>,
    built: &mut Built,
) -> Result<usize, CutSheetError> {
    let sheet = sheet_of(spec);
    // Lay out the cut paths (nominal outline grown by kerf/2, mitred corners included) with the template's
    // spacing between them: the web of material between two cuts is what must survive.
    let cut_outline = kerfed(
        design,
        outline,
        spec.kerf_mm / 2.0,
        &format!("{layer} part outline"),
    )?;
    let gap = spec.spacing_mm;
    let rotations = vec![0.0, 180.0];
    let item = PartSpec {
        outline: cut_outline,
        count,
        rotations_deg: rotations.clone(),
    };
    let layouts: Vec<SheetLayout> = layout_parts(std::slice::from_ref(&item), &sheet, gap, None)
        .map_err(|e| layout_error(design, layer, e))?;
    let fail = |v: Vec<crate::layout::Violation>| {
        layout_error(
            design,
            &format!("{layer} (verifier)"),
            format_violations(&v),
        )
    };
    verify_copies(&layouts, &[count]).map_err(fail)?;
    for layout in &layouts {
        verify_sheet(layout, &sheet, (gap - 1e-9).max(0.0), &|_| {
            rotations.clone()
        })
        .map_err(fail)?;
        verify_outlines(layout, &|_| item.outline.clone(), 1e-9).map_err(fail)?;
        let n = layout.sheet_index + 1;
        let mut d = Drawing::new(
            &format!("{} {layer}, sheet {n}", design.name),
            sheet.width_mm,
            sheet.height_mm,
        );
        // Inner features first: holes, then labels, then the outer contours (cut order).
        for p in &layout.placements {
            for (centre, radius) in holes {
                let r = radius - spec.kerf_mm / 2.0;
                if r <= 0.0 {
                    return Err(geometry_error(
                        design,
                        format!(
                            "{layer}: a {:.3} mm hole vanishes inside the {} mm kerf",
                            2.0 * radius,
                            spec.kerf_mm
                        ),
                    ));
                }
                d.add(
                    Operation::Cut,
                    Shape::Circle {
                        center: place_point(*centre, p.rotation_deg, p.offset),
                        radius: r,
                    },
                );
            }
        }
        for p in &layout.placements {
            if let Some(strokes) = label(p.copy) {
                for s in strokes {
                    d.add(
                        Operation::Engrave,
                        Shape::Polyline(place(&s, p.rotation_deg, p.offset)),
                    );
                }
            }
        }
        for p in &layout.placements {
            d.add(Operation::Cut, Shape::Polygon(p.outline.clone()));
        }
        built.drawings.push(SheetDrawing {
            stem: format!("{layer}-{n}"),
            layer: layer.into(),
            drawing: d,
        });
    }
    Ok(layouts.len())
}

fn passive_sheets(
    design: &Design,
    template: &Template,
    g: &PartGeometry,
    built: &mut Built,
) -> Result<(), CutSheetError> {
    let spec = &template.passive;
    let outline = g.passive_outline();
    let area = ring_area(&outline);
    let margin = spec.kerf_mm.max(0.2);
    let name = design.name.clone();
    let height = template.label_height_mm;
    let label = |copy: usize| {
        axis_label(g, &format!("{name} {}", copy + 1), height, margin)
            .or_else(|| axis_label(g, &format!("{}", copy + 1), height, margin))
    };
    let material = format!("{} ({})", design.ply.name, spec.material);
    match template.passive_cut {
        PassiveCut::Stack => {
            let sheets = cut_part_sheets(
                design,
                "passive",
                spec,
                &outline,
                design.quantity,
                &[],
                &label,
                built,
            )?;
            built.layers.push(LayerRow::new(LayerRow {
                layer: "passive".into(),
                material,
                thickness_mm: design.ply_thickness * 1e3 * design.layup_deg.len() as f64,
                density_kg_per_m3: design.ply.density,
                part_area_mm2: area,
                parts_per_actuator: 1,
                sheets,
                utilization: utilization(area, design.quantity, sheets, &sheet_of(spec)),
                mass_per_actuator_mg: 0.0,
            }));
        }
        PassiveCut::PlyByPly => {
            // Registration holes through every ply, in the passive-only base tab (clamped, so they do
            // not touch the active part): two pins stack one actuator's plies in register.
            let d = REGISTRATION_HOLE_MM;
            let web = spec.kerf_mm.max(0.2);
            if g.base_tab_mm < d + 2.0 * web || g.base_width_mm / 4.0 < d / 2.0 + web {
                return Err(geometry_error(
                    design,
                    format!(
                        "geometry.base_tab_mm = {}: ply-by-ply cutting puts two {d} mm registration holes in the base tab; it needs a tab of at least {:.2} mm and a base width of at least {:.2} mm",
                        g.base_tab_mm,
                        d + 2.0 * web,
                        4.0 * (d / 2.0 + web)
                    ),
                ));
            }
            let holes: Vec<(Point, f64)> = [-1.0, 1.0]
                .iter()
                .map(|side| {
                    (
                        [side * g.base_width_mm / 4.0, -g.base_tab_mm / 2.0],
                        d / 2.0,
                    )
                })
                .collect();
            for (i, angle) in design.layup_deg.iter().enumerate() {
                // Prepreg fibres run along the sheet's y axis; turning the part by -θ puts them at +θ
                // (counter-clockwise) from its axis.
                let turned = place(&outline, -angle, [0.0, 0.0]);
                let turned_holes: Vec<(Point, f64)> = holes
                    .iter()
                    .map(|(c, r)| (place_point(*c, -angle, [0.0, 0.0]), *r))
                    .collect();
                let layer = format!("passive-ply{}-{}deg", i + 1, angle);
                let sheets = cut_part_sheets(
                    design,
                    &layer,
                    spec,
                    &turned,
                    design.quantity,
                    &turned_holes,
                    &|_| None,
                    built,
                )?;
                built.layers.push(LayerRow::new(LayerRow {
                    layer,
                    material: material.clone(),
                    thickness_mm: design.ply_thickness * 1e3,
                    density_kg_per_m3: design.ply.density,
                    part_area_mm2: area,
                    parts_per_actuator: 1,
                    sheets,
                    utilization: utilization(area, design.quantity, sheets, &sheet_of(spec)),
                    mass_per_actuator_mg: 0.0,
                }));
            }
        }
    }
    Ok(())
}

fn pyralux_sheets(
    design: &Design,
    template: &Template,
    g: &PartGeometry,
    built: &mut Built,
) -> Result<(), CutSheetError> {
    let bond = template.bond.as_ref().expect("caller checked");
    let outline = g.pzt_outline();
    let via = (
        [0.0, bond.via_position * g.piezo_length_mm],
        bond.via_diameter_mm / 2.0,
    );
    let via_edge_room = g.width_at_mm(via.0[1]) / 2.0 - via.1;
    if via_edge_room < 2.0 * bond.sheet.kerf_mm {
        return Err(geometry_error(design, format!("pyralux: the {} mm via leaves {:.3} mm to the plate edge, less than twice the kerf", bond.via_diameter_mm, via_edge_room)));
    }
    let sheets = cut_part_sheets(
        design,
        "pyralux",
        &bond.sheet,
        &outline,
        2 * design.quantity,
        &[via],
        &|_| None,
        built,
    )?;
    let area = ring_area(&outline);
    built.layers.push(LayerRow::new(LayerRow {
        layer: "pyralux".into(),
        material: bond.sheet.material.clone(),
        thickness_mm: bond.thickness_mm,
        density_kg_per_m3: bond.density_kg_per_m3,
        part_area_mm2: area,
        parts_per_actuator: 2,
        sheets,
        utilization: utilization(area, 2 * design.quantity, sheets, &sheet_of(&bond.sheet)),
        mass_per_actuator_mg: 0.0,
    }));
    Ok(())
}

/// The cavity shape of mold layer `j` (height band `[j t, (j+1) t]` from the bottom of the stack): the
/// passive outline where the band meets the passive core or bond layers, the PZT outline elsewhere.
fn cavity_outline(
    design: &Design,
    g: &PartGeometry,
    mold_thickness_mm: f64,
    j: usize,
) -> Vec<Point> {
    let t_p = design.pzt_thickness * 1e3;
    let t_b = design.bond.as_ref().map(|(_, t)| t * 1e3).unwrap_or(0.0);
    let core = design.ply_thickness * 1e3 * design.layup_deg.len() as f64 + 2.0 * t_b;
    let (lo, hi) = (
        j as f64 * mold_thickness_mm,
        (j + 1) as f64 * mold_thickness_mm,
    );
    if lo < t_p + core && hi > t_p {
        g.passive_outline()
    } else {
        g.pzt_outline()
    }
}

fn clamp_layers(
    design: &Design,
    template: &Template,
    g: &PartGeometry,
    built: &mut Built,
) -> Result<(), CutSheetError> {
    let c = &template.clamp;
    let panels = layout_panels(c, g, design.quantity)
        .map_err(|e| geometry_error(design, format!("clamp panel: {e}")))?;
    built.panels = panels.panels.len();
    for (p, members) in panels.panels.iter().enumerate() {
        for (i, _) in members {
            built
                .placement_map
                .push(format!("actuator {}: clamp panel {}", i + 1, p + 1));
        }
    }
    let laminate_mm = (2.0 * design.pzt_thickness
        + design.ply_thickness * design.layup_deg.len() as f64
        + 2.0 * design.bond.as_ref().map(|(_, t)| *t).unwrap_or(0.0))
        * 1e3;
    let molds = ((laminate_mm / template.mold.thickness_mm) - 1e-9)
        .ceil()
        .max(1.0) as usize;
    // Expand the stack: "mold" becomes mold-1..n; other layers are numbered by occurrence.
    let mut stack: Vec<(String, String, usize)> = Vec::new(); // (layer kind, stem prefix, index)
    for name in &c.stack {
        if name == "mold" {
            for j in 0..molds {
                stack.push(("mold".into(), format!("mold-{}", j + 1), j));
            }
        } else {
            let occurrence = stack.iter().filter(|(k, _, _)| k == name).count() + 1;
            stack.push((name.clone(), format!("{name}-{occurrence}"), 0));
        }
    }
    built.stack = stack.iter().map(|(_, stem, _)| stem.clone()).collect();
    let outline = panel_outline(c);
    let levels = stack.len();
    for (k, (kind, prefix, j)) in stack.iter().enumerate() {
        let spec = if kind == "mold" {
            &template.mold
        } else {
            &template.covers[kind]
        };
        let kerf = spec.kerf_mm;
        for (p, members) in panels.panels.iter().enumerate() {
            let mut d = Drawing::new(
                &format!(
                    "{} clamp layer {}/{levels} ({prefix}), panel {}",
                    design.name,
                    k + 1,
                    p + 1
                ),
                c.panel_width_mm,
                c.panel_height_mm,
            );
            for centre in pin_centres(c) {
                let r = c.pin_radius_mm - kerf / 2.0;
                if r <= 0.0 {
                    return Err(geometry_error(
                        design,
                        format!(
                            "clamp: pin hole radius {} mm vanishes in the {kerf} mm kerf",
                            c.pin_radius_mm
                        ),
                    ));
                }
                d.add(
                    Operation::Cut,
                    Shape::Circle {
                        center: centre,
                        radius: r,
                    },
                );
            }
            // Windows through this layer onto every layer below it: the stacking order shows from the top.
            for below in 0..k {
                let w = rect(
                    window_origin(c, below),
                    c.window_width_mm,
                    c.window_height_mm,
                );
                d.add(
                    Operation::Cut,
                    Shape::Polygon(kerfed(design, &w, -kerf / 2.0, "stacking window")?),
                );
            }
            if kind == "mold" {
                let cavity = cavity_outline(design, g, template.mold.thickness_mm, *j);
                let grown = kerfed(
                    design,
                    &cavity,
                    c.cavity_clearance_mm,
                    "mold cavity clearance",
                )?;
                for (_, base) in members {
                    let placed = place(&grown, 0.0, *base);
                    d.add(
                        Operation::Cut,
                        Shape::Polygon(kerfed(design, &placed, -kerf / 2.0, "mold cavity")?),
                    );
                }
            }
            let number = format!("{}", k + 1);
            let h = (c.window_height_mm * 0.6).min(2.0);
            let o = window_origin(c, k);
            for s in label_strokes(
                &number,
                [o[0] + 0.5, o[1] + (c.window_height_mm - h) / 2.0],
                h,
            ) {
                d.add(Operation::Engrave, Shape::Polyline(s));
            }
            let title = format!("{} {prefix} P{}", design.name, p + 1);
            let th = (c.border_mm * 0.3).min(2.5);
            if th > 0.0 && label_width(&title, th) < c.panel_width_mm - 6.0 * c.pin_inset_mm {
                for s in label_strokes(
                    &title,
                    [
                        3.0 * c.pin_inset_mm + 2.0,
                        c.panel_height_mm - (c.border_mm + th) / 2.0,
                    ],
                    th,
                ) {
                    d.add(Operation::Engrave, Shape::Polyline(s));
                }
            }
            for f in fiducials(c) {
                d.add(Operation::Engrave, Shape::Polyline(f));
            }
            d.add(
                Operation::Cut,
                Shape::Polygon(kerfed(design, &outline, kerf / 2.0, "panel outline")?),
            );
            built.drawings.push(SheetDrawing {
                stem: format!("{prefix}-{}", p + 1),
                layer: kind.clone(),
                drawing: d,
            });
        }
    }
    let panel_area = ring_area(&outline);
    for name in
        std::iter::once("mold".to_string()).chain(c.stack.iter().filter(|n| *n != "mold").cloned())
    {
        if built.layers.iter().any(|l| l.layer == name) {
            continue;
        }
        let spec = if name == "mold" {
            &template.mold
        } else {
            &template.covers[&name]
        };
        let count = stack.iter().filter(|(k, _, _)| *k == name).count();
        built.layers.push(LayerRow::new(LayerRow {
            layer: name,
            material: spec.material.clone(),
            thickness_mm: spec.thickness_mm,
            density_kg_per_m3: spec.density_kg_per_m3,
            part_area_mm2: panel_area,
            parts_per_actuator: 0,
            sheets: count * panels.panels.len(),
            utilization: None,
            mass_per_actuator_mg: 0.0,
        }));
    }
    Ok(())
}

/// The assembled actuator: passive outline (green) under the PZT plate (red), with a 1 mm margin.
fn preview(g: &PartGeometry, name: &str) -> Drawing {
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
        Shape::Polygon(place(&g.passive_outline(), 0.0, origin)),
    );
    d.add(
        Operation::Cut,
        Shape::Polygon(place(&g.pzt_outline(), 0.0, origin)),
    );
    d
}

fn format_violations<V: std::fmt::Display>(v: &[V]) -> String {
    v.iter()
        .take(3)
        .map(|x| x.to_string())
        .collect::<Vec<_>>()
        .join("; ")
}
