//! The irregular nester's layout of a cut layer ([`super::Packing::Irregular`]) on sheets or a
//! roll, verified and compared with the bounding-box baseline on the same parts.

use super::drawn::{fill_drawn, verify_drawn};
use super::holes::{carry, fill_holes, verify_hosted, Hosted};
use super::packing::{BaselineRow, NestObserver, NestOptions, SearchRow, WORKERS};
use super::promise::{verify_cut_layouts, Promise};
use super::refusal::refusal;
use super::{items_of, onto_sheet, placed_as, room_of, sheet_of, PlacedLayer};
use crate::pipeline::cut::CutLayer;
use crate::pipeline::jobs::Names;
use crate::pipeline::BuildError;
use cam_nest::{
    nest_bounding_boxes, nest_strip_until, nest_until, verify_copies, NestBin, NestError, NestItem,
    NestProgress, NestSettings, NestSolution, NestViolation, NestedBin, Reached, SearchEnd,
    SearchLimit,
};
use std::time::Instant;

/// The irregular nester on the nominal outlines at each item's rotations (0° / 180° for actuator
/// parts), kerf + spacing between parts and kerf + edge gap to the sheet edge; on sheets, or on a roll
/// ([`crate::process::template::SheetSpec::roll`]: one strip of the roll's width, as short as the
/// nester finds, drawn to its used length rounded up to 0.1 mm). The bounding-box baseline is nested too for the report.
pub(super) fn irregular(
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
    let refused = |e: NestError| refusal(layer, e, &fail);
    let observe = |p: &NestProgress| observer.progress(p);
    // `bin` is the sheet the layout is verified and drawn on; `room` the one the baseline uses.
    let limit = opts.limit(deadline);
    // The nesters keep one gap to everything: see `room_of` and `onto_sheet`.
    let shift = spec.edge_shift_mm();
    let (mut drawn, mut hosted, mut held) = (Vec::new(), Vec::new(), vec![0; items.len()]);
    let (mut solution, bin, room, strip_length_mm, reached) = if spec.roll {
        let [width_mm, _] = spec.packing_room();
        let (strip, reached) =
            nest_strip_until(&items, width_mm, &settings, &limit, &observe).map_err(refused)?;
        let length = ((strip.length_mm + 2.0 * shift) * 10.0).ceil() / 10.0;
        let bin = NestBin {
            width_mm: spec.width_mm,
            height_mm: length,
            stock: 1,
        };
        // The strip the nester probed, in the sheet's frame as `bin` is.
        let room = NestBin {
            width_mm: spec.width_mm,
            height_mm: strip.bin.height_mm + 2.0 * shift,
            stock: copies.max(1),
        };
        (strip.solution, bin, room, Some(length), reached)
    } else {
        let on = on_sheets(layer, &items, &settings, &limit, &observe).map_err(|e| match e {
            Stage::Drawn(e) => fail(format!("drawn sheets or holes: {e}")),
            Stage::Whole(e) => refused(e),
        })?;
        (drawn, hosted, held) = (on.drawn, on.hosted, on.held);
        let (solution, stock, reached) = (on.solution, on.stock, on.reached);
        let bin = sheet_of(spec, drawn.len() + stock);
        let room = NestBin {
            stock: copies.max(1),
            ..bin
        };
        (solution, bin, room, None, reached)
    };
    onto_sheet(spec, &mut solution.bins, bin.width_mm * bin.height_mm);
    let layouts = cut_layouts(layer, &solution);
    let mut promise = Promise {
        sheet: bin,
        packed: items,
        clearance_mm: settings.separation_mm,
        edge_mm: settings.separation_mm + shift,
    };
    verify_layer(
        layer,
        (&layouts, &solution),
        &promise,
        (&drawn, &hosted, &held),
        settings.separation_mm,
    )
    .map_err(|v| fail(format!("nest verifier: {v}")))?;
    let [room_width_mm, room_height_mm] =
        [room.width_mm - 2.0 * shift, room.height_mm - 2.0 * shift];
    let mut boxes: NestSolution = nest_bounding_boxes(
        &promise.packed,
        &NestBin {
            width_mm: room_width_mm,
            height_mm: room_height_mm,
            ..room
        },
        &settings,
    )
    .map_err(|e| fail(format!("bounding-box baseline: {e}")))?;
    onto_sheet(spec, &mut boxes.bins, room.width_mm * room.height_mm);
    promise.sheet = room;
    verify_cut_layouts(layer, &cut_layouts(layer, &boxes), &promise)
        .map_err(|v| fail(format!("baseline verifier: {v}")))?;
    // Only where a limit could end the search: a plain iteration budget's report stays as it is.
    let search =
        (deadline.is_some() || reached.ended != SearchEnd::Budget).then(|| SearchRow::of(&reached));
    // Measured on the outlines as the baseline's boxes are: a part in a hole is in its host's area.
    let outlines = NestSolution {
        bins: without_hosted(&solution.bins, &hosted),
    };
    let baseline = baseline_row(
        layer,
        (&outlines, &bin),
        (&boxes, &room),
        settings.separation_mm,
        strip_length_mm,
        search,
    );
    Ok(PlacedLayer {
        layouts,
        baseline: Some(baseline),
        strip_length_mm,
        drawn,
    })
}

/// Which nest of a layer on sheets failed: on its drawn sheets, or on its whole ones.
enum Stage {
    Drawn(NestError),
    Whole(NestError),
}

/// A layer nested on its sheets ([`on_sheets`]).
struct OnSheets {
    solution: NestSolution,
    /// The drawn sheet each of the first sheets is.
    drawn: Vec<usize>,
    /// Whole sheets in stock.
    stock: usize,
    /// How far the whole sheets' search got.
    reached: Reached,
    /// The parts in holes of each sheet.
    hosted: Vec<Vec<Hosted>>,
    /// Copies of each item placed in holes (numbered after the others).
    held: Vec<usize>,
}

/// The layer's items on its sheets in the packers' room ([`room_of`]): parts in the cut-outs of
/// larger parts first ([`fill_holes`]), then its drawn sheets (remnants, sheets with flaws), then
/// whole sheets for the rest, copies numbered on from the drawn sheets', the parts in holes
/// carried onto the sheets with the copies that hold them.
fn on_sheets(
    layer: &CutLayer,
    items: &[NestItem],
    settings: &NestSettings,
    limit: &SearchLimit<'_>,
    observe: &dyn Fn(&NestProgress),
) -> Result<OnSheets, Stage> {
    let spec = &layer.spec;
    let copies: usize = items.iter().map(|i| i.demand).sum();
    let kits = fill_holes(layer, items, settings, limit, observe).map_err(Stage::Drawn)?;
    let with = |left: &[usize]| -> Vec<NestItem> {
        items
            .iter()
            .zip(left)
            .map(|(i, &n)| NestItem {
                demand: n,
                ..i.clone()
            })
            .collect()
    };
    let outside = with(&kits.left);
    let room = room_of(spec, copies.max(1));
    let shift = spec.edge_shift_mm();
    let on_drawn = fill_drawn(layer, &outside, &room, shift, settings, limit, observe)
        .map_err(Stage::Drawn)?;
    let rest = with(&on_drawn.left);
    let stock = spec.stock.unwrap_or(copies.max(1));
    let (mut whole, reached) =
        nest_until(&rest, &room_of(spec, stock), settings, limit, observe).map_err(Stage::Whole)?;
    let mut bins = on_drawn.sheets;
    for mut b in whole.bins.drain(..) {
        for p in &mut b.parts {
            p.copy += kits.left[p.item] - on_drawn.left[p.item];
        }
        b.index = bins.len();
        bins.push(b);
    }
    let hosted = carry(&kits, items, &mut bins);
    let held = items
        .iter()
        .zip(&kits.left)
        .map(|(i, l)| i.demand - l)
        .collect();
    Ok(OnSheets {
        solution: NestSolution { bins },
        drawn: on_drawn.drawn,
        stock,
        reached,
        hosted,
        held,
    })
}

/// The report row of `layer`'s nest (`solution` on the sheet `bin` it is drawn on) against the
/// bounding-box baseline (`boxes` on the sheets `room`), parts `separation_mm` apart.
fn baseline_row(
    layer: &CutLayer,
    (solution, bin): (&NestSolution, &NestBin),
    (boxes, room): (&NestSolution, &NestBin),
    separation_mm: f64,
    strip_length_mm: Option<f64>,
    search: Option<SearchRow>,
) -> BaselineRow {
    let roll = layer.spec.roll;
    let used = solution.used_length_utilization(bin, separation_mm);
    let boxes_used = boxes.used_length_utilization(room, separation_mm);
    BaselineRow {
        layer: layer.layer.clone(),
        material: layer.material.clone(),
        parts: layer.items.iter().map(|i| i.count).sum(),
        sheets: solution.bins_used(),
        // On a roll the one sheet is the used strip: its utilisation is the used-length one.
        utilization: if roll { used } else { solution.utilization() },
        used_length_utilization: used,
        baseline_sheets: boxes.bins_used(),
        baseline_utilization: if roll {
            boxes_used
        } else {
            boxes.utilization()
        },
        baseline_used_length_utilization: boxes_used,
        strip_length_mm,
        baseline_strip_length_mm: strip_length_mm
            .map(|_| boxes.used_length_mm(room, separation_mm)),
        search,
    }
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

/// The verifier's check of a layer's nest: `layouts` (cut paths) and `solution` (the nominal
/// outlines) against what the packer promised; the parts in holes (`held` copies of each item,
/// `hosted` on each sheet) against their holes; the drawn sheets against their outlines and
/// keep-outs.
fn verify_layer(
    layer: &CutLayer,
    (layouts, solution): (&[NestedBin], &NestSolution),
    promise: &Promise,
    (drawn, hosted, held): (&[usize], &[Vec<Hosted>], &[usize]),
    separation_mm: f64,
) -> Result<(), NestViolation> {
    verify_copies(&promise.packed, layouts)?;
    // The parts in holes lie inside other parts' outlines: checked against their holes, the
    // others as the packer promised.
    let outside = Promise {
        packed: promise
            .packed
            .iter()
            .zip(held)
            .map(|(i, h)| NestItem {
                demand: i.demand - h,
                ..i.clone()
            })
            .collect(),
        ..promise.clone()
    };
    verify_cut_layouts(layer, &without_hosted(layouts, hosted), &outside)?;
    verify_drawn(layer, &solution.bins, drawn, separation_mm)?;
    let items = &promise.packed;
    verify_hosted(
        layer,
        items,
        &promise.sheet,
        &solution.bins,
        hosted,
        separation_mm,
    )
}

/// `layouts` without the parts in holes.
fn without_hosted(layouts: &[NestedBin], hosted: &[Vec<Hosted>]) -> Vec<NestedBin> {
    layouts
        .iter()
        .enumerate()
        .map(|(s, b)| NestedBin {
            parts: b
                .parts
                .iter()
                .enumerate()
                .filter(|(k, _)| {
                    hosted
                        .get(s)
                        .is_none_or(|h| h.iter().all(|h| h.guest != *k))
                })
                .map(|(_, p)| p.clone())
                .collect(),
            ..b.clone()
        })
        .collect()
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
                .map(|p| placed_as(p, &layer.items[p.item].cut))
                .collect(),
            utilization: b.utilization,
            score_lines: b.score_lines.clone(),
        })
        .collect()
}
