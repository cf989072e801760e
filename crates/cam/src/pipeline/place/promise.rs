//! What a packer promised for a cut layer, and the check of its layouts against it by
//! `cam_nest`'s verifier.

use super::{items_of, placed_as, promised, ROUNDING_MM};
use crate::pipeline::cut::CutLayer;
use cam_nest::{
    verify_copies, verify_outlines, verify_sheet, verify_stock, Clearance, NestBin, NestItem,
    NestViolation, NestedBin, PlacedPart,
};

/// What a packing promised for one cut layer, for the verifier.
#[derive(Clone)]
pub(super) struct Promise {
    /// The sheet, with the stock the packer had to keep to.
    pub sheet: NestBin,
    /// The items as packed: the ring of each part the packer kept apart (cut path or nominal
    /// outline), its copies and rotations.
    pub packed: Vec<NestItem>,
    /// Clearance between those rings, mm.
    pub clearance_mm: f64,
    /// Clearance from those rings to the sheet edge, mm.
    pub edge_mm: f64,
}

/// Verify layouts of cut paths against what the packing promised: every copy once within the stock,
/// every outline its item's cut path turned and moved as stated, and the packed rings (placed the
/// same way) inside the sheet, the clearances apart and from its edge, in allowed rotations.
pub(super) fn verify_cut_layouts(
    layer: &CutLayer,
    layouts: &[NestedBin],
    promise: &Promise,
) -> Result<(), NestViolation> {
    verify_stock(layouts, promise.sheet.stock)?;
    verify_copies(&promise.packed, layouts)?;
    let cut = items_of(layer, |i| &i.cut);
    let clearance = Clearance {
        between_parts_mm: promised(promise.clearance_mm),
        to_edge_mm: promised(promise.edge_mm),
    };
    for layout in layouts {
        verify_outlines(&cut, layout.index, &layout.parts, ROUNDING_MM)?;
        let packed: Vec<PlacedPart> = layout
            .parts
            .iter()
            .map(|p| placed_as(p, &promise.packed[p.item].outline))
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
