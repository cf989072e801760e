//! Independent placement verifier.
//!
//! Checks a finished [`SheetLayout`] without trusting the code that made it: distances, overlaps
//! and containment come from `geo` predicates and metrics (through [`cam_nest::clearance`], the
//! one clearance check the nester's own verifier shares), and the snap check replays the breaks
//! on the sheet itself. Nothing here reuses the arithmetic of [`super::plates`] or
//! [`super::shelf`], nor of the irregular nester: every layout the pipeline makes, scored, shelved
//! or nested, is checked here.
//!
//! - `clearance` ([`verify_sheet`], [`verify_sheet_edges`]): parts inside the sheet, apart from
//!   each other and the edge, in allowed rotations;
//! - `bookkeeping` ([`verify_outlines`], [`verify_copies`], [`verify_stock`]): each outline its
//!   part as stated, every copy once, the stock;
//! - `snap` ([`verify_snappable`], [`verify_break_order`], [`verify_offcuts`]): score lines that
//!   can be snapped in order, free every plate and leave no offcut too narrow to snap.

mod bookkeeping;
mod clearance;
mod snap;
#[cfg(test)]
mod tests;

pub use bookkeeping::{verify_copies, verify_outlines, verify_stock};
pub use clearance::{verify_sheet, verify_sheet_edges};
pub use snap::{verify_break_order, verify_offcuts, verify_snappable};

use super::placement::{Sheet, SheetLayout};
use cam_geometry::Point;
use geo::{Coord, Polygon};
use std::fmt;
use thiserror::Error;

/// Which part a violation is about: its index in `placements`, its item and copy.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PartRef {
    pub index: usize,
    pub item: usize,
    pub copy: usize,
}

impl fmt::Display for PartRef {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "part {} (item {} copy {})",
            self.index, self.item, self.copy
        )
    }
}

/// One thing wrong with a layout.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum Violation {
    #[error("{part} has an invalid outline: {reason}")]
    InvalidOutline { part: PartRef, reason: String },
    #[error("{part} lies (partly) outside the {sheet_width_mm} x {sheet_height_mm} mm sheet")]
    OutsideSheet {
        part: PartRef,
        sheet_width_mm: f64,
        sheet_height_mm: f64,
    },
    #[error(
        "{part} is {distance_mm:.6} mm from the sheet edge, less than the required {min_mm:.6} mm"
    )]
    EdgeGap {
        part: PartRef,
        distance_mm: f64,
        min_mm: f64,
    },
    #[error("{a} and {b} overlap ({area_mm2:.6} mm²)")]
    Overlap {
        a: PartRef,
        b: PartRef,
        area_mm2: f64,
    },
    #[error("{a} and {b} are {distance_mm:.6} mm apart, less than the required {min_mm:.6} mm")]
    Gap {
        a: PartRef,
        b: PartRef,
        distance_mm: f64,
        min_mm: f64,
    },
    #[error("{part} is rotated by {rotation_deg}°, not one of the allowed {allowed:?}")]
    ForbiddenRotation {
        part: PartRef,
        rotation_deg: f64,
        allowed: Vec<f64>,
    },
    #[error("{part} outline is not its item's nominal outline rotated and moved as stated (off by {deviation_mm:.3e} mm)")]
    OutlineMismatch { part: PartRef, deviation_mm: f64 },
    #[error("score line {line} is not a proper segment (too short or not finite)")]
    DegenerateScoreLine { line: usize },
    #[error("score line {line} leaves the sheet")]
    ScoreLineOutsideSheet { line: usize },
    #[error("score line {line} ends in mid-air at ({x:.4}, {y:.4}): not on the sheet edge nor on another score line")]
    ScoreLineMidAir { line: usize, x: f64, y: f64 },
    #[error("score lines {lines:?} cannot be snapped in any order: each ends on another of them")]
    NotGuillotine { lines: Vec<usize> },
    #[error("score line {line} is listed before the line its end ({x:.4}, {y:.4}) rests on")]
    OutOfOrder { line: usize, x: f64, y: f64 },
    #[error("score line {line} ends inside a piece it should split edge to edge")]
    ScoreLineEndsInPiece { line: usize },
    #[error("score line {line} crosses the interior of {part}")]
    ScoreLineCrossesPlate { line: usize, part: PartRef },
    #[error("{part} does not lie inside one cell of the score lines")]
    PlateNotInCell { part: PartRef },
    #[error("score line {line} leaves an offcut {width_mm:.3} mm wide, narrower than the {min_mm:.3} mm strip that snaps off cleanly")]
    NarrowOffcut {
        line: usize,
        width_mm: f64,
        min_mm: f64,
    },
    #[error("{a} and {b} lie in the same cell: no score line separates them")]
    SharedCell { a: PartRef, b: PartRef },
    #[error("the layout uses {used} sheets but the stock is {stock}")]
    StockExceeded { used: usize, stock: usize },
    #[error("item {item}: copies placed {placed:?}, wanted each of 0..{wanted} once")]
    WrongCopies {
        item: usize,
        wanted: usize,
        placed: Vec<usize>,
    },
}

/// Tolerance for "lies on" in the snap check, mm (as specified for score line ends).
const ON_TOL: f64 = 1e-6;
/// Tolerance for rotations, degrees.
const ANGLE_TOL: f64 = 1e-9;

fn part_ref(layout: &SheetLayout, index: usize) -> PartRef {
    let p = &layout.placements[index];
    PartRef {
        index,
        item: p.item,
        copy: p.copy,
    }
}

fn coord(p: Point) -> Coord<f64> {
    Coord { x: p[0], y: p[1] }
}

fn polygon(ring: &[Point]) -> Polygon<f64> {
    Polygon::new(ring.iter().map(|&p| coord(p)).collect(), vec![])
}

fn sheet_polygon(sheet: &Sheet) -> Polygon<f64> {
    polygon(&[
        [0.0, 0.0],
        [sheet.width_mm, 0.0],
        [sheet.width_mm, sheet.height_mm],
        [0.0, sheet.height_mm],
    ])
}

fn finish(violations: Vec<Violation>) -> Result<(), Vec<Violation>> {
    if violations.is_empty() {
        Ok(())
    } else {
        Err(violations)
    }
}
