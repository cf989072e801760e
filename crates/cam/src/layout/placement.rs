//! Shared layout types: sheets, placed parts, sheet layouts and layout errors.

use cam_geometry::{normalize_deg, rotate, Bounds, Point};
use serde::{Deserialize, Serialize};
use thiserror::Error;

/// A rectangular sheet of stock from (0, 0) to (`width_mm`, `height_mm`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Sheet {
    pub width_mm: f64,
    pub height_mm: f64,
}

/// A part placed on a sheet.
///
/// `outline` is the item's nominal ring rotated about the origin by `rotation_deg` (CCW) and then
/// translated by `offset`: `outline[i] = R(rotation_deg) * nominal[i] + offset`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Placement {
    /// Index into the caller's item list.
    pub item: usize,
    /// Which copy of the item (0-based, over all sheets).
    pub copy: usize,
    /// Rotation of the nominal outline, degrees CCW, in [0, 360).
    pub rotation_deg: f64,
    /// Translation applied after the rotation, mm.
    pub offset: Point,
    /// The placed ring in sheet coordinates.
    pub outline: Vec<Point>,
}

/// Everything placed on one sheet.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SheetLayout {
    /// 0-based index of the sheet in the stock.
    pub sheet_index: usize,
    pub placements: Vec<Placement>,
    /// Score lines (open segments) in break order: every line ends on the sheet edge or on an
    /// earlier line. Empty for cut-through parts.
    pub score_lines: Vec<[Point; 2]>,
}

/// Why a layout could not be made.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum LayoutError {
    #[error("invalid sheet: {width_mm} x {height_mm} mm (both sides must be finite and > 0)")]
    InvalidSheet { width_mm: f64, height_mm: f64 },
    #[error("invalid {name}: {value} (must be finite and >= 0)")]
    InvalidParameter { name: &'static str, value: f64 },
    #[error("item {item} is invalid: {reason}")]
    InvalidItem { item: usize, reason: String },
    #[error(
        "item {item} is larger than the sheet: {width_mm:.1} x {height_mm:.1} mm on a \
         {sheet_width_mm:.1} x {sheet_height_mm:.1} mm sheet ({usable_width_mm:.2} x \
         {usable_height_mm:.2} mm usable inside the edge clearance, in no allowed rotation)"
    )]
    TooLarge {
        item: usize,
        width_mm: f64,
        height_mm: f64,
        sheet_width_mm: f64,
        sheet_height_mm: f64,
        usable_width_mm: f64,
        usable_height_mm: f64,
    },
    #[error("needs {needed} sheets but the stock is {stock}")]
    TooManySheets { needed: usize, stock: usize },
}

impl Sheet {
    /// Checks that both sides are finite and positive.
    pub fn validate(&self) -> Result<(), LayoutError> {
        let ok = |v: f64| v.is_finite() && v > 0.0;
        if ok(self.width_mm) && ok(self.height_mm) {
            Ok(())
        } else {
            Err(LayoutError::InvalidSheet {
                width_mm: self.width_mm,
                height_mm: self.height_mm,
            })
        }
    }
}

/// Checks that a length parameter (kerf, gap, margin) is finite and not negative.
pub(crate) fn check_length(name: &'static str, value: f64) -> Result<(), LayoutError> {
    if value.is_finite() && value >= 0.0 {
        Ok(())
    } else {
        Err(LayoutError::InvalidParameter { name, value })
    }
}

/// Places `nominal` rotated by `rotation_deg` so that its bounding box starts at `bbox_min`.
pub(crate) fn place_at(
    item: usize,
    copy: usize,
    nominal: &[Point],
    rotation_deg: f64,
    bbox_min: Point,
) -> Placement {
    let rotated: Vec<Point> = nominal.iter().map(|p| rotate(*p, rotation_deg)).collect();
    let lo = Bounds::of(&rotated).min;
    let offset = [bbox_min[0] - lo[0], bbox_min[1] - lo[1]];
    let outline = rotated
        .iter()
        .map(|p| [p[0] + offset[0], p[1] + offset[1]])
        .collect();
    Placement {
        item,
        copy,
        rotation_deg: normalize_deg(rotation_deg),
        offset,
        outline,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn place_at_puts_the_bbox_where_asked() {
        let tri = [[0.0, 0.0], [4.0, 0.0], [0.0, 3.0]];
        let p = place_at(1, 2, &tri, 180.0, [10.0, 20.0]);
        assert_eq!(Bounds::of(&p.outline).min, [10.0, 20.0]);
        assert_eq!(p.offset, [14.0, 23.0]);
        assert!((cam_geometry::signed_area(&p.outline) - 6.0).abs() < 1e-12);
    }

    #[test]
    fn errors_read_well() {
        let e = LayoutError::TooManySheets {
            needed: 3,
            stock: 2,
        };
        assert_eq!(e.to_string(), "needs 3 sheets but the stock is 2");
    }
}
