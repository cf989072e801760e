//! The one placement-and-verification step of the pipeline: where the parts of a layer go on its
//! sheets, checked by the independent verifier ([`crate::layout::verify`]) before anything is drawn.
//!
//! PZT plates always get a snappable (guillotine) layout of score lines ([`place_plates`]). A
//! cut-through layer is packed by the [`Packing`] strategy of the build
//! ([`layers::place_cut_layer`]): the fast shelf packer for one design, or the irregular nester for a
//! batch, both in `cam_nest`.
//! Every layout is in `cam_nest`'s vocabulary, and whichever packs the layer, `cam_nest`'s verifier
//! checks the result: every copy placed once, within the stock, each placed outline its part turned
//! and moved as stated, inside the sheet and apart from the others by the clearance the strategy
//! promised; scored sheets add the snap checks of [`crate::layout::verify`].
//!
//! | file | what |
//! |---|---|
//! | `packing.rs` | the [`Packing`] strategies, the nester's options and its report rows |
//! | `plates.rs` | the PZT plates' snappable layout, verified |
//! | `layers.rs` | every cut layer placed, several nested at once |
//! | `shelf.rs`, `irregular.rs` | the two packers of a cut layer, each verified |
//! | `drawn.rs` | a layer's drawn sheets (remnants, sheets with flaws) filled first, verified |
//! | `holes.rs` | parts nested in other parts' cut-outs, carried with them, verified |
//! | `promise.rs` | what a packer promised, and the verifier's check of it |
//! | `refusal.rs` | the refusal of a part that fits no sheet |

mod drawn;
mod holes;
mod irregular;
mod layers;
mod packing;
mod plates;
mod promise;
mod refusal;
mod shelf;

pub use irregular::sheets_instead_of_roll;
pub(crate) use layers::place_cut_layers;
pub use packing::{
    BaselineRow, NestObserver, NestOptions, Packing, SearchRow, TimeBudget, Unobserved, WORKERS,
};
pub(crate) use plates::{place_plates, PlacedPlates};

use super::cut::{CutItem, CutLayer};
use crate::process::template::SheetSpec;
use cam_geometry::{place_ring, Point};
use cam_nest::{NestBin, NestItem, NestedBin, PlacedPart};

/// A cut layer placed and verified.
#[derive(Debug, Clone)]
pub(crate) struct PlacedLayer {
    /// Sheet layouts of the cut paths: each part's outline is its item's cut path placed.
    pub layouts: Vec<NestedBin>,
    /// The irregular nest against the bounding-box baseline ([`Packing::Irregular`] only).
    pub baseline: Option<BaselineRow>,
    /// On roll stock: the used length, mm (the one sheet is drawn this long).
    pub strip_length_mm: Option<f64>,
    /// The drawn sheet ([`crate::process::template::SheetSpec::drawn`]) each of the first
    /// `drawn.len()` layouts is cut from; the others are whole sheets.
    pub drawn: Vec<usize>,
}

/// The template's sheet with `stock` sheets of it.
fn sheet_of(spec: &SheetSpec, stock: usize) -> NestBin {
    NestBin {
        width_mm: spec.width_mm,
        height_mm: spec.height_mm,
        stock,
    }
}

/// The sheet the packers work on for `spec`, with `stock` sheets of it: the sheet shrunk by the
/// difference of its edge gap and its spacing ([`SheetSpec::packing_room`]), so that a packer that
/// keeps one gap to everything keeps the edge gap to the sheet's edge once its layout is moved back
/// ([`onto_sheet`]). A roll's room has the width only; its length is the packer's.
fn room_of(spec: &SheetSpec, stock: usize) -> NestBin {
    let [width_mm, height_mm] = spec.packing_room();
    NestBin {
        width_mm,
        height_mm,
        stock,
    }
}

/// Sheets packed on [`room_of`]`(spec)` moved onto the sheet itself: every part moved by the edge
/// shift along both axes, fills against the sheet's area. Unchanged when the edge gap is the
/// spacing.
fn onto_sheet(spec: &SheetSpec, sheets: &mut [NestedBin], sheet_area_mm2: f64) {
    let d = spec.edge_shift_mm();
    if d == 0.0 {
        return;
    }
    for sheet in sheets {
        for part in &mut sheet.parts {
            part.translation = [part.translation[0] + d, part.translation[1] + d];
            for q in &mut part.outline {
                *q = [q[0] + d, q[1] + d];
            }
        }
        sheet.utilization = sheet.part_area_mm2() / sheet_area_mm2;
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

/// `part` with `ring`, a ring of its item, in place of its outline: turned and moved as the part was.
fn placed_as(part: &PlacedPart, ring: &[Point]) -> PlacedPart {
    PlacedPart {
        item: part.item,
        copy: part.copy,
        rotation_deg: part.rotation_deg,
        translation: part.translation,
        outline: place_ring(ring, part.rotation_deg, part.translation),
    }
}
