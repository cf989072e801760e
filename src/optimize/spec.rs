//! The optimization spec file: plain serde structs that mirror the TOML ([`RawSpec`]) and one conversion
//! that validates them into SI settings ([`Spec`]). Everything after [`Spec::from_file`] trusts its input.
//!
//! The helpers for the parts a sweep file shares (materials, drive) live here too and are reused by
//! [`crate::sweep`].

use actuator_model::material::builtin_names;
use actuator_model::{DriveMode, Material};
use serde::Deserialize;
use std::fmt::Display;
use std::path::Path;
use thiserror::Error;

/// A spec file that cannot be used. Every variant names the file; field errors also name the field, the
/// value as written and what is allowed.
#[derive(Debug, Error)]
pub enum SpecError {
    /// The file cannot be read.
    #[error("{file}: cannot read: {source}")]
    Read {
        /// Path as given.
        file: String,
        /// The I/O error.
        source: std::io::Error,
    },
    /// TOML syntax, a missing or unknown field, a wrong type.
    #[error("{file}: {message}")]
    Parse {
        /// Path as given.
        file: String,
        /// The parser's message (with line and column).
        message: String,
    },
    /// A field whose value is outside what the tool accepts.
    #[error("{file}: {field} = {value}: {reason}")]
    Field {
        /// Path as given.
        file: String,
        /// Dotted field name, `search.length_mm`.
        field: String,
        /// The value as written.
        value: String,
        /// What is wrong and what is allowed.
        reason: String,
    },
}

/// Read and deserialize a TOML file into raw structs.
pub(crate) fn read_toml<T: for<'de> Deserialize<'de>>(path: &Path) -> Result<T, SpecError> {
    let file = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|source| SpecError::Read {
        file: file.clone(),
        source,
    })?;
    toml::from_str(&text).map_err(|e| SpecError::Parse {
        file,
        message: e.to_string().trim_end().replace('\n', "\n  "),
    })
}

/// Builds [`SpecError::Field`] for one file.
#[derive(Debug, Clone)]
pub(crate) struct FieldErrors {
    file: String,
}

impl FieldErrors {
    pub(crate) fn new(path: &Path) -> Self {
        FieldErrors {
            file: path.display().to_string(),
        }
    }

    pub(crate) fn error(
        &self,
        field: &str,
        value: impl Display,
        reason: impl Display,
    ) -> SpecError {
        SpecError::Field {
            file: self.file.clone(),
            field: field.to_string(),
            value: value.to_string(),
            reason: reason.to_string(),
        }
    }

    /// A finite number inside `(lo, hi)` (or `[lo, hi)` when `lo_inclusive`); `allowed` describes it.
    pub(crate) fn number(
        &self,
        field: &str,
        value: f64,
        lo: f64,
        lo_inclusive: bool,
        hi: f64,
        allowed: &str,
    ) -> Result<f64, SpecError> {
        let above = if lo_inclusive {
            value >= lo
        } else {
            value > lo
        };
        if value.is_finite() && above && value < hi {
            Ok(value)
        } else {
            Err(self.error(field, value, format!("must be in {allowed}")))
        }
    }

    /// A PZT from the built-in library.
    pub(crate) fn pzt(&self, field: &str, name: &str) -> Result<Material, SpecError> {
        let m = self.material(field, name)?;
        if m.is_piezoelectric() {
            Ok(m)
        } else {
            Err(self.error(
                field,
                quoted(name),
                "is not a piezoelectric material; use PZT-5H or PZT-5A",
            ))
        }
    }

    /// A passive ply from the built-in library, with its standard ply thickness.
    pub(crate) fn ply(&self, field: &str, name: &str) -> Result<(Material, f64), SpecError> {
        let m = self.material(field, name)?;
        if m.is_piezoelectric() {
            return Err(self.error(
                field,
                quoted(name),
                "is a piezoelectric material, not a ply",
            ));
        }
        match m.ply_thickness {
            Some(t) => Ok((m, t)),
            None => Err(self.error(field, quoted(name), "has no standard ply thickness")),
        }
    }

    fn material(&self, field: &str, name: &str) -> Result<Material, SpecError> {
        Material::builtin(name).ok_or_else(|| {
            self.error(
                field,
                quoted(name),
                format!(
                    "unknown material; the library has {}",
                    builtin_names().join(", ")
                ),
            )
        })
    }

    /// A drive mode by its design-file name.
    pub(crate) fn drive_mode(&self, field: &str, name: &str) -> Result<DriveMode, SpecError> {
        DriveMode::from_name(name).ok_or_else(|| {
            let names: Vec<&str> = DriveMode::ALL.iter().map(|m| m.name()).collect();
            self.error(
                field,
                quoted(name),
                format!("unknown drive mode; use one of {}", names.join(", ")),
            )
        })
    }

    /// The drive field, V/m: given in V/mm, or the level a survival share withstands in the mode's
    /// Weibull fit (thesis eq. 3.2, Table 4.12). Exactly one of the two.
    pub(crate) fn field(
        &self,
        mode: DriveMode,
        field_v_per_mm: Option<f64>,
        survival: Option<f64>,
    ) -> Result<(f64, FieldSource), SpecError> {
        match (field_v_per_mm, survival) {
            (Some(_), Some(_)) => Err(self.error(
                "drive.field_V_per_mm / drive.survival",
                "both given",
                "give one of them",
            )),
            (None, None) => Err(self.error(
                "drive.field_V_per_mm / drive.survival",
                "missing",
                "give the field in V/mm or a survival share in (0, 1)",
            )),
            (Some(e), None) => Ok((
                self.number(
                    "drive.field_V_per_mm",
                    e,
                    0.0,
                    false,
                    f64::INFINITY,
                    "(0, inf) V/mm",
                )? * 1e3,
                FieldSource::Given,
            )),
            (None, Some(s)) => {
                let s = self.number("drive.survival", s, 0.0, false, 1.0, "(0, 1)")?;
                let field = mode
                    .field_limit()
                    .threshold(s)
                    .map_err(|e| self.error("drive.survival", s, e))?;
                Ok((field, FieldSource::Survival(s)))
            }
        }
    }

    /// A layup: a non-empty list of finite ply angles in degrees.
    pub(crate) fn layup(&self, field: &str, angles: &[f64]) -> Result<Vec<f64>, SpecError> {
        if angles.is_empty() {
            return Err(self.error(field, "[]", "a layup needs at least one ply"));
        }
        if angles.iter().any(|a| !a.is_finite()) {
            return Err(self.error(field, list(angles), "ply angles must be finite degrees"));
        }
        Ok(angles.to_vec())
    }
}

pub(crate) fn quoted(s: &str) -> String {
    format!("\"{s}\"")
}

/// A list as TOML writes it: `[40, 60]`.
pub(crate) fn list(values: &[f64]) -> String {
    let items: Vec<String> = values.iter().map(|v| v.to_string()).collect();
    format!("[{}]", items.join(", "))
}

/// Raw spec, as in the file.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawSpec {
    /// `[requirement]`.
    pub requirement: RawRequirement,
    /// `[drive]`.
    pub drive: RawDrive,
    /// `[search]`.
    pub search: RawSearch,
    /// `[laminate]`.
    pub laminate: RawLaminate,
    /// `[constraints]`, optional.
    #[serde(default)]
    pub constraints: RawConstraints,
}

/// `[requirement]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
pub struct RawRequirement {
    /// Minimum mechanical energy `U = ½ F_b δ`, mJ.
    pub energy_mJ: f64,
}

/// `[drive]`: mode and either a field or a survival share.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
pub struct RawDrive {
    /// `parallel`, `series`, `simultaneous`, `alternating`.
    pub mode: String,
    /// Peak plate field, V/mm.
    pub field_V_per_mm: Option<f64>,
    /// Survival share; the field comes from the mode's Weibull fit (thesis Table 4.12).
    pub survival: Option<f64>,
    /// Highest supply voltage, V.
    pub max_voltage_V: Option<f64>,
}

/// A continuous search variable: `[min, max]`, or one number for a fixed value.
#[derive(Debug, Clone, Deserialize)]
#[serde(untagged)]
pub enum RawRange {
    /// A fixed value.
    Fixed(f64),
    /// `[min, max]`.
    Span(Vec<f64>),
}

/// `[search]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawSearch {
    /// Total length range, mm.
    pub length_mm: RawRange,
    /// Base width range, mm.
    pub base_width_mm: RawRange,
    /// Extension ratio range.
    pub extension_ratio: RawRange,
    /// Width ratio range.
    pub width_ratio: RawRange,
    /// PZT plate thicknesses to try, mm.
    pub pzt_thickness_mm: Vec<f64>,
    /// Passive layups to try, degrees.
    pub layups_deg: Vec<Vec<f64>>,
    /// Points per continuous variable in the exhaustive stage.
    pub grid: i64,
}

/// `[laminate]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawLaminate {
    /// PZT material name.
    pub pzt: String,
    /// Passive ply material name.
    pub ply: String,
}

/// `[constraints]`.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawConstraints {
    /// Smallest tip width, mm.
    pub min_tip_width_mm: Option<f64>,
    /// Largest peak |strain| on a PZT surface in free deflection.
    pub max_peak_pzt_strain: Option<f64>,
}

/// A closed interval of one continuous search variable, SI; `lo == hi` fixes the variable.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Range {
    /// Lower bound.
    pub lo: f64,
    /// Upper bound.
    pub hi: f64,
}

impl Range {
    /// A fixed value.
    pub fn fixed(value: f64) -> Self {
        Range {
            lo: value,
            hi: value,
        }
    }

    /// True when the variable does not vary.
    pub fn is_fixed(&self) -> bool {
        self.lo == self.hi
    }

    /// `n` evenly spaced points from `lo` to `hi` inclusive (one point for a fixed variable).
    pub fn grid(&self, n: usize) -> Vec<f64> {
        if self.is_fixed() {
            return vec![self.lo];
        }
        (0..n)
            .map(|i| {
                if i + 1 == n {
                    self.hi
                } else {
                    self.lo + (self.hi - self.lo) * i as f64 / (n - 1) as f64
                }
            })
            .collect()
    }

    /// The point at fraction `u` in `[0, 1]`.
    pub fn at(&self, u: f64) -> f64 {
        if u >= 1.0 {
            self.hi
        } else {
            self.lo + (self.hi - self.lo) * u
        }
    }

    /// Fraction of the way from `lo` to `hi` (0 for a fixed variable).
    pub fn fraction(&self, x: f64) -> f64 {
        if self.is_fixed() {
            0.0
        } else {
            ((x - self.lo) / (self.hi - self.lo)).clamp(0.0, 1.0)
        }
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

/// The bounds of the four continuous planform variables, SI.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bounds {
    /// Total length `l_tot`, m.
    pub length: Range,
    /// Base width `w_0`, m.
    pub base_width: Range,
    /// Extension ratio `l_r`.
    pub extension_ratio: Range,
    /// Width ratio `w_r`.
    pub width_ratio: Range,
}

/// A validated spec, SI units.
#[derive(Debug, Clone)]
pub struct Spec {
    /// Minimum mechanical energy, J.
    pub energy: f64,
    /// Drive mode.
    pub mode: DriveMode,
    /// Requested peak plate field, V/m (before the voltage and strain limits).
    pub field: f64,
    /// How the field was given.
    pub field_source: FieldSource,
    /// Highest supply voltage, V.
    pub max_voltage: Option<f64>,
    /// Planform bounds.
    pub bounds: Bounds,
    /// PZT plate thicknesses, m.
    pub pzt_thicknesses: Vec<f64>,
    /// Passive layups, degrees.
    pub layups: Vec<Vec<f64>>,
    /// Points per continuous variable in the exhaustive stage.
    pub grid: usize,
    /// PZT material.
    pub pzt: Material,
    /// Passive ply material.
    pub ply: Material,
    /// Ply thickness from the library, m.
    pub ply_thickness: f64,
    /// Smallest tip width, m (0 when unconstrained).
    pub min_tip_width: f64,
    /// Largest peak PZT strain.
    pub max_peak_pzt_strain: Option<f64>,
}

/// Largest accepted `grid`: 500⁴ points per laminate is already hours of work.
pub const MAX_GRID: i64 = 500;

impl Spec {
    /// Read and validate a spec file.
    pub fn from_file(path: &Path) -> Result<Spec, SpecError> {
        let raw: RawSpec = read_toml(path)?;
        Spec::from_raw(&raw, path)
    }

    /// Validate raw input; `path` names the file in errors.
    pub fn from_raw(raw: &RawSpec, path: &Path) -> Result<Spec, SpecError> {
        let f = FieldErrors::new(path);
        let energy = f.number(
            "requirement.energy_mJ",
            raw.requirement.energy_mJ,
            0.0,
            false,
            f64::INFINITY,
            "(0, inf) mJ",
        )? * 1e-3;
        let mode = f.drive_mode("drive.mode", &raw.drive.mode)?;
        let (field, field_source) = f.field(mode, raw.drive.field_V_per_mm, raw.drive.survival)?;
        let max_voltage = raw
            .drive
            .max_voltage_V
            .map(|v| {
                f.number(
                    "drive.max_voltage_V",
                    v,
                    0.0,
                    false,
                    f64::INFINITY,
                    "(0, inf) V",
                )
            })
            .transpose()?;
        let s = &raw.search;
        let bounds = Bounds {
            length: range(
                &f,
                "search.length_mm",
                &s.length_mm,
                1e-3,
                (0.0, false),
                f64::INFINITY,
                "0 < min <= max mm",
            )?,
            base_width: range(
                &f,
                "search.base_width_mm",
                &s.base_width_mm,
                1e-3,
                (0.0, false),
                f64::INFINITY,
                "0 < min <= max mm",
            )?,
            extension_ratio: range(
                &f,
                "search.extension_ratio",
                &s.extension_ratio,
                1.0,
                (0.0, true),
                f64::INFINITY,
                "0 <= min <= max",
            )?,
            width_ratio: range(
                &f,
                "search.width_ratio",
                &s.width_ratio,
                1.0,
                (0.0, false),
                2.0,
                "0 < min <= max < 2",
            )?,
        };
        if s.pzt_thickness_mm.is_empty() {
            return Err(f.error(
                "search.pzt_thickness_mm",
                "[]",
                "list at least one thickness in mm",
            ));
        }
        let pzt_thicknesses = s
            .pzt_thickness_mm
            .iter()
            .map(|&t| {
                f.number(
                    "search.pzt_thickness_mm",
                    t,
                    0.0,
                    false,
                    f64::INFINITY,
                    "(0, inf) mm",
                )
                .map(|t| t * 1e-3)
            })
            .collect::<Result<Vec<f64>, SpecError>>()?;
        if s.layups_deg.is_empty() {
            return Err(f.error(
                "search.layups_deg",
                "[]",
                "list at least one layup, e.g. [[0, 90, 0]]",
            ));
        }
        let layups = s
            .layups_deg
            .iter()
            .map(|l| f.layup("search.layups_deg", l))
            .collect::<Result<Vec<_>, _>>()?;
        if !(2..=MAX_GRID).contains(&s.grid) {
            return Err(f.error(
                "search.grid",
                s.grid,
                format!("must be an integer in [2, {MAX_GRID}]"),
            ));
        }
        let pzt = f.pzt("laminate.pzt", &raw.laminate.pzt)?;
        let (ply, ply_thickness) = f.ply("laminate.ply", &raw.laminate.ply)?;
        let c = &raw.constraints;
        let min_tip_width = c
            .min_tip_width_mm
            .map(|w| {
                f.number(
                    "constraints.min_tip_width_mm",
                    w,
                    0.0,
                    true,
                    f64::INFINITY,
                    "[0, inf) mm",
                )
            })
            .transpose()?
            .unwrap_or(0.0)
            * 1e-3;
        let max_peak_pzt_strain = c
            .max_peak_pzt_strain
            .map(|e| {
                f.number(
                    "constraints.max_peak_pzt_strain",
                    e,
                    0.0,
                    false,
                    f64::INFINITY,
                    "(0, inf)",
                )
            })
            .transpose()?;
        let spec = Spec {
            energy,
            mode,
            field,
            field_source,
            max_voltage,
            bounds,
            pzt_thicknesses,
            layups,
            grid: s.grid as usize,
            pzt,
            ply,
            ply_thickness,
            min_tip_width,
            max_peak_pzt_strain,
        };
        spec.check_tip_width_reachable(&f, c.min_tip_width_mm.unwrap_or(0.0))?;
        Ok(spec)
    }

    /// The widest tip in the bounds is `w0_max (2 - w_r,min) / w_r,min`; a larger minimum admits nothing.
    fn check_tip_width_reachable(&self, f: &FieldErrors, written: f64) -> Result<(), SpecError> {
        let b = &self.bounds;
        let widest = b.base_width.hi * (2.0 - b.width_ratio.lo) / b.width_ratio.lo;
        if self.min_tip_width > widest {
            return Err(f.error(
                "constraints.min_tip_width_mm",
                written,
                format!(
                    "no design in the search ranges has so wide a tip (widest {} mm)",
                    fmt_sig(widest * 1e3)
                ),
            ));
        }
        Ok(())
    }
}

/// Validate `[min, max]` (or one number) and scale it to SI. `lo` bounds `min` (inclusive or not),
/// `hi` bounds `max` (exclusive).
fn range(
    f: &FieldErrors,
    field: &str,
    raw: &RawRange,
    scale: f64,
    lo: (f64, bool),
    hi: f64,
    allowed: &str,
) -> Result<Range, SpecError> {
    let (a, b, written) = match raw {
        RawRange::Fixed(v) => (*v, *v, v.to_string()),
        RawRange::Span(v) if v.len() == 2 => (v[0], v[1], list(v)),
        RawRange::Span(v) => {
            return Err(f.error(
                field,
                list(v),
                format!(
                    "give [min, max] (two numbers) or one number; allowed {allowed}{}",
                    if v.is_empty() {
                        " (the range is empty)"
                    } else {
                        ""
                    }
                ),
            ))
        }
    };
    let inside = |x: f64| x.is_finite() && (if lo.1 { x >= lo.0 } else { x > lo.0 }) && x < hi;
    if !(inside(a) && inside(b)) {
        return Err(f.error(field, written, format!("out of range; allowed {allowed}")));
    }
    if a > b {
        return Err(f.error(
            field,
            written,
            format!("inverted range: min > max; allowed {allowed}"),
        ));
    }
    Ok(Range {
        lo: a * scale,
        hi: b * scale,
    })
}

/// Six significant digits, fixed notation, for messages and reports.
pub(crate) fn fmt_sig(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let digits = 6 - 1 - x.abs().log10().floor() as i32;
    format!("{:.*}", digits.clamp(0, 12) as usize, x)
}

#[cfg(test)]
mod tests {
    use super::*;

    const EXAMPLE: &str = r#"
[requirement]
energy_mJ = 0.059
[drive]
mode = "parallel"
field_V_per_mm = 800
[search]
length_mm = [40, 60]
base_width_mm = [5, 20]
extension_ratio = [0, 1.5]
width_ratio = [1, 1.95]
pzt_thickness_mm = [0.127, 0.191, 0.267]
layups_deg = [[0, 90, 0], [0, 0, 90, 0, 0], [0, 0, 0, 90, 0, 0, 0]]
grid = 70
[laminate]
pzt = "PZT-5H"
ply = "CF-thesis"
[constraints]
min_tip_width_mm = 0.5
max_peak_pzt_strain = 0.0009
"#;

    fn parse(text: &str) -> Result<Spec, SpecError> {
        let raw: RawSpec = toml::from_str(text).map_err(|e| SpecError::Parse {
            file: "t.toml".into(),
            message: e.to_string(),
        })?;
        Spec::from_raw(&raw, Path::new("t.toml"))
    }

    #[test]
    fn the_issue_example_validates_into_si() {
        let s = parse(EXAMPLE).unwrap();
        assert!((s.energy - 0.059e-3).abs() < 1e-18);
        assert_eq!(
            s.bounds.length,
            Range {
                lo: 40e-3,
                hi: 60e-3
            }
        );
        assert_eq!(s.pzt_thicknesses.len(), 3);
        assert_eq!(s.grid, 70);
        assert!((s.ply_thickness - 61.8e-6).abs() < 1e-18);
        assert!((s.min_tip_width - 0.5e-3).abs() < 1e-18);
        assert_eq!(s.field, 800e3);
    }

    #[test]
    fn survival_gives_the_weibull_field() {
        // Source: thesis Table 4.12, parallel drive: 90% survive 833 V/mm.
        let text = EXAMPLE.replace("field_V_per_mm = 800", "survival = 0.9");
        let s = parse(&text).unwrap();
        assert!((s.field / 1e3 - 833.0).abs() < 1.0, "{}", s.field);
        assert_eq!(s.field_source, FieldSource::Survival(0.9));
    }

    #[test]
    fn bad_input_names_the_field_value_and_range() {
        let cases = [
            ("length_mm = [40, 60]", "length_mm = [60, 40]", "inverted"),
            ("length_mm = [40, 60]", "length_mm = []", "empty"),
            ("width_ratio = [1, 1.95]", "width_ratio = [1, 2.5]", "< 2"),
            ("grid = 70", "grid = 1", "[2, 500]"),
            (
                "ply = \"CF-thesis\"",
                "ply = \"unobtainium\"",
                "unknown material",
            ),
            (
                "pzt = \"PZT-5H\"",
                "pzt = \"CF-thesis\"",
                "not a piezoelectric",
            ),
            (
                "mode = \"parallel\"",
                "mode = \"sideways\"",
                "unknown drive mode",
            ),
            ("energy_mJ = 0.059", "energy_mJ = -1", "(0, inf) mJ"),
            ("min_tip_width_mm = 0.5", "min_tip_width_mm = 50", "widest"),
            (
                "layups_deg = [[0, 90, 0]",
                "layups_deg = [[]",
                "at least one ply",
            ),
        ];
        for (from, to, expect) in cases {
            let text = EXAMPLE.replace(from, to);
            assert_ne!(text, EXAMPLE, "{from}");
            let err = parse(&text).unwrap_err().to_string();
            assert!(err.starts_with("t.toml: "), "{err}");
            assert!(err.contains(expect), "{to}: {err}");
        }
    }

    #[test]
    fn fixed_variables_take_one_grid_point() {
        let r = Range::fixed(1.0);
        assert_eq!(r.grid(70), vec![1.0]);
        let g = Range { lo: 0.0, hi: 1.5 }.grid(4);
        assert_eq!(g, vec![0.0, 0.5, 1.0, 1.5]);
    }
}
