//! Nesting of cut-through parts (carbon-fibre prepreg, Pyralux) on sheets.
//!
//! [`nest`] is the irregular nester: jagua-rs's bin-packing model for collision detection and
//! feasibility, our own greedy fill and ruin-and-recreate local search on top, and last a
//! compression of the final sheet through overlap (`compress`, on the penetration measure of
//! `overlap`); [`irregular`] explains how. [`nest_bounding_boxes`] is the baseline it is
//! measured against: bounding boxes packed by MaxRects. [`verify`] checks any result with plain
//! `geo` geometry.
//!
//! Units are millimetres, y up; the sheet spans `[0, width_mm] x [0, height_mm]`. Both nesters
//! stop on an iteration budget, never on time, so the same input and seed give the same layout.

mod baseline;
mod compress;
pub mod irregular;
mod overlap;
mod problem;

pub use baseline::nest_bounding_boxes;
pub use irregular::nest;
pub use problem::{
    clean_ring, place_outline, rotate, signed_area, verify, NestBin, NestError, NestItem,
    NestSettings, NestSolution, NestViolation, NestedBin, PlacedPart, Point,
};
