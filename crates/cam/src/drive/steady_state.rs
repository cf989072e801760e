//! The steady state the drive reports: the one at the required stroke when the field limits allow it,
//! else the best one within them, with the limit or the linkage's reach that binds and what would
//! have to change.

use super::report::Unreachable;
use super::spec::DriveSpec;
use super::stages;
use crate::design::Design;
use crate::input::fixed;
use actuator_model::drive::Drive;
use actuator_model::flapping::{FlappingSystem, SteadyState};
use actuator_model::poling::{Binding, FieldCheck};

/// The steady state at the required stroke, when the field limits allow it; else the best one within
/// them, and why the stroke is out of reach. Also the force amplitude the required stroke takes at any
/// field, where it has a steady state.
pub fn steady_state(
    spec: &DriveSpec,
    system: &FlappingSystem,
    design: &Design,
    per_field: f64,
    limits: &FieldCheck,
) -> (Option<SteadyState>, Option<Unreachable>, Option<f64>) {
    let force_limit = per_field * limits.max_signal;
    let f = spec.frequency;
    // The force the stroke needs whatever the field, then whether the field limits allow it.
    match system.force_for_stroke(spec.transmission.stroke, f, f64::INFINITY) {
        Ok(s) if s.force <= force_limit => (Some(s), None, Some(s.force)),
        Ok(s) => {
            let (best, why) = beyond_field_limit(spec, system, design, per_field, limits, &s);
            (best, why, Some(s.force))
        }
        Err(_) => {
            let (best, why) = no_steady_state(spec, system, design, limits, force_limit);
            (best, why, None)
        }
    }
}

/// The limit that binds the design's mode, in words.
fn binding_text(spec: &DriveSpec, design: &Design, limits: &FieldCheck) -> String {
    let mode = design.drive.mode.name();
    match limits.binds {
        Binding::Failure => format!(
            "the field limit of {mode} drive: {:.0} V/mm (Weibull survival {})",
            limits.max_signal * 1e-3,
            spec.survival
        ),
        Binding::Depolarization => format!(
            "the depolarization limit of {mode} drive: {:.0} V/mm against the poling ({}'s depolarization field)",
            limits.depolarization_limit * 1e-3,
            design.pzt.name
        ),
        Binding::Bias => format!(
            "the bias of biased drive: a signal of at most {:.0} V/mm, half the bias, keeps it between 0 and the bias",
            limits.max_signal * 1e-3
        ),
    }
}

/// What would relax the binding limit, besides a stronger actuator.
fn relief(limits: &FieldCheck) -> &'static str {
    match limits.binds {
        Binding::Failure => "a lower survival share",
        Binding::Depolarization => {
            "a drive that keeps each plate along its poling (mode = \"biased\" with a DC bias)"
        }
        Binding::Bias => "a higher bias (drive.bias_V)",
    }
}

/// The best steady state the stroke search found with the force held within `force_limit`.
fn best_within(spec: &DriveSpec, system: &FlappingSystem, force_limit: f64) -> Option<SteadyState> {
    system
        .force_for_stroke(spec.transmission.stroke, spec.frequency, force_limit)
        .err()
        .and_then(|u| u.best)
        .map(|b| *b)
}

/// A stroke whose steady state `s` needs more than the field limit: the best stroke within the
/// limit, and what would bring the required one within it.
fn beyond_field_limit(
    spec: &DriveSpec,
    system: &FlappingSystem,
    design: &Design,
    per_field: f64,
    limits: &FieldCheck,
    s: &SteadyState,
) -> (Option<SteadyState>, Option<Unreachable>) {
    let force_limit = per_field * limits.max_signal;
    let best = best_within(spec, system, force_limit);
    let field = s.force / per_field;
    // A bias past the limit on its own leaves no signal within it, and no stronger actuator helps.
    let stronger = if force_limit > 0.0 {
        format!(
            "it takes {:.2} times the blocked force per volt at this stiffness (a wider, longer or thinner-plated actuator)",
            s.force / force_limit
        )
    } else {
        "the bias alone is past the limit, so no signal is within it (a lower drive.bias_V)"
            .to_string()
    };
    let change = format!(
        "the stroke needs {:.0} V/mm in {} drive (field survival {}) against the limit of {:.0} V/mm ({}): {stronger}, {}, a smaller stroke, or a flapping frequency nearer the resonance ({:.1} Hz)",
        field * 1e-3,
        design.drive.mode.name(),
        fixed(Drive { field, ..design.drive }.survival(), 4),
        limits.max_signal * 1e-3,
        limits.binds.name(),
        relief(limits),
        nearest_resonance(system, spec.transmission.stroke),
    );
    (
        best,
        Some(Unreachable {
            best_stroke_deg: best.map_or(0.0, |b| b.stroke_amplitude.to_degrees()),
            binding: binding_text(spec, design, limits),
            change,
        }),
    )
}

/// A stroke with no steady state at any force: the best stroke within the field limit, and what
/// binds, the field limit, the linkage's dead point or its reach.
fn no_steady_state(
    spec: &DriveSpec,
    system: &FlappingSystem,
    design: &Design,
    limits: &FieldCheck,
    force_limit: f64,
) -> (Option<SteadyState>, Option<Unreachable>) {
    let linkage = system.linkage;
    let best = best_within(spec, system, force_limit);
    let reach = [-1.0, 1.0].map(|s| linkage.travel(s * spec.transmission.stroke).is_some());
    let at_limit = best.is_some_and(|b| b.force >= force_limit * (1.0 - 1e-6));
    let (binding, change) = if at_limit {
        (
            binding_text(spec, design, limits),
            format!(
                "more blocked force per volt at this stiffness (a wider, longer or thinner-plated actuator), {}, a smaller stroke, or a flapping frequency nearer the resonance ({:.1} Hz)",
                relief(limits),
                nearest_resonance(system, spec.transmission.stroke)
            ),
        )
    } else if reach == [true, true] {
        (
            format!(
                "no steady stroke of ±{:.1}° through this linkage ({}): the stroke's mean angle drifts toward the linkage's dead point",
                spec.transmission.stroke.to_degrees(),
                stages::describe(&linkage)
            ),
            "stiffer flexures (flexure_stiffness_uNm_per_rad) to centre the stroke, a longer coupler, or a smaller stroke".to_string(),
        )
    } else {
        (
            format!(
                "the linkage's reach: {} cannot turn the wing to ±{:.1}°",
                stages::describe(&linkage),
                spec.transmission.stroke.to_degrees()
            ),
            "a longer coupler, or a linkage solved for the stroke (solve_for_stroke = true)"
                .to_string(),
        )
    };
    (
        best,
        Some(Unreachable {
            best_stroke_deg: best.map_or(0.0, |b| b.stroke_amplitude.to_degrees()),
            binding,
            change,
        }),
    )
}

/// The resonance a user should move the flapping frequency towards: the one at the required stroke,
/// or the small-stroke one where the stroke has no steady state to resonate at.
fn nearest_resonance(system: &FlappingSystem, stroke: f64) -> f64 {
    system
        .resonance_at_stroke(stroke, system.linear_resonance())
        .unwrap_or_else(|_| system.linear_resonance())
}
