//! Nesting of cut-through parts on sheets: polygons, sheets, separation and rotations, nothing
//! about what the parts are for.
//!
//! * [`nest`] is the irregular nester: jagua-rs's bin-packing model for collision detection and
//!   feasibility, our own greedy fill and ruin-and-recreate local search on top, and last a
//!   compression of the final sheet through overlap; [`irregular`] explains how.
//! * [`nest_observed`] is [`nest`] reporting a [`NestProgress`] to the caller as it goes (for a
//!   progress bar); [`nest_strip`] nests on roll stock: fixed width, unbounded length, the used
//!   length minimised ([`StripLayout`]).
//! * [`nest_bounding_boxes`] is the baseline it is measured against: bounding boxes packed by
//!   MaxRects.
//! * [`nest_shelves`] is the shelf packer: rows of parts slid together, fast and deterministic, for a
//!   single design's few parts (`cut-sheet`).
//! * [`verify()`] checks any layout, from these nesters or from elsewhere, with plain `geo`
//!   geometry: inside the sheet with the separation to every edge, the separation between parts,
//!   allowed rotations, outlines equal to the item moved as stated, every copy placed once.
//!   Its parts are public for layouts made by other packers (the app's scored PZT plates, whose
//!   gap to the edge differs from the gap between plates): [`verify_sheet`] checks one sheet with
//!   its own [`Clearance`], [`verify_outlines`] the outlines and rotations alone, [`verify_copies`]
//!   and [`verify_stock`] the bookkeeping over all sheets. All rest on [`clearance()`], the one
//!   clearance check of placed rings (inside the sheet, gap to the edge, gap and overlap between
//!   parts). This is the one verifier of every layout the app makes.
//!
//! The vocabulary: an item ([`NestItem`]) is an outline with a demand and the rotations it may be
//! cut at; a sheet ([`NestBin`]) is `[0, width_mm] x [0, height_mm]` with a stock count; a layout
//! ([`NestSolution`]) is a list of sheets ([`NestedBin`]) of placed parts ([`PlacedPart`]: item,
//! copy, rotation, translation and the placed outline), with the score lines of a scored sheet in
//! snap order. The app's CAM pipeline uses this vocabulary for every layout it draws. Units are
//! millimetres, y up; points and rotations are those of [`cam_geometry`]. The nesters stop on an
//! iteration budget, so the same input and seed give the same layout on any machine;
//! [`nest_until`] and [`nest_strip_until`] may also end at a deadline or an interrupt
//! ([`SearchLimit`]), and say which iteration budget replays the layout ([`Reached`]).
//!
//! ```
//! use cam_nest::{nest, verify, NestBin, NestItem, NestSettings};
//!
//! // Six 20 x 8 mm rectangles and four trapezoids (a part turned by 180° fills the slanted gap
//! // of its neighbour) on 60 mm square sheets.
//! let items = vec![
//!     NestItem {
//!         outline: vec![[0.0, 0.0], [20.0, 0.0], [20.0, 8.0], [0.0, 8.0]],
//!         demand: 6,
//!         rotations_deg: vec![0.0, 90.0],
//!     },
//!     NestItem {
//!         outline: vec![[0.0, 0.0], [30.0, 0.0], [25.0, 10.0], [5.0, 10.0]],
//!         demand: 4,
//!         rotations_deg: vec![0.0, 180.0],
//!     },
//! ];
//! let sheet = NestBin { width_mm: 60.0, height_mm: 60.0, stock: 3 };
//! let settings = NestSettings { separation_mm: 0.5, seed: 1, iterations: 20, workers: 2 };
//!
//! let layout = nest(&items, &sheet, &settings)?;
//! assert_eq!(layout.parts_placed(), 10);
//! assert_eq!(layout.bins_used(), 1);
//! verify(&items, &sheet, &settings, &layout, 1e-9)?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod baseline;
mod clearance;
mod compress;
pub mod irregular;
mod job;
mod limit;
mod overlap;
mod placement;
mod problem;
mod progress;
mod shelf;
mod strip;
mod verify;

#[cfg(test)]
mod test_support;

pub use baseline::nest_bounding_boxes;
pub use cam_geometry::Point;
pub use clearance::{clearance, Clearance, ClearanceViolation};
pub use irregular::{nest, nest_observed, nest_shaped_until, nest_until};
pub use job::{clean_ring, fits_empty_sheet, EmptySheetFit};
pub use limit::{Reached, SearchEnd, SearchLimit};
pub use problem::{
    NestBin, NestError, NestItem, NestSettings, NestSolution, NestedBin, PlacedPart, SheetShape,
};
pub use progress::NestProgress;
pub use shelf::nest_shelves;
pub use strip::{nest_strip, nest_strip_until, StripLayout};
pub use verify::{
    verify, verify_copies, verify_outlines, verify_shape, verify_sheet, verify_stock, NestViolation,
};
