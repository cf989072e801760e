//! The one placement-and-verification step of the pipeline: where the parts of a layer go on its
//! sheets, checked by the independent verifier ([`crate::layout::verify`]) before anything is drawn.
//!
//! PZT plates always get a snappable (guillotine) layout of score lines ([`place_plates`]). A
//! cut-through layer is packed by the [`Packing`] strategy of the build ([`place_cut_layer`]): the
//! fast shelf packer for one design, or the irregular nester for a batch, both in `cam_nest`.
//! Every layout is in `cam_nest`'s vocabulary, and whichever packs the layer, `cam_nest`'s verifier
//! checks the result: every copy placed once, within the stock, each placed outline its part turned
//! and moved as stated, inside the sheet and apart from the others by the clearance the strategy
//! promised; scored sheets add the snap checks of [`crate::layout::verify`].

use super::cut::{CutItem, CutLayer};
use super::jobs::{format_violations, Job, Names};
use super::BuildError;
use crate::input::{short_number, InputError};
use crate::layout::{
    layout_plates, verify_break_order, verify_offcuts, verify_snappable, LayoutError, PlateSpec,
};
use crate::process::template::SheetSpec;
use cam_geometry::{place_ring, Point};
use cam_nest::{
    nest_bounding_boxes, nest_shelves, nest_strip_until, nest_until, verify_copies,
    verify_outlines, verify_sheet, verify_stock, Clearance, NestBin, NestError, NestItem,
    NestProgress, NestSettings, NestSolution, NestViolation, NestedBin, PlacedPart, Reached,
    SearchEnd, SearchLimit,
};
use serde::Serialize;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// Settings of the irregular nester.
#[derive(Debug, Clone, Copy)]
pub struct NestOptions {
    /// Seed of the irregular nester.
    pub seed: u64,
    /// Optimiser budget (improvement moves over all workers); above the default 1000, anytime
    /// rounds after the base search ([`cam_nest::nest_until`]).
    pub iterations: usize,
    /// Wall-clock budget of the whole nest, if any: each layer searches until its share of it
    /// ([`TimeBudget::share`]) or until `iterations`, whichever comes first.
    pub time: Option<TimeBudget>,
    /// Set by the command line's first Ctrl-C: every layer ends its search with its best layout
    /// so far, and the build goes on with those.
    pub interrupt: Option<&'static AtomicBool>,
}

impl NestOptions {
    /// A seed and an iteration budget, with neither a time budget nor an interrupt.
    pub fn budget(seed: u64, iterations: usize) -> NestOptions {
        NestOptions {
            seed,
            iterations,
            time: None,
            interrupt: None,
        }
    }

    /// The nester's limit for a layer whose search ends at `deadline`.
    fn limit(&self, deadline: Option<Instant>) -> SearchLimit<'static> {
        SearchLimit {
            deadline,
            interrupt: self.interrupt,
        }
    }
}

/// A time budget of a nest: the seconds asked for, and the instant they run out.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TimeBudget {
    pub seconds: f64,
    pub deadline: Instant,
}

impl TimeBudget {
    /// `seconds` from now.
    pub fn from_now(seconds: f64) -> TimeBudget {
        TimeBudget {
            seconds,
            deadline: Instant::now() + Duration::from_secs_f64(seconds),
        }
    }

    /// The deadline of a layer that starts now with `left` layers (itself included) still to
    /// nest, `at_once` of them at a time: an equal share of the time left per turn, so the
    /// layers after it keep theirs.
    fn share(&self, left: usize, at_once: usize) -> Instant {
        let now = Instant::now();
        let turns = left.div_ceil(at_once.max(1)).max(1);
        now + self.deadline.saturating_duration_since(now) / turns as u32
    }
}

/// How a layer's search ended, in the report when a time budget or an interrupt ended it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SearchRow {
    /// Iterations the layout is the result of.
    pub iterations: usize,
    /// True if `--iterations` with `iterations` gives the same layout on any machine.
    pub replayable: bool,
    /// What ended the search: `budget` (iterations or the search's stop rules), `time`, or
    /// `interrupt`.
    pub ended: String,
}

impl SearchRow {
    /// The row of a search that ended as `reached` says.
    fn of(reached: &Reached) -> SearchRow {
        SearchRow {
            iterations: reached.iterations,
            replayable: reached.replayable,
            ended: match reached.ended {
                SearchEnd::Budget => "budget",
                SearchEnd::Time => "time",
                SearchEnd::Interrupt => "interrupt",
            }
            .into(),
        }
    }
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
    /// How the search ended, when a time budget or an interrupt could end it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub search: Option<SearchRow>,
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
    /// Sheet layouts of the cut paths: each part's outline is its item's cut path placed.
    pub layouts: Vec<NestedBin>,
    /// The irregular nest against the bounding-box baseline ([`Packing::Irregular`] only).
    pub baseline: Option<BaselineRow>,
    /// On roll stock: the used length, mm (the one sheet is drawn this long).
    pub strip_length_mm: Option<f64>,
}

/// The template's sheet with `stock` sheets of it.
fn sheet_of(spec: &SheetSpec, stock: usize) -> NestBin {
    NestBin {
        width_mm: spec.width_mm,
        height_mm: spec.height_mm,
        stock,
    }
}

/// Rounding the verifier absorbs, mm: a part may come this much closer than promised and still pass.
const ROUNDING_MM: f64 = 1e-9;

/// The clearance a packer promised, less the rounding the check absorbs.
fn promised(mm: f64) -> f64 {
    (mm - ROUNDING_MM).max(0.0)
}

/// The layer's parts as the nester's items: `ring` picks which ring of each part is packed or
/// checked (its cut path, or its nominal outline).
fn items_of(layer: &CutLayer, ring: fn(&CutItem) -> &Vec<Point>) -> Vec<NestItem> {
    layer
        .items
        .iter()
        .map(|i| NestItem {
            outline: ring(i).clone(),
            demand: i.count,
            rotations_deg: i.rotations_deg.clone(),
        })
        .collect()
}

/// How far above its estimate a refusal looks for a size the packer takes, in hundredths of a mm.
const PROBED_HUNDREDTHS: usize = 1000;

/// A part that fits no sheet: the refusal names the sheet field to change, where it was written (the
/// template, or a batch's `[sheets]`), and the least size that holds the part. `border` is what the
/// sheet loses across its width and height (edge margins, clearances); `turns` whether a quarter turn is
/// allowed (PZT plates); other parts come at their best allowed rotation already. `takes`, where
/// the packer has rules beyond a border (the PZT plates' planner, which refuses a rest narrower than
/// a snappable strip), says whether it takes the part on a `width x height` sheet: the size named is
/// then the first hundredth from the border's estimate up that it takes. Without it the packer's
/// check is strict, and the estimate is rounded up to the next hundredth.
fn sheet_too_small(
    spec: &SheetSpec,
    what: &str,
    part: [f64; 2],
    border: [f64; 2],
    turns: bool,
    takes: Option<&dyn Fn(f64, f64) -> bool>,
) -> BuildError {
    let (w, h) = (spec.width_mm, spec.height_mm);
    let orientations: &[[f64; 2]] = if turns {
        &[part, [part[1], part[0]]]
    } else {
        &[part]
    };
    // The least width that holds the part with the height as it is (a roll has no height); else the
    // least height with the width as it is; else both.
    let least = |side: usize, other: f64| {
        orientations
            .iter()
            .filter(|p| spec.roll && side == 0 || p[1 - side] + border[1 - side] <= other)
            .map(|p| p[side] + border[side])
            .fold(f64::INFINITY, f64::min)
    };
    // Sizes in hundredths: the first from `estimate` up (by both sides at once) that `takes` takes.
    let hundredths = |estimate: [f64; 2], takes: &dyn Fn(f64, f64) -> bool| {
        let from = estimate.map(|mm| (mm * 100.0 - 1e-6).floor());
        (0..PROBED_HUNDREDTHS)
            .map(|k| from.map(|f| (f + k as f64) / 100.0))
            .find(|s| takes(s[0], s[1]))
    };
    let up = |mm: f64| (mm * 100.0 + 1e-6).ceil() / 100.0;
    // The least sizes [width, height] for `estimate`; `fixed` the sides kept as they are.
    let sized = |estimate: [f64; 2], fixed: [bool; 2]| -> [f64; 2] {
        let probed = takes.and_then(|takes| {
            hundredths(estimate, &|sw, sh| {
                takes(if fixed[0] { w } else { sw }, if fixed[1] { h } else { sh })
            })
        });
        probed.unwrap_or(estimate.map(up))
    };
    let origin = &spec.origin;
    let (field, value, need) = if least(0, h).is_finite() {
        (
            &origin.width_field,
            w,
            format!(
                "at least {:.2} mm",
                sized([least(0, h), h], [false, true])[0]
            ),
        )
    } else if !spec.roll && least(1, w).is_finite() {
        (
            &origin.height_field,
            h,
            format!(
                "at least {:.2} mm",
                sized([w, least(1, w)], [true, false])[1]
            ),
        )
    } else {
        let p = orientations[0];
        let [sw, sh] = sized([p[0] + border[0], p[1] + border[1]], [false, false]);
        (
            &origin.width_field,
            w,
            format!("at least {sw:.2} x {sh:.2} mm (width x height)"),
        )
    };
    BuildError::Input(InputError::invalid(
        &origin.file,
        field,
        short_number(value),
        format!("{what} does not fit the sheet; it needs {need}"),
    ))
}

/// Lay out two plates per actuator of every job on `spec` sheets (at most `stock`) as a snappable
/// layout, and verify it: every copy once, the score lines snappable and listed in break order, each
/// plate its nominal trapezoid placed, the kerf between plates and the margin to the sheet edge.
pub(crate) fn place_plates(
    jobs: &[Job<'_>],
    spec: &SheetSpec,
    stock: Option<usize>,
    names: &Names,
) -> Result<Vec<NestedBin>, BuildError> {
    let plates: Vec<PlateSpec> = jobs
        .iter()
        .map(|j| PlateSpec {
            length_mm: j.geometry.plate_length_mm(),
            base_width_mm: j.geometry.plate_base_width_mm(),
            tip_width_mm: j.geometry.plate_tip_width_mm(),
            count: 2 * j.quantity,
        })
        .collect();
    let copies: usize = plates.iter().map(|p| p.count).sum();
    let sheet = sheet_of(spec, stock.unwrap_or(copies.max(1)));
    // The narrowest snappable strip scales with the plate thickness (docs/cam.md §4).
    let thickness_mm = jobs
        .iter()
        .map(|j| j.design.pzt_thickness * 1e3)
        .fold(0.0, f64::max);
    let min_strip_mm = spec.min_snap_strip_thicknesses * thickness_mm;
    let layout = layout_plates(
        &plates,
        &sheet,
        spec.kerf_mm,
        spec.edge_margin_mm,
        min_strip_mm,
    )
    .map_err(|e| match e {
        LayoutError::TooLarge {
            item,
            width_mm,
            height_mm,
            sheet_width_mm,
            sheet_height_mm,
            usable_width_mm,
            usable_height_mm,
        } => {
            // The planner's own answer for the plate alone on a sheet of the size to name.
            let alone = [PlateSpec {
                count: 1,
                ..plates[item]
            }];
            let takes = |width_mm: f64, height_mm: f64| {
                let sheet = NestBin {
                    width_mm,
                    height_mm,
                    stock: 1,
                };
                layout_plates(
                    &alone,
                    &sheet,
                    spec.kerf_mm,
                    spec.edge_margin_mm,
                    min_strip_mm,
                )
                .is_ok()
            };
            sheet_too_small(
                spec,
                &format!("a {width_mm:.2} x {height_mm:.2} mm PZT plate"),
                [width_mm, height_mm],
                [
                    sheet_width_mm - usable_width_mm,
                    sheet_height_mm - usable_height_mm,
                ],
                true,
                Some(&takes),
            )
        }
        other => names.error(format!("pzt layout: {other}")),
    })?;
    let fail = |what: String| names.error(format!("pzt (verifier) layout: {what}"));
    // PZT is in-plane isotropic: strips may run either way, so any quarter turn is allowed.
    let items: Vec<NestItem> = jobs
        .iter()
        .zip(&plates)
        .map(|(j, p)| NestItem {
            outline: j.geometry.pzt_outline(),
            demand: p.count,
            rotations_deg: vec![0.0, 90.0, 180.0, 270.0],
        })
        .collect();
    verify_stock(&layout.bins, sheet.stock).map_err(|v| fail(v.to_string()))?;
    verify_copies(&items, &layout.bins).map_err(|v| fail(v.to_string()))?;
    // Scored plates keep the kerf between each other but only the margin to the sheet edge.
    let clearance = Clearance {
        between_parts_mm: promised(spec.kerf_mm),
        to_edge_mm: promised(spec.edge_margin_mm),
    };
    for bin in &layout.bins {
        verify_sheet(
            &items,
            &sheet,
            clearance,
            bin.index,
            &bin.parts,
            ROUNDING_MM,
        )
        .map_err(|v| fail(v.to_string()))?;
        let snap = |v: Vec<crate::layout::Violation>| fail(format_violations(&v));
        verify_snappable(bin, &sheet).map_err(snap)?;
        verify_break_order(bin, &sheet).map_err(snap)?;
        verify_offcuts(bin, &sheet, min_strip_mm).map_err(snap)?;
    }
    Ok(layout.bins)
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
        Packing::Irregular(opts, observer) => {
            let deadline = opts.time.map(|t| t.share(1, 1));
            irregular(layer, opts, deadline, *observer, names)
        }
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
                let deadline = opts.time.map(|t| t.share(count - index, LAYERS_AT_ONCE));
                let result = irregular(&layers[index], opts, deadline, &forward, names);
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
struct Promise {
    /// The sheet, with the stock the packer had to keep to.
    sheet: NestBin,
    /// The items as packed: the ring of each part the packer kept apart (cut path or nominal
    /// outline), its copies and rotations.
    packed: Vec<NestItem>,
    /// Clearance between those rings and to the sheet edge, mm.
    clearance_mm: f64,
}

/// Verify layouts of cut paths against what the packing promised: every copy once within the stock,
/// every outline its item's cut path turned and moved as stated, and the packed rings (placed the
/// same way) inside the sheet, the clearance apart, in allowed rotations.
fn verify_cut_layouts(
    layer: &CutLayer,
    layouts: &[NestedBin],
    promise: &Promise,
) -> Result<(), NestViolation> {
    verify_stock(layouts, promise.sheet.stock)?;
    verify_copies(&promise.packed, layouts)?;
    let cut = items_of(layer, |i| &i.cut);
    let clearance = Clearance::uniform(promised(promise.clearance_mm));
    for layout in layouts {
        verify_outlines(&cut, layout.index, &layout.parts, ROUNDING_MM)?;
        let packed: Vec<PlacedPart> = layout
            .parts
            .iter()
            .map(|p| PlacedPart {
                item: p.item,
                copy: p.copy,
                rotation_deg: p.rotation_deg,
                translation: p.translation,
                outline: place_ring(
                    &promise.packed[p.item].outline,
                    p.rotation_deg,
                    p.translation,
                ),
            })
            .collect();
        verify_sheet(
            &promise.packed,
            &promise.sheet,
            clearance,
            layout.index,
            &packed,
            ROUNDING_MM,
        )?;
    }
    Ok(())
}

/// The shelf packer on the cut paths, the template's spacing between them and to the sheet edge.
fn shelf(layer: &CutLayer, names: &Names) -> Result<Vec<NestedBin>, BuildError> {
    let spec = &layer.spec;
    let items = items_of(layer, |i| &i.cut);
    // Without a stock limit a sheet takes at least one part, so no layout needs more sheets.
    let copies: usize = items.iter().map(|i| i.demand).sum();
    let sheet = sheet_of(spec, copies.max(1));
    let layout = nest_shelves(&items, &sheet, spec.spacing_mm)
        .map_err(|e| names.error(format!("{} layout: {e}", layer.layer)))?;
    let promise = Promise {
        sheet,
        packed: items,
        clearance_mm: spec.spacing_mm,
    };
    verify_cut_layouts(layer, &layout.bins, &promise)
        .map_err(|v| names.error(format!("{} (verifier) layout: {v}", layer.layer)))?;
    Ok(layout.bins)
}

/// The irregular nester on the nominal outlines at each item's rotations (0° / 180° for actuator
/// parts), kerf + spacing between parts and to the sheet edge; on sheets, or on a roll
/// ([`SheetSpec::roll`]: one strip of the roll's width, as short as the nester finds, drawn to its
/// used length rounded up to 0.1 mm). The bounding-box baseline is nested too for the report.
fn irregular(
    layer: &CutLayer,
    opts: &NestOptions,
    deadline: Option<Instant>,
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
    let items = items_of(layer, |i| &i.nominal);
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
            edge_gap_mm,
            ..
        } => sheet_too_small(
            spec,
            &format!(
                "the {} part of {} ({part_width_mm:.3} x {part_height_mm:.3} mm at its best allowed rotation, with {separation_mm} mm of kerf and spacing to each edge, {edge_gap_mm:.3} mm with the nester's working margin)",
                layer.layer, layer.items[item].owner
            ),
            [part_width_mm, part_height_mm],
            [2.0 * edge_gap_mm; 2],
            false,
            None,
        ),
        NestError::StockTooSmall { needed, stock } => fail(format!(
            "stock too small: the batch needs {needed} sheets but the stock is {stock}"
        )),
        other => fail(other.to_string()),
    }
    };
    let observe = |p: &NestProgress| observer.progress(p);
    // `bin` is the sheet the layout is verified and drawn on; `room` the one the baseline uses.
    let limit = opts.limit(deadline);
    let (solution, bin, room, strip_length_mm, reached) = if spec.roll {
        let (strip, reached) = nest_strip_until(&items, spec.width_mm, &settings, &limit, &observe)
            .map_err(refused)?;
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
        (strip.solution, bin, room, Some(length), reached)
    } else {
        let bin = NestBin {
            width_mm: spec.width_mm,
            height_mm: spec.height_mm,
            stock: spec.stock.unwrap_or(copies.max(1)),
        };
        let (solution, reached) =
            nest_until(&items, &bin, &settings, &limit, &observe).map_err(refused)?;
        let room = NestBin {
            stock: copies.max(1),
            ..bin
        };
        (solution, bin, room, None, reached)
    };
    let layouts = cut_layouts(layer, &solution);
    let mut promise = Promise {
        sheet: bin,
        packed: items,
        clearance_mm: settings.separation_mm,
    };
    verify_cut_layouts(layer, &layouts, &promise)
        .map_err(|v| fail(format!("nest verifier: {v}")))?;
    let boxes: NestSolution = nest_bounding_boxes(&promise.packed, &room, &settings)
        .map_err(|e| fail(format!("bounding-box baseline: {e}")))?;
    promise.sheet = room;
    verify_cut_layouts(layer, &cut_layouts(layer, &boxes), &promise)
        .map_err(|v| fail(format!("baseline verifier: {v}")))?;
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
        // Only where a limit could end the search: a plain iteration budget's report stays as
        // it is.
        search: (deadline.is_some() || reached.ended != SearchEnd::Budget)
            .then(|| SearchRow::of(&reached)),
    };
    Ok(PlacedLayer {
        layouts,
        baseline: Some(baseline),
        strip_length_mm,
    })
}

/// How many sheets of `width_mm` x `height_mm` (no stock limit) the parts of a layer nested on a
/// roll would take instead: the irregular nester on the same parts, separation, seed and budget,
/// checked by the same verifier. What a roll's cost is compared with. Under a time budget, which
/// the roll's own nest has spent, the sheets get the base search's budget alone: a comparison of
/// sheet counts, quick and the same on any machine.
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
    let opts = match opts.time {
        Some(_) => NestOptions {
            iterations: opts.iterations.min(NestSettings::default().iterations),
            time: None,
            ..*opts
        },
        None => *opts,
    };
    let placed = irregular(&on_sheets, &opts, None, observer, names)?;
    Ok(placed.layouts.len())
}

/// The sheets of a nest as layouts of the layer's cut paths, each turned and moved as its part was.
fn cut_layouts(layer: &CutLayer, solution: &NestSolution) -> Vec<NestedBin> {
    solution
        .bins
        .iter()
        .map(|b| NestedBin {
            index: b.index,
            parts: b
                .parts
                .iter()
                .map(|p| PlacedPart {
                    item: p.item,
                    copy: p.copy,
                    rotation_deg: p.rotation_deg,
                    translation: p.translation,
                    outline: place_ring(&layer.items[p.item].cut, p.rotation_deg, p.translation),
                })
                .collect(),
            utilization: b.utilization,
            score_lines: b.score_lines.clone(),
        })
        .collect()
}
