//! Fields that name things rather than numbers, shared by several file kinds: a material from the
//! built-in library, a drive mode, and the drive field given directly or as a survival share.

use super::limits::{FIELD_V_PER_MM, SURVIVAL};
use super::{InputError, TableReader};
use actuator_model::material::builtin_names;
use actuator_model::{DriveMode, Material};
use std::path::Path;

/// The drive-mode names as the files spell them, for messages.
pub fn drive_mode_names() -> String {
    DriveMode::ALL
        .iter()
        .map(|m| m.name())
        .collect::<Vec<_>>()
        .join(", ")
}

/// A drive mode by its file name; `field` names where it was written.
pub fn drive_mode(file: &Path, field: &str, name: &str) -> Result<DriveMode, InputError> {
    DriveMode::from_name(name).ok_or_else(|| {
        InputError::invalid(
            file,
            field,
            format!("{name:?}"),
            format!("unknown drive mode; expected one of {}", drive_mode_names()),
        )
    })
}

/// The required `mode` of a `[drive]` table.
pub fn read_drive_mode(t: &TableReader<'_>) -> Result<DriveMode, InputError> {
    let name = t.string("mode", &format!("a drive mode: {}", drive_mode_names()))?;
    drive_mode(t.file(), &t.path("mode"), name)
}

fn library(file: &Path, field: &str, name: &str) -> Result<Material, InputError> {
    Material::builtin(name).ok_or_else(|| {
        InputError::invalid(
            file,
            field,
            format!("{name:?}"),
            format!(
                "unknown material; the library has {}",
                builtin_names().join(", ")
            ),
        )
    })
}

/// A piezoelectric material from the built-in library.
pub fn library_pzt(file: &Path, field: &str, name: &str) -> Result<Material, InputError> {
    let m = library(file, field, name)?;
    if m.is_piezoelectric() {
        Ok(m)
    } else {
        Err(InputError::invalid(
            file,
            field,
            format!("{name:?}"),
            "is not a piezoelectric material; use PZT-5H or PZT-5A",
        ))
    }
}

/// The `[laminate]` table of a spec (optimize, sweep): a library PZT and a library passive ply, with the
/// ply's thickness. The design file names its own materials instead (`design::materials`).
pub fn read_library_laminate(t: &TableReader<'_>) -> Result<(Material, Material, f64), InputError> {
    let pzt_name = t.string("pzt", "a PZT material name from the library")?;
    let pzt = library_pzt(t.file(), &t.path("pzt"), pzt_name)?;
    let ply_name = t.string("ply", "a passive ply material name from the library")?;
    let (ply, ply_thickness) = library_ply(t.file(), &t.path("ply"), ply_name)?;
    t.finish()?;
    Ok((pzt, ply, ply_thickness))
}

/// A passive ply from the built-in library, with its standard ply thickness (m).
pub fn library_ply(file: &Path, field: &str, name: &str) -> Result<(Material, f64), InputError> {
    let m = library(file, field, name)?;
    if m.is_piezoelectric() {
        return Err(InputError::invalid(
            file,
            field,
            format!("{name:?}"),
            "is a piezoelectric material, not a ply",
        ));
    }
    match m.ply_thickness {
        Some(t) => Ok((m, t)),
        None => Err(InputError::invalid(
            file,
            field,
            format!("{name:?}"),
            "has no standard ply thickness",
        )),
    }
}

/// Where the drive field came from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FieldSource {
    /// Given as `field_V_per_mm`.
    Given,
    /// From `survival` through the mode's Weibull fit; the share.
    Survival(f64),
}

/// The drive field of a `[drive]` table, V/m: `field_V_per_mm`, or the level a `survival` share
/// withstands in the mode's Weibull fit (thesis eq. 3.2, Table 4.12). Exactly one of the two.
pub fn read_drive_field(
    t: &TableReader<'_>,
    mode: DriveMode,
) -> Result<(f64, FieldSource), InputError> {
    let field = t.optional_number_in("field_V_per_mm", FIELD_V_PER_MM)?;
    let survival = t.optional_number_in("survival", SURVIVAL)?;
    match (field, survival) {
        (Some(e), Some(s)) => Err(InputError::invalid(
            t.file(),
            &t.prefix_or("drive"),
            format!("field_V_per_mm = {e} and survival = {s}"),
            "give exactly one of field_V_per_mm and survival",
        )),
        (None, None) => Err(t.missing_one_of(
            &["field_V_per_mm", "survival"],
            &format!("exactly one of field_V_per_mm ({FIELD_V_PER_MM}) and survival ({SURVIVAL})"),
        )),
        (Some(e), None) => Ok((e * 1e3, FieldSource::Given)),
        (None, Some(s)) => {
            let field = mode.field_limit().threshold(s).map_err(|e| {
                InputError::invalid(t.file(), &t.path("survival"), s, e.to_string())
            })?;
            if !FIELD_V_PER_MM.contains(field * 1e-3) {
                return Err(InputError::invalid(
                    t.file(),
                    &t.path("survival"),
                    s,
                    format!(
                        "gives a field of {} V/mm, outside the {FIELD_V_PER_MM}",
                        super::short_number(field * 1e-3)
                    ),
                ));
            }
            Ok((field, FieldSource::Survival(s)))
        }
    }
}
