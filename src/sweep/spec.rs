//! The sweep's factors file: raw serde structs and their validation into SI levels.

use crate::optimize::report::decimal;
use crate::optimize::spec::{list, read_toml, FieldErrors, FieldSource, RawLaminate, SpecError};
use actuator_model::{DriveMode, Material};
use serde::Deserialize;
use std::path::Path;

/// Raw factors file.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawSweep {
    /// `[laminate]`: the materials.
    pub laminate: RawLaminate,
    /// `[drive]`: mode and field, the same for every design.
    pub drive: RawSweepDrive,
    /// `[factors]`: the levels of each factor.
    pub factors: RawFactors,
}

/// `[drive]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
pub struct RawSweepDrive {
    /// Drive mode.
    pub mode: String,
    /// Peak plate field, V/mm.
    pub field_V_per_mm: Option<f64>,
    /// Or a survival share (field from the Weibull fit).
    pub survival: Option<f64>,
}

/// `[factors]`: lists of levels. The geometry and laminate factors are required; `extension_ratio` and
/// `width_ratio` default to a rectangle, the PZT property factors to the library values.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
pub struct RawFactors {
    /// PZT Young's modulus levels, GPa (thesis Table 3.1).
    pub pzt_modulus_GPa: Option<Vec<f64>>,
    /// PZT |d31| levels, pm/V (thesis Table 3.1); the sign of the library material is kept.
    pub pzt_d31_pm_per_V: Option<Vec<f64>>,
    /// PZT plate thickness levels, mm.
    pub pzt_thickness_mm: Vec<f64>,
    /// Passive layup levels, degrees.
    pub layups_deg: Vec<Vec<f64>>,
    /// Total length levels, mm.
    pub length_mm: Vec<f64>,
    /// Extension ratio levels.
    pub extension_ratio: Option<Vec<f64>>,
    /// Base width levels, mm.
    pub base_width_mm: Vec<f64>,
    /// Width ratio levels.
    pub width_ratio: Option<Vec<f64>>,
}

/// One factor of the sweep.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Factor {
    /// PZT Young's modulus.
    PztModulus,
    /// PZT |d31|.
    PztD31,
    /// PZT plate thickness.
    PztThickness,
    /// Passive layup (ordered by ply count).
    Layup,
    /// Total length.
    Length,
    /// Extension ratio.
    ExtensionRatio,
    /// Base width.
    BaseWidth,
    /// Width ratio.
    WidthRatio,
}

impl Factor {
    /// All factors, outermost (laminate) first: the design order of the sweep.
    pub const ALL: [Factor; 8] = [
        Factor::PztModulus,
        Factor::PztD31,
        Factor::PztThickness,
        Factor::Layup,
        Factor::Length,
        Factor::ExtensionRatio,
        Factor::BaseWidth,
        Factor::WidthRatio,
    ];

    /// Name as in the factors file and the CSV.
    pub fn name(self) -> &'static str {
        match self {
            Factor::PztModulus => "pzt_modulus_GPa",
            Factor::PztD31 => "pzt_d31_pm_per_V",
            Factor::PztThickness => "pzt_thickness_mm",
            Factor::Layup => "layups_deg",
            Factor::Length => "length_mm",
            Factor::ExtensionRatio => "extension_ratio",
            Factor::BaseWidth => "base_width_mm",
            Factor::WidthRatio => "width_ratio",
        }
    }
}

/// A validated sweep, SI levels.
#[derive(Debug, Clone)]
pub struct SweepSpec {
    /// PZT material (library values; modulus and d31 levels override them per design).
    pub pzt: Material,
    /// Passive ply.
    pub ply: Material,
    /// Ply thickness from the library, m.
    pub ply_thickness: f64,
    /// Drive mode.
    pub mode: DriveMode,
    /// Peak plate field, V/m.
    pub field: f64,
    /// How the field was given.
    pub field_source: FieldSource,
    /// PZT modulus levels, Pa.
    pub pzt_modulus: Vec<f64>,
    /// PZT d31 levels, m/V, signed as the library material.
    pub pzt_d31: Vec<f64>,
    /// PZT thickness levels, m.
    pub pzt_thickness: Vec<f64>,
    /// Layup levels, degrees.
    pub layups: Vec<Vec<f64>>,
    /// Total length levels, m.
    pub length: Vec<f64>,
    /// Extension ratio levels.
    pub extension_ratio: Vec<f64>,
    /// Base width levels, m.
    pub base_width: Vec<f64>,
    /// Width ratio levels.
    pub width_ratio: Vec<f64>,
}

/// Largest accepted sweep: every design is kept in memory and written to the CSV.
pub const MAX_DESIGNS: usize = 10_000_000;

impl SweepSpec {
    /// Read and validate a factors file.
    pub fn from_file(path: &Path) -> Result<SweepSpec, SpecError> {
        let raw: RawSweep = read_toml(path)?;
        SweepSpec::from_raw(&raw, path)
    }

    /// Validate raw input; `path` names the file in errors.
    pub fn from_raw(raw: &RawSweep, path: &Path) -> Result<SweepSpec, SpecError> {
        let f = FieldErrors::new(path);
        let pzt = f.pzt("laminate.pzt", &raw.laminate.pzt)?;
        let (ply, ply_thickness) = f.ply("laminate.ply", &raw.laminate.ply)?;
        let mode = f.drive_mode("drive.mode", &raw.drive.mode)?;
        let (field, field_source) = f.field(mode, raw.drive.field_V_per_mm, raw.drive.survival)?;
        let r = &raw.factors;
        let positive = (0.0, false, f64::INFINITY);
        let pzt_modulus = match &r.pzt_modulus_GPa {
            Some(v) => levels(
                &f,
                "factors.pzt_modulus_GPa",
                v,
                positive,
                "(0, inf) GPa",
                1e9,
            )?,
            None => vec![pzt.e1],
        };
        let sign = pzt.d31.signum();
        let pzt_d31 = match &r.pzt_d31_pm_per_V {
            Some(v) => levels(
                &f,
                "factors.pzt_d31_pm_per_V",
                v,
                positive,
                "(0, inf) pm/V",
                1e-12,
            )?
            .into_iter()
            .map(|d| sign * d)
            .collect(),
            None => vec![pzt.d31],
        };
        if r.layups_deg.is_empty() {
            return Err(f.error(
                "factors.layups_deg",
                "[]",
                "list at least one layup, e.g. [[0, 90, 0]]",
            ));
        }
        let layups = r
            .layups_deg
            .iter()
            .map(|l| f.layup("factors.layups_deg", l))
            .collect::<Result<Vec<_>, _>>()?;
        let spec = SweepSpec {
            ply_thickness,
            mode,
            field,
            field_source,
            pzt_modulus,
            pzt_d31,
            pzt_thickness: levels(
                &f,
                "factors.pzt_thickness_mm",
                &r.pzt_thickness_mm,
                positive,
                "(0, inf) mm",
                1e-3,
            )?,
            layups,
            length: levels(
                &f,
                "factors.length_mm",
                &r.length_mm,
                positive,
                "(0, inf) mm",
                1e-3,
            )?,
            extension_ratio: match &r.extension_ratio {
                Some(v) => levels(
                    &f,
                    "factors.extension_ratio",
                    v,
                    (0.0, true, f64::INFINITY),
                    "[0, inf)",
                    1.0,
                )?,
                None => vec![0.0],
            },
            base_width: levels(
                &f,
                "factors.base_width_mm",
                &r.base_width_mm,
                positive,
                "(0, inf) mm",
                1e-3,
            )?,
            width_ratio: match &r.width_ratio {
                Some(v) => levels(
                    &f,
                    "factors.width_ratio",
                    v,
                    (0.0, false, 2.0),
                    "(0, 2)",
                    1.0,
                )?,
                None => vec![1.0],
            },
            pzt,
            ply,
        };
        let count = spec.count();
        if count > MAX_DESIGNS {
            return Err(f.error(
                "factors",
                format!("{count} designs"),
                format!("a sweep may have at most {MAX_DESIGNS} designs"),
            ));
        }
        Ok(spec)
    }

    /// Number of levels of a factor.
    pub fn level_count(&self, factor: Factor) -> usize {
        match factor {
            Factor::PztModulus => self.pzt_modulus.len(),
            Factor::PztD31 => self.pzt_d31.len(),
            Factor::PztThickness => self.pzt_thickness.len(),
            Factor::Layup => self.layups.len(),
            Factor::Length => self.length.len(),
            Factor::ExtensionRatio => self.extension_ratio.len(),
            Factor::BaseWidth => self.base_width.len(),
            Factor::WidthRatio => self.width_ratio.len(),
        }
    }

    /// The value that orders a factor's levels, in file units (layups: their ply count).
    pub fn level_value(&self, factor: Factor, level: usize) -> f64 {
        match factor {
            Factor::PztModulus => self.pzt_modulus[level] * 1e-9,
            Factor::PztD31 => self.pzt_d31[level].abs() * 1e12,
            Factor::PztThickness => self.pzt_thickness[level] * 1e3,
            Factor::Layup => self.layups[level].len() as f64,
            Factor::Length => self.length[level] * 1e3,
            Factor::ExtensionRatio => self.extension_ratio[level],
            Factor::BaseWidth => self.base_width[level] * 1e3,
            Factor::WidthRatio => self.width_ratio[level],
        }
    }

    /// A level as written in reports and the CSV.
    pub fn level_label(&self, factor: Factor, level: usize) -> String {
        match factor {
            Factor::Layup => crate::optimize::report::layup_label(&self.layups[level]),
            _ => decimal(self.level_value(factor, level), 9),
        }
    }

    /// Number of designs: the product of the level counts.
    pub fn count(&self) -> usize {
        Factor::ALL.iter().map(|f| self.level_count(*f)).product()
    }
}

/// A non-empty list of levels inside `(lo, hi)` (`[lo, hi)` when inclusive), scaled to SI.
fn levels(
    f: &FieldErrors,
    field: &str,
    values: &[f64],
    (lo, lo_inclusive, hi): (f64, bool, f64),
    allowed: &str,
    scale: f64,
) -> Result<Vec<f64>, SpecError> {
    if values.is_empty() {
        return Err(f.error(field, "[]", "list at least one level"));
    }
    for &v in values {
        let above = if lo_inclusive { v >= lo } else { v > lo };
        if !(v.is_finite() && above && v < hi) {
            return Err(f.error(
                field,
                list(values),
                format!("level {v} is outside {allowed}"),
            ));
        }
    }
    Ok(values.iter().map(|v| v * scale).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<SweepSpec, SpecError> {
        let raw: RawSweep = toml::from_str(text).map_err(|e| SpecError::Parse {
            file: "s.toml".into(),
            message: e.to_string(),
        })?;
        SweepSpec::from_raw(&raw, Path::new("s.toml"))
    }

    const TABLE_3_1: &str = r#"
[laminate]
pzt = "PZT-5H"
ply = "CF-thesis"
[drive]
mode = "parallel"
field_V_per_mm = 800
[factors]
pzt_modulus_GPa = [80, 76, 59]
pzt_d31_pm_per_V = [400, 320, 90]
length_mm = [75, 50, 25]
base_width_mm = [7.5, 5, 2.5]
pzt_thickness_mm = [0.267, 0.191, 0.127]
layups_deg = [[0, 90, 0], [0, 0, 90, 0, 0], [0, 0, 0, 90, 0, 0, 0]]
"#;

    #[test]
    fn table_3_1_has_729_rectangular_designs() {
        let s = parse(TABLE_3_1).unwrap();
        assert_eq!(s.count(), 729);
        assert_eq!(s.extension_ratio, vec![0.0]);
        assert_eq!(s.width_ratio, vec![1.0]);
        // d31 keeps the library's (negative) sign.
        assert!(s.pzt_d31.iter().all(|d| *d < 0.0));
        assert!((s.pzt_modulus[0] - 80e9).abs() < 1.0);
        assert_eq!(s.level_label(Factor::Layup, 1), "[0/0/90/0/0]");
    }

    #[test]
    fn bad_levels_name_the_field() {
        for (from, to, expect) in [
            (
                "length_mm = [75, 50, 25]",
                "length_mm = []",
                "factors.length_mm",
            ),
            (
                "base_width_mm = [7.5, 5, 2.5]",
                "base_width_mm = [7.5, -5]",
                "-5",
            ),
            ("ply = \"CF-thesis\"", "ply = \"balsa\"", "unknown material"),
        ] {
            let err = parse(&TABLE_3_1.replace(from, to)).unwrap_err().to_string();
            assert!(err.contains(expect) && err.starts_with("s.toml"), "{err}");
        }
    }
}
