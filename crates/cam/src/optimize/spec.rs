//! The optimization spec file: one validating conversion ([`Spec::from_table`]) from the parsed TOML
//! into SI settings ([`Spec`]), through the checked reader and the shared field ranges of
//! [`crate::input`]. Everything after [`Spec::from_file`] trusts its input.

use crate::input::library::{
    read_drive_bias, read_drive_field, read_drive_mode, read_library_laminate,
};
use crate::input::limits::{
    BASE_WIDTH_MM, ENERGY_MJ, EXTENSION_RATIO, GRID, LENGTH_MM, MAX_LEVELS, MAX_PLIES,
    MIN_TIP_WIDTH_MM, PLY_ANGLE_DEG, PZT_STRAIN, PZT_THICKNESS_MM, VOLTAGE_V, WIDTH_RATIO,
};
use crate::input::{read_toml, InputError, TableReader};
use actuator_model::{DriveMode, Material};
use std::path::{Path, PathBuf};

pub use crate::input::FieldSource;

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

/// The ranges the search spans for the four continuous planform variables, SI.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SearchRanges {
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
    /// Minimum mechanical energy, J (0 with a flapping requirement).
    pub energy: f64,
    /// The drive file whose wing the design must flap (`requirement.flap`), resolved against the spec's
    /// folder; `None` for an energy requirement.
    pub flap: Option<PathBuf>,
    /// Drive mode.
    pub mode: DriveMode,
    /// Requested peak plate field, V/m (before the voltage and strain limits).
    pub field: f64,
    /// How the field was given.
    pub field_source: FieldSource,
    /// The biased mode's bias field, V/m (0 for the other modes).
    pub bias: f64,
    /// Highest supply voltage, V.
    pub max_voltage: Option<f64>,
    /// Planform bounds.
    pub bounds: SearchRanges,
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
    /// The survival share at which the field is held to the mode's limits on the plates (the failure
    /// fit and the depolarization field, docs/physics.md §2.1): the drive file's, when optimizing for a
    /// wing; `None` holds the field to the spec's own limits alone.
    pub poling_survival: Option<f64>,
}

impl Spec {
    /// Read and validate a spec file.
    pub fn from_file(path: &Path) -> Result<Spec, InputError> {
        let table = read_toml(path)?;
        Spec::from_table(path, &table)
    }

    /// Validate a parsed spec file; `path` names the file in errors.
    pub fn from_table(path: &Path, table: &toml::Table) -> Result<Spec, InputError> {
        let root = TableReader::new(path, "", table);
        root.only_keys(&["requirement", "drive", "search", "laminate", "constraints"])?;

        let r = root.table("requirement")?;
        // Either an energy, or a drive file whose wing the design must flap (optimize for a wing).
        let flap = if r.has("flap") {
            let written = r.string("flap", "a drive file (a path relative to this file)")?;
            let resolved = path.parent().unwrap_or(Path::new(".")).join(written);
            if r.has("energy_mJ") || !resolved.is_file() {
                return Err(InputError::invalid(
                    path,
                    "requirement.flap",
                    format!("{written:?}"),
                    if resolved.is_file() {
                        "give energy_mJ or flap, not both".to_string()
                    } else {
                        format!("expected an existing drive file ({})", resolved.display())
                    },
                ));
            }
            Some(resolved)
        } else {
            None
        };
        let energy = match flap {
            Some(_) => 0.0,
            None => match r.optional_number_in("energy_mJ", ENERGY_MJ)? {
                Some(energy) => energy * 1e-3,
                None => {
                    return Err(r.missing_one_of(
                        &["energy_mJ", "flap"],
                        &format!("energy_mJ ({ENERGY_MJ}) or flap (a drive file)"),
                    ))
                }
            },
        };
        r.finish()?;

        let d = root.table("drive")?;
        let mode = read_drive_mode(&d)?;
        let bias = read_drive_bias(&d, mode, None)?;
        let (field, field_source) = read_drive_field(&d, mode, bias)?;
        let max_voltage = d.optional_number_in("max_voltage_V", VOLTAGE_V)?;
        d.finish()?;

        let s = root.table("search")?;
        let span = |key: &str, allowed, scale: f64| {
            s.span_in(key, allowed).map(|(lo, hi)| Range {
                lo: lo * scale,
                hi: hi * scale,
            })
        };
        let bounds = SearchRanges {
            length: span("length_mm", LENGTH_MM, 1e-3)?,
            base_width: span("base_width_mm", BASE_WIDTH_MM, 1e-3)?,
            extension_ratio: span("extension_ratio", EXTENSION_RATIO, 1.0)?,
            width_ratio: span("width_ratio", WIDTH_RATIO, 1.0)?,
        };
        let pzt_thicknesses = s
            .numbers_in("pzt_thickness_mm", PZT_THICKNESS_MM, 1, MAX_LEVELS)?
            .into_iter()
            .map(|t| t * 1e-3)
            .collect();
        let layups = s.number_lists_in("layups_deg", PLY_ANGLE_DEG, (1, MAX_LEVELS), MAX_PLIES)?;
        let grid = s.count("grid", GRID.0, GRID.1)?;
        s.finish()?;

        let l = root.table("laminate")?;
        let (pzt, ply, ply_thickness) = read_library_laminate(&l)?;

        let (min_tip_width_mm, max_peak_pzt_strain) = match root.optional_table("constraints")? {
            Some(c) => {
                let both = (
                    c.optional_number_in("min_tip_width_mm", MIN_TIP_WIDTH_MM)?,
                    c.optional_number_in("max_peak_pzt_strain", PZT_STRAIN)?,
                );
                c.finish()?;
                both
            }
            None => (None, None),
        };
        root.finish()?;

        let spec = Spec {
            energy,
            flap,
            mode,
            field,
            field_source,
            bias,
            max_voltage,
            bounds,
            pzt_thicknesses,
            layups,
            grid,
            pzt,
            ply,
            ply_thickness,
            min_tip_width: min_tip_width_mm.unwrap_or(0.0) * 1e-3,
            max_peak_pzt_strain,
            poling_survival: None,
        };
        spec.check_tip_width_reachable(path, min_tip_width_mm.unwrap_or(0.0))?;
        Ok(spec)
    }

    /// The widest tip in the bounds is `w0_max (2 - w_r,min) / w_r,min`; a larger minimum admits nothing.
    fn check_tip_width_reachable(&self, path: &Path, written: f64) -> Result<(), InputError> {
        let b = &self.bounds;
        let widest = b.base_width.hi * (2.0 - b.width_ratio.lo) / b.width_ratio.lo;
        if self.min_tip_width > widest {
            return Err(InputError::invalid(
                path,
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

    fn parse(text: &str) -> Result<Spec, InputError> {
        let path = Path::new("t.toml");
        Spec::from_table(path, &crate::input::parse_toml(path, text)?)
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
            (
                "width_ratio = [1, 1.95]",
                "width_ratio = [1, 2.5]",
                "search.width_ratio[1] = 2.5: outside the allowed range [0.25, 2)",
            ),
            (
                "grid = 70",
                "grid = 8.5",
                "t.toml: search.grid = 8.5: expected a whole number in [2, 500]",
            ),
            (
                "base_width_mm = [5, 20]",
                "base_width_mm = \"5-20\"",
                "t.toml: search.base_width_mm = \"5-20\": expected a number or [min, max], \
                 each in the allowed range [0.5, 1000] mm",
            ),
            ("[search]", "[serach]", "serach = (table): unknown key"),
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
            ("energy_mJ = 0.059", "energy_mJ = -1", "[1e-9, 1000000] mJ"),
            ("min_tip_width_mm = 0.5", "min_tip_width_mm = 50", "widest"),
            (
                "layups_deg = [[0, 90, 0]",
                "layups_deg = [[]",
                "search.layups_deg[0] = []: expected an array of 1 to 64 numbers",
            ),
        ];
        for (from, to, expect) in cases {
            let text = EXAMPLE.replace(from, to);
            assert_ne!(text, EXAMPLE, "{from}");
            let err = parse(&text).unwrap_err().to_string();
            assert!(err.starts_with("t.toml: "), "{err}");
            assert_eq!(err.lines().count(), 1, "{err}");
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
