//! The sweep's factors file: one validating conversion ([`SweepSpec::from_table`]) from the parsed TOML
//! into SI levels, through the checked reader and the shared field ranges of [`crate::input`].

use crate::design::check_planform;
use crate::input::library::{
    read_drive_bias, read_drive_field, read_drive_mode, read_library_laminate,
};
use crate::input::limits::{
    BASE_WIDTH_MM, D31_MAGNITUDE_PM_PER_V, EXTENSION_RATIO, LENGTH_MM, MAX_DESIGNS, MAX_LEVELS,
    MAX_PLIES, MODULUS_GPA, PLY_ANGLE_DEG, PZT_THICKNESS_MM, WIDTH_RATIO,
};
use crate::input::{read_toml, FieldSource, InputError, Range, TableReader};
use crate::optimize::report::decimal;
use actuator_model::{DriveMode, Material, Planform};
use std::path::Path;

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
    /// The biased mode's bias field, V/m (0 for the other modes).
    pub bias: f64,
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

impl SweepSpec {
    /// Read and validate a factors file.
    pub fn from_file(path: &Path) -> Result<SweepSpec, InputError> {
        let table = read_toml(path)?;
        SweepSpec::from_table(path, &table)
    }

    /// Validate a parsed factors file; `path` names the file in errors. The geometry and laminate
    /// factors are required; `extension_ratio` and `width_ratio` default to a rectangle, the PZT
    /// property factors to the library values.
    pub fn from_table(path: &Path, table: &toml::Table) -> Result<SweepSpec, InputError> {
        let root = TableReader::new(path, "", table);
        root.only_keys(&["laminate", "drive", "factors"])?;

        let l = root.table("laminate")?;
        let (pzt, ply, ply_thickness) = read_library_laminate(&l)?;

        let d = root.table("drive")?;
        let mode = read_drive_mode(&d)?;
        let bias = read_drive_bias(&d, mode, None)?;
        let (field, field_source) = read_drive_field(&d, mode, bias)?;
        d.finish()?;

        let f = root.table("factors")?;
        let levels = |key: &str, allowed: Range, scale: f64| {
            f.numbers_in(key, allowed, 1, MAX_LEVELS)
                .map(|v| scaled(&v, scale))
        };
        let optional_levels = |key: &str, allowed: Range, scale: f64| {
            f.optional_numbers_in(key, allowed, 1, MAX_LEVELS)
                .map(|v| v.map(|v| scaled(&v, scale)))
        };
        let pzt_modulus =
            optional_levels("pzt_modulus_GPa", MODULUS_GPA, 1e9)?.unwrap_or_else(|| vec![pzt.e1]);
        let sign = pzt.d31.signum();
        let pzt_d31 = match optional_levels("pzt_d31_pm_per_V", D31_MAGNITUDE_PM_PER_V, 1e-12)? {
            Some(v) => v.into_iter().map(|d| sign * d).collect(),
            None => vec![pzt.d31],
        };
        let spec = SweepSpec {
            ply_thickness,
            mode,
            field,
            field_source,
            bias,
            pzt_modulus,
            pzt_d31,
            pzt_thickness: levels("pzt_thickness_mm", PZT_THICKNESS_MM, 1e-3)?,
            layups: f.number_lists_in("layups_deg", PLY_ANGLE_DEG, (1, MAX_LEVELS), MAX_PLIES)?,
            length: levels("length_mm", LENGTH_MM, 1e-3)?,
            extension_ratio: optional_levels("extension_ratio", EXTENSION_RATIO, 1.0)?
                .unwrap_or_else(|| vec![0.0]),
            base_width: levels("base_width_mm", BASE_WIDTH_MM, 1e-3)?,
            width_ratio: optional_levels("width_ratio", WIDTH_RATIO, 1.0)?
                .unwrap_or_else(|| vec![1.0]),
            pzt,
            ply,
        };
        f.finish()?;
        root.finish()?;
        spec.refuse_repeated_levels(path)?;
        spec.check_smallest_features(path)?;
        let count = spec.count();
        if count > MAX_DESIGNS {
            return Err(InputError::invalid(
                path,
                "factors",
                format!("{count} designs"),
                format!("a sweep may have at most {MAX_DESIGNS} designs"),
            ));
        }
        Ok(spec)
    }

    /// A level listed twice would count every design of it twice in the main effects: refuse it, naming
    /// the factor and the repeated level as written.
    fn refuse_repeated_levels(&self, path: &Path) -> Result<(), InputError> {
        for factor in Factor::ALL {
            let labels: Vec<String> = (0..self.level_count(factor))
                .map(|i| self.level_label(factor, i))
                .collect();
            for (i, label) in labels.iter().enumerate() {
                if labels[..i].contains(label) {
                    return Err(InputError::invalid(
                        path,
                        &format!("factors.{}", factor.name()),
                        format!("[{}]", labels.join(", ")),
                        format!("level {label} is listed twice; list each level once"),
                    ));
                }
            }
        }
        Ok(())
    }

    /// Every design of the sweep is one a lab could build (`docs/limits.md` §1): the shortest PZT plate
    /// (shortest length, longest extension) and the narrowest tip (narrowest base, largest width ratio)
    /// pass the design file's derived-geometry check. The error names `factors.*` and the levels.
    fn check_smallest_features(&self, path: &Path) -> Result<(), InputError> {
        let min = |v: &[f64]| v.iter().copied().fold(f64::INFINITY, f64::min);
        let max = |v: &[f64]| v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let worst = |length: f64, l_r: f64, w0: f64, w_r: f64| {
            Planform::new(length, l_r, w0, w_r, 0.0)
                .map_err(|e| InputError::invalid(path, "factors", "(levels)", e.to_string()))
                .and_then(|p| check_planform(path, "factors", &p))
        };
        let (l_r, w_r) = (max(&self.extension_ratio), max(&self.width_ratio));
        worst(min(&self.length), l_r, max(&self.base_width), 1.0)?;
        worst(max(&self.length), 0.0, min(&self.base_width), w_r)
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

/// Levels in file units scaled to SI.
fn scaled(values: &[f64], scale: f64) -> Vec<f64> {
    values.iter().map(|v| v * scale).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<SweepSpec, InputError> {
        let path = Path::new("s.toml");
        SweepSpec::from_table(path, &crate::input::parse_toml(path, text)?)
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
            (
                "length_mm = [75, 50, 25]",
                "length_mm = [50, 50]",
                "s.toml: factors.length_mm = [50, 50]: level 50 is listed twice",
            ),
            (
                "layups_deg = [[0, 90, 0],",
                "layups_deg = [[0, 0, 90, 0, 0],",
                "s.toml: factors.layups_deg = [[0/0/90/0/0], [0/0/90/0/0], [0/0/0/90/0/0/0]]: level [0/0/90/0/0] is listed twice",
            ),
            (
                "base_width_mm = [7.5, 5, 2.5]",
                "base_width_mm = [7.5, 5, 2.5]\nwidth_ratio = [1, 1.95]",
                "s.toml: factors.width_ratio = length_mm = 75, extension_ratio = 0, base_width_mm = 2.5, \
                 width_ratio = 1.95: the tip width",
            ),
            (
                "length_mm = [75, 50, 25]",
                "length_mm = [75, 50, 2]\nextension_ratio = [0, 2]",
                "s.toml: factors.length_mm = length_mm = 2, extension_ratio = 2, base_width_mm = 7.5, \
                 width_ratio = 1: the PZT plate",
            ),
            (
                "length_mm = [75, 50, 25]",
                "length_mm = [1e300]",
                "s.toml: factors.length_mm[0] = 1e300: outside the allowed range [1, 1000] mm",
            ),
        ] {
            let err = parse(&TABLE_3_1.replace(from, to)).unwrap_err().to_string();
            assert!(err.contains(expect) && err.starts_with("s.toml"), "{err}");
        }
    }
}
