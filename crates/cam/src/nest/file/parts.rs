//! A batch's `[[part]]` tables: the parts of a drawing, each on the sheet it is cut from (the
//! prepreg of a design of the batch, or the Pyralux), at its rotations, checked to fit that sheet.

use super::{existing_file, BatchItem};
use crate::input::limits::{MAX_PLIES, MAX_QUANTITY, PART_ROTATION_DEG, PLY_ANGLE_DEG};
use crate::input::{InputError, TableReader};
use crate::parts::{import, ImportedPart, PartOrder, PartSheet};
use crate::process::template::{PassiveCut, SheetSpec};
use std::path::Path;

/// Ply-by-ply cutting cuts each ply of a prepreg part on its own sheet, and the lab stacks any piece
/// of ply 1 on any piece of ply 2: the pieces come out in the layup only if every rotation the part
/// may take leaves the fibres where they were, that is if the rotations differ by half turns (fibres
/// have an axis, not a sense). A quarter turn allowed beside 0° would let one ply's pieces come out
/// with their fibres turned and another's not.
fn one_fibre_direction(
    t: &TableReader<'_>,
    rotations_deg: &[f64],
    process: &str,
) -> Result<(), InputError> {
    let first = rotations_deg[0];
    if rotations_deg
        .iter()
        .all(|r| ((r - first).rem_euclid(180.0)).min(180.0 - (r - first).rem_euclid(180.0)) < 1e-9)
    {
        return Ok(());
    }
    Err(InputError::invalid(
        t.file(),
        &t.path("rotations_deg"),
        format!("{rotations_deg:?}"),
        format!(
            "process {process:?} cuts the prepreg ply by ply, so the rotations of a prepreg part must keep its fibre direction: all equal modulo 180 degrees (e.g. [0, 180])"
        ),
    ))
}

/// One `[[part]]`: a drawing's parts, how many of each, on which sheets, at which rotations.
pub(super) fn part_orders(
    t: &TableReader<'_>,
    base: &Path,
    items: &[BatchItem],
    template: &crate::process::Template,
) -> Result<Vec<PartOrder>, InputError> {
    let file = t.string("file", "a DXF or SVG drawing, relative to the batch file")?;
    let quantity = t.count("quantity", 1, MAX_QUANTITY)?;
    let sheet_name = t
        .optional_string("sheet", "\"prepreg\" or \"pyralux\"")?
        .unwrap_or("prepreg");
    let (sheet, spec, default_rotations) = part_sheet(t, sheet_name, items, template)?;
    let rotations_deg = t
        .optional_numbers_in("rotations_deg", PART_ROTATION_DEG, 1, 360)?
        .unwrap_or(default_rotations);
    // The turn of each sheet the part is cut from: none on the laid-up stack, -θ on the sheet of a
    // ply at θ (ply-by-ply cutting, as the actuators' plies).
    let by_ply =
        matches!(sheet, PartSheet::Prepreg { .. }) && template.passive_cut == PassiveCut::PlyByPly;
    let ply_turns_deg: Vec<f64> = match &sheet {
        PartSheet::Prepreg { layup_deg, .. } if by_ply => {
            one_fibre_direction(t, &rotations_deg, &template.name)?;
            layup_deg.iter().map(|a| -a).collect()
        }
        _ => vec![0.0],
    };
    // The sheet's fibres run along its y axis; the part's fibre axis is turned onto it, and its
    // rotations (half turns by default) come on top.
    let fibre_turn_deg = match &sheet {
        PartSheet::Prepreg { fibre_axis_deg, .. } => 90.0 - fibre_axis_deg,
        PartSheet::Pyralux | PartSheet::Own(_) => 0.0,
    };
    let name = t.optional_string("name", "a part name (text)")?;
    t.finish()?;
    let drawing = existing_file(t, "file", base, file, "no such drawing")?;
    let imported = import(&drawing)?;
    let stem = name.map(str::to_string).unwrap_or_else(|| {
        drawing
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "part".into())
    });
    let several = imported.len() > 1;
    let fit = PartFit {
        drawing: &drawing,
        sheet_name,
        spec: &spec,
        rotations_deg: &rotations_deg,
        ply_turns_deg: &ply_turns_deg,
        by_ply,
    };
    imported
        .into_iter()
        .enumerate()
        .map(|(k, part)| {
            let part = part.turned(fibre_turn_deg).at_base_point();
            fit.check(&part)?;
            Ok(PartOrder {
                name: if several {
                    format!("{stem}-{}", k + 1)
                } else {
                    stem.clone()
                },
                part,
                quantity,
                rotations_deg: rotations_deg.clone(),
                sheet: sheet.clone(),
                pin_holes: Vec::new(),
                bonded_zone: None,
                labels: Vec::new(),
            })
        })
        .collect()
}

/// The sheet a `[[part]]` is cut from (`sheet`, with `layup_deg` and `fibre_axis_deg` on prepreg),
/// the sheet's size and the part's rotations when the batch gives none.
fn part_sheet(
    t: &TableReader<'_>,
    sheet_name: &str,
    items: &[BatchItem],
    template: &crate::process::Template,
) -> Result<(PartSheet, SheetSpec, Vec<f64>), InputError> {
    let path = t.file();
    match sheet_name {
        "prepreg" => Ok((
            prepreg_sheet(t, items)?,
            template.passive.clone(),
            // Fibre direction matters: only half turns keep it.
            vec![0.0, 180.0],
        )),
        "pyralux" if t.has("fibre_axis_deg") => Err(InputError::invalid(
            path,
            &t.path("fibre_axis_deg"),
            "(given)",
            "a Pyralux part has no fibres: fibre_axis_deg is for prepreg parts",
        )),
        "pyralux" => match &template.bond {
            Some(b) => Ok((
                PartSheet::Pyralux,
                b.sheet.clone(),
                vec![0.0, 90.0, 180.0, 270.0],
            )),
            None => Err(InputError::invalid(
                path,
                &t.path("sheet"),
                "\"pyralux\"",
                format!("process {:?} has no Pyralux layer", template.name),
            )),
        },
        other => Err(InputError::invalid(
            path,
            &t.path("sheet"),
            format!("{other:?}"),
            "expected \"prepreg\" or \"pyralux\" (PZT plates are scored, not cut to shape)",
        )),
    }
}

/// A prepreg part's sheet: the laid-up stack of the one design of the batch with the part's
/// `layup_deg`, and the part's `fibre_axis_deg`.
fn prepreg_sheet(t: &TableReader<'_>, items: &[BatchItem]) -> Result<PartSheet, InputError> {
    let path = t.file();
    let layup_deg = t.numbers_in("layup_deg", PLY_ANGLE_DEG, 1, MAX_PLIES)?;
    let layups: Vec<String> = items.iter().map(|i| i.design.layup_text()).collect();
    let like = items
        .iter()
        .position(|i| i.design.layup_deg == layup_deg)
        .ok_or_else(|| {
            InputError::invalid(
                path,
                &t.path("layup_deg"),
                format!("{layup_deg:?}"),
                format!(
                    "no design of the batch has this layup, so there is no such prepreg sheet; the batch's layups: {}",
                    layups.join(", ")
                ),
            )
        })?;
    let d = &items[like].design;
    if let Some(other) = items.iter().find(|i| {
        i.design.layup_deg == layup_deg
            && (i.design.ply.name != d.ply.name || i.design.ply_thickness != d.ply_thickness)
    }) {
        return Err(InputError::invalid(
            path,
            &t.path("layup_deg"),
            format!("{layup_deg:?}"),
            format!(
                "two prepreg sheets have this layup ({} and {}, of different plies): the part's sheet is ambiguous",
                d.name, other.design.name
            ),
        ));
    }
    let fibre_axis_deg = t.number_in("fibre_axis_deg", PART_ROTATION_DEG)?;
    Ok(PartSheet::Prepreg {
        layup_deg,
        like,
        fibre_axis_deg,
    })
}

/// The sheet a drawing's parts must fit on, empty, at one of their rotations on every ply's turn.
struct PartFit<'a> {
    drawing: &'a Path,
    sheet_name: &'a str,
    spec: &'a SheetSpec,
    rotations_deg: &'a [f64],
    ply_turns_deg: &'a [f64],
    by_ply: bool,
}

impl PartFit<'_> {
    /// The nester's own check, refused here naming the entity.
    fn check(&self, part: &ImportedPart) -> Result<(), InputError> {
        let spec = self.spec;
        let sheet_name = self.sheet_name;
        for (ply, turn) in self.ply_turns_deg.iter().enumerate() {
            let turned: Vec<f64> = self.rotations_deg.iter().map(|r| r + turn).collect();
            let fit = spec.empty_sheet_fit(&part.outer, &turned);
            if fit.fits {
                continue;
            }
            let size = fit.size_mm;
            let sheet = if spec.roll {
                format!("the {sheet_name} roll ({} mm wide)", spec.width_mm)
            } else {
                format!(
                    "the {sheet_name} sheet ({} x {} mm)",
                    spec.width_mm, spec.height_mm
                )
            };
            return Err(crate::parts::entity_error(
                self.drawing,
                &part.entity,
                format!(
                    "part too large: {:.3} x {:.3} mm at its best allowed rotation{} does not fit {sheet} with {} mm (kerf + edge gap) to every edge ({:.3} mm with the nester's working margin)",
                    size[0],
                    size[1],
                    if self.by_ply {
                        format!(" for ply {} (turned by {turn} deg to its fibre angle)", ply + 1)
                    } else {
                        String::new()
                    },
                    spec.kerf_mm + spec.edge_gap(),
                    fit.edge_gap_mm
                ),
            ));
        }
        Ok(())
    }
}
