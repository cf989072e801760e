//! The transmission the drive flaps the wing through, in whichever form the drive file gives it: the
//! slider-crank of eq. 2.5, the two-stage linkage of a slider-crank and an amplifying four-bar, or a
//! published ratio law (docs/physics.md §12, §16.8).

use super::linkage_row::RatioLawRow;
use super::report::LinkageRow;
use crate::design::transmission::{LinkageSpec, TransmissionSpec};
use crate::linkage::flexures::check_two_stage;
use crate::process::template::Template;
use actuator_model::fourbar::{TwoStage, TWO_STAGE_JOINTS};
use actuator_model::kinematics::Kinematics;
use actuator_model::transmission::Linkage;
use actuator_model::{ModelError, Performance};

/// The first stage's linkage of the spec; a solved one from `travel` (the actuator's free deflection
/// unless the file gives one). A ratio alone has none.
pub fn linkage(spec: &LinkageSpec, performance: &Performance) -> Result<Linkage, ModelError> {
    match *spec {
        LinkageSpec::Given {
            coupler,
            crank,
            offset,
        } => Linkage::new(coupler, crank, offset),
        LinkageSpec::Solve {
            angle_minus,
            angle_plus,
            coupler_ratio,
            travel,
        } => Linkage::solve(
            travel.unwrap_or(performance.free_deflection),
            angle_minus,
            angle_plus,
            coupler_ratio,
        ),
        LinkageSpec::Ratio(law) => Err(ModelError::OutOfRange {
            name: "transmission",
            value: law.ratio,
            range: "a linkage's lengths, not a ratio alone",
        }),
    }
}

/// The transmission's kinematics: a solved two-stage linkage's first stage is solved for the four-bar's
/// input turns at the wing's end angles ([`TwoStage::solve`]).
pub fn kinematics(spec: &TransmissionSpec, perf: &Performance) -> Result<Kinematics, ModelError> {
    match (spec.linkage, spec.four_bar) {
        (LinkageSpec::Ratio(law), _) => Ok(Kinematics::Ratio(law)),
        (
            LinkageSpec::Solve {
                angle_minus,
                angle_plus,
                coupler_ratio,
                travel,
            },
            Some(second),
        ) => TwoStage::solve(
            travel.unwrap_or(perf.free_deflection),
            angle_minus,
            angle_plus,
            coupler_ratio,
            second,
        )
        .ok_or(ModelError::OutOfRange {
            name: "four_bar",
            value: angle_plus,
            range: "end angles within the four-bar's toggles",
        })?
        .map(Kinematics::TwoStage),
        (given, Some(second)) => Ok(Kinematics::TwoStage(TwoStage {
            first: linkage(&given, perf)?,
            second,
        })),
        (given, None) => linkage(&given, perf).map(Kinematics::from),
    }
}

/// The two-stage linkage's flexures at the template's film and flexure width, each the shortest the film
/// allows over the stroke (docs/physics.md §16.8); `Err` says why one cannot be made, for the report's
/// NOT BUILDABLE line. `None` without a two-stage linkage or a `[linkage]` in the template.
pub fn two_stage_flexures(
    kinematics: &Kinematics,
    spec: &TransmissionSpec,
    template: Option<&Template>,
) -> Option<Result<Vec<crate::linkage::flexures::FlexureRow>, String>> {
    let (Kinematics::TwoStage(stage), Some(process)) =
        (kinematics, template.and_then(|t| t.linkage.as_ref()))
    else {
        return None;
    };
    Some(
        check_two_stage(
            stage,
            spec.end_angles(),
            process.flexure_width_mm,
            process.film.thickness_mm,
            process,
        )
        .map_err(|r| {
            format!(
                "flexure {}: {}; to build it: a longer crank (a larger travel_mm), longer four-bar links, or a thinner film",
                TWO_STAGE_JOINTS[r.joint], r.allowed
            )
        }),
    )
}

/// The transmission in the report: lengths, the four-bar's or the ratio law's numbers, the flexures.
pub fn linkage_row(
    kinematics: &Kinematics,
    spec: &TransmissionSpec,
    flexures: Option<Vec<crate::linkage::flexures::FlexureRow>>,
    stiffness_and_inertia: (f64, f64),
) -> LinkageRow {
    let first = match kinematics {
        Kinematics::SliderCrank(l) => Some(*l),
        Kinematics::TwoStage(s) => Some(s.first),
        Kinematics::Ratio(_) => None,
    };
    let t0 = kinematics.ratio(0.0).unwrap_or(1.0 / kinematics.lever());
    let ratio_law = match spec.linkage {
        LinkageSpec::Ratio(law) => Some(RatioLawRow {
            at_rest_rad_per_m: law.ratio,
            stroke_deg: spec.stroke.to_degrees(),
            at_stroke_rad_per_m: kinematics.ratio_at_angle(spec.stroke),
        }),
        _ => None,
    };
    LinkageRow {
        coupler_mm: first.map_or(0.0, |l| l.coupler * 1e3),
        crank_mm: first.map_or(0.0, |l| l.crank * 1e3),
        offset_mm: first.map_or(0.0, |l| l.offset * 1e3),
        ratio_at_rest_deg_per_mm: t0.to_degrees() * 1e-3,
        flexure_stiffness_uNm_per_rad: stiffness_and_inertia.0 * 1e6,
        link_inertia_mg_mm2: stiffness_and_inertia.1 * 1e12,
        four_bar_mm: spec
            .four_bar
            .map(|f| [f.input * 1e3, f.coupler * 1e3, f.output * 1e3]),
        ratio_law,
        flexures,
    }
}

/// The linkage in words for a binding line: its lengths, or the ratio law.
pub fn describe(kinematics: &Kinematics) -> String {
    match kinematics {
        Kinematics::SliderCrank(l) => format!(
            "coupler {:.3} mm, crank {:.3} mm",
            l.coupler * 1e3,
            l.crank * 1e3
        ),
        Kinematics::TwoStage(s) => format!(
            "coupler {:.3} mm, crank {:.3} mm, four-bar {:.3} / {:.3} / {:.3} mm",
            s.first.coupler * 1e3,
            s.first.crank * 1e3,
            s.second.input * 1e3,
            s.second.coupler * 1e3,
            s.second.output * 1e3
        ),
        Kinematics::Ratio(r) => format!("the ratio law of {:.0} rad/m at rest", r.ratio),
    }
}
