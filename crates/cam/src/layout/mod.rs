//! Sheet layout: placing parts on material sheets, and an independent verifier.
//!
//! - [`plates`]: snappable (guillotine) layouts of PZT trapezoid plates, scored and snapped.
//! - [`shelf`]: a simple shelf layout for cut-through parts (carbon fibre, Pyralux).
//! - [`verify`]: checks any layout with `geo` predicates, independent of the layout arithmetic.
//!
//! Coordinates are in mm, y up; a sheet spans (0, 0) to (width, height). Rings are closed
//! polygons without a repeated closing point, counter-clockwise.

pub mod placement;
pub mod plates;
pub mod shelf;
pub mod verify;

pub use placement::{LayoutError, Placement, Sheet, SheetLayout};
pub use plates::{layout_plates, plate_outline, PlateSpec};
pub use shelf::{layout_parts, PartSpec};
pub use verify::{
    verify_break_order, verify_copies, verify_offcuts, verify_outlines, verify_sheet,
    verify_sheet_edges, verify_snappable, verify_stock, PartRef, Violation,
};
