//! The shelf packer's layout of a cut layer ([`super::Packing::Shelf`]), verified.

use super::promise::{verify_cut_layouts, Promise};
use super::refusal::refusal;
use super::{items_of, onto_sheet, room_of, sheet_of};
use crate::pipeline::cut::CutLayer;
use crate::pipeline::jobs::Names;
use crate::pipeline::BuildError;
use cam_nest::{nest_shelves, NestedBin};

/// The shelf packer on the cut paths, the template's spacing between them and its edge gap to the
/// sheet edge.
pub(super) fn shelf(layer: &CutLayer, names: &Names) -> Result<Vec<NestedBin>, BuildError> {
    let spec = &layer.spec;
    let items = items_of(layer, |i| &i.cut);
    // Without a stock limit a sheet takes at least one part, so no layout needs more sheets.
    let copies: usize = items.iter().map(|i| i.demand).sum();
    let sheet = sheet_of(spec, copies.max(1));
    let fail = |what: String| names.error(format!("{} layout: {what}", layer.layer));
    let mut layout = nest_shelves(&items, &room_of(spec, sheet.stock), spec.spacing_mm)
        .map_err(|e| refusal(layer, e, &fail))?;
    onto_sheet(spec, &mut layout.bins, sheet.width_mm * sheet.height_mm);
    let promise = Promise {
        sheet,
        packed: items,
        clearance_mm: spec.spacing_mm,
        edge_mm: spec.edge_gap(),
    };
    verify_cut_layouts(layer, &layout.bins, &promise)
        .map_err(|v| names.error(format!("{} (verifier) layout: {v}", layer.layer)))?;
    Ok(layout.bins)
}
