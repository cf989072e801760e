//! Stock given as a drawing: a remnant a run of `nest` wrote, or a sheet with a flaw drawn round.
//! A batch names it (`[[stock]]`); the layer of its material nests on it before its whole sheets.

use cam_nest::SheetShape;

/// A sheet of a cut-through layer given as a drawing: the stock's outline and the regions no part
/// may touch (flaws, earlier cuts), in the frame of the layer's sheet (`[0, width] x [0, height]`).
/// Cut-through layers only: a PZT plate layout starts from a whole sheet's straight edges.
#[derive(Debug, Clone, PartialEq)]
pub struct DrawnSheet {
    /// The drawing, as the batch names it.
    pub file: String,
    /// For a prepreg sheet, the batch item whose layup it is laid up in; `None` for Pyralux.
    pub like: Option<usize>,
    /// Outline and keep-outs.
    pub shape: SheetShape,
}

impl DrawnSheet {
    /// Area parts may take, mm²: the outline's (the sheet's when it has none) less the keep-outs'.
    pub fn free_area_mm2(shape: &SheetShape, width_mm: f64, height_mm: f64) -> f64 {
        let outline = if shape.outline.is_empty() {
            width_mm * height_mm
        } else {
            cam_geometry::area(&shape.outline).abs()
        };
        outline
            - shape
                .keep_outs
                .iter()
                .map(|k| cam_geometry::area(k).abs())
                .sum::<f64>()
    }
}
