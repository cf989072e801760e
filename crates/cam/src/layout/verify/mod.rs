//! The snap checks of a scored sheet, independent of the planner that made it.
//!
//! [`verify_snappable`], [`verify_break_order`] and [`verify_offcuts`] replay the breaks on the sheet
//! with `geo` predicates, reusing none of the arithmetic of [`super::plates`]: the score lines can be
//! snapped in order, free every plate, and leave no offcut too narrow to snap. What every layout must
//! satisfy, scored or not (copies, stock, outlines, rotations, clearance), is checked by `cam_nest`'s
//! verifier, the one front end for all of them.

mod snap;
#[cfg(test)]
mod tests;

pub use snap::{verify_break_order, verify_offcuts, verify_snappable};

use cam_geometry::Point;
use cam_nest::{NestBin, NestedBin};
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
}

/// Tolerance for "lies on" in the snap check, mm (as specified for score line ends).
const ON_TOL: f64 = 1e-6;

fn part_ref(layout: &NestedBin, index: usize) -> PartRef {
    let p = &layout.parts[index];
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

fn sheet_polygon(sheet: &NestBin) -> Polygon<f64> {
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
