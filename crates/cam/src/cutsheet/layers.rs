//! The cut-sheet report's layer rows: per layer of one design, the material, the part area, how many
//! parts one actuator needs and the mass they add, the sheets used and their utilisation.

use super::template::{SheetSpec, Template};
use crate::design::Design;
use crate::pipeline::{panel_outline, Build};
use cam_geometry::signed_area;
use serde::Serialize;

/// One layer's row (JSON `layers[]`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LayerRow {
    pub layer: String,
    pub material: String,
    pub thickness_mm: f64,
    pub density_kg_per_m3: f64,
    pub part_area_mm2: f64,
    pub parts_per_actuator: usize,
    pub mass_per_actuator_mg: f64,
    pub sheets: usize,
    pub utilization: Option<f64>,
}

impl LayerRow {
    /// Fill in the mass this layer adds to one actuator, mg: `area x thickness x density x parts`.
    pub fn new(row: LayerRow) -> LayerRow {
        // mm² x mm = 1e-9 m³; x kg/m³ = kg; x 1e6 = mg.
        let mass = row.part_area_mm2
            * row.thickness_mm
            * row.density_kg_per_m3
            * 1e-3
            * row.parts_per_actuator as f64;
        LayerRow {
            mass_per_actuator_mg: mass,
            ..row
        }
    }
}

fn utilization(area_each: f64, parts: usize, sheets: usize, spec: &SheetSpec) -> Option<f64> {
    (sheets > 0)
        .then(|| area_each * parts as f64 / (sheets as f64 * spec.width_mm * spec.height_mm))
}

/// The rows of a build of one design (`design.quantity` actuators): PZT, the cut-through layers,
/// then the clamp layers.
pub fn layer_rows(design: &Design, template: &Template, built: &Build) -> Vec<LayerRow> {
    let g = &built.geometry[0];
    let mut layers = Vec::new();
    let spec = &template.pzt;
    layers.push(LayerRow::new(LayerRow {
        layer: "pzt".into(),
        material: format!("{} ({})", design.pzt.name, spec.material),
        thickness_mm: design.pzt_thickness * 1e3,
        density_kg_per_m3: design.pzt.density,
        part_area_mm2: signed_area(&g.pzt_outline()),
        parts_per_actuator: 2,
        sheets: built.pzt_sheets,
        utilization: utilization(
            signed_area(&g.pzt_outline()),
            2 * design.quantity,
            built.pzt_sheets,
            spec,
        ),
        mass_per_actuator_mg: 0.0,
    }));
    for cut in &built.cut_layers {
        let layer = &cut.layer;
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
            sheets: cut.sheets,
            utilization: utilization(area, item.count, cut.sheets, &layer.spec),
            mass_per_actuator_mg: 0.0,
        }));
    }
    let clamp = &built.clamps[0];
    clamp_rows(
        template,
        &clamp.stack,
        &clamp.mold.films_mm,
        clamp.panels.len(),
        &mut layers,
    );
    layers
}

/// Report rows of the clamp layers: mold first, one row per film thickness (naming the mold sheets cut
/// from it, numbered bottom to top), then the others in stack order, each once.
fn clamp_rows(
    template: &Template,
    stack: &[String],
    films_mm: &[f64],
    panels: usize,
    layers: &mut Vec<LayerRow>,
) {
    let c = &template.clamp;
    let panel_area = signed_area(&panel_outline(c));
    let mut thicknesses: Vec<f64> = Vec::new();
    for t in films_mm {
        if !thicknesses.contains(t) {
            thicknesses.push(*t);
        }
    }
    for t in thicknesses {
        let sheets: Vec<String> = (1..=films_mm.len())
            .filter(|k| films_mm[k - 1] == t)
            .map(|k| k.to_string())
            .collect();
        layers.push(LayerRow::new(LayerRow {
            layer: format!("mold {}", sheets.join(", ")),
            material: template.mold.material.clone(),
            thickness_mm: t,
            density_kg_per_m3: template.mold.density_kg_per_m3,
            part_area_mm2: panel_area,
            parts_per_actuator: 0,
            sheets: sheets.len() * panels,
            utilization: None,
            mass_per_actuator_mg: 0.0,
        }));
    }
    for name in c.stack.iter().filter(|n| *n != "mold").cloned() {
        if layers.iter().any(|l| l.layer == name) {
            continue;
        }
        let spec = &template.covers[&name];
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
