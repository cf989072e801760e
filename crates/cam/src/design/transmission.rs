//! The transmission as a `[transmission]` table gives it, in a drive file or in a design file (docs/cam.md
//! §7), read through the one input layer: the linkage (given or solved), and either the transmission's
//! stiffness, inertia and mass or the flexures of the drawn linkage.

use crate::input::limits::{
    COUPLER_RATIO, END_ANGLE_DEG, FILM_THICKNESS_UM, FLEXURE_LENGTH_UM,
    FLEXURE_STIFFNESS_UNM_PER_RAD, FLEXURE_WIDTH_MM, INERTIA_MG_MM2, LINK_LENGTH_MM,
    LINK_OFFSET_MM, PART_MASS_MG, RATIO_STROKE_DEG, TRANSMISSION_RATIO_RAD_PER_M, TRAVEL_MM,
};
use crate::input::{short_number, InputError, TableReader};
use actuator_model::fourbar::FourBar;
use actuator_model::kinematics::RatioLaw;

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
    /// A published ratio and its nonlinearity, without a linkage (`ratio_rad_per_m` alone).
    Ratio(RatioLaw),
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
    /// The second stage, an amplifying four-bar after the slider-crank (`[transmission.four_bar]`).
    pub four_bar: Option<FourBar>,
}

impl TransmissionSpec {
    /// Read `[transmission]` for a stroke of `±stroke` (rad); the caller finishes the table.
    pub fn read(t: &TableReader<'_>, stroke: f64) -> Result<TransmissionSpec, InputError> {
        let mut linkage = read_linkage(t, stroke)?;
        let flexures = read_flexures(t)?;
        let four_bar = read_four_bar(t, &linkage, stroke)?;
        // A published ratio is the whole transmission's: before a four-bar of gain a/c the slider-crank's
        // crank is (a/c)/T, so that the stages' product at rest is T (docs/physics.md §16.8).
        if let (Some(f), LinkageSpec::Given { coupler, crank, .. }) = (four_bar, &mut linkage) {
            if t.has("ratio_rad_per_m") {
                *coupler *= f.input / f.output;
                *crank *= f.input / f.output;
            }
        }
        if let (Some(_), true) = (
            &flexures,
            four_bar.is_some() || matches!(linkage, LinkageSpec::Ratio(_)),
        ) {
            let key = ["flexure_length_um", "flexure_width_mm", "film_thickness_um"]
                .into_iter()
                .find(|k| t.has(k))
                .unwrap_or("flexure_length_um");
            return Err(InputError::invalid(
                t.file(),
                &t.path(key),
                "(given)",
                "left out of a two-stage linkage or a ratio: no linkage drawing is made of either; give flexure_stiffness_uNm_per_rad, link_inertia_mg_mm2 and mass_mg",
            ));
        }
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
            four_bar,
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
            LinkageSpec::Given { .. } | LinkageSpec::Ratio(_) => (-self.stroke, self.stroke),
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
/// `ratio_rad_per_m` with `coupler_ratio` is the slider-crank of that ratio at rest (crank `1/T`, docs/drive.md §1),
/// and alone the ratio law of docs/physics.md §12.4.
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
        return read_ratio(t, stroke);
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

/// `ratio_rad_per_m`: with `coupler_ratio`, the slider-crank whose slope at rest is `T` (eq. 2.5's is
/// `1/L3`, so the crank is `1/T`) and whose ratio rises with the stroke as eq. 2.5's does; alone, the
/// ratio law through `T` at rest and, if given, `ratio_at_stroke_rad_per_m` at `ratio_at_stroke_deg`
/// (docs/physics.md §12.4), which must not reach its dead point within the stroke.
fn read_ratio(t: &TableReader<'_>, stroke: f64) -> Result<LinkageSpec, InputError> {
    let ratio = t.number_in("ratio_rad_per_m", TRANSMISSION_RATIO_RAD_PER_M)?;
    let at_deg = t.optional_number_in("ratio_at_stroke_deg", RATIO_STROKE_DEG)?;
    let at_ratio =
        t.optional_number_in("ratio_at_stroke_rad_per_m", TRANSMISSION_RATIO_RAD_PER_M)?;
    if t.has("coupler_ratio") {
        if let Some(key) = ["ratio_at_stroke_deg", "ratio_at_stroke_rad_per_m"]
            .into_iter()
            .find(|k| t.has(k))
        {
            return Err(InputError::invalid(
                t.file(),
                &t.path(key),
                "(given)",
                "left out with coupler_ratio: the slider-crank's ratio changes with the stroke as eq. 2.5's does",
            ));
        }
        let crank = 1.0 / ratio;
        return Ok(LinkageSpec::Given {
            coupler: t.number_in("coupler_ratio", COUPLER_RATIO)? * crank,
            crank,
            offset: 0.0,
        });
    }
    let law = match (at_deg, at_ratio) {
        (None, None) => RatioLaw::through(ratio, 1.0, ratio),
        (Some(deg), Some(t1)) => RatioLaw::through(ratio, deg.to_radians(), t1),
        (given, _) => {
            let (has, lacks) = match given {
                Some(_) => ("ratio_at_stroke_deg", "ratio_at_stroke_rad_per_m"),
                None => ("ratio_at_stroke_rad_per_m", "ratio_at_stroke_deg"),
            };
            return Err(t.missing_one_of(
                &[lacks],
                &format!("{lacks} with {has}: the ratio at that stroke angle"),
            ));
        }
    };
    if law.reach() <= stroke {
        // T0/T1 - 1 > -θ1²/θ² keeps the dead point past the stroke θ.
        let (deg, t1) = (at_deg.unwrap_or(0.0), at_ratio.unwrap_or(ratio));
        let below = ratio / (1.0 - (deg / stroke.to_degrees()).powi(2));
        return Err(InputError::invalid(
            t.file(),
            &t.path("ratio_at_stroke_rad_per_m"),
            short_number(t1),
            format!(
                "below {} rad/m: a ratio rising from {} rad/m at rest to {} at {}° turns the wing no further past ±{:.1}°, inside the ±{}° stroke",
                short_number(below),
                short_number(ratio),
                short_number(t1),
                short_number(deg),
                law.reach().to_degrees(),
                short_number(stroke.to_degrees())
            ),
        ));
    }
    Ok(LinkageSpec::Ratio(law))
}

/// The smallest transmission angle a four-bar may reach over the stroke, and 180° less it the largest.
/// An assumption: machine design holds it to about 40° (Norton, *Design of Machinery*, §4.10), but a
/// flapping four-bar's rocker strokes ±55-60° about its rest at 90°, which keeps it near 90° ± the stroke
/// whatever the lengths; at 30° the coupler still pushes across the rocker with half its force, and the
/// toggles (0° and 180°) stay a third of a right angle away.
pub const MIN_TRANSMISSION_ANGLE_DEG: f64 = 30.0;

/// `[transmission.four_bar]`: the second stage's `input_mm`, `coupler_mm` and `output_mm`, held to a
/// transmission angle within [`MIN_TRANSMISSION_ANGLE_DEG`] of toggling over the stroke.
fn read_four_bar(
    t: &TableReader<'_>,
    linkage: &LinkageSpec,
    stroke: f64,
) -> Result<Option<FourBar>, InputError> {
    let Some(f) = t.optional_table("four_bar")? else {
        return Ok(None);
    };
    if let LinkageSpec::Ratio(_) = linkage {
        return Err(InputError::invalid(
            t.file(),
            &f.prefix_or("four_bar"),
            "(given)",
            "left out with ratio_rad_per_m alone: the ratio is the whole transmission's (give coupler_ratio for a slider-crank of that ratio before the four-bar)",
        ));
    }
    let bar = FourBar {
        input: f.number_in("input_mm", LINK_LENGTH_MM)? * 1e-3,
        coupler: f.number_in("coupler_mm", LINK_LENGTH_MM)? * 1e-3,
        output: f.number_in("output_mm", LINK_LENGTH_MM)? * 1e-3,
    };
    f.finish()?;
    let (lo, hi) = match *linkage {
        LinkageSpec::Solve {
            angle_minus,
            angle_plus,
            ..
        } => (angle_minus, angle_plus),
        _ => (-stroke, stroke),
    };
    let limit = MIN_TRANSMISSION_ANGLE_DEG.to_radians();
    let range = bar.transmission_angle_range(lo, hi);
    if range.is_none_or(|(min, max)| min < limit || max > std::f64::consts::PI - limit) {
        let reached = range.map_or("past a toggle".to_string(), |(min, max)| {
            format!("from {:.1}° to {:.1}°", min.to_degrees(), max.to_degrees())
        });
        return Err(InputError::invalid(
            t.file(),
            &f.prefix_or("four_bar"),
            format!(
                "input {} mm, coupler {} mm, output {} mm",
                short_number(bar.input * 1e3),
                short_number(bar.coupler * 1e3),
                short_number(bar.output * 1e3)
            ),
            format!(
                "a four-bar whose transmission angle stays within {MIN_TRANSMISSION_ANGLE_DEG}° to {}° over the stroke from {:.1}° to {:.1}° (this one's runs {reached}): a longer coupler, a smaller gain input_mm/output_mm, or a smaller stroke",
                180.0 - MIN_TRANSMISSION_ANGLE_DEG,
                lo.to_degrees(),
                hi.to_degrees()
            ),
        ));
    }
    Ok(Some(bar))
}
