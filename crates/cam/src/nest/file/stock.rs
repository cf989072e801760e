//! A batch's `[[stock]]` tables: sheets given as drawings (a remnant an earlier run wrote, a sheet
//! with a flaw drawn round), read with the extra parts' drawing import: the one outline is the
//! stock, the contours inside it are keep-outs. A PZT sheet is a rectangle with no keep-out: plates
//! are laid out by score lines that run from edge to edge of straight edges (docs/cam.md §4).

use super::{existing_file, BatchItem};
use crate::input::limits::{MAX_PLIES, PLY_ANGLE_DEG, PZT_THICKNESS_MM};
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

/// The item of the batch whose PZT plates the stock's `pzt_thickness_mm` (and `pzt`, the material,
/// where two share a thickness) names.
fn pzt_item(t: &TableReader<'_>, items: &[BatchItem]) -> Result<usize, InputError> {
    let thickness_mm = t.number_in("pzt_thickness_mm", PZT_THICKNESS_MM)?;
    let material = t.optional_string("pzt", "the PZT material's name, as the designs give it")?;
    let same = |i: &BatchItem| {
        (i.design.pzt_thickness * 1e3 - thickness_mm).abs() < 1e-9
            && material.is_none_or(|m| i.design.pzt.name == m)
    };
    let stocks: Vec<String> = items
        .iter()
        .map(|i| format!("{} {} mm", i.design.pzt.name, i.design.pzt_thickness * 1e3))
        .collect();
    let refuse = |why: &str| {
        InputError::invalid(
            t.file(),
            &t.path("pzt_thickness_mm"),
            thickness_mm,
            format!("{why} ({})", stocks.join(", ")),
        )
    };
    let first = items
        .iter()
        .position(same)
        .ok_or_else(|| refuse("no design of the batch has these PZT plates; the batch's are"))?;
    let name = &items[first].design.pzt.name;
    if items
        .iter()
        .filter(|i| same(i))
        .any(|i| &i.design.pzt.name != name)
    {
        return Err(refuse(
            "designs of two PZT materials have plates this thick: name one with pzt = \"…\"",
        ));
    }
    Ok(first)
}

/// One `[[stock]]`: `file` (DXF or SVG), `sheet` (`"prepreg"`, the default, with `layup_deg`;
/// `"pyralux"`; or `"pzt"`, with `pzt_thickness_mm`), added to the template's sheet of that material. A drawing whose extent lies on the
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
        .optional_string("sheet", "\"prepreg\", \"pyralux\" or \"pzt\"")?
        .unwrap_or("prepreg");
    let (like, pzt) = match sheet_name {
        "pzt" => (Some(pzt_item(t, items)?), true),
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
            (Some(layup_item(t, items)?), false)
        }
        "pyralux" if template.bond.is_some() => (None, false),
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
                "expected \"prepreg\", \"pyralux\" or \"pzt\"",
            ))
        }
    };
    t.finish()?;
    let spec = match (like, pzt) {
        (_, true) => &mut template.pzt,
        (Some(_), false) => &mut template.passive,
        (None, false) => &mut template.bond.as_mut().expect("checked above").sheet,
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
    if pzt {
        if !part.holes.is_empty() {
            return Err(refuse(format!(
                "a PZT sheet has no keep-outs ({} drawn): score lines run from edge to edge, so snap the flawed part off and draw the rectangle left",
                part.holes.len()
            )));
        }
        if !is_rectangle(&part.outer, &b) {
            return Err(refuse(
                "a PZT sheet is a rectangle with straight, axis-aligned edges (the snapped remnant nest writes): the plates' score lines run from edge to edge of it".to_string(),
            ));
        }
    }
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

/// Whether `ring` is the rectangle `b` bounds: every vertex on a corner or along a side, and its
/// area the rectangle's (collinear points along a side allowed).
fn is_rectangle(ring: &[cam_geometry::Point], b: &Bounds) -> bool {
    let near = |x: f64, y: f64| (x - y).abs() <= EXTENT_ROUNDING_MM;
    let on_side = |q: &cam_geometry::Point| {
        near(q[0], b.min[0]) || near(q[0], b.max[0]) || near(q[1], b.min[1]) || near(q[1], b.max[1])
    };
    // An outline along the sides only, within the rounding of each side: its area is the box's.
    let area = cam_geometry::area(ring).abs();
    let slack = EXTENT_ROUNDING_MM * 2.0 * (b.width() + b.height());
    ring.iter().all(on_side) && (area - b.width() * b.height()).abs() <= slack
}
