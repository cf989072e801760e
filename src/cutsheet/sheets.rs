//! Layer drawings for one design: PZT score sheets, passive and Pyralux cut sheets (shelf layout),
//! clamp-panel layers. The layer builders are shared with batch nesting (`crate::batch`).

use super::clamp::clamp_layers;
use super::cut::{draw_cut_sheets, passive_layers, pyralux_layer, CutLayer, CUT_ROTATIONS_DEG};
use super::jobs::{check_geometry, format_violations, Drawn, Job, Names};
use super::parts::PartGeometry;
use super::pzt::pzt_sheets;
use super::report::LayerRow;
use super::template::Template;
use super::{CutSheetError, SheetDrawing};
use crate::cam::drawing::{Drawing, Operation, Shape};
use crate::design::Design;
use crate::layout::{
    layout_parts, verify_copies, verify_outlines, verify_sheet, PartSpec, Sheet, SheetLayout,
    Violation,
};
use cam_geometry::place_ring;
use cam_geometry::signed_area;

pub use super::cut::REGISTRATION_HOLE_MM;

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

fn utilization(
    area_each: f64,
    parts: usize,
    sheets: usize,
    spec: &super::template::SheetSpec,
) -> Option<f64> {
    (sheets > 0)
        .then(|| area_each * parts as f64 / (sheets as f64 * spec.width_mm * spec.height_mm))
}

/// Build every layer of `design.quantity` actuators.
pub fn build(design: &Design, template: &Template) -> Result<Built, CutSheetError> {
    let job = Job::new(design, design.quantity, template);
    check_geometry(&job, template)?;
    let g = job.geometry;
    let names = Names {
        title: design.name.clone(),
        file: design.source.display().to_string(),
        name_designs: false,
    };
    let mut drawn = Drawn::default();
    let mut layers = Vec::new();
    let pzt = pzt_sheets(
        &[job],
        &template.pzt,
        None,
        &names,
        &template.features,
        &mut drawn,
    )?;
    let spec = &template.pzt;
    layers.push(LayerRow::new(LayerRow {
        layer: "pzt".into(),
        material: format!("{} ({})", design.pzt.name, spec.material),
        thickness_mm: design.pzt_thickness * 1e3,
        density_kg_per_m3: design.pzt.density,
        part_area_mm2: signed_area(&g.pzt_outline()),
        parts_per_actuator: 2,
        sheets: pzt,
        utilization: utilization(signed_area(&g.pzt_outline()), 2 * job.quantity, pzt, spec),
        mass_per_actuator_mg: 0.0,
    }));
    let mut cut_layers = passive_layers(&[(0, job)], template, &template.passive)?;
    cut_layers.extend(pyralux_layer(&[job], template, None)?);
    for layer in &cut_layers {
        let sheets = shelf_sheets(layer, &names, &mut drawn)?;
        let item = &layer.items[0];
        let area = signed_area(&g.passive_outline());
        let (area, parts) = if layer.layer == "pyralux" {
            (signed_area(&item.nominal), item.per_actuator)
        } else {
            (area, 1)
        };
        layers.push(LayerRow::new(LayerRow {
            layer: layer.layer.clone(),
            material: layer.material.clone(),
            thickness_mm: layer.thickness_mm,
            density_kg_per_m3: layer.density_kg_per_m3,
            part_area_mm2: area,
            parts_per_actuator: parts,
            sheets,
            utilization: utilization(area, item.count, sheets, &layer.spec),
            mass_per_actuator_mg: 0.0,
        }));
    }
    let clamp = clamp_layers(&[(0, job)], template, &names, &mut drawn)?;
    clamp_rows(template, &clamp.stack, clamp.panels.len(), &mut layers);
    Ok(Built {
        drawings: drawn.drawings,
        preview: preview(&g, &design.name),
        layers,
        stack: clamp.stack,
        panels: drawn.panels,
        placement_map: drawn.placement_map,
    })
}

/// Lay out a cut layer with the shelf packer (cut paths, the template's spacing between them), verify
/// it independently and draw it. Returns the number of sheets.
fn shelf_sheets(
    layer: &CutLayer,
    names: &Names,
    drawn: &mut Drawn,
) -> Result<usize, CutSheetError> {
    let spec = &layer.spec;
    let sheet = Sheet {
        width_mm: spec.width_mm,
        height_mm: spec.height_mm,
    };
    let gap = spec.spacing_mm;
    let rotations = CUT_ROTATIONS_DEG.to_vec();
    let items: Vec<PartSpec> = layer
        .items
        .iter()
        .map(|i| PartSpec {
            outline: i.cut.clone(),
            count: i.count,
            rotations_deg: rotations.clone(),
        })
        .collect();
    let layouts: Vec<SheetLayout> = layout_parts(&items, &sheet, gap, None)
        .map_err(|e| names.error(format!("{} layout: {e}", layer.layer)))?;
    let fail = |v: Vec<Violation>| {
        names.error(format!(
            "{} (verifier) layout: {}",
            layer.layer,
            format_violations(&v)
        ))
    };
    let counts: Vec<usize> = items.iter().map(|i| i.count).collect();
    verify_copies(&layouts, &counts).map_err(fail)?;
    for layout in &layouts {
        verify_sheet(layout, &sheet, (gap - 1e-9).max(0.0), &|_| {
            rotations.clone()
        })
        .map_err(fail)?;
        verify_outlines(layout, &|i| items[i].outline.clone(), 1e-9).map_err(fail)?;
    }
    draw_cut_sheets(layer, &layouts, names, drawn);
    Ok(layouts.len())
}

/// Report rows of the clamp layers: mold first, then the others in stack order, each once.
pub fn clamp_rows(
    template: &Template,
    stack: &[String],
    panels: usize,
    layers: &mut Vec<LayerRow>,
) {
    let c = &template.clamp;
    let panel_area = signed_area(&super::panel::panel_outline(c));
    for name in
        std::iter::once("mold".to_string()).chain(c.stack.iter().filter(|n| *n != "mold").cloned())
    {
        if layers.iter().any(|l| l.layer == name) {
            continue;
        }
        let spec = if name == "mold" {
            &template.mold
        } else {
            &template.covers[&name]
        };
        let count = stack
            .iter()
            .filter(|s| s.rsplit_once('-').map(|(kind, _)| kind) == Some(name.as_str()))
            .count();
        layers.push(LayerRow::new(LayerRow {
            layer: name,
            material: spec.material.clone(),
            thickness_mm: spec.thickness_mm,
            density_kg_per_m3: spec.density_kg_per_m3,
            part_area_mm2: panel_area,
            parts_per_actuator: 0,
            sheets: count * panels,
            utilization: None,
            mass_per_actuator_mg: 0.0,
        }));
    }
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
        Shape::Polygon(place_ring(&g.passive_outline(), 0.0, origin)),
    );
    d.add(
        Operation::Cut,
        Shape::Polygon(place_ring(&g.pzt_outline(), 0.0, origin)),
    );
    d
}
