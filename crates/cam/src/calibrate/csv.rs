//! Measured-data CSV → validated [`Measurement`]s grouped by actuator.
//!
//! Columns: `id,l_tot_mm,l_r,w0_mm,w_r,t_p_mm,layup,voltage_V,mass_mg,free_deflection_mm,blocked_force_N`,
//! optional `drive` (parallel), `pzt` (PZT-5H), `ply` (CF-thesis), `base_tab_mm` (0), and per actuator
//! the bare clamped actuator's first resonance `resonance_Hz` and its `quality_factor`. `#` lines are
//! comments; an empty cell is "not measured". Units convert to SI here and nowhere else.
//!
//! The raw representation is the CSV record with its header; [`parse_file`] is the one validating
//! conversion. Geometry is checked against the same ranges as the design file ([`crate::input::limits`]),
//! and every problem is an [`InputError`] naming the file, the line, the column and the value.

use crate::design::layup::parse_layup;
use crate::input::library::{drive_mode, library_ply, library_pzt};
use crate::input::limits::{
    BASE_TAB_MM, BASE_WIDTH_MM, BLOCKED_FORCE_N, EXTENSION_RATIO, FREE_DEFLECTION_MM, LENGTH_MM,
    MASS_MG, MAX_PLIES, MEASURED_VOLTAGE_V, PLY_ANGLE_DEG, PZT_THICKNESS_MM, QUALITY_FACTOR,
    RESONANCE_HZ, RESONANCE_SD_HZ, WIDTH_RATIO,
};
use crate::input::{nearest, InputError, Range};
use actuator_model::effects::{drive_at_voltage, Actuator};
use actuator_model::{DriveMode, Material, Planform};
use std::collections::BTreeMap;
use std::path::Path;

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

/// The columns a file may add: `drive`, `pzt`, `ply`, `base_tab_mm`, `resonance_Hz`,
/// `quality_factor`, `resonance_sd_Hz` (in this order).
pub const OPTIONAL_COLUMNS: [&str; 7] = [
    "drive",
    "pzt",
    "ply",
    "base_tab_mm",
    "resonance_Hz",
    "quality_factor",
    "resonance_sd_Hz",
];

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
    /// Measured first resonance of the bare clamped actuator, Hz (shared by all rows of the id).
    pub resonance: Option<f64>,
    /// Measured quality factor of that resonance (shared by all rows of the id).
    pub quality_factor: Option<f64>,
    /// Standard deviation of that resonance's reading, Hz (shared by all rows of the id): the
    /// precision its residual is tested against (docs/calibration.md §3, "The resonance").
    pub resonance_sd: Option<f64>,
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
    /// Header names that are neither required nor optional columns, in file order: read past, and named
    /// in one warning by the command (see [`Dataset::unknown_columns_warning`]).
    pub unknown_columns: Vec<String>,
}

impl Dataset {
    /// Group the rows by id; the measured mass is copied to every row of its id. `file` names the
    /// measured-data file in errors.
    pub fn new(file: &Path, mut rows: Vec<Measurement>) -> Result<Self, InputError> {
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
            let (mut resonance, mut quality, mut sd) = (None, None, None);
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
                        return Err(inconsistent(file, r, column, v * unit, v0 * unit));
                    }
                }
                for (column, v, v0) in [
                    ("layup", &r.layup, &first.layup),
                    ("pzt", &r.pzt.name, &first.pzt.name),
                    ("ply", &r.ply.name, &first.ply.name),
                ] {
                    if v != v0 {
                        return Err(inconsistent(file, r, column, v, v0));
                    }
                }
                if let Some(m) = r.mass {
                    match mass {
                        Some((m0, _)) if !same(m, m0) => {
                            return Err(inconsistent(file, r, "mass_mg", m * 1e6, m0 * 1e6))
                        }
                        _ => mass = Some((m, r.line)),
                    }
                }
                for (column, v, shared) in [
                    ("resonance_Hz", r.resonance, &mut resonance),
                    ("quality_factor", r.quality_factor, &mut quality),
                    ("resonance_sd_Hz", r.resonance_sd, &mut sd),
                ] {
                    match (v, *shared) {
                        (Some(v), Some(v0)) if !same(v, v0) => {
                            return Err(inconsistent(file, r, column, v, v0))
                        }
                        (Some(v), _) => *shared = Some(v),
                        _ => {}
                    }
                }
            }
            if let Some(why) = unreadable_precision(sd, resonance) {
                // Named on the row that states the precision.
                let r = g
                    .iter()
                    .map(|&i| &rows[i])
                    .find(|r| r.resonance_sd.is_some());
                if let (Some(r), Some(sd)) = (r, sd) {
                    return Err(InputError::cell(file, r.line, "resonance_sd_Hz", sd, why));
                }
            }
            for &i in g {
                rows[i].mass = mass.map(|(m, _)| m).or(rows[i].mass);
                rows[i].resonance = resonance;
                rows[i].quality_factor = quality;
                rows[i].resonance_sd = sd;
            }
        }
        Ok(Dataset {
            rows,
            groups,
            group_of,
            unknown_columns: Vec::new(),
        })
    }

    /// One line naming every unknown column (`None` when there is none): the run goes on, but a misspelt
    /// optional column (`base_tab` for `base_tab_mm`) must not be dropped without a word.
    pub fn unknown_columns_warning(&self, file: &Path) -> Option<String> {
        if self.unknown_columns.is_empty() {
            return None;
        }
        Some(format!(
            "{}: ignoring unknown column{} {}; known columns: {},{}",
            file.display(),
            if self.unknown_columns.len() == 1 {
                ""
            } else {
                "s"
            },
            self.unknown_columns.join(", "),
            REQUIRED_COLUMNS.join(","),
            OPTIONAL_COLUMNS.join(",")
        ))
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

/// Rows of one actuator that disagree about its design (or its mass).
fn inconsistent(
    file: &Path,
    row: &Measurement,
    column: &str,
    value: impl std::fmt::Display,
    earlier: impl std::fmt::Display,
) -> InputError {
    InputError::cell(
        file,
        row.line,
        column,
        value,
        format!(
            "actuator `{}` has {column} = {earlier} on earlier lines; the rows of one actuator must agree",
            row.id
        ),
    )
}

/// Why an actuator's stated f1 precision cannot stand: it has no f1 to qualify, or one too coarse to
/// tell f1 (half of it or more).
fn unreadable_precision(sd: Option<f64>, resonance: Option<f64>) -> Option<String> {
    match (sd, resonance) {
        (Some(_), None) => Some(
            "a precision of a resonance the actuator's rows do not give (no resonance_Hz)".into(),
        ),
        (Some(sd), Some(f)) if sd >= 0.5 * f => Some(format!(
            "must be below half of resonance_Hz ({f}): a reading that does not tell f1"
        )),
        _ => None,
    }
}

/// Read and validate a measured-data file.
pub fn read_path(path: &Path) -> Result<Dataset, InputError> {
    let text = crate::input::read_text(path)?;
    parse_file(path, &text)
}

/// Parse and validate measured-data CSV text that has no file (errors name it "measured data").
pub fn parse(text: &str) -> Result<Dataset, InputError> {
    parse_file(Path::new("measured data"), text)
}

/// The raw cells of one record, read with the header names: every getter checks against a shared range
/// and names the file, line and column in its error.
struct Row<'a> {
    file: &'a Path,
    line: u64,
    headers: &'a ::csv::StringRecord,
    record: &'a ::csv::StringRecord,
}

impl Row<'_> {
    fn cell(&self, c: usize) -> &str {
        self.record.get(c).unwrap_or("")
    }

    fn error(
        &self,
        c: usize,
        value: impl std::fmt::Display,
        expected: impl Into<String>,
    ) -> InputError {
        InputError::cell(self.file, self.line, &self.headers[c], value, expected)
    }

    /// An optional number in `range` (an empty cell is "not measured").
    fn number(&self, c: usize, range: Range) -> Result<Option<f64>, InputError> {
        let s = self.cell(c);
        if s.is_empty() {
            return Ok(None);
        }
        match s.parse::<f64>() {
            Ok(v) if range.contains(v) => Ok(Some(v)),
            Ok(_) => Err(self.error(c, s, format!("outside the {range}"))),
            Err(_) => Err(self.error(c, format!("{s:?}"), format!("expected a number, {range}"))),
        }
    }

    /// A required number in `range`.
    fn needed(&self, c: usize, range: Range) -> Result<f64, InputError> {
        self.number(c, range)?.ok_or_else(|| {
            InputError::missing(
                self.file,
                &format!("line {}, column {}", self.line, &self.headers[c]),
                &format!("a number, {range}"),
            )
        })
    }

    /// An optional text cell of an optional column.
    fn text(&self, c: Option<usize>) -> Option<&str> {
        c.map(|c| self.cell(c)).filter(|s| !s.is_empty())
    }

    fn field(&self, column: &str) -> String {
        format!("line {}, column {column}", self.line)
    }
}

/// Parse and validate measured-data CSV text; `file` names it in errors.
pub fn parse_file(file: &Path, text: &str) -> Result<Dataset, InputError> {
    let mut reader = ::csv::ReaderBuilder::new()
        .comment(Some(b'#'))
        .trim(::csv::Trim::All)
        .flexible(false)
        .from_reader(text.as_bytes());
    let headers = reader
        .headers()
        .map_err(|e| InputError::whole_file(file, format!("not valid CSV in the header: {e}")))?
        .clone();
    crate::input::refuse_repeated_columns(file, &headers)?;
    let unknown_columns: Vec<String> = headers
        .iter()
        .filter(|h| !REQUIRED_COLUMNS.contains(h) && !OPTIONAL_COLUMNS.contains(h))
        .map(str::to_string)
        .collect();
    let columns = Columns::of(file, &headers)?;
    let mut rows = Vec::new();
    for record in reader.records() {
        let record = record.map_err(|e| csv_error(file, &e))?;
        let line = record.position().map(|p| p.line()).unwrap_or(0);
        let row = Row {
            file,
            line,
            headers: &headers,
            record: &record,
        };
        rows.push(measurement(&row, &columns)?);
    }
    if rows.is_empty() {
        return Err(InputError::whole_file(file, "the file has no data rows"));
    }
    let mut data = Dataset::new(file, rows)?;
    data.unknown_columns = unknown_columns;
    Ok(data)
}

/// Where each column is: the required ones in [`REQUIRED_COLUMNS`] order, the optional ones in
/// [`OPTIONAL_COLUMNS`] order where present.
struct Columns {
    required: [usize; 11],
    optional: [Option<usize>; 7],
}

impl Columns {
    /// The columns of `headers`, or the error naming the first required column missing.
    fn of(file: &Path, headers: &::csv::StringRecord) -> Result<Self, InputError> {
        let col = |name: &str| headers.iter().position(|h| h == name);
        let mut required = [0usize; 11];
        for (slot, name) in required.iter_mut().zip(REQUIRED_COLUMNS) {
            *slot = col(name).ok_or_else(|| {
                // A header the file kind does not know, one typo from the missing column, is what the
                // user wrote for it.
                let unknown = headers
                    .iter()
                    .filter(|h| !REQUIRED_COLUMNS.contains(h) && !OPTIONAL_COLUMNS.contains(h));
                if let Some(typo) = unknown
                    .into_iter()
                    .find(|h| nearest(h, std::iter::once(name)).is_some())
                {
                    return InputError::invalid(
                        file,
                        "header",
                        typo,
                        format!(
                            "unknown column; did you mean `{name}`? required: {}",
                            REQUIRED_COLUMNS.join(",")
                        ),
                    );
                }
                InputError::invalid(
                    file,
                    "header",
                    headers.iter().collect::<Vec<_>>().join(","),
                    format!(
                        "missing column `{name}`; required: {}",
                        REQUIRED_COLUMNS.join(",")
                    ),
                )
            })?;
        }
        Ok(Columns {
            required,
            optional: OPTIONAL_COLUMNS.map(col),
        })
    }
}

/// One row validated into a measurement in SI units.
fn measurement(row: &Row, columns: &Columns) -> Result<Measurement, InputError> {
    let file = row.file;
    let [c_drive, c_pzt, c_ply, c_tab, c_f1, c_q, c_sd] = columns.optional;
    let [c_id, c_l, c_lr, c_w0, c_wr, c_tp, c_layup, c_v, c_m, c_d, c_f] = columns.required;
    let id = row.cell(c_id).to_string();
    if id.is_empty() {
        return Err(InputError::missing(
            file,
            &row.field("id"),
            "an actuator id (text)",
        ));
    }
    let l_tot = row.needed(c_l, LENGTH_MM)?;
    let l_r = row.needed(c_lr, EXTENSION_RATIO)?;
    let w0 = row.needed(c_w0, BASE_WIDTH_MM)?;
    let w_r = row.needed(c_wr, WIDTH_RATIO)?;
    let t_p = row.needed(c_tp, PZT_THICKNESS_MM)?;
    let voltage = row.needed(c_v, MEASURED_VOLTAGE_V)?;
    let tab = match c_tab {
        Some(c) => row.number(c, BASE_TAB_MM)?.unwrap_or(0.0),
        None => 0.0,
    };
    let mass = row.number(c_m, MASS_MG)?;
    let delta = row.number(c_d, FREE_DEFLECTION_MM)?;
    let force = row.number(c_f, BLOCKED_FORCE_N)?;
    let resonance = match c_f1 {
        Some(c) => row.number(c, RESONANCE_HZ)?,
        None => None,
    };
    let quality_factor = match c_q {
        Some(c) => row.number(c, QUALITY_FACTOR)?,
        None => None,
    };
    let resonance_sd = match c_sd {
        Some(c) => row.number(c, RESONANCE_SD_HZ)?,
        None => None,
    };
    let layup_text = row.cell(c_layup).to_string();
    let layup_deg = parse_layup(&layup_text).map_err(|_| {
        row.error(
            c_layup,
            format!("{layup_text:?}"),
            format!(
                "expected 1 to {MAX_PLIES} ply angles separated by `/`, like 0/90/0, each in the {PLY_ANGLE_DEG}"
            ),
        )
    })?;
    let pzt = library_pzt(file, &row.field("pzt"), row.text(c_pzt).unwrap_or("PZT-5H"))?;
    let (ply, ply_thickness) = library_ply(
        file,
        &row.field("ply"),
        row.text(c_ply).unwrap_or("CF-thesis"),
    )?;
    let drive_mode = match row.text(c_drive) {
        None => DriveMode::Parallel,
        Some(name) => drive_mode(file, &row.field("drive"), name)?,
    };
    let planform = Planform::new(l_tot * 1e-3, l_r, w0 * 1e-3, w_r, tab * 1e-3)
        .map_err(|e| row.error(c_l, l_tot, format!("gives an invalid planform: {e}")))?;
    let pzt_thickness = t_p * 1e-3;
    Ok(Measurement {
        id,
        line: row.line,
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
        resonance,
        quality_factor,
        resonance_sd,
    })
}

/// A record the CSV reader refuses (a row with the wrong number of cells, text that is not UTF-8),
/// named by its line when the reader knows it.
fn csv_error(file: &Path, e: &::csv::Error) -> InputError {
    let what = match e.kind() {
        ::csv::ErrorKind::UnequalLengths {
            expected_len, len, ..
        } => format!("has {len} cells; the header has {expected_len}"),
        _ => format!("not valid CSV: {e}"),
    };
    match e.position() {
        Some(p) => InputError::invalid(file, &format!("line {}", p.line()), "(row)", what),
        None => InputError::whole_file(file, what),
    }
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
    fn a_misspelt_required_column_is_named_as_written() {
        let header = HEADER.replace("free_deflection_mm", "free_defelction_mm");
        let e = parse_file(
            Path::new("m.csv"),
            &format!("{header}\nA,40,0.5,8,1.2,0.191,0/90/0,50,500,0.1,0.05\n"),
        )
        .unwrap_err()
        .to_string();
        assert!(
            e.starts_with("m.csv: header = free_defelction_mm: unknown column; did you mean `free_deflection_mm`?"),
            "{e}"
        );
    }

    #[test]
    fn duplicate_column_is_refused_and_unknown_ones_are_named() {
        let f = Path::new("m.csv");
        let e = parse_file(
            f,
            &format!("{HEADER},mass_mg\nA,40,0.5,8,1.2,0.191,0/90/0,50,500,0.1,0.05,600\n"),
        )
        .unwrap_err()
        .to_string();
        assert!(
            e.starts_with("m.csv: header, column \"mass_mg\" = id,")
                && e.ends_with("appears twice; keep one"),
            "{e}"
        );
        let d = parse_file(
            f,
            &format!("{HEADER},note,base_tab\nA,40,0.5,8,1.2,0.191,0/90/0,50,500,0.1,0.05,x,1\n"),
        )
        .unwrap();
        assert_eq!(d.unknown_columns, ["note", "base_tab"]);
        let w = d.unknown_columns_warning(f).unwrap();
        assert!(
            w.starts_with("m.csv: ignoring unknown columns note, base_tab; known columns: id,"),
            "{w}"
        );
        assert!(!w.contains('\n'));
        let d = parse_file(
            f,
            &format!("{HEADER}\nA,40,0.5,8,1.2,0.191,0/90/0,50,500,0.1,0.05\n"),
        );
        assert_eq!(d.unwrap().unknown_columns_warning(f), None);
    }

    #[test]
    fn resonance_and_quality_factor_are_shared_per_actuator_and_checked() {
        let head = format!("{HEADER},resonance_Hz,quality_factor");
        let d = parse(&format!(
            "{head}\nA,40,0.5,8,1.2,0.191,0/90/0,50,500,0.1,0.05,212.5,28\nA,40,0.5,8,1.2,0.191,0/90/0,100,,0.2,,,\n"
        ))
        .unwrap();
        assert_eq!(d.rows[1].resonance, Some(212.5));
        assert_eq!(d.rows[1].quality_factor, Some(28.0));
        let e = parse_file(
            Path::new("m.csv"),
            &format!("{head}\nA,40,0.5,8,1.2,0.191,0/90/0,50,500,0.1,0.05,2e6,28\n"),
        )
        .unwrap_err()
        .to_string();
        assert!(
            e.contains("m.csv: line 2, column resonance_Hz = 2e6: outside the allowed range [0.1, 1000000] Hz"),
            "{e}"
        );
        let e = parse(&format!(
            "{head}\nA,40,0.5,8,1.2,0.191,0/90/0,50,500,0.1,0.05,200,0.5\n"
        ))
        .unwrap_err()
        .to_string();
        assert!(
            e.contains("quality_factor = 0.5") && !e.contains('\n'),
            "{e}"
        );
        let e = parse(&format!(
            "{head}\nA,40,0.5,8,1.2,0.191,0/90/0,50,500,0.1,0.05,200,\nA,40,0.5,8,1.2,0.191,0/90/0,100,,0.2,,210,\n"
        ))
        .unwrap_err()
        .to_string();
        assert!(
            e.contains("resonance_Hz = 210") && e.contains("must agree"),
            "{e}"
        );
    }

    #[test]
    fn a_resonances_precision_is_shared_per_actuator_and_held_below_half_of_it() {
        let head = format!("{HEADER},resonance_Hz,resonance_sd_Hz");
        let d = parse(&format!(
            "{head}\nA,40,0.5,8,1.2,0.191,0/90/0,50,500,0.1,0.05,212.5,2.1\nA,40,0.5,8,1.2,0.191,0/90/0,100,,0.2,,,\n"
        ))
        .unwrap();
        assert_eq!(d.rows[1].resonance_sd, Some(2.1));
        let e = parse_file(
            Path::new("m.csv"),
            &format!("{head}\nA,40,0.5,8,1.2,0.191,0/90/0,50,500,0.1,0.05,200,150\n"),
        )
        .unwrap_err()
        .to_string();
        assert!(
            e.contains("m.csv: line 2, column resonance_sd_Hz = 150: must be below half of resonance_Hz (200)")
                && !e.contains('\n'),
            "{e}"
        );
        let e = parse(&format!(
            "{head}\nA,40,0.5,8,1.2,0.191,0/90/0,50,500,0.1,0.05,200,2\nA,40,0.5,8,1.2,0.191,0/90/0,100,,0.2,,,3\n"
        ))
        .unwrap_err()
        .to_string();
        assert!(
            e.contains("resonance_sd_Hz = 3") && e.contains("must agree"),
            "{e}"
        );
        // Held per actuator: f1 on one row, its precision on another.
        let e = parse_file(
            Path::new("m.csv"),
            &format!("{head}\nA,40,0.5,8,1.2,0.191,0/90/0,50,500,0.1,0.05,200,\nA,40,0.5,8,1.2,0.191,0/90/0,100,,0.2,,,120\n"),
        )
        .unwrap_err()
        .to_string();
        assert!(
            e.contains("m.csv: line 3, column resonance_sd_Hz = 120: must be below half of resonance_Hz (200)"),
            "{e}"
        );
        // A precision without a resonance is refused, not ignored.
        let e = parse_file(
            Path::new("m.csv"),
            &format!("{head}\nA,40,0.5,8,1.2,0.191,0/90/0,50,500,0.1,0.05,,2\n"),
        )
        .unwrap_err()
        .to_string();
        assert!(
            e.contains("m.csv: line 2, column resonance_sd_Hz = 2: a precision of a resonance")
                && !e.contains('\n'),
            "{e}"
        );
    }

    #[test]
    fn a_short_row_names_its_line() {
        let e = parse_file(Path::new("m.csv"), &format!("{HEADER}\nA,40,0.5\n"))
            .unwrap_err()
            .to_string();
        assert_eq!(e, "m.csv: line 2 = (row): has 3 cells; the header has 11");
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
        assert!(
            e.contains(
                "line 2, column mass_mg = -3: outside the allowed range [0.01, 10000000] mg"
            ),
            "{e}"
        );
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
