//! The drive file: a design, a wing, a transmission and the flapping requirement, read through the one
//! input layer (every number checked against `input::limits`, unknown keys refused).

pub use crate::design::transmission::LinkageSpec;
use crate::design::transmission::{TransmissionSpec, MG_MM2};
use crate::input::limits::{
    AIR_DENSITY_KG_PER_M3, AREAL_DENSITY_G_PER_M2, CHORD_MM, DRAG_COEFFICIENT,
    FLAPPING_FREQUENCY_HZ, INCIDENCE_DEG, INERTIA_MG_MM2, LOSS_FACTOR, MASS_BUDGET_MG,
    PART_MASS_MG, QUALITY_FACTOR, STROKE_DEG, SURVIVAL, TABLE_CHORD_MM, WING_DAMPING_NN_M_S2,
    WING_ROOT_OFFSET_MM, WING_SPAN_MM,
};
use crate::input::{read_toml, short_number, InputError, TableReader};
use actuator_model::dynamics::DEFAULT_LOSS_FACTOR;
use actuator_model::wing::{Chord, Wing, WingPlanform, AIR_DENSITY};
use actuator_model::ModelChoice;
use std::path::{Path, PathBuf};

/// The wing's angle of attack at mid-stroke when the drive file gives none, deg: the 37.5° of the
/// drive examples, inside the 30-40° Manduca keeps (Willmott & Ellington, J. Exp. Biol. 200:2723, 1997)
/// and the 20-45° of RoboBee's passive hinge (Jafferis, Graule & Wood, ICRA 2016). An assumption, used
/// only for the added mass (docs/drive.md §4).
pub const DEFAULT_INCIDENCE_DEG: f64 = 37.5;

/// Actuator + transmission mass per wing of the thesis' hawk-moth-sized vehicle: half the thorax
/// (thesis §2.3.1), kg.
pub const DEFAULT_MASS_BUDGET: f64 = 0.29e-3;

/// Field survival share that bounds the drive when the file gives none: the thesis' design level,
/// 800 V/mm, "should give a survival rate of over 90%" (thesis §4.10).
pub const DEFAULT_SURVIVAL: f64 = 0.9;

/// The wing as given.
#[derive(Debug, Clone, PartialEq)]
pub enum WingSpec {
    /// From a planform.
    Planform(WingPlanform),
    /// Inertia, drag coefficient and mass given directly.
    Direct(Wing),
}

impl WingSpec {
    /// The wing the drive sees.
    pub fn wing(&self) -> Wing {
        match self {
            // The planform was validated when read.
            WingSpec::Planform(p) => p.wing().unwrap_or(Wing {
                inertia: 0.0,
                added_inertia: 0.0,
                damping: 0.0,
                mass: 0.0,
            }),
            WingSpec::Direct(w) => *w,
        }
    }
}

/// A validated drive file, SI inside.
#[derive(Debug, Clone, PartialEq)]
pub struct DriveSpec {
    /// The drive file.
    pub source: PathBuf,
    /// The design file, resolved against the drive file's folder.
    pub design: PathBuf,
    /// Flapping frequency, Hz.
    pub frequency: f64,
    /// Field survival share that bounds the drive.
    pub survival: f64,
    /// Structural loss factor of the actuator as the file gives it, `loss_factor` or `1/quality_factor`
    /// (None: see [`DriveSpec::loss_factor`]).
    pub loss_factor_given: Option<f64>,
    /// Mass budget of actuator + transmission, kg.
    pub mass_budget: f64,
    /// The wing.
    pub wing: WingSpec,
    /// The `[transmission]`: the required stroke, the linkage, and either its stiffness, inertia and
    /// mass or the flexures of the drawn linkage, computed from the laminate the design's process cuts.
    pub transmission: TransmissionSpec,
}

/// The actuator's loss as a drive file gives it: `loss_factor` η, or a measured `quality_factor` Q of
/// its first resonance as `η = 1/Q`; at most one of the two.
fn read_loss(root: &TableReader<'_>) -> Result<Option<f64>, InputError> {
    let eta = root.optional_number_in("loss_factor", LOSS_FACTOR)?;
    let q = root.optional_number_in("quality_factor", QUALITY_FACTOR)?;
    match (eta, q) {
        (Some(e), Some(q)) => Err(InputError::invalid(
            root.file(),
            "loss_factor",
            format!("{e} and quality_factor = {q}"),
            "give at most one of loss_factor and quality_factor (η = 1/Q)",
        )),
        (None, Some(q)) => Ok(Some(1.0 / q)),
        (eta, None) => Ok(eta),
    }
}

impl DriveSpec {
    /// The actuator's structural loss factor: the file's `loss_factor` or `1/quality_factor`, else a
    /// calibrated model's measured one (`η = 1/Q` of its actuators, docs/calibration.md §3), else
    /// [`DEFAULT_LOSS_FACTOR`], `1/Q` of built bending actuators (docs/physics.md §11.4).
    pub fn loss_factor(&self, model: &ModelChoice) -> f64 {
        let measured = match model {
            ModelChoice::Calibrated(c) => c.loss.map(|l| l.loss_factor),
            ModelChoice::Kind(_) => None,
        };
        self.loss_factor_given
            .or(measured)
            .unwrap_or(DEFAULT_LOSS_FACTOR)
    }

    /// Read and check a drive file.
    pub fn load(path: &Path) -> Result<DriveSpec, InputError> {
        let table = read_toml(path)?;
        Self::from_table(path, &table)
    }

    /// Check a parsed drive file.
    pub fn from_table(path: &Path, table: &toml::Table) -> Result<DriveSpec, InputError> {
        let root = TableReader::new(path, "", table);
        root.only_keys(&[
            "design",
            "frequency_Hz",
            "stroke_deg",
            "survival",
            "loss_factor",
            "quality_factor",
            "mass_budget_mg",
            "wing",
            "transmission",
        ])?;
        let written = root.string("design", "the design file (a path relative to this file)")?;
        let base = path.parent().unwrap_or(Path::new("."));
        let design = base.join(written);
        if !design.is_file() {
            return Err(InputError::invalid(
                path,
                "design",
                format!("{written:?}"),
                format!("expected an existing design file ({})", design.display()),
            ));
        }
        let frequency = root.number_in("frequency_Hz", FLAPPING_FREQUENCY_HZ)?;
        let stroke = root.number_in("stroke_deg", STROKE_DEG)?.to_radians();
        let survival = root
            .optional_number_in("survival", SURVIVAL)?
            .unwrap_or(DEFAULT_SURVIVAL);
        let loss_factor_given = read_loss(&root)?;
        let mass_budget = root
            .optional_number_in("mass_budget_mg", MASS_BUDGET_MG)?
            .map_or(DEFAULT_MASS_BUDGET, |m| m * 1e-6);
        let wing = read_wing(&root.table("wing")?)?;
        let t = root.table("transmission")?;
        let transmission = TransmissionSpec::read(&t, stroke)?;
        t.finish()?;
        root.finish()?;
        Ok(DriveSpec {
            source: path.to_path_buf(),
            design,
            frequency,
            survival,
            loss_factor_given,
            mass_budget,
            wing,
            transmission,
        })
    }
}

/// `[wing]`: a planform (`span_mm`, a chord, `areal_density_g_per_m2`, `drag_coefficient`) or the wing
/// directly (`inertia_mg_mm2`, `damping_nN_m_s2`).
fn read_wing(t: &TableReader<'_>) -> Result<WingSpec, InputError> {
    let planform = t.has("span_mm");
    let direct = t.has("inertia_mg_mm2");
    const WAYS: &str = "give a planform (span_mm, chord, areal_density_g_per_m2, drag_coefficient) or the wing directly (inertia_mg_mm2, damping_nN_m_s2), not both";
    if !planform && !direct {
        return Err(t.missing_one_of(&["span_mm", "inertia_mg_mm2"], WAYS));
    }
    if planform == direct {
        return Err(InputError::invalid(
            t.file(),
            &t.prefix_or("wing"),
            "span_mm and inertia_mg_mm2",
            WAYS,
        ));
    }
    let spec = if direct {
        WingSpec::Direct(Wing {
            inertia: t.number_in("inertia_mg_mm2", INERTIA_MG_MM2)? * MG_MM2,
            added_inertia: 0.0,
            damping: t.number_in("damping_nN_m_s2", WING_DAMPING_NN_M_S2)? * 1e-9,
            mass: t
                .optional_number_in("mass_mg", PART_MASS_MG)?
                .unwrap_or(0.0)
                * 1e-6,
        })
    } else {
        let span = t.number_in("span_mm", WING_SPAN_MM)? * 1e-3;
        let shape = t.string("chord", "rectangle, half-ellipse or table")?;
        let chord = match shape {
            "rectangle" => Chord::Rectangle(t.number_in("chord_mm", CHORD_MM)? * 1e-3),
            "half-ellipse" => Chord::Elliptic(t.number_in("chord_mm", CHORD_MM)? * 1e-3),
            "table" => Chord::Table(read_chord_table(t, span)?),
            other => {
                return Err(InputError::invalid(
                    t.file(),
                    &t.path("chord"),
                    format!("{other:?}"),
                    "expected rectangle, half-ellipse or table",
                ))
            }
        };
        let planform = WingPlanform {
            span,
            root_offset: t
                .optional_number_in("root_offset_mm", WING_ROOT_OFFSET_MM)?
                .unwrap_or(0.0)
                * 1e-3,
            chord,
            areal_density: t.number_in("areal_density_g_per_m2", AREAL_DENSITY_G_PER_M2)? * 1e-3,
            drag_coefficient: t.number_in("drag_coefficient", DRAG_COEFFICIENT)?,
            air_density: t
                .optional_number_in("air_density_kg_per_m3", AIR_DENSITY_KG_PER_M3)?
                .unwrap_or(AIR_DENSITY),
            incidence: t
                .optional_number_in("incidence_deg", INCIDENCE_DEG)?
                .unwrap_or(DEFAULT_INCIDENCE_DEG)
                .to_radians(),
        };
        planform.validate().map_err(|e| {
            InputError::invalid(t.file(), &t.prefix_or("wing"), "(planform)", e.to_string())
        })?;
        WingSpec::Planform(planform)
    };
    t.finish()?;
    Ok(spec)
}

/// `chord_table_mm = [[s, c], ...]`: stations from 0 at the wing root to the span, increasing.
fn read_chord_table(t: &TableReader<'_>, span: f64) -> Result<Vec<(f64, f64)>, InputError> {
    let rows = t.number_lists_in("chord_table_mm", TABLE_CHORD_MM, (2, 200), 2)?;
    let field = t.path("chord_table_mm");
    let mut points = Vec::with_capacity(rows.len());
    for (i, row) in rows.iter().enumerate() {
        let [s, c] = row[..] else {
            return Err(InputError::invalid(
                t.file(),
                &format!("{field}[{i}]"),
                format!("{row:?}"),
                "expected [station_mm, chord_mm]",
            ));
        };
        points.push((s * 1e-3, c * 1e-3));
    }
    let first = points[0].0;
    let last = points[points.len() - 1].0;
    let increasing = points.windows(2).all(|w| w[1].0 > w[0].0);
    if first != 0.0 || (last - span).abs() > 1e-9 * span || !increasing {
        return Err(InputError::invalid(
            t.file(),
            &field,
            format!(
                "stations {} to {} mm",
                short_number(first * 1e3),
                short_number(last * 1e3)
            ),
            format!(
                "expected stations increasing from 0 to span_mm = {}",
                short_number(span * 1e3)
            ),
        ));
    }
    Ok(points)
}
