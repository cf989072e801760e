//! Measured-data CSV (issue 6 interface) → validated [`Measurement`]s grouped by actuator.
//!
//! Columns: `id,l_tot_mm,l_r,w0_mm,w_r,t_p_mm,layup,voltage_V,mass_mg,free_deflection_mm,blocked_force_N`,
//! optional `drive` (parallel), `pzt` (PZT-5H), `ply` (CF-thesis), `base_tab_mm` (0). `#` lines are
//! comments; an empty cell is "not measured". Units convert to SI here and nowhere else.

use actuator_model::effects::{drive_at_voltage, Actuator};
use actuator_model::material::builtin_names;
use actuator_model::{DriveMode, Material, Planform};
use std::collections::BTreeMap;
use std::path::Path;
use thiserror::Error;

/// The columns every file must have.
pub const REQUIRED_COLUMNS: [&str; 11] = [
    "id",
    "l_tot_mm",
    "l_r",
    "w0_mm",
    "w_r",
    "t_p_mm",
    "layup",
    "voltage_V",
    "mass_mg",
    "free_deflection_mm",
    "blocked_force_N",
];

/// A problem with the measured-data file; row numbers are file line numbers.
#[derive(Debug, Error)]
pub enum InputError {
    /// The file cannot be read or is not CSV.
    #[error("{0}")]
    Io(String),
    /// A required column is absent from the header.
    #[error("missing column `{0}` (required: {cols})", cols = REQUIRED_COLUMNS.join(","))]
    MissingColumn(String),
    /// A cell is not a number.
    #[error("line {line}, column `{column}`: `{value}` is not a number")]
    NotNumeric {
        /// File line.
        line: u64,
        /// Column name.
        column: String,
        /// Cell text.
        value: String,
    },
    /// A value outside its range.
    #[error("line {line}, column `{column}`: {value} {why}")]
    OutOfRange {
        /// File line.
        line: u64,
        /// Column name.
        column: String,
        /// Offending value.
        value: String,
        /// What is allowed.
        why: String,
    },
    /// Rows of one actuator disagree about its design.
    #[error("actuator `{id}`: line {line} gives {column} = {value}, earlier rows {earlier}")]
    Inconsistent {
        /// Actuator id.
        id: String,
        /// File line.
        line: u64,
        /// Column name.
        column: String,
        /// Value on this line.
        value: String,
        /// Value on earlier lines.
        earlier: String,
    },
    /// Not enough data for the fit.
    #[error("{0}")]
    TooFew(String),
}

/// One measured actuator at one drive level, validated and in SI units.
#[derive(Debug, Clone)]
pub struct Measurement {
    /// Actuator id.
    pub id: String,
    /// Line of the file.
    pub line: u64,
    /// PZT material.
    pub pzt: Material,
    /// Passive ply material.
    pub ply: Material,
    /// PZT plate thickness, m.
    pub pzt_thickness: f64,
    /// Nominal ply thickness, m (from the ply material).
    pub ply_thickness: f64,
    /// Ply angles, degrees.
    pub layup_deg: Vec<f64>,
    /// Layup as written (`0/90/0`).
    pub layup: String,
    /// Planform.
    pub planform: Planform,
    /// Drive mode.
    pub drive_mode: DriveMode,
    /// Applied voltage, V.
    pub voltage: f64,
    /// Drive field, V/m.
    pub field: f64,
    /// Measured mass of the actuator, kg (shared by all rows of the id).
    pub mass: Option<f64>,
    /// Measured one-sided free deflection, m.
    pub free_deflection: Option<f64>,
    /// Measured blocked force, N.
    pub blocked_force: Option<f64>,
}

impl Measurement {
    /// The model's view of this row.
    pub fn actuator(&self) -> Actuator<'_> {
        Actuator {
            pzt: &self.pzt,
            pzt_thickness: self.pzt_thickness,
            ply: &self.ply,
            ply_thickness: self.ply_thickness,
            layup_deg: &self.layup_deg,
            planform: self.planform,
            drive: drive_at_voltage(self.drive_mode, self.voltage, self.pzt_thickness),
        }
    }
}

/// All rows plus their grouping by actuator (ids in order of first appearance).
#[derive(Debug, Clone)]
pub struct Dataset {
    /// Rows in file order.
    pub rows: Vec<Measurement>,
    /// Row indices of each actuator.
    pub groups: Vec<Vec<usize>>,
    /// Group index of each row.
    pub group_of: Vec<usize>,
}

impl Dataset {
    /// Group the rows by id; the measured mass is copied to every row of its id.
    pub fn new(mut rows: Vec<Measurement>) -> Result<Self, InputError> {
        let mut index: BTreeMap<String, usize> = BTreeMap::new();
        let mut groups: Vec<Vec<usize>> = Vec::new();
        let mut group_of = Vec::with_capacity(rows.len());
        for (i, r) in rows.iter().enumerate() {
            let g = *index.entry(r.id.clone()).or_insert_with(|| {
                groups.push(Vec::new());
                groups.len() - 1
            });
            groups[g].push(i);
            group_of.push(g);
        }
        for g in &groups {
            let first = &rows[g[0]];
            let mut mass: Option<(f64, u64)> = None;
            for &i in g {
                let r = &rows[i];
                let same = |a: f64, b: f64| (a - b).abs() <= 1e-9 * a.abs().max(b.abs());
                let checks = [
                    ("l_tot_mm", r.planform.length, first.planform.length, 1e3),
                    (
                        "l_r",
                        r.planform.extension_ratio,
                        first.planform.extension_ratio,
                        1.0,
                    ),
                    (
                        "w0_mm",
                        r.planform.base_width,
                        first.planform.base_width,
                        1e3,
                    ),
                    (
                        "w_r",
                        r.planform.width_ratio,
                        first.planform.width_ratio,
                        1.0,
                    ),
                    ("t_p_mm", r.pzt_thickness, first.pzt_thickness, 1e3),
                    (
                        "base_tab_mm",
                        r.planform.base_tab,
                        first.planform.base_tab,
                        1e3,
                    ),
                ];
                for (column, v, v0, unit) in checks {
                    if !same(v, v0) {
                        return Err(InputError::Inconsistent {
                            id: r.id.clone(),
                            line: r.line,
                            column: column.into(),
                            value: format!("{}", v * unit),
                            earlier: format!("{}", v0 * unit),
                        });
                    }
                }
                for (column, v, v0) in [
                    ("layup", &r.layup, &first.layup),
                    ("pzt", &r.pzt.name, &first.pzt.name),
                    ("ply", &r.ply.name, &first.ply.name),
                ] {
                    if v != v0 {
                        return Err(InputError::Inconsistent {
                            id: r.id.clone(),
                            line: r.line,
                            column: column.into(),
                            value: v.clone(),
                            earlier: v0.clone(),
                        });
                    }
                }
                if let Some(m) = r.mass {
                    match mass {
                        Some((m0, _)) if !same(m, m0) => {
                            return Err(InputError::Inconsistent {
                                id: r.id.clone(),
                                line: r.line,
                                column: "mass_mg".into(),
                                value: format!("{}", m * 1e6),
                                earlier: format!("{}", m0 * 1e6),
                            })
                        }
                        _ => mass = Some((m, r.line)),
                    }
                }
            }
            if let Some((m, _)) = mass {
                for &i in g {
                    rows[i].mass = Some(m);
                }
            }
        }
        Ok(Dataset {
            rows,
            groups,
            group_of,
        })
    }

    /// Number of actuators.
    pub fn actuators(&self) -> usize {
        self.groups.len()
    }

    /// Measured mass of actuator `g`, kg.
    pub fn group_mass(&self, g: usize) -> Option<f64> {
        self.rows[self.groups[g][0]].mass
    }
}

/// Read and validate a measured-data file.
pub fn read_path(path: &Path) -> Result<Dataset, InputError> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| InputError::Io(format!("cannot read {}: {e}", path.display())))?;
    parse(&text)
}

/// Parse and validate measured-data CSV text.
pub fn parse(text: &str) -> Result<Dataset, InputError> {
    let mut reader = ::csv::ReaderBuilder::new()
        .comment(Some(b'#'))
        .trim(::csv::Trim::All)
        .flexible(false)
        .from_reader(text.as_bytes());
    let headers = reader
        .headers()
        .map_err(|e| InputError::Io(format!("CSV header: {e}")))?
        .clone();
    let col = |name: &str| headers.iter().position(|h| h == name);
    let mut required = [0usize; 11];
    for (slot, name) in required.iter_mut().zip(REQUIRED_COLUMNS) {
        *slot = col(name).ok_or_else(|| InputError::MissingColumn(name.into()))?;
    }
    let optional = |name| col(name);
    let (c_drive, c_pzt, c_ply, c_tab) = (
        optional("drive"),
        optional("pzt"),
        optional("ply"),
        optional("base_tab_mm"),
    );
    let mut rows = Vec::new();
    for record in reader.records() {
        let record = record.map_err(|e| InputError::Io(format!("CSV: {e}")))?;
        let line = record.position().map(|p| p.line()).unwrap_or(0);
        let cell = |c: usize| record.get(c).unwrap_or("");
        let number = |c: usize| -> Result<Option<f64>, InputError> {
            let s = cell(c);
            if s.is_empty() {
                return Ok(None);
            }
            match s.parse::<f64>() {
                Ok(v) if v.is_finite() => Ok(Some(v)),
                _ => Err(InputError::NotNumeric {
                    line,
                    column: headers[c].to_string(),
                    value: s.to_string(),
                }),
            }
        };
        let range = |c: usize, v: f64, why: &str| InputError::OutOfRange {
            line,
            column: headers[c].to_string(),
            value: format!("{v}"),
            why: why.to_string(),
        };
        let needed = |c: usize| -> Result<f64, InputError> {
            number(c)?.ok_or_else(|| InputError::OutOfRange {
                line,
                column: headers[c].to_string(),
                value: "(empty)".into(),
                why: "is required".into(),
            })
        };
        let positive = |c: usize, v: f64| {
            if v > 0.0 {
                Ok(v)
            } else {
                Err(range(c, v, "must be > 0"))
            }
        };
        let [c_id, c_l, c_lr, c_w0, c_wr, c_tp, c_layup, c_v, c_m, c_d, c_f] = required;
        let id = cell(c_id).to_string();
        if id.is_empty() {
            return Err(InputError::OutOfRange {
                line,
                column: "id".into(),
                value: "(empty)".into(),
                why: "is required".into(),
            });
        }
        let l_tot = positive(c_l, needed(c_l)?)?;
        let l_r = needed(c_lr)?;
        if l_r < 0.0 {
            return Err(range(c_lr, l_r, "must be >= 0"));
        }
        let w0 = positive(c_w0, needed(c_w0)?)?;
        let w_r = needed(c_wr)?;
        if !(w_r > 0.0 && w_r < 2.0) {
            return Err(range(c_wr, w_r, "must be in (0, 2)"));
        }
        let t_p = positive(c_tp, needed(c_tp)?)?;
        let voltage = needed(c_v)?;
        if voltage < 0.0 {
            return Err(range(c_v, voltage, "must be >= 0"));
        }
        let tab = match c_tab {
            Some(c) => number(c)?.unwrap_or(0.0),
            None => 0.0,
        };
        if tab < 0.0 {
            return Err(range(c_tab.unwrap_or(0), tab, "must be >= 0"));
        }
        let mass = number(c_m)?;
        let delta = number(c_d)?;
        let force = number(c_f)?;
        for (c, v) in [(c_m, mass), (c_d, delta), (c_f, force)] {
            if let Some(v) = v {
                positive(c, v)?;
            }
        }
        let layup_text = cell(c_layup).to_string();
        let layup_deg = parse_layup(&layup_text).ok_or_else(|| InputError::OutOfRange {
            line,
            column: "layup".into(),
            value: format!("`{layup_text}`"),
            why: "is not a known layup: write ply angles in degrees separated by `/`, like 0/90/0"
                .into(),
        })?;
        let material = |c: Option<usize>, default: &str, piezo: bool| {
            let name = c.map(cell).filter(|s| !s.is_empty()).unwrap_or(default);
            match Material::builtin(name) {
                Some(m) if m.is_piezoelectric() == piezo => Ok(m),
                _ => Err(InputError::OutOfRange {
                    line,
                    column: if piezo { "pzt" } else { "ply" }.into(),
                    value: format!("`{name}`"),
                    why: format!(
                        "is not a known {} material (built in: {})",
                        if piezo { "piezoelectric" } else { "ply" },
                        builtin_names().join(", ")
                    ),
                }),
            }
        };
        let pzt = material(c_pzt, "PZT-5H", true)?;
        let ply = material(c_ply, "CF-thesis", false)?;
        let ply_thickness = ply.ply_thickness.unwrap_or(61.8e-6);
        let drive_name = c_drive.map(cell).filter(|s| !s.is_empty());
        let drive_mode = match drive_name {
            None => DriveMode::Parallel,
            Some(name) => DriveMode::from_name(name).ok_or_else(|| InputError::OutOfRange {
                line,
                column: "drive".into(),
                value: format!("`{name}`"),
                why: "is not a drive mode (parallel, series, simultaneous, alternating)".into(),
            })?,
        };
        let planform = Planform::new(l_tot * 1e-3, l_r, w0 * 1e-3, w_r, tab * 1e-3)
            .map_err(|e| range(c_l, l_tot, &format!("gives an invalid planform: {e}")))?;
        let pzt_thickness = t_p * 1e-3;
        rows.push(Measurement {
            id,
            line,
            pzt,
            ply,
            pzt_thickness,
            ply_thickness,
            layup_deg,
            layup: layup_text,
            planform,
            drive_mode,
            voltage,
            field: drive_mode.field_from_voltage(voltage, pzt_thickness),
            mass: mass.map(|m| m * 1e-6),
            free_deflection: delta.map(|d| d * 1e-3),
            blocked_force: force,
        });
    }
    if rows.is_empty() {
        return Err(InputError::TooFew("the file has no data rows".into()));
    }
    Dataset::new(rows)
}

/// `0/90/0` → angles; `None` if any part is not an angle in [-90, 90].
pub fn parse_layup(text: &str) -> Option<Vec<f64>> {
    let angles: Option<Vec<f64>> = text
        .split('/')
        .map(|p| {
            p.trim()
                .parse::<f64>()
                .ok()
                .filter(|a| a.is_finite() && a.abs() <= 90.0)
        })
        .collect();
    angles.filter(|a| !a.is_empty())
}

#[cfg(test)]
mod tests {
    use super::*;

    const HEADER: &str =
        "id,l_tot_mm,l_r,w0_mm,w_r,t_p_mm,layup,voltage_V,mass_mg,free_deflection_mm,blocked_force_N";

    #[test]
    fn reads_a_sweep_and_shares_the_mass() {
        let text = format!(
            "# comment\n{HEADER}\nA,40,0.5,8,1.2,0.191,0/90/0,50,500,0.1,0.05\nA,40,0.5,8,1.2,0.191,0/90/0,100,,0.2,\n"
        );
        let d = parse(&text).unwrap();
        assert_eq!(d.actuators(), 1);
        assert_eq!(d.rows[1].mass, Some(500e-6));
        assert_eq!(d.rows[1].blocked_force, None);
        assert!((d.rows[1].field - 100.0 / 191e-6).abs() < 1e-6);
    }

    #[test]
    fn names_line_and_column_of_a_bad_cell() {
        let text = format!("{HEADER}\nA,40,0.5,8,1.2,0.191,0/90/0,50,abc,0.1,0.05\n");
        let e = parse(&text).unwrap_err().to_string();
        assert!(
            e.contains("line 2") && e.contains("mass_mg") && e.contains("abc"),
            "{e}"
        );
    }

    #[test]
    fn rejects_missing_column_negative_mass_unknown_layup_and_material() {
        let no_force = HEADER.replace(",blocked_force_N", "");
        let e = parse(&format!(
            "{no_force}\nA,40,0.5,8,1.2,0.191,0/90/0,50,1,0.1\n"
        ))
        .unwrap_err()
        .to_string();
        assert!(e.contains("blocked_force_N"), "{e}");
        let e = parse(&format!(
            "{HEADER}\nA,40,0.5,8,1.2,0.191,0/90/0,50,-3,0.1,0.05\n"
        ))
        .unwrap_err()
        .to_string();
        assert!(e.contains("mass_mg") && e.contains("> 0"), "{e}");
        let e = parse(&format!(
            "{HEADER}\nA,40,0.5,8,1.2,0.191,quasi-iso,50,3,0.1,0.05\n"
        ))
        .unwrap_err()
        .to_string();
        assert!(e.contains("layup"), "{e}");
        let e = parse(&format!(
            "{HEADER},ply\nA,40,0.5,8,1.2,0.191,0/90/0,50,3,0.1,0.05,kevlar\n"
        ))
        .unwrap_err()
        .to_string();
        assert!(e.contains("kevlar"), "{e}");
    }
}
