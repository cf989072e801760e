//! Shared layout types: sheets, placed parts, sheet layouts and layout errors.

use serde::{Deserialize, Serialize};
use thiserror::Error;

/// A point in sheet coordinates, mm, y up.
pub type Point = [f64; 2];

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

/// Reduces an angle in degrees to [0, 360).
pub(crate) fn normalize_deg(deg: f64) -> f64 {
    let r = deg.rem_euclid(360.0);
    if r >= 360.0 {
        0.0
    } else {
        r
    }
}

/// (cos, sin) of an angle in degrees, exact for quarter turns so that axis-aligned layouts
/// stay free of 1e-17 noise.
pub(crate) fn cos_sin_deg(deg: f64) -> (f64, f64) {
    let d = normalize_deg(deg);
    match d {
        0.0 => (1.0, 0.0),
        90.0 => (0.0, 1.0),
        180.0 => (-1.0, 0.0),
        270.0 => (0.0, -1.0),
        _ => {
            let r = d.to_radians();
            (r.cos(), r.sin())
        }
    }
}

/// Rotates a ring about the origin by `deg` (CCW).
pub(crate) fn rotate_ring(ring: &[Point], deg: f64) -> Vec<Point> {
    let (c, s) = cos_sin_deg(deg);
    ring.iter()
        .map(|p| [c * p[0] - s * p[1], s * p[0] + c * p[1]])
        .collect()
}

/// Rotates a point about the origin by `deg` (CCW), then translates it by `offset`: how a placement
/// carries any feature of its part (holes, labels) onto the sheet.
pub fn place_point(p: Point, deg: f64, offset: Point) -> Point {
    let (c, s) = cos_sin_deg(deg);
    [
        c * p[0] - s * p[1] + offset[0],
        s * p[0] + c * p[1] + offset[1],
    ]
}

/// [`place_point`] over a ring or polyline.
pub fn place_ring(ring: &[Point], deg: f64, offset: Point) -> Vec<Point> {
    ring.iter().map(|p| place_point(*p, deg, offset)).collect()
}

/// Axis-aligned bounding box `(min, max)` of a non-empty ring.
pub(crate) fn bbox(ring: &[Point]) -> (Point, Point) {
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    for p in ring {
        for a in 0..2 {
            lo[a] = lo[a].min(p[a]);
            hi[a] = hi[a].max(p[a]);
        }
    }
    (lo, hi)
}

/// Signed area of a ring (shoelace formula), positive for CCW.
pub fn signed_area(ring: &[Point]) -> f64 {
    let n = ring.len();
    (0..n)
        .map(|i| {
            let (p, q) = (ring[i], ring[(i + 1) % n]);
            p[0] * q[1] - q[0] * p[1]
        })
        .sum::<f64>()
        / 2.0
}

/// Places `nominal` rotated by `rotation_deg` so that its bounding box starts at `bbox_min`.
pub(crate) fn place_at(
    item: usize,
    copy: usize,
    nominal: &[Point],
    rotation_deg: f64,
    bbox_min: Point,
) -> Placement {
    let rotated = rotate_ring(nominal, rotation_deg);
    let (lo, _) = bbox(&rotated);
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
    fn quarter_turns_are_exact() {
        let r = rotate_ring(&[[1.0, 2.0]], 90.0);
        assert_eq!(r, vec![[-2.0, 1.0]]);
        let r = rotate_ring(&[[1.0, 2.0]], -90.0);
        assert_eq!(r, vec![[2.0, -1.0]]);
    }

    #[test]
    fn place_at_puts_the_bbox_where_asked() {
        let tri = [[0.0, 0.0], [4.0, 0.0], [0.0, 3.0]];
        let p = place_at(1, 2, &tri, 180.0, [10.0, 20.0]);
        assert_eq!(bbox(&p.outline).0, [10.0, 20.0]);
        assert_eq!(p.offset, [14.0, 23.0]);
        assert!((signed_area(&p.outline) - 6.0).abs() < 1e-12);
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
