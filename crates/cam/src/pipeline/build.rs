//! The build: every layer of a list of designs with quantities, in file order. PZT plates of one
//! material and thickness share a snappable layout; passive parts of one layup (and the Pyralux
//! parts) share cut sheets packed by the build's [`Packing`]; actuators of one laminate height share a
//! stack of clamp panels. One design is a build of one job: every group then holds just it.

use super::clamp::{clamp_layers, laminate_bands, ClampBuild};
use super::cut::{draw_cut_sheets, extra_item, passive_layers, pyralux_layer, CutLayer};
use super::jobs::{check_geometry, DrawingSink, Drawn, Job, Names, SheetRecord, StockCount};
use super::parts::PartGeometry;
use super::place::{place_cut_layers, place_plates, BaselineRow, Packing};
use super::score_lines::draw_pzt_sheets;
use super::{BuildError, SheetDrawing};
use crate::design::Design;
use crate::drawing::model::Stock;
use crate::parts::{PartOrder, PartSheet};
use crate::process::template::Template;

/// A cut-through layer as built: its parts and how many sheets they took.
#[derive(Debug, Clone)]
pub struct CutLayerSheets {
    /// The layer (name, material, sheet, parts).
    pub layer: CutLayer,
    /// Sheets used.
    pub sheets: usize,
    /// The irregular nest against the bounding-box baseline ([`Packing::Irregular`] only).
    pub baseline: Option<BaselineRow>,
}

/// Everything a build makes, in memory, before anything is written.
#[derive(Debug, Clone)]
pub struct Build {
    /// Drawings in file order.
    pub drawings: Vec<SheetDrawing>,
    /// Sheets of each stock the drawings are cut from: the stock list.
    pub stock: Vec<StockCount>,
    /// Cut-material sheets (PZT, passive, Pyralux) with the parts on them.
    pub sheets: Vec<SheetRecord>,
    /// Which clamp panel holds each actuator, and which PZT sheet holds each plate.
    pub placement_map: Vec<String>,
    /// Clamp panels used.
    pub panels: usize,
    /// Part sheets too full for their stock label (`super::sheet_label`).
    pub unlabelled_sheets: usize,
    /// Plan geometry of each design as built (PZT plates inset by the template's margin).
    pub geometry: Vec<PartGeometry>,
    /// PZT sheets used.
    pub pzt_sheets: usize,
    /// Cut-through layers in file order.
    pub cut_layers: Vec<CutLayerSheets>,
    /// Clamp stacks, one per laminate height.
    pub clamps: Vec<ClampBuild>,
    /// The snapping-order picture of each PZT sheet, (file name, SVG), in sheet order: written beside
    /// the layer files, not a layer file.
    pub snap_guides: Vec<(String, String)>,
    /// The test-score coupon of each PZT stock, (file stem, [width, height] mm), in sheet order: cut
    /// from an offcut, before the production sheets.
    pub coupons: Vec<(String, [f64; 2])>,
}

impl Build {
    /// The mass of job `job`'s bond parts as drawn, per actuator, mg (`area x thickness x density x
    /// parts`), if the build cuts any: what the model's bond mass is set to, so that the drawn and the
    /// predicted mass agree.
    pub fn drawn_bond_mg(&self, job: usize) -> Option<f64> {
        let layer = &self
            .cut_layers
            .iter()
            .find(|c| c.layer.layer == "pyralux")?
            .layer;
        let item = layer.items.iter().find(|i| i.job == job)?;
        // mm² x mm x kg/m³ = 1e-9 kg = 1e-3 mg.
        Some(
            cam_geometry::signed_area(&item.nominal)
                * layer.thickness_mm
                * layer.density_kg_per_m3
                * 1e-3
                * item.per_actuator as f64,
        )
    }
}

/// Jobs grouped by a key, groups in order of first appearance, each member with its job index.
fn groups<'a, K: PartialEq>(
    jobs: &[Job<'a>],
    key: impl Fn(&Job<'a>) -> K,
) -> Vec<Vec<(usize, Job<'a>)>> {
    let mut keys: Vec<K> = Vec::new();
    let mut out: Vec<Vec<(usize, Job<'a>)>> = Vec::new();
    for (i, job) in jobs.iter().enumerate() {
        let k = key(job);
        match keys.iter().position(|x| *x == k) {
            Some(g) => out[g].push((i, *job)),
            None => {
                keys.push(k);
                out.push(vec![(i, *job)]);
            }
        }
    }
    out
}

/// Build every layer of `designs` (each with its quantity) and of the extra `parts` cut beside them
/// (numbered as jobs after the designs in the sheets' records): lay out, verify, draw. Nothing is
/// written here.
pub fn build(
    designs: &[(&Design, usize)],
    parts: &[PartOrder],
    template: &Template,
    names: &Names,
    packing: &Packing<'_>,
) -> Result<Build, BuildError> {
    build_into(designs, parts, template, names, packing, None)
}

/// [`build`], handing each drawing to `sink` as soon as it is made (file order) instead of keeping it:
/// a large build then holds one drawing at a time, and its [`Build::drawings`] is empty. A sink error
/// ends the build at its next stage ([`BuildError::Sink`]).
pub fn build_into<'s>(
    designs: &[(&Design, usize)],
    parts: &[PartOrder],
    template: &Template,
    names: &Names,
    packing: &Packing<'_>,
    sink: Option<&'s mut DrawingSink<'s>>,
) -> Result<Build, BuildError> {
    let jobs: Vec<Job<'_>> = designs
        .iter()
        .map(|(design, quantity)| Job::new(design, *quantity, template))
        .collect();
    for job in &jobs {
        check_geometry(job, template)?;
    }
    let mut drawn = Drawn::new(sink);

    let pzt_sheets = build_pzt(&jobs, template, names, &mut drawn)?;
    let mut layers = passive_and_pyralux_layers(&jobs, parts, template, names)?;
    layers.extend(own_sheet_layers(jobs.len(), parts, template, names)?);
    let mut cut_layers = Vec::with_capacity(layers.len());
    let placed = place_cut_layers(&layers, packing, names);
    for (mut layer, placed) in layers.into_iter().zip(placed) {
        let placed = placed?;
        if let Some(length) = placed.strip_length_mm {
            // Roll stock: the drawing and the sheet record show the strip as used.
            layer.spec.height_mm = length;
        }
        draw_cut_sheets(&layer, &placed.layouts, &placed.drawn, names, &mut drawn);
        drawn.check_sink()?;
        cut_layers.push(CutLayerSheets {
            sheets: placed.layouts.len(),
            baseline: placed.baseline,
            layer,
        });
    }

    // Clamp panels: actuators of one laminate (plate and core thickness) share a stack of mold layers,
    // whose films are chosen band by band.
    let mut clamps = Vec::new();
    let key = |j: &Job<'_>| {
        let b = laminate_bands(j.design);
        (
            (b.plate_mm * 1e6).round() as i64,
            (b.core_mm * 1e6).round() as i64,
        )
    };
    for group in groups(&jobs, key) {
        clamps.push(clamp_layers(&group, template, names, &mut drawn)?);
        drawn.check_sink()?;
    }
    Ok(Build {
        drawings: drawn.drawings,
        stock: drawn.stock,
        sheets: drawn.sheets,
        placement_map: drawn.placement_map,
        panels: drawn.panels,
        unlabelled_sheets: drawn.unlabelled_sheets,
        geometry: jobs.iter().map(|j| j.geometry).collect(),
        pzt_sheets,
        cut_layers,
        clamps,
        snap_guides: drawn.snap_guides,
        coupons: drawn.coupons,
    })
}

/// PZT: one snappable layout per plate thickness (and PZT material), placed, verified and drawn;
/// the PZT sheets used.
fn build_pzt(
    jobs: &[Job<'_>],
    template: &Template,
    names: &Names,
    drawn: &mut Drawn,
) -> Result<usize, BuildError> {
    let mut pzt_sheets = 0;
    for group in groups(jobs, |j| {
        (
            j.design.pzt.name.clone(),
            (j.design.pzt_thickness * 1e9).round() as i64,
        )
    }) {
        let d = group[0].1.design;
        // The plates of a group share the PZT and its thickness: the stock every sheet names.
        let stock = Stock {
            material: format!("{} ({})", d.pzt.name, template.pzt.material),
            thickness_mm: d.pzt_thickness * 1e3,
            kerf_mm: template.pzt.kerf_mm,
            fibre_axis: None,
        };
        let mut spec = template.pzt.clone();
        if names.name_designs {
            spec.material = format!(
                "{} {} mm ({})",
                d.pzt.name,
                d.pzt_thickness * 1e3,
                spec.material
            );
        }
        // A drawn PZT sheet (a remnant) is of the plates of the design it names.
        spec.drawn
            .retain(|d| d.like.is_some_and(|l| group.iter().any(|(i, _)| *i == l)));
        let members: Vec<Job<'_>> = group.iter().map(|(_, j)| *j).collect();
        let layouts = place_plates(&members, &spec, spec.stock, names)
            .map_err(|e| names.in_group(e, &format!("PZT sheets of {}", spec.material)))?;
        super::coupon::draw_coupon(&spec, &stock, &names.title, &template.features, drawn);
        let before = drawn.sheets.len();
        draw_pzt_sheets(
            &members,
            &spec,
            &stock,
            &layouts,
            names,
            &template.features,
            drawn,
        );
        for record in &mut drawn.sheets[before..] {
            for part in &mut record.parts {
                part.job = group[part.job].0;
            }
        }
        pzt_sheets += layouts.bins.len();
        drawn.check_sink()?;
    }
    Ok(pzt_sheets)
}

/// Passive parts: one layer per layup (and per ply when plies are cut one by one), then Pyralux;
/// the extra `parts` of each sheet on it.
fn passive_and_pyralux_layers(
    jobs: &[Job<'_>],
    parts: &[PartOrder],
    template: &Template,
    names: &Names,
) -> Result<Vec<CutLayer>, BuildError> {
    let mut layers: Vec<CutLayer> = Vec::new();
    for group in groups(jobs, |j| {
        (
            j.design.ply.name.clone(),
            (j.design.ply_thickness * 1e9).round() as i64,
            j.design.layup_text(),
        )
    }) {
        let layup = group[0].1.design.layup_text();
        for mut layer in passive_layers(&group, template, &template.passive)? {
            // A drawn prepreg sheet is of the layup of the design it names.
            layer
                .spec
                .drawn
                .retain(|d| d.like.is_some_and(|l| group.iter().any(|(i, _)| *i == l)));
            if names.name_designs {
                layer.material = format!("{}, layup {layup}", layer.material);
            }
            // Extra parts of this layup go on the same sheets: on the stack's one layer, or on
            // every ply's layer, turned to that ply's angle (ply-by-ply cutting).
            for (k, order) in parts.iter().enumerate() {
                if let PartSheet::Prepreg { like, .. } = order.sheet {
                    if group.iter().any(|(i, _)| *i == like) {
                        let item = extra_item(jobs.len() + k, order, &layer, names)?;
                        layer.items.push(item);
                    }
                }
            }
            layers.push(layer);
        }
    }
    if let Some(mut layer) = pyralux_layer(jobs, template, None)? {
        for (k, order) in parts.iter().enumerate() {
            if order.sheet == PartSheet::Pyralux {
                let item = extra_item(jobs.len() + k, order, &layer, names)?;
                layer.items.push(item);
            }
        }
        layers.push(layer);
    }
    Ok(layers)
}

/// Parts on sheets of their own (a linkage's film and adhesive): one layer per sheet, in order of
/// first use; the parts are numbered as jobs after the `designs` designs.
fn own_sheet_layers(
    designs: usize,
    parts: &[PartOrder],
    template: &Template,
    names: &Names,
) -> Result<Vec<CutLayer>, BuildError> {
    let mut own: Vec<CutLayer> = Vec::new();
    for (k, order) in parts.iter().enumerate() {
        let PartSheet::Own(sheet) = &order.sheet else {
            continue;
        };
        let at = match own.iter().position(|l| {
            l.layer == sheet.layer
                && l.material == sheet.material
                && l.thickness_mm == sheet.thickness_mm
        }) {
            Some(at) => at,
            None => {
                own.push(CutLayer {
                    layer: sheet.layer.clone(),
                    material: sheet.material.clone(),
                    thickness_mm: sheet.thickness_mm,
                    density_kg_per_m3: sheet.density_kg_per_m3,
                    spec: sheet.spec.clone(),
                    items: Vec::new(),
                    features: template.features,
                    ply_deg: None,
                    prepreg: sheet.prepreg,
                });
                own.len() - 1
            }
        };
        let item = extra_item(designs + k, order, &own[at], names)?;
        own[at].items.push(item);
    }
    Ok(own)
}
