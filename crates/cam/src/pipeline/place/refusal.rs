//! The refusal of a part that fits no sheet: which sheet field to change, where it was written,
//! and the least size that holds the part.

use crate::input::{short_number, InputError};
use crate::pipeline::cut::CutLayer;
use crate::pipeline::BuildError;
use crate::process::template::SheetSpec;
use cam_nest::NestError;

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
pub(super) fn sheet_too_small(
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

/// The refusal of a nester's error `e` on `layer` (the irregular nester's or the shelf packer's): a part larger than the sheet names
/// the sheet field to change; anything else is a build error by `fail`, which names the stock.
pub(super) fn refusal(
    layer: &CutLayer,
    e: NestError,
    fail: &dyn Fn(String) -> BuildError,
) -> BuildError {
    match e {
        NestError::PartLargerThanBin {
            item,
            part_width_mm,
            part_height_mm,
            separation_mm,
            edge_gap_mm,
            ..
        } => {
            // The packer worked on the sheet shrunk by the edge shift (`super::room_of`).
            let shift = layer.spec.edge_shift_mm();
            let (to_edge_mm, edge_gap_mm) = (separation_mm + shift, edge_gap_mm + shift);
            sheet_too_small(
                &layer.spec,
                &format!(
                    "the {} part of {} ({part_width_mm:.3} x {part_height_mm:.3} mm at its best allowed rotation, with {} mm of kerf and edge gap to each edge, {edge_gap_mm:.3} mm with the nester's working margin)",
                    layer.layer, layer.items[item].owner, short_number(to_edge_mm)
                ),
                [part_width_mm, part_height_mm],
                [2.0 * edge_gap_mm; 2],
                false,
                None,
            )
        }
        NestError::StockTooSmall { needed, stock } => fail(format!(
            "stock too small: the batch needs {needed} sheets but the stock is {stock}"
        )),
        other => fail(other.to_string()),
    }
}
