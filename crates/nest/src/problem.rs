//! Input and output types of the nesting engine: the parts to cut ([`NestItem`]), the sheet
//! ([`NestBin`]), the knobs ([`NestSettings`]), the layout ([`NestSolution`] of [`NestedBin`]s of
//! [`PlacedPart`]s) and why a nest could not be made ([`NestError`]).
//!
//! Coordinates are millimetres with y up. Rings are closed implicitly (no repeated closing point).
//! A placed part is `R(rotation_deg) * p + translation` for every vertex `p` of the item outline:
//! rotation about the outline's own origin, then translation into sheet coordinates, where the
//! sheet spans `[0, width_mm] x [0, height_mm]`.
//!
//! Two measures of a nest:
//! * **utilisation** ([`NestSolution::utilization`]): part area / area of the sheets used. What
//!   the report prints per sheet; it jumps when the parts spill onto one more sheet and cannot
//!   tell apart two nests on the same number of sheets.
//! * **used-length utilisation** ([`NestSolution::used_length_utilization`]): part area /
//!   (sheet width x used length), used length = all sheets but one counted whole + the used
//!   height of the sheet with the lowest top (top of its highest part + separation). The rest of
//!   that sheet is a reusable remnant (the nester packs toward `y = 0`). On one long sheet it is
//!   the density of strip packing (fixed width, length minimised), the usual benchmark of
//!   irregular nesting; it is the measure to compare nesters with.

use cam_geometry::{area, normalize_deg, rotate, Bounds, Point};
use serde::{Deserialize, Serialize};
use thiserror::Error;

/// One part design to cut, with how many copies are wanted.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct NestItem {
    /// Outer outline (holes are not nested into), counterclockwise, without repeated closing point.
    pub outline: Vec<Point>,
    /// Number of copies to place; 0 skips the item.
    pub demand: usize,
    /// Rotations the part may be cut at, in degrees counterclockwise, e.g. `[0, 180]` to keep the
    /// fibre direction of a prepreg ply.
    pub rotations_deg: Vec<f64>,
}

/// The sheet parts are cut from, `[0, width_mm] x [0, height_mm]`, and how many are in stock.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct NestBin {
    pub width_mm: f64,
    pub height_mm: f64,
    /// Number of sheets available.
    pub stock: usize,
}

/// Stock that is not a whole rectangle: a remnant of a sheet cut before, or a sheet with a flaw.
/// The sheet is its [`NestBin`]'s `[0, width_mm] x [0, height_mm]` cut down to `outline` (when
/// given), less the `keep_outs` (flaws, earlier cuts); parts keep the separation from both, as
/// from a sheet edge. Rings as an item's outline: counterclockwise, no closing repeat.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct SheetShape {
    /// The stock's outline, within the bin's rectangle; empty for the whole rectangle.
    pub outline: Vec<Point>,
    /// Regions inside the outline no part may touch.
    pub keep_outs: Vec<Vec<Point>>,
}

impl SheetShape {
    /// The whole rectangle of the bin, nothing kept out.
    #[must_use]
    pub fn is_whole(&self) -> bool {
        self.outline.is_empty() && self.keep_outs.is_empty()
    }
}

/// Knobs of a nesting run. The same settings and input give the same layout on any machine.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct NestSettings {
    /// Minimum gap between two parts and between a part and the sheet edge (kerf plus web).
    pub separation_mm: f64,
    /// Seed of every random choice.
    pub seed: u64,
    /// Optimiser budget: number of improvement moves (ruin-and-recreate steps) over all workers
    /// for a job of 60 copies or more; smaller jobs get a proportional share, at least 100 (a
    /// small batch on a mostly empty sheet gains nothing from more). Not wall-clock time, so
    /// runs are reproducible; 0 keeps the greedy fill.
    pub iterations: usize,
    /// Number of parallel workers; fixed, so the result does not depend on the machine.
    pub workers: usize,
}

impl Default for NestSettings {
    fn default() -> Self {
        Self {
            separation_mm: 0.3,
            seed: 0,
            iterations: 1000,
            workers: 2,
        }
    }
}

/// One copy of an item placed on a sheet.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PlacedPart {
    /// Index into the `items` slice given to the nester.
    pub item: usize,
    /// Which copy of the item (0..demand).
    pub copy: usize,
    /// Rotation, one of the item's `rotations_deg` (the value as given).
    pub rotation_deg: f64,
    /// Translation applied after the rotation.
    pub translation: Point,
    /// The placed ring in sheet coordinates: `R(rotation_deg) * p + translation`.
    pub outline: Vec<Point>,
}

impl PlacedPart {
    /// Copy `copy` of item `item`: the item's `outline` turned by `rotation_deg` about its own origin and
    /// moved so that its bounding box starts at `bbox_min` (how shelf and row packers place a part). The
    /// rotation is kept in [0, 360).
    #[must_use]
    pub fn at(
        item: usize,
        copy: usize,
        outline: &[Point],
        rotation_deg: f64,
        bbox_min: Point,
    ) -> Self {
        let rotated: Vec<Point> = outline.iter().map(|p| rotate(*p, rotation_deg)).collect();
        let lo = Bounds::of(&rotated).min;
        let translation = [bbox_min[0] - lo[0], bbox_min[1] - lo[1]];
        let outline = rotated
            .iter()
            .map(|p| [p[0] + translation[0], p[1] + translation[1]])
            .collect();
        PlacedPart {
            item,
            copy,
            rotation_deg: normalize_deg(rotation_deg),
            translation,
            outline,
        }
    }
}

/// One sheet of the solution: the parts cut from it, and for a scored (guillotine) layout the score
/// lines that free them.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct NestedBin {
    /// Position of the sheet in the solution (0-based), fullest sheet first.
    pub index: usize,
    pub parts: Vec<PlacedPart>,
    /// Part area / sheet area.
    pub utilization: f64,
    /// Score lines (open segments) in snap order: every line ends on the sheet edge or on an
    /// earlier line. Empty for cut-through parts, which the laser frees itself.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub score_lines: Vec<[Point; 2]>,
}

/// A finished nest: the sheets used, fullest first.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct NestSolution {
    pub bins: Vec<NestedBin>,
}

impl NestSolution {
    /// Number of sheets used.
    #[must_use]
    pub fn bins_used(&self) -> usize {
        self.bins.len()
    }

    /// Total part area over total area of the sheets used (0 when nothing is placed).
    #[must_use]
    pub fn utilization(&self) -> f64 {
        if self.bins.is_empty() {
            return 0.0;
        }
        self.bins.iter().map(|b| b.utilization).sum::<f64>() / self.bins.len() as f64
    }

    /// Number of parts placed on all sheets.
    #[must_use]
    pub fn parts_placed(&self) -> usize {
        self.bins.iter().map(|b| b.parts.len()).sum()
    }

    /// Total area of the placed parts, mm².
    #[must_use]
    pub fn part_area_mm2(&self) -> f64 {
        self.bins.iter().map(NestedBin::part_area_mm2).sum()
    }

    /// Used length: all sheets but one counted whole (`height_mm` each), plus the used height
    /// of the sheet with the lowest top ([`NestedBin::used_height_mm`]), whose rest is a
    /// reusable remnant. This is the strip length of strip packing, measured on sheets.
    #[must_use]
    pub fn used_length_mm(&self, bin: &NestBin, separation_mm: f64) -> f64 {
        let remnant = self
            .bins
            .iter()
            .map(|b| b.used_height_mm(bin, separation_mm))
            .fold(f64::INFINITY, f64::min);
        if self.bins.is_empty() {
            return 0.0;
        }
        (self.bins.len() - 1) as f64 * bin.height_mm + remnant
    }

    /// Used-length utilisation: part area / (sheet width x [`Self::used_length_mm`]). Unlike
    /// [`Self::utilization`] it does not jump when the parts spill onto one more sheet, so it
    /// compares nesters on the same parts; on a single long sheet it is the density of strip
    /// packing. 0 when nothing is placed.
    #[must_use]
    pub fn used_length_utilization(&self, bin: &NestBin, separation_mm: f64) -> f64 {
        let length = self.used_length_mm(bin, separation_mm);
        if length <= 0.0 {
            return 0.0;
        }
        self.part_area_mm2() / (bin.width_mm * length)
    }
}

impl NestedBin {
    /// Total area of the parts on this sheet, mm².
    #[must_use]
    pub fn part_area_mm2(&self) -> f64 {
        self.parts.iter().map(|p| area(&p.outline)).sum()
    }

    /// Height of the strip `[0, used]` of the sheet the parts need: the top of the highest part
    /// plus the separation a cut along it must keep, at most the sheet height; 0 when empty.
    /// The rest of the sheet above is a remnant, whole if the nester packed toward `y = 0`.
    #[must_use]
    pub fn used_height_mm(&self, bin: &NestBin, separation_mm: f64) -> f64 {
        let top = self
            .parts
            .iter()
            .flat_map(|p| p.outline.iter().map(|q| q[1]))
            .fold(f64::NEG_INFINITY, f64::max);
        if top.is_finite() {
            (top + separation_mm).min(bin.height_mm)
        } else {
            0.0
        }
    }
}

/// A sheet as an error names it: a strip (roll stock) has no length.
fn sheet_name(width_mm: f64, height_mm: f64) -> String {
    if height_mm.is_finite() {
        format!("{width_mm} x {height_mm} mm sheet")
    } else {
        format!("{width_mm} mm wide strip")
    }
}

/// Why a nest could not be made.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum NestError {
    #[error(
        "item {item}: part is {part_width_mm:.3} x {part_height_mm:.3} mm at its best allowed rotation, \
         which with {separation_mm} mm edge separation ({edge_gap_mm:.4} mm to each edge with the nester's \
         working margin) does not fit the {}", sheet_name(*.bin_width_mm, *.bin_height_mm)
    )]
    PartLargerThanBin {
        item: usize,
        part_width_mm: f64,
        part_height_mm: f64,
        bin_width_mm: f64,
        bin_height_mm: f64,
        separation_mm: f64,
        /// Gap the nester needed to each edge: the separation plus its working margin, so that a
        /// sheet `part + 2 * edge_gap_mm` across (a little more) takes the part.
        edge_gap_mm: f64,
    },
    #[error("stock too small: the parts need {needed} sheets but only {stock} are in stock")]
    StockTooSmall { needed: usize, stock: usize },
    #[error("item {item}: outline is empty or degenerate: {reason}")]
    DegenerateOutline { item: usize, reason: String },
    #[error("item {item}: rotations_deg must hold at least one finite angle, got {rotations:?}")]
    BadRotations { item: usize, rotations: Vec<f64> },
    #[error("bad settings: {0}")]
    BadSettings(String),
}
