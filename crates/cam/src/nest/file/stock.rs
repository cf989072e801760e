//! A batch's `[[stock]]` tables: sheets given as drawings (a remnant an earlier run wrote, a sheet
//! with a flaw drawn round), read with the extra parts' drawing import: the one outline is the
//! stock, the contours inside it are keep-outs.

use super::{existing_file, BatchItem};
use crate::input::limits::{MAX_PLIES, PLY_ANGLE_DEG};
use crate::input::{InputError, TableReader};
use crate::parts::import;
use crate::process::template::PassiveCut;
use crate::process::{DrawnSheet, Template};
use cam_geometry::Bounds;
use cam_nest::SheetShape;
use std::path::Path;

/// Rounding a drawing's extent may have past the sheet it is drawn on, mm.
const EXTENT_ROUNDING_MM: f64 = 1e-6;

/// The item of the batch whose layup the stock's `layup_deg` names.
fn layup_item(t: &TableReader<'_>, items: &[BatchItem]) -> Result<usize, InputError> {
    let layup_deg = t.numbers_in("layup_deg", PLY_ANGLE_DEG, 1, MAX_PLIES)?;
    items
        .iter()
        .position(|i| i.design.layup_deg == layup_deg)
        .ok_or_else(|| {
            let layups: Vec<String> = items.iter().map(|i| i.design.layup_text()).collect();
            InputError::invalid(
                t.file(),
                &t.path("layup_deg"),
                format!("{layup_deg:?}"),
                format!(
                    "no design of the batch has this layup; the batch's layups: {}",
                    layups.join(", ")
                ),
            )
        })
}

/// One `[[stock]]`: `file` (DXF or SVG), `sheet` (`"prepreg"`, the default, with `layup_deg`; or
/// `"pyralux"`), added to the template's sheet of that material. A drawing whose extent lies on the
/// sheet `[0, width] x [0, height]` (as a remnant's does) keeps its coordinates; any other is moved
/// so that its extent starts at the sheet's corner.
pub(super) fn stock_sheet(
    t: &TableReader<'_>,
    base: &Path,
    items: &[BatchItem],
    template: &mut Template,
) -> Result<(), InputError> {
    let file = t.string(
        "file",
        "a DXF or SVG drawing of the sheet, relative to the batch file",
    )?;
    let sheet_name = t
        .optional_string("sheet", "\"prepreg\" or \"pyralux\"")?
        .unwrap_or("prepreg");
    let like = match sheet_name {
        "prepreg" => {
            if template.passive_cut == PassiveCut::PlyByPly {
                return Err(InputError::invalid(
                    t.file(),
                    &t.path("sheet"),
                    "\"prepreg\"",
                    format!(
                        "process {:?} cuts the prepreg ply by ply: a drawn sheet is of the laid-up stack or of Pyralux",
                        template.name
                    ),
                ));
            }
            let like = layup_item(t, items)?;
            Some(like)
        }
        "pyralux" if template.bond.is_some() => None,
        "pyralux" => {
            return Err(InputError::invalid(
                t.file(),
                &t.path("sheet"),
                "\"pyralux\"",
                format!("process {:?} has no Pyralux layer", template.name),
            ))
        }
        other => {
            return Err(InputError::invalid(
                t.file(),
                &t.path("sheet"),
                format!("{other:?}"),
                "expected \"prepreg\" or \"pyralux\" (PZT plates are laid out from a whole sheet's straight edges)",
            ))
        }
    };
    t.finish()?;
    let spec = match like {
        Some(_) => &mut template.passive,
        None => &mut template.bond.as_mut().expect("checked above").sheet,
    };
    if spec.roll {
        return Err(InputError::invalid(
            t.file(),
            &t.path("sheet"),
            format!("{sheet_name:?}"),
            "this material comes on a roll ([sheets] strip = true): drawn sheets are cut sheets",
        ));
    }
    let drawing = existing_file(t, "file", base, file, "no such drawing")?;
    let refuse =
        |why: String| InputError::invalid(t.file(), &t.path("file"), format!("{file:?}"), why);
    let mut parts = import(&drawing)?;
    if parts.len() != 1 {
        return Err(refuse(format!(
            "a drawn sheet is one outline with its keep-outs inside; the drawing has {} outlines side by side",
            parts.len()
        )));
    }
    let part = parts.remove(0);
    let b = Bounds::of(&part.outer);
    let (w, h) = (spec.width_mm, spec.height_mm);
    let on_sheet = b.min[0] >= -EXTENT_ROUNDING_MM
        && b.min[1] >= -EXTENT_ROUNDING_MM
        && b.max[0] <= w + EXTENT_ROUNDING_MM
        && b.max[1] <= h + EXTENT_ROUNDING_MM;
    if !on_sheet && (b.width() > w + EXTENT_ROUNDING_MM || b.height() > h + EXTENT_ROUNDING_MM) {
        return Err(refuse(format!(
            "the drawn sheet is {:.3} x {:.3} mm, larger than the {sheet_name} sheet ({w} x {h} mm) its files are drawn on: give [sheets] {sheet_name} a size that holds it",
            b.width(),
            b.height()
        )));
    }
    let shift = if on_sheet { [0.0, 0.0] } else { b.min };
    let moved = |ring: &[cam_geometry::Point]| -> Vec<cam_geometry::Point> {
        ring.iter()
            .map(|q| [q[0] - shift[0], q[1] - shift[1]])
            .collect()
    };
    spec.drawn.push(DrawnSheet {
        file: file.to_string(),
        like,
        shape: SheetShape {
            outline: moved(&part.outer),
            keep_outs: part.holes.iter().map(|k| moved(k)).collect(),
        },
    });
    Ok(())
}
