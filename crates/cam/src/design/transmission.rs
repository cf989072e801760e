//! The transmission as a `[transmission]` table gives it, in a drive file or in a design file (docs/cam.md
//! §7), read through the one input layer: the linkage (given or solved), and either the transmission's
//! stiffness, inertia and mass or the flexures of the drawn linkage.

use crate::input::limits::{
    COUPLER_RATIO, END_ANGLE_DEG, FILM_THICKNESS_UM, FLEXURE_LENGTH_UM,
    FLEXURE_STIFFNESS_UNM_PER_RAD, FLEXURE_WIDTH_MM, INERTIA_MG_MM2, LINK_LENGTH_MM,
    LINK_OFFSET_MM, PART_MASS_MG, TRANSMISSION_RATIO_RAD_PER_M, TRAVEL_MM,
};
use crate::input::{short_number, InputError, TableReader};

/// The flexures a drive file asks for (SI); lists of one value hold for all three joints.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct FlexureRequest {
    /// Gap lengths at O, B, A, m (one value: all three); `None`: the shortest the film allows.
    pub lengths: Option<Vec<f64>>,
    /// Widths, m (one value: all three); `None`: the template's.
    pub widths: Option<Vec<f64>>,
    /// Film thickness, m; `None`: the template's.
    pub film_thickness: Option<f64>,
}

impl FlexureRequest {
    pub(crate) fn pick(values: &Option<Vec<f64>>, i: usize) -> Option<f64> {
        values
            .as_ref()
            .map(|v| if v.len() == 1 { v[0] } else { v[i] })
    }

    /// The field of joint `i`'s value as the drive file wrote it.
    pub(crate) fn field(values: &Option<Vec<f64>>, key: &str, i: usize) -> String {
        match values {
            Some(v) if v.len() > 1 => format!("transmission.{key}[{i}]"),
            _ => format!("transmission.{key}"),
        }
    }
}

/// mg·mm² in kg·m².
pub const MG_MM2: f64 = 1e-12;

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

/// A validated `[transmission]`, SI inside.
#[derive(Debug, Clone, PartialEq)]
pub struct TransmissionSpec {
    /// Required stroke amplitude, rad: a drive file's `stroke_deg`, or the design file's
    /// `transmission.stroke_deg`.
    pub stroke: f64,
    /// The linkage.
    pub linkage: LinkageSpec,
    /// Flexure stiffness about the wing hinge, N·m/rad (0 with `flexures`: the drawn linkage's).
    pub flexure_stiffness: f64,
    /// Link inertia about the wing hinge, kg·m² (0 with `flexures`).
    pub link_inertia: f64,
    /// Transmission mass, kg (0 with `flexures`).
    pub transmission_mass: f64,
    /// The flexures of a drawn linkage, if given.
    pub flexures: Option<FlexureRequest>,
}

impl TransmissionSpec {
    /// Read `[transmission]` for a stroke of `±stroke` (rad); the caller finishes the table.
    pub fn read(t: &TableReader<'_>, stroke: f64) -> Result<TransmissionSpec, InputError> {
        let linkage = read_linkage(t, stroke)?;
        let flexures = read_flexures(t)?;
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
        Ok(TransmissionSpec {
            stroke,
            linkage,
            flexure_stiffness,
            link_inertia,
            transmission_mass,
            flexures,
        })
    }

    /// The stroke's end angles the linkage is built for, rad: a solved linkage's, else ±stroke.
    pub fn end_angles(&self) -> (f64, f64) {
        match self.linkage {
            LinkageSpec::Solve {
                angle_minus,
                angle_plus,
                ..
            } => (angle_minus, angle_plus),
            LinkageSpec::Given { .. } => (-self.stroke, self.stroke),
        }
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

/// The linkage of `[transmission]`: `coupler_mm` and `crank_mm` (and `offset_mm`), or `end_angles_deg`
/// with `coupler_ratio` (and `travel_mm`); `solve_for_stroke = true` solves for `±stroke_deg`;
/// `ratio_rad_per_m` with `coupler_ratio` is the slider-crank of that ratio at rest (crank `1/T`, docs/drive.md §1).
fn read_linkage(t: &TableReader<'_>, stroke: f64) -> Result<LinkageSpec, InputError> {
    let given = t.has("crank_mm");
    let angles = t.has("end_angles_deg");
    let symmetric = t.optional_bool("solve_for_stroke")?.unwrap_or(false);
    let ratio = t.has("ratio_rad_per_m");
    let ways = [given, angles, symmetric, ratio]
        .iter()
        .filter(|w| **w)
        .count();
    const WAYS: &str = "give exactly one of: coupler_mm and crank_mm; end_angles_deg and coupler_ratio; solve_for_stroke = true and coupler_ratio; ratio_rad_per_m and coupler_ratio";
    if ways == 0 {
        return Err(t.missing_one_of(
            &[
                "crank_mm",
                "end_angles_deg",
                "solve_for_stroke",
                "ratio_rad_per_m",
            ],
            WAYS,
        ));
    }
    if ways != 1 {
        return Err(InputError::invalid(
            t.file(),
            &t.prefix_or("transmission"),
            format!("{ways} linkages given"),
            WAYS,
        ));
    }
    if ratio {
        // The slider-crank turns by x / L3 at rest (eq. 2.5's slope at θ = 0), so the crank of a
        // published ratio T is 1/T; its rise with the stroke is the slider-crank's own.
        let crank = 1.0 / t.number_in("ratio_rad_per_m", TRANSMISSION_RATIO_RAD_PER_M)?;
        return Ok(LinkageSpec::Given {
            coupler: t.number_in("coupler_ratio", COUPLER_RATIO)? * crank,
            crank,
            offset: 0.0,
        });
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
