//! Fields that name things rather than numbers, shared by several file kinds: a material from the
//! built-in library, a drive mode, and the drive field given directly or as a survival share.

use super::limits::{FIELD_V_PER_MM, SURVIVAL, VOLTAGE_V};
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

/// The bias field of a `[drive]` table, V/m: `bias_V_per_mm`, or `bias_V` over a PZT plate of
/// `pzt_thickness` (m) where the file fixes one. Required by the biased mode and refused by every other.
pub fn read_drive_bias(
    t: &TableReader<'_>,
    mode: DriveMode,
    pzt_thickness: Option<f64>,
) -> Result<f64, InputError> {
    let keys: &[&str] = if pzt_thickness.is_some() {
        &["bias_V_per_mm", "bias_V"]
    } else {
        &["bias_V_per_mm"]
    };
    if mode != DriveMode::Biased {
        if let Some(k) = keys.iter().find(|k| t.has(k)) {
            return Err(InputError::invalid(
                t.file(),
                &t.path(k),
                "(set)",
                format!(
                    "only mode = \"biased\" takes a bias; {} = \"{}\" does not",
                    t.path("mode"),
                    mode.name()
                ),
            ));
        }
        return Ok(0.0);
    }
    let field = t.optional_number_in("bias_V_per_mm", FIELD_V_PER_MM)?;
    let voltage = match pzt_thickness {
        Some(_) => t.optional_number_in("bias_V", VOLTAGE_V)?,
        None => None,
    };
    let bias = match (field, voltage, pzt_thickness) {
        (Some(e), None, _) => e * 1e3,
        (None, Some(v), Some(tp)) => v / tp,
        (Some(e), Some(v), _) => {
            return Err(InputError::invalid(
                t.file(),
                &t.prefix_or("drive"),
                format!("bias_V_per_mm = {e} and bias_V = {v}"),
                "give exactly one of bias_V_per_mm and bias_V",
            ))
        }
        // A plain "missing": the keys read after the bias (the signal's) are not misspellings of it.
        _ => {
            return Err(InputError::missing(
                t.file(),
                &t.path(keys[0]),
                &format!(
                    "the bias of mode = \"biased\": {} ({FIELD_V_PER_MM})",
                    keys.join(" or ")
                ),
            ))
        }
    };
    if !FIELD_V_PER_MM.contains(bias * 1e-3) {
        return Err(InputError::invalid(
            t.file(),
            &t.path("bias_V"),
            super::short_number(bias * pzt_thickness.unwrap_or(1e-3)),
            format!(
                "gives a bias field of {} V/mm, outside the {FIELD_V_PER_MM}",
                super::short_number(bias * 1e-3)
            ),
        ));
    }
    Ok(bias)
}

/// A biased drive's signal as the file wrote it: its key, its value, the factor from a field (V/m) to
/// that value's unit, and the unit.
pub struct BiasedSignal<'a> {
    pub key: &'a str,
    pub value: f64,
    pub per_field: f64,
    pub unit: &'a str,
}

impl BiasedSignal<'_> {
    /// Refuse a biased signal field above half the bias field (V/m), which would take it outside 0 to
    /// the bias (docs/physics.md §2.1), naming the key as written; other modes pass.
    pub fn check(
        &self,
        t: &TableReader<'_>,
        mode: DriveMode,
        field: f64,
        bias: f64,
    ) -> Result<(), InputError> {
        if mode != DriveMode::Biased || field <= 0.5 * bias * (1.0 + 1e-12) {
            return Ok(());
        }
        Err(InputError::invalid(
            t.file(),
            &t.path(self.key),
            super::short_number(self.value),
            format!(
                "the biased signal's amplitude is at most half the bias ({} {}), so that the signal stays between 0 and the bias",
                super::short_number(0.5 * bias * self.per_field),
                self.unit
            ),
        ))
    }
}

/// The drive field of a `[drive]` table, V/m: `field_V_per_mm`, or the level a `survival` share
/// withstands in the mode's Weibull fit (thesis eq. 3.2, Table 4.12; for the biased mode the signal
/// that takes the plates to it over the bias `bias`, V/m, and at most half the bias). Exactly one of
/// the two.
pub fn read_drive_field(
    t: &TableReader<'_>,
    mode: DriveMode,
    bias: f64,
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
        (Some(e), None) => {
            let signal = BiasedSignal {
                key: "field_V_per_mm",
                value: e,
                per_field: 1e-3,
                unit: "V/mm",
            };
            signal.check(t, mode, e * 1e3, bias)?;
            Ok((e * 1e3, FieldSource::Given))
        }
        (None, Some(s)) => {
            let open = actuator_model::Drive {
                mode,
                field: 0.0,
                bias,
            };
            let field = actuator_model::poling::FieldCheck::new(&open, s, f64::INFINITY)
                .map_err(|e| InputError::invalid(t.file(), &t.path("survival"), s, e.to_string()))?
                .max_signal;
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
