//! Planning a batch: every design's parts on shared sheets. PZT plates of one thickness in one
//! snappable layout; passive parts of one layup (and Pyralux parts) by the irregular nester, checked by
//! its independent verifier and compared with the bounding-box baseline; clamp panels per laminate
//! height. Nothing is written here.

use super::file::Batch;
use super::report::{BaselineRow, NestReport};
use crate::cutsheet::clamp::{clamp_layers, laminate_mm, ClampBuild};
use crate::cutsheet::cut::{
    draw_cut_sheets, passive_layers, pyralux_layer, CutLayer, CUT_ROTATIONS_DEG,
};
use crate::cutsheet::jobs::{check_geometry, Drawn, Job, Names};
use crate::cutsheet::pzt::pzt_sheets;
use crate::cutsheet::{CutSheetError, SheetDrawing};
use crate::layout::{Placement, SheetLayout};
use crate::nest::{
    nest, nest_bounding_boxes, verify, NestBin, NestError, NestItem, NestSettings, NestSolution,
};
use cam_geometry::place_ring;

/// Settings of one nest run after the command line is read.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NestOptions {
    /// Seed of the irregular nester.
    pub seed: u64,
    /// Optimiser budget (improvement moves over all workers).
    pub iterations: usize,
}

/// Parallel workers of the irregular nester: fixed, so the layout does not depend on the machine.
pub const WORKERS: usize = 2;

/// Everything a batch run produces, in memory, before anything is written.
#[derive(Debug, Clone)]
pub struct Planned {
    /// Drawings in file order.
    pub drawings: Vec<SheetDrawing>,
    /// The report (files filled in when rendered).
    pub report: NestReport,
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

/// Plan every layer of a batch.
pub fn plan(batch: &Batch, opts: &NestOptions) -> Result<Planned, CutSheetError> {
    let template = &batch.template;
    let jobs: Vec<Job<'_>> = batch
        .items
        .iter()
        .map(|i| Job::new(&i.design, i.quantity, template))
        .collect();
    for job in &jobs {
        check_geometry(job, template)?;
    }
    let names = Names {
        title: batch.name.clone(),
        file: batch.source.display().to_string(),
        name_designs: true,
    };
    let mut drawn = Drawn::default();

    // PZT: one snappable layout per plate thickness (and PZT material).
    for group in groups(&jobs, |j| {
        (
            j.design.pzt.name.clone(),
            (j.design.pzt_thickness * 1e9).round() as i64,
        )
    }) {
        let d = group[0].1.design;
        let mut spec = template.pzt.clone();
        spec.material = format!(
            "{} {} mm ({})",
            d.pzt.name,
            d.pzt_thickness * 1e3,
            spec.material
        );
        let members: Vec<Job<'_>> = group.iter().map(|(_, j)| *j).collect();
        let before = drawn.sheets.len();
        pzt_sheets(
            &members,
            &spec,
            spec.stock,
            &names,
            &template.features,
            &mut drawn,
        )
        .map_err(|e| in_context(e, &format!("PZT sheets of {}", spec.material)))?;
        for record in &mut drawn.sheets[before..] {
            for part in &mut record.parts {
                part.job = group[part.job].0;
            }
        }
    }

    // Passive parts: one nest per layup (and per ply when plies are cut one by one).
    let mut baseline = Vec::new();
    let mut cut_layers: Vec<CutLayer> = Vec::new();
    for group in groups(&jobs, |j| {
        (
            j.design.ply.name.clone(),
            (j.design.ply_thickness * 1e9).round() as i64,
            j.design.layup_text(),
        )
    }) {
        let layup = group[0].1.design.layup_text();
        for mut layer in passive_layers(&group, template, &template.passive)? {
            layer.material = format!("{}, layup {layup}", layer.material);
            cut_layers.push(layer);
        }
    }
    cut_layers.extend(pyralux_layer(&jobs, template, None)?);
    for layer in &cut_layers {
        let (layouts, row) = nest_layer(layer, opts, &jobs, &names)?;
        baseline.push(row);
        draw_cut_sheets(layer, &layouts, &names, &mut drawn);
    }

    // Clamp panels: actuators of one laminate height share a stack of mold layers.
    let mut clamps: Vec<ClampBuild> = Vec::new();
    for group in groups(&jobs, |j| (laminate_mm(j.design) * 1e6).round() as i64) {
        clamps.push(clamp_layers(&group, template, &names, &mut drawn)?);
    }
    let report = NestReport::new(batch, opts, &jobs, &drawn, &clamps, baseline);
    Ok(Planned {
        drawings: drawn.drawings,
        report,
    })
}

/// Prefix an error's message with where in the batch it happened.
fn in_context(e: CutSheetError, context: &str) -> CutSheetError {
    match e {
        CutSheetError::Geometry { file, what } => CutSheetError::Geometry {
            file,
            what: format!("{context}: {what}"),
        },
        other => other,
    }
}

/// Nest one cut layer with the irregular nester: nominal outlines at rotations 0° / 180°, kerf +
/// spacing between parts and to the sheet edge. Every nest is checked by `crate::nest::verify`; the
/// bounding-box baseline is nested too for the report. Returns the sheet layouts of the cut paths.
fn nest_layer(
    layer: &CutLayer,
    opts: &NestOptions,
    jobs: &[Job<'_>],
    names: &Names,
) -> Result<(Vec<SheetLayout>, BaselineRow), CutSheetError> {
    let spec = &layer.spec;
    let context = format!(
        "{} sheets ({}, {} x {} mm)",
        layer.layer, layer.material, spec.width_mm, spec.height_mm
    );
    let fail = |what: String| names.error(format!("{context}: {what}"));
    let items: Vec<NestItem> = layer
        .items
        .iter()
        .map(|i| NestItem {
            outline: i.nominal.clone(),
            demand: i.count,
            rotations_deg: CUT_ROTATIONS_DEG.to_vec(),
        })
        .collect();
    let copies: usize = items.iter().map(|i| i.demand).sum();
    let bin = NestBin {
        width_mm: spec.width_mm,
        height_mm: spec.height_mm,
        stock: spec.stock.unwrap_or(copies.max(1)),
    };
    let settings = NestSettings {
        separation_mm: spec.kerf_mm + spec.spacing_mm,
        seed: opts.seed,
        iterations: opts.iterations,
        workers: WORKERS,
    };
    let design_of = |item: usize| &jobs[layer.items[item].job].design.name;
    let solution = nest(&items, &bin, &settings).map_err(|e| match e {
        NestError::PartLargerThanBin {
            item,
            part_width_mm,
            part_height_mm,
            separation_mm,
            ..
        } => fail(format!(
            "the {} part of {} is {part_width_mm:.3} x {part_height_mm:.3} mm at its best allowed rotation: larger than the sheet, it does not fit with {separation_mm} mm (kerf + spacing) to the sheet edge",
            layer.layer,
            design_of(item)
        )),
        NestError::StockTooSmall { needed, stock } => fail(format!(
            "stock too small: the batch needs {needed} sheets but the stock is {stock}"
        )),
        other => fail(other.to_string()),
    })?;
    verify(&items, &bin, &settings, &solution, 1e-9)
        .map_err(|v| fail(format!("nest verifier: {v}")))?;
    let unlimited = NestBin {
        stock: copies.max(1),
        ..bin
    };
    let boxes: NestSolution = nest_bounding_boxes(&items, &unlimited, &settings)
        .map_err(|e| fail(format!("bounding-box baseline: {e}")))?;
    verify(&items, &unlimited, &settings, &boxes, 1e-9)
        .map_err(|v| fail(format!("baseline verifier: {v}")))?;
    let layouts = solution
        .bins
        .iter()
        .enumerate()
        .map(|(index, b)| SheetLayout {
            sheet_index: index,
            placements: b
                .parts
                .iter()
                .map(|p| Placement {
                    item: p.item,
                    copy: p.copy,
                    rotation_deg: p.rotation_deg,
                    offset: p.translation,
                    outline: place_ring(&layer.items[p.item].cut, p.rotation_deg, p.translation),
                })
                .collect(),
            score_lines: Vec::new(),
        })
        .collect();
    let row = BaselineRow {
        layer: layer.layer.clone(),
        material: layer.material.clone(),
        parts: copies,
        sheets: solution.bins_used(),
        utilization: solution.utilization(),
        used_length_utilization: solution.used_length_utilization(&bin, settings.separation_mm),
        baseline_sheets: boxes.bins_used(),
        baseline_utilization: boxes.utilization(),
        baseline_used_length_utilization: boxes
            .used_length_utilization(&bin, settings.separation_mm),
    };
    Ok((layouts, row))
}
