//! Scored PZT layouts and their snap checks: what only a sheet of snapped ceramic needs.
//!
//! - [`plates`]: snappable (guillotine) layouts of PZT trapezoid plates, with score lines in snap order.
//! - [`pzt_remnant`]: the rectangle of a scored sheet that one edge-to-edge line frees, to keep.
//! - [`verify`]: the snap checks (score lines that can be snapped in order, free every plate and leave no
//!   offcut too narrow to snap), replayed on the sheet with `geo`, independent of the planner.
//!
//! Layouts are in the nester's vocabulary: a sheet is a [`cam_nest::NestBin`], a laid-out sheet a
//! [`cam_nest::NestedBin`] (its score lines included), a part a [`cam_nest::PlacedPart`]. Cut-through
//! parts are packed by `cam_nest` (the shelf packer or the irregular nester), and every layout, scored or
//! not, passes `cam_nest`'s verifier for copies, stock, outlines, rotations and clearance.
//!
//! Coordinates are in mm, y up; a sheet spans (0, 0) to (width, height). Rings are closed
//! polygons without a repeated closing point, counter-clockwise.

mod error;
pub mod plates;
mod remnant;
pub mod verify;

pub use error::LayoutError;
pub use plates::{layout_plates, layout_plates_on_remnant, PlateSpec};
pub use remnant::pzt_remnant;
pub use verify::{verify_break_order, verify_offcuts, verify_snappable, Violation};
