//! The drive file: a design, a wing, a transmission and the flapping requirement, read through the one
//! input layer (every number checked against `input::limits`, unknown keys refused).

use crate::input::limits::{
    AIR_DENSITY_KG_PER_M3, AREAL_DENSITY_G_PER_M2, CHORD_MM, COUPLER_RATIO, DRAG_COEFFICIENT,
    END_ANGLE_DEG, FILM_THICKNESS_UM, FLAPPING_FREQUENCY_HZ, FLEXURE_LENGTH_UM,
    FLEXURE_STIFFNESS_UNM_PER_RAD, FLEXURE_WIDTH_MM, INERTIA_MG_MM2, LINK_LENGTH_MM,
    LINK_OFFSET_MM, LOSS_FACTOR, MASS_BUDGET_MG, PART_MASS_MG, STROKE_DEG, SURVIVAL,
    TABLE_CHORD_MM, TRAVEL_MM, WING_DAMPING_NN_M_S2, WING_ROOT_OFFSET_MM, WING_SPAN_MM,
};
use crate::input::{read_toml, short_number, InputError, TableReader};
use crate::linkage::FlexureRequest;
use actuator_model::dynamics::DEFAULT_LOSS_FACTOR;
use actuator_model::wing::{Chord, Wing, WingPlanform, AIR_DENSITY};
use actuator_model::ModelChoice;
use std::path::{Path, PathBuf};

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
                damping: 0.0,
                mass: 0.0,
            }),
            WingSpec::Direct(w) => *w,
        }
    }
}

/// The linkage as given.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum LinkageSpec {
    /// Lengths given: coupler `L1`, crank `L3`, the linkage's `δ` at rest (m).
    Given {
        /// Coupler, m.
        coupler: f64,
        /// Crank, m.
        crank: f64,
        /// Offset, m.
        offset: f64,
    },
    /// Solved for end angles (rad) from the actuator's travel (m; the actuator's free deflection at
    /// its design field when `None`), with the coupler `coupler_ratio` times the crank.
    Solve {
        /// Lower end angle, rad.
        angle_minus: f64,
        /// Upper end angle, rad.
        angle_plus: f64,
        /// `L1 / L3`.
        coupler_ratio: f64,
        /// One-sided actuator travel, m.
        travel: Option<f64>,
    },
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
    /// Required stroke amplitude (half the peak-to-peak angle), rad.
    pub stroke: f64,
    /// Field survival share that bounds the drive.
    pub survival: f64,
    /// Structural loss factor of the actuator as the file gives it (None: see [`DriveSpec::loss_factor`]).
    pub loss_factor_given: Option<f64>,
    /// Mass budget of actuator + transmission, kg.
    pub mass_budget: f64,
    /// The wing.
    pub wing: WingSpec,
    /// The linkage.
    pub linkage: LinkageSpec,
    /// Flexure stiffness about the wing hinge, N·m/rad.
    pub flexure_stiffness: f64,
    /// Link inertia about the wing hinge, kg·m².
    pub link_inertia: f64,
    /// Transmission mass, kg.
    pub transmission_mass: f64,
    /// The flexures of a drawn linkage (`flexure_length_um`, `flexure_width_mm`, `film_thickness_um`):
    /// then the stiffness, inertia and mass above are not given but computed from the linkage laminate
    /// the design's process cuts.
    pub flexures: Option<FlexureRequest>,
}

/// mg·mm² in kg·m².
const MG_MM2: f64 = 1e-12;

impl DriveSpec {
    /// The actuator's structural loss factor: the file's `loss_factor`, else a calibrated model's
    /// measured one (`η = 1/Q` of its actuators, docs/calibration.md §3), else the PZT's
    /// [`DEFAULT_LOSS_FACTOR`].
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
        let loss_factor_given = root.optional_number_in("loss_factor", LOSS_FACTOR)?;
        let mass_budget = root
            .optional_number_in("mass_budget_mg", MASS_BUDGET_MG)?
            .map_or(DEFAULT_MASS_BUDGET, |m| m * 1e-6);
        let wing = read_wing(&root.table("wing")?)?;
        let t = root.table("transmission")?;
        let linkage = read_linkage(&t, stroke)?;
        let flexures = read_flexures(&t)?;
        let (flexure_stiffness, link_inertia, transmission_mass) = if flexures.is_some() {
            // Computed from the drawn linkage when the drive is analysed.
            (0.0, 0.0, 0.0)
        } else {
            (
                t.number_in(
                    "flexure_stiffness_uNm_per_rad",
                    FLEXURE_STIFFNESS_UNM_PER_RAD,
                )? * 1e-6,
                t.number_in("link_inertia_mg_mm2", INERTIA_MG_MM2)? * MG_MM2,
                t.number_in("mass_mg", PART_MASS_MG)? * 1e-6,
            )
        };
        t.finish()?;
        root.finish()?;
        Ok(DriveSpec {
            source: path.to_path_buf(),
            design,
            frequency,
            stroke,
            survival,
            loss_factor_given,
            mass_budget,
            wing,
            linkage,
            flexure_stiffness,
            link_inertia,
            transmission_mass,
            flexures,
        })
    }
}

/// The flexures of a drawn linkage, if `[transmission]` gives any of `flexure_length_um`,
/// `flexure_width_mm` (each a number for all three joints or `[O, B, A]`) or `film_thickness_um`; then
/// the stiffness, inertia and mass come from the drawn linkage and may not be given too.
fn read_flexures(t: &TableReader<'_>) -> Result<Option<FlexureRequest>, InputError> {
    let drawn = ["flexure_length_um", "flexure_width_mm", "film_thickness_um"]
        .iter()
        .any(|k| t.has(k));
    if !drawn {
        return Ok(None);
    }
    for key in [
        "flexure_stiffness_uNm_per_rad",
        "link_inertia_mg_mm2",
        "mass_mg",
    ] {
        if t.has(key) {
            return Err(InputError::invalid(
                t.file(),
                &t.path(key),
                "(given)",
                "left out with flexure_length_um, flexure_width_mm or film_thickness_um: the drawn linkage gives it",
            ));
        }
    }
    let scaled = |v: Option<Vec<f64>>, by: f64| v.map(|v| v.iter().map(|x| x * by).collect());
    Ok(Some(FlexureRequest {
        lengths: scaled(
            t.optional_number_or_numbers_in("flexure_length_um", FLEXURE_LENGTH_UM, 3)?,
            1e-6,
        ),
        widths: scaled(
            t.optional_number_or_numbers_in("flexure_width_mm", FLEXURE_WIDTH_MM, 3)?,
            1e-3,
        ),
        film_thickness: t
            .optional_number_in("film_thickness_um", FILM_THICKNESS_UM)?
            .map(|x| x * 1e-6),
    }))
}

/// `[wing]`: a planform (`span_mm`, a chord, `areal_density_g_per_m2`, `drag_coefficient`) or the wing
/// directly (`inertia_mg_mm2`, `damping_nN_m_s2`).
fn read_wing(t: &TableReader<'_>) -> Result<WingSpec, InputError> {
    let planform = t.has("span_mm");
    let direct = t.has("inertia_mg_mm2");
    if planform == direct {
        return Err(InputError::invalid(
            t.file(),
            &t.prefix_or("wing"),
            if planform {
                "span_mm and inertia_mg_mm2"
            } else {
                "neither span_mm nor inertia_mg_mm2"
            },
            "give a planform (span_mm, chord, areal_density_g_per_m2, drag_coefficient) or the wing directly (inertia_mg_mm2, damping_nN_m_s2), not both",
        ));
    }
    let spec = if direct {
        WingSpec::Direct(Wing {
            inertia: t.number_in("inertia_mg_mm2", INERTIA_MG_MM2)? * MG_MM2,
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

/// The linkage of `[transmission]`: `coupler_mm` and `crank_mm` (and `offset_mm`), or `end_angles_deg`
/// with `coupler_ratio` (and `travel_mm`); `solve_for_stroke = true` solves for `±stroke_deg`.
fn read_linkage(t: &TableReader<'_>, stroke: f64) -> Result<LinkageSpec, InputError> {
    let given = t.has("crank_mm");
    let angles = t.has("end_angles_deg");
    let symmetric = t.optional_bool("solve_for_stroke")?.unwrap_or(false);
    let ways = [given, angles, symmetric].iter().filter(|w| **w).count();
    if ways != 1 {
        return Err(InputError::invalid(
            t.file(),
            &t.prefix_or("transmission"),
            format!("{ways} linkages given"),
            "give exactly one of: coupler_mm and crank_mm; end_angles_deg and coupler_ratio; solve_for_stroke = true and coupler_ratio",
        ));
    }
    if given {
        return Ok(LinkageSpec::Given {
            coupler: t.number_in("coupler_mm", LINK_LENGTH_MM)? * 1e-3,
            crank: t.number_in("crank_mm", LINK_LENGTH_MM)? * 1e-3,
            offset: t
                .optional_number_in("offset_mm", LINK_OFFSET_MM)?
                .unwrap_or(0.0)
                * 1e-3,
        });
    }
    let (angle_minus, angle_plus) = if angles {
        let a = t.numbers_in("end_angles_deg", END_ANGLE_DEG, 2, 2)?;
        if a[0] >= a[1] {
            return Err(InputError::invalid(
                t.file(),
                &t.path("end_angles_deg"),
                format!("[{}, {}]", short_number(a[0]), short_number(a[1])),
                "expected [lower, upper] with lower < upper",
            ));
        }
        (a[0].to_radians(), a[1].to_radians())
    } else {
        (-stroke, stroke)
    };
    Ok(LinkageSpec::Solve {
        angle_minus,
        angle_plus,
        coupler_ratio: t.number_in("coupler_ratio", COUPLER_RATIO)?,
        travel: t
            .optional_number_in("travel_mm", TRAVEL_MM)?
            .map(|x| x * 1e-3),
    })
}
