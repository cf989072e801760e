//! The remnant of each cut-through sheet a batch cuts: the sheet's outline with the parts' cut
//! outlines (and the sheet's own keep-outs) as keep-outs, drawn as reference contours a later batch
//! reads back as a drawn sheet (`[[stock]]`, [`crate::process::DrawnSheet`]).

use crate::drawing::model::{Drawing, Operation, Shape};
use crate::pipeline::{SheetDrawing, SheetRecord};
use crate::process::DrawnSheet;
use serde::Serialize;

/// A sheet's remnant as the report gives it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RemnantRow {
    /// The remnant drawing's file stem (`remnant-passive-1_…`).
    pub file_stem: String,
    /// Area left to cut from: the outline's less the keep-outs', mm².
    pub free_area_mm2: f64,
}

/// The report row of `sheet`'s remnant, if it is a cut-through sheet of whole or drawn stock.
pub fn remnant_row(sheet: &SheetRecord) -> Option<RemnantRow> {
    let shape = sheet.remnant.as_ref()?;
    Some(RemnantRow {
        file_stem: format!("remnant-{}", sheet.file_stem),
        free_area_mm2: DrawnSheet::free_area_mm2(shape, sheet.width_mm, sheet.height_mm),
    })
}

/// The remnant drawings of a build's cut-through sheets, on the same stock and page as each sheet
/// (`drawings` are the build's, where each sheet's stock is found).
pub fn remnant_drawings(
    title: &str,
    sheets: &[SheetRecord],
    drawings: &[SheetDrawing],
) -> Vec<SheetDrawing> {
    sheets
        .iter()
        .filter_map(|sheet| {
            let shape = sheet.remnant.as_ref()?;
            let (w, h) = (sheet.width_mm, sheet.height_mm);
            let name = format!("{title} remnant of {}", sheet.stem);
            let stock = drawings
                .iter()
                .find(|d| d.stem == sheet.file_stem)
                .and_then(|d| d.drawing.stock.clone());
            let mut d = match stock {
                Some(stock) => Drawing::on_stock(&name, w, h, stock),
                None => Drawing::new(&name, w, h),
            };
            let outline = if shape.outline.is_empty() {
                vec![[0.0, 0.0], [w, 0.0], [w, h], [0.0, h]]
            } else {
                shape.outline.clone()
            };
            d.add(Operation::Reference, Shape::Polygon(outline));
            for k in &shape.keep_outs {
                d.add(Operation::Reference, Shape::Polygon(k.clone()));
            }
            Some(SheetDrawing {
                stem: format!("remnant-{}", sheet.file_stem),
                layer: "remnant".into(),
                drawing: d,
            })
        })
        .collect()
}
