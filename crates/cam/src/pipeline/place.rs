//! The one placement-and-verification step of the pipeline: where the parts of a layer go on its
//! sheets, checked by the independent verifier ([`crate::layout::verify`]) before anything is drawn.
//!
//! PZT plates always get a snappable (guillotine) layout of score lines ([`place_plates`]). A
//! cut-through layer is packed by the [`Packing`] strategy of the build ([`place_cut_layer`]): the
//! fast shelf packer for one design, or the irregular nester for a batch. Whichever packs the layer,
//! the same verifier checks the result: every copy placed once, within the stock, each placed outline
//! its part turned and moved as stated, inside the sheet and apart from the others by the clearance
//! the strategy promised.

use super::cut::CutLayer;
use super::jobs::{format_violations, Job, Names};
use super::BuildError;
use crate::layout::{
    layout_parts, layout_plates, verify_break_order, verify_copies, verify_offcuts,
    verify_outlines, verify_sheet, verify_sheet_edges, verify_snappable, verify_stock, PartSpec,
    Placement, PlateSpec, Sheet, SheetLayout, Violation,
};
use crate::process::template::SheetSpec;
use cam_geometry::{place_ring, Point};
use cam_nest::{
    nest_bounding_boxes, nest_observed, nest_strip, NestBin, NestError, NestItem, NestProgress,
    NestSettings, NestSolution,
};
use serde::Serialize;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

/// Settings of the irregular nester.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NestOptions {
    /// Seed of the irregular nester.
    pub seed: u64,
    /// Optimiser budget (improvement moves over all workers).
    pub iterations: usize,
}

/// Parallel workers of the irregular nester: fixed, so the layout does not depend on the machine.
pub const WORKERS: usize = 2;

/// What a build reports while the irregular nester works (a progress bar in the command layer).
/// Calls come from the thread that runs the build, layer after layer in order (even when layers
/// are nested at once, [`place_cut_layers`]); an observer never changes the layout.
pub trait NestObserver {
    /// Cut layer `index` (0-based) of the build's `count` starts nesting `parts` part copies.
    fn layer(&self, index: usize, count: usize, layer: &str, parts: usize);
    /// A snapshot of the layer being nested (sheets, best density, iterations).
    fn progress(&self, progress: &NestProgress);
}

/// An observer that ignores every report.
#[derive(Debug, Clone, Copy, Default)]
pub struct Unobserved;

impl NestObserver for Unobserved {
    fn layer(&self, _: usize, _: usize, _: &str, _: usize) {}
    fn progress(&self, _: &NestProgress) {}
}

/// How a build packs its cut-through layers (passive plies, Pyralux).
#[derive(Clone, Copy)]
pub enum Packing<'a> {
    /// The shelf packer: fast and deterministic, cut paths (outline + kerf/2) the template's spacing
    /// apart, no stock limit. What `cut-sheet` uses for one design.
    Shelf,
    /// The irregular nester: nominal outlines kerf + spacing apart within the stock (or along a
    /// roll, [`SheetSpec::roll`]), compared with the bounding-box baseline on the same parts,
    /// reporting to the observer as it goes. What `nest` uses for a batch.
    Irregular(NestOptions, &'a dyn NestObserver),
}

impl std::fmt::Debug for Packing<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Packing::Shelf => write!(f, "Shelf"),
            Packing::Irregular(opts, _) => write!(f, "Irregular({opts:?})"),
        }
    }
}

/// Irregular nest against the bounding-box baseline on the same parts and sheet.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BaselineRow {
    pub layer: String,
    pub material: String,
    pub parts: usize,
    pub sheets: usize,
    /// Part area / area of the sheets used.
    pub utilization: f64,
    /// Part area / (sheet width x used length): the emptiest sheet counts up to its highest part,
    /// the rest being a remnant (`NestSolution::used_length_utilization`).
    pub used_length_utilization: f64,
    pub baseline_sheets: usize,
    pub baseline_utilization: f64,
    pub baseline_used_length_utilization: f64,
    /// On roll stock: the used length of the strip, mm (as drawn, rounded up to 0.1 mm).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub strip_length_mm: Option<f64>,
    /// On roll stock: the length the bounding-box baseline uses, mm.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub baseline_strip_length_mm: Option<f64>,
}

impl BaselineRow {
    /// One line: parts, sheets and utilisation of the nest and of the baseline.
    pub fn summary(&self) -> String {
        if let (Some(length), Some(boxes)) = (self.strip_length_mm, self.baseline_strip_length_mm) {
            return format!(
                "{} {} parts: {length:.1} mm of roll, density {:.1}%; bounding boxes {boxes:.1} mm, {:.1}%",
                self.layer,
                self.parts,
                self.used_length_utilization * 100.0,
                self.baseline_used_length_utilization * 100.0
            );
        }
        format!(
            "{} {} parts: {} sheet(s) {:.1}% (used length {:.1}%), bounding boxes {} sheet(s) {:.1}% (used length {:.1}%)",
            self.layer,
            self.parts,
            self.sheets,
            self.utilization * 100.0,
            self.used_length_utilization * 100.0,
            self.baseline_sheets,
            self.baseline_utilization * 100.0,
            self.baseline_used_length_utilization * 100.0
        )
    }
}

/// A cut layer placed and verified.
#[derive(Debug, Clone)]
pub(crate) struct PlacedLayer {
    /// Sheet layouts of the cut paths: each placement's outline is its item's cut path placed.
    pub layouts: Vec<SheetLayout>,
    /// The irregular nest against the bounding-box baseline ([`Packing::Irregular`] only).
    pub baseline: Option<BaselineRow>,
    /// On roll stock: the used length, mm (the one sheet is drawn this long).
    pub strip_length_mm: Option<f64>,
}

fn sheet_of(spec: &SheetSpec) -> Sheet {
    Sheet {
        width_mm: spec.width_mm,
        height_mm: spec.height_mm,
    }
}

/// Lay out two plates per actuator of every job on `spec` sheets (at most `stock`) as a snappable
/// layout, and verify it: every copy once, the score lines snappable and listed in break order, each
/// plate its nominal trapezoid placed, the kerf between plates and the margin to the sheet edge.
pub(crate) fn place_plates(
    jobs: &[Job<'_>],
    spec: &SheetSpec,
    stock: Option<usize>,
    names: &Names,
) -> Result<Vec<SheetLayout>, BuildError> {
    let sheet = sheet_of(spec);
    let items: Vec<PlateSpec> = jobs
        .iter()
        .map(|j| PlateSpec {
            length_mm: j.geometry.plate_length_mm(),
            base_width_mm: j.geometry.plate_base_width_mm(),
            tip_width_mm: j.geometry.plate_tip_width_mm(),
            count: 2 * j.quantity,
        })
        .collect();
    let counts: Vec<usize> = items.iter().map(|i| i.count).collect();
    // The narrowest snappable strip scales with the plate thickness (docs/cam.md §4).
    let thickness_mm = jobs
        .iter()
        .map(|j| j.design.pzt_thickness * 1e3)
        .fold(0.0, f64::max);
    let min_strip_mm = spec.min_snap_strip_thicknesses * thickness_mm;
    let layouts = layout_plates(
        &items,
        &sheet,
        spec.kerf_mm,
        spec.edge_margin_mm,
        min_strip_mm,
        stock,
    )
    .map_err(|e| names.error(format!("pzt layout: {e}")))?;
    let fail = |v: Vec<Violation>| {
        names.error(format!("pzt (verifier) layout: {}", format_violations(&v)))
    };
    verify_copies(&layouts, &counts).map_err(fail)?;
    let nominal: Vec<_> = jobs.iter().map(|j| j.geometry.pzt_outline()).collect();
    for layout in &layouts {
        verify_snappable(layout, &sheet).map_err(fail)?;
        verify_break_order(layout, &sheet).map_err(fail)?;
        verify_offcuts(layout, &sheet, min_strip_mm).map_err(fail)?;
        verify_outlines(layout, &|item| nominal[item].clone(), 1e-9).map_err(fail)?;
        // PZT is in-plane isotropic: strips may run either way, so any quarter turn is allowed.
        verify_sheet_edges(
            layout,
            &sheet,
            (spec.kerf_mm - 1e-9).max(0.0),
            (spec.edge_margin_mm - 1e-9).max(0.0),
            &|_| vec![0.0, 90.0, 180.0, 270.0],
        )
        .map_err(fail)?;
    }
    Ok(layouts)
}

/// Lay out a cut layer with the build's packing strategy and verify it.
pub(crate) fn place_cut_layer(
    layer: &CutLayer,
    packing: &Packing<'_>,
    names: &Names,
) -> Result<PlacedLayer, BuildError> {
    match packing {
        Packing::Shelf => Ok(PlacedLayer {
            layouts: shelf(layer, names)?,
            baseline: None,
            strip_length_mm: None,
        }),
        Packing::Irregular(opts, observer) => irregular(layer, opts, *observer, names),
    }
}

/// Cut layers the irregular nester works on at once. Each nest has its own `WORKERS` threads;
/// with two at a time the cores stay busy while one nest waits for its slower worker, and a
/// small layer is nested beside a large one instead of after it.
const LAYERS_AT_ONCE: usize = 2;

/// What a layer nested on another thread tells the thread that runs the build: a progress
/// report, or `None` once it is placed.
type Relayed = (usize, Option<NestProgress>);

/// The observer of a layer nested on another thread: sends its reports to the build's thread.
struct Forward {
    index: usize,
    to: std::sync::mpsc::Sender<Relayed>,
}

impl NestObserver for Forward {
    fn layer(&self, _: usize, _: usize, _: &str, _: usize) {}
    fn progress(&self, progress: &NestProgress) {
        // The receiver lives until every layer is placed; a send cannot fail before that.
        let _ = self.to.send((self.index, Some(*progress)));
    }
}

/// Lay out and verify every cut layer ([`place_cut_layer`]), results in layer order. The
/// irregular nester works on `LAYERS_AT_ONCE` layers at once; its observer still hears of the
/// layers one after the other, as if they were nested in order (a layer's reports wait until
/// the layers before it are placed), on the thread that runs the build. A layout never depends
/// on this: each nest is a function of its layer and the seed.
pub(crate) fn place_cut_layers(
    layers: &[CutLayer],
    packing: &Packing<'_>,
    names: &Names,
) -> Vec<Result<PlacedLayer, BuildError>> {
    let Packing::Irregular(opts, observer) = packing else {
        return layers
            .iter()
            .map(|layer| place_cut_layer(layer, packing, names))
            .collect();
    };
    let count = layers.len();
    let announce = |index: usize| {
        let layer = &layers[index];
        let copies = layer.items.iter().map(|i| i.count).sum();
        observer.layer(index, count, &layer.layer, copies);
    };
    let next = AtomicUsize::new(0);
    let placed: Mutex<Vec<Option<Result<PlacedLayer, BuildError>>>> =
        Mutex::new((0..count).map(|_| None).collect());
    let (to, relayed) = std::sync::mpsc::channel::<Relayed>();
    std::thread::scope(|scope| {
        for _ in 0..LAYERS_AT_ONCE.min(count) {
            let (to, next, placed) = (to.clone(), &next, &placed);
            scope.spawn(move || loop {
                let index = next.fetch_add(1, Ordering::Relaxed);
                if index >= count {
                    break;
                }
                let forward = Forward {
                    index,
                    to: to.clone(),
                };
                let result =
                    place_cut_layer(&layers[index], &Packing::Irregular(*opts, &forward), names);
                placed.lock().expect("no thread panics holding it")[index] = Some(result);
                let _ = to.send((index, None));
            });
        }
        drop(to);
        // Relay in layer order: the current layer's reports at once, later layers' held back.
        let mut held: Vec<Vec<NestProgress>> = vec![Vec::new(); count];
        let mut done = vec![false; count];
        let mut current = 0;
        if count > 0 {
            announce(0);
        }
        for (index, report) in relayed {
            match report {
                Some(p) if index == current => observer.progress(&p),
                Some(p) => held[index].push(p),
                None => done[index] = true,
            }
            while current < count && done[current] {
                current += 1;
                if current < count {
                    announce(current);
                    for p in held[current].drain(..) {
                        observer.progress(&p);
                    }
                }
            }
        }
    });
    placed
        .into_inner()
        .expect("no thread panicked")
        .into_iter()
        .map(|r| r.expect("every layer placed"))
        .collect()
}

/// What a packing promised for one cut layer, for the verifier.
struct Promise<'a> {
    sheet: Sheet,
    /// Copies of each item.
    counts: Vec<usize>,
    stock: Option<usize>,
    /// The ring of each item the packer kept apart (cut path or nominal outline).
    packed: &'a dyn Fn(usize) -> &'a [Point],
    /// Clearance between those rings and to the sheet edge, mm.
    clearance_mm: f64,
}

/// Verify layouts of cut paths against what the packing promised: every copy once within the stock,
/// every outline its item's cut path turned and moved as stated, and the packed rings (placed the
/// same way) inside the sheet, the clearance apart, in allowed rotations.
fn verify_cut_layouts(
    layer: &CutLayer,
    layouts: &[SheetLayout],
    promise: &Promise<'_>,
) -> Result<(), Vec<Violation>> {
    verify_copies(layouts, &promise.counts)?;
    if let Some(stock) = promise.stock {
        verify_stock(layouts, stock)?;
    }
    for layout in layouts {
        verify_outlines(layout, &|i| layer.items[i].cut.clone(), 1e-9)?;
        let packed = SheetLayout {
            sheet_index: layout.sheet_index,
            placements: layout
                .placements
                .iter()
                .map(|p| Placement {
                    outline: place_ring((promise.packed)(p.item), p.rotation_deg, p.offset),
                    ..p.clone()
                })
                .collect(),
            score_lines: Vec::new(),
        };
        verify_sheet(
            &packed,
            &promise.sheet,
            (promise.clearance_mm - 1e-9).max(0.0),
            &|i| layer.items[i].rotations_deg.clone(),
        )?;
    }
    Ok(())
}

/// The shelf packer on the cut paths, the template's spacing between them and to the sheet edge.
fn shelf(layer: &CutLayer, names: &Names) -> Result<Vec<SheetLayout>, BuildError> {
    let spec = &layer.spec;
    let sheet = sheet_of(spec);
    let items: Vec<PartSpec> = layer
        .items
        .iter()
        .map(|i| PartSpec {
            outline: i.cut.clone(),
            count: i.count,
            rotations_deg: i.rotations_deg.clone(),
        })
        .collect();
    let layouts = layout_parts(&items, &sheet, spec.spacing_mm, None)
        .map_err(|e| names.error(format!("{} layout: {e}", layer.layer)))?;
    let promise = Promise {
        sheet,
        counts: items.iter().map(|i| i.count).collect(),
        stock: None,
        packed: &|i| &layer.items[i].cut,
        clearance_mm: spec.spacing_mm,
    };
    verify_cut_layouts(layer, &layouts, &promise).map_err(|v| {
        names.error(format!(
            "{} (verifier) layout: {}",
            layer.layer,
            format_violations(&v)
        ))
    })?;
    Ok(layouts)
}

/// The irregular nester on the nominal outlines at each item's rotations (0° / 180° for actuator
/// parts), kerf + spacing between parts and to the sheet edge; on sheets, or on a roll
/// ([`SheetSpec::roll`]: one strip of the roll's width, as short as the nester finds, drawn to its
/// used length rounded up to 0.1 mm). The bounding-box baseline is nested too for the report.
fn irregular(
    layer: &CutLayer,
    opts: &NestOptions,
    observer: &dyn NestObserver,
    names: &Names,
) -> Result<PlacedLayer, BuildError> {
    let spec = &layer.spec;
    let context = if spec.roll {
        format!(
            "{} roll ({}, {} mm wide)",
            layer.layer, layer.material, spec.width_mm
        )
    } else {
        format!(
            "{} sheets ({}, {} x {} mm)",
            layer.layer, layer.material, spec.width_mm, spec.height_mm
        )
    };
    let fail = |what: String| names.error(format!("{context}: {what}"));
    let items: Vec<NestItem> = layer
        .items
        .iter()
        .map(|i| NestItem {
            outline: i.nominal.clone(),
            demand: i.count,
            rotations_deg: i.rotations_deg.clone(),
        })
        .collect();
    let copies: usize = items.iter().map(|i| i.demand).sum();
    let settings = NestSettings {
        separation_mm: spec.kerf_mm + spec.spacing_mm,
        seed: opts.seed,
        iterations: opts.iterations,
        workers: WORKERS,
    };
    let refused = |e: NestError| {
        match e {
        NestError::PartLargerThanBin {
            item,
            part_width_mm,
            part_height_mm,
            separation_mm,
            ..
        } => fail(format!(
            "the {} part of {} is {part_width_mm:.3} x {part_height_mm:.3} mm at its best allowed rotation: larger than the sheet, it does not fit with {separation_mm} mm (kerf + spacing) to the sheet edge",
            layer.layer,
            layer.items[item].owner
        )),
        NestError::StockTooSmall { needed, stock } => fail(format!(
            "stock too small: the batch needs {needed} sheets but the stock is {stock}"
        )),
        other => fail(other.to_string()),
    }
    };
    let observe = |p: &NestProgress| observer.progress(p);
    // `bin` is the sheet the layout is verified and drawn on; `room` the one the baseline uses.
    let (solution, bin, room, strip_length_mm) = if spec.roll {
        let strip = nest_strip(&items, spec.width_mm, &settings, &observe).map_err(refused)?;
        let length = (strip.length_mm * 10.0).ceil() / 10.0;
        let bin = NestBin {
            width_mm: spec.width_mm,
            height_mm: length,
            stock: 1,
        };
        let room = NestBin {
            stock: copies.max(1),
            ..strip.bin
        };
        (strip.solution, bin, room, Some(length))
    } else {
        let bin = NestBin {
            width_mm: spec.width_mm,
            height_mm: spec.height_mm,
            stock: spec.stock.unwrap_or(copies.max(1)),
        };
        let solution = nest_observed(&items, &bin, &settings, &observe).map_err(refused)?;
        let room = NestBin {
            stock: copies.max(1),
            ..bin
        };
        (solution, bin, room, None)
    };
    let layouts = cut_layouts(layer, &solution);
    let mut promise = Promise {
        sheet: Sheet {
            width_mm: bin.width_mm,
            height_mm: bin.height_mm,
        },
        counts: items.iter().map(|i| i.demand).collect(),
        stock: Some(bin.stock),
        packed: &|i| &layer.items[i].nominal,
        clearance_mm: settings.separation_mm,
    };
    verify_cut_layouts(layer, &layouts, &promise)
        .map_err(|v| fail(format!("nest verifier: {}", format_violations(&v))))?;
    let boxes: NestSolution = nest_bounding_boxes(&items, &room, &settings)
        .map_err(|e| fail(format!("bounding-box baseline: {e}")))?;
    promise.stock = Some(room.stock);
    promise.sheet = Sheet {
        width_mm: room.width_mm,
        height_mm: room.height_mm,
    };
    verify_cut_layouts(layer, &cut_layouts(layer, &boxes), &promise)
        .map_err(|v| fail(format!("baseline verifier: {}", format_violations(&v))))?;
    let used = solution.used_length_utilization(&bin, settings.separation_mm);
    let boxes_used = boxes.used_length_utilization(&room, settings.separation_mm);
    let baseline = BaselineRow {
        layer: layer.layer.clone(),
        material: layer.material.clone(),
        parts: copies,
        sheets: solution.bins_used(),
        // On a roll the one sheet is the used strip: its utilisation is the used-length one.
        utilization: if spec.roll {
            used
        } else {
            solution.utilization()
        },
        used_length_utilization: used,
        baseline_sheets: boxes.bins_used(),
        baseline_utilization: if spec.roll {
            boxes_used
        } else {
            boxes.utilization()
        },
        baseline_used_length_utilization: boxes_used,
        strip_length_mm,
        baseline_strip_length_mm: strip_length_mm
            .map(|_| boxes.used_length_mm(&room, settings.separation_mm)),
    };
    Ok(PlacedLayer {
        layouts,
        baseline: Some(baseline),
        strip_length_mm,
    })
}

/// How many sheets of `width_mm` x `height_mm` (no stock limit) the parts of a layer nested on a
/// roll would take instead: the irregular nester on the same parts, separation, seed and budget,
/// checked by the same verifier. What a roll's cost is compared with.
pub fn sheets_instead_of_roll(
    layer: &CutLayer,
    width_mm: f64,
    height_mm: f64,
    opts: &NestOptions,
    observer: &dyn NestObserver,
    names: &Names,
) -> Result<usize, BuildError> {
    let mut on_sheets = layer.clone();
    on_sheets.spec.roll = false;
    on_sheets.spec.stock = None;
    on_sheets.spec.width_mm = width_mm;
    on_sheets.spec.height_mm = height_mm;
    let placed = irregular(&on_sheets, opts, observer, names)?;
    Ok(placed.layouts.len())
}

/// The sheets of a nest as layouts of the layer's cut paths, each turned and moved as its part was.
fn cut_layouts(layer: &CutLayer, solution: &NestSolution) -> Vec<SheetLayout> {
    solution
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
        .collect()
}
