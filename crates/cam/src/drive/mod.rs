//! `drive`: will this actuator flap this wing to the required stroke at the flapping frequency, at
//! what voltage, with what margin to the field limit, through which linkage and at what mass
//! (docs/physics.md §15). The design's lumped tip model (§11.3), the transmission (§12) and the wing
//! (§13) make the flapping system of §14, whose harmonic balance gives the blocked-force amplitude,
//! and so the field, that holds the required stroke.

pub mod linkage_row;
pub mod mechanism;
pub mod operating_field;
pub mod operating_point;
pub mod operating_row;
pub mod report;
pub mod spec;
pub mod stages;
pub mod steady_state;
pub mod sweep;

use crate::design::Design;
use crate::input::InputError;
use crate::linkage::LinkageLaminate;
use actuator_model::flapping::{FlappingSystem, SteadyState};
use actuator_model::large_deflection::{small_angle_error_at, SMALL_ANGLE_BOUND};
use actuator_model::model::ModelChoice;
use actuator_model::ModelError;
pub use mechanism::{linkage_laminate_in, Mechanism};
use operating_field::FieldSearch;
use operating_point::OperatingPoint;
use operating_row::{mode_rows, operating_row};
use report::{ActuatorRow, DriveReport, MassRow, WingRow};
use spec::DriveSpec;
use stages::linkage_row;
use sweep::sweep;

/// Why a drive cannot be analysed.
#[derive(Debug, thiserror::Error)]
pub enum DriveError {
    /// The physics refused an input.
    #[error(transparent)]
    Model(#[from] ModelError),
    /// The drawn linkage cannot be made (a flexure, the template's `[linkage]`).
    #[error(transparent)]
    Input(#[from] InputError),
}

/// The analysis: the system, the steady state at the required stroke (or the best one within the field
/// limit) and the report in lab units.
#[derive(Debug, Clone)]
pub struct Analysis {
    /// Actuator + transmission + wing.
    pub system: FlappingSystem,
    /// The steady state reported: the required stroke when reached, else the best stroke within the
    /// field limit (`None` when no steady state was found at all).
    pub state: Option<SteadyState>,
    /// Everything printed and written.
    pub report: DriveReport,
    /// The signal field the steady state asks for (V/m; `None` without a steady state).
    pub operating_field: Option<f64>,
}

/// Analyse a drive file's design (already built for its process) under a model. With flexures in the
/// file, the transmission's stiffness, inertia and mass are the drawn linkage's. A model whose
/// stiffness and blocked force per field depend on the field (the nonlinear ceramic) is predicted at
/// the field its operating point needs: the operating point is found again at that field until the
/// field settles (docs/physics.md §18.5), and a field that does not settle is reported, not drawn on.
/// The wing and the linkage do not depend on the field: they are built once (`Mechanism`).
pub fn analyse(
    spec: &DriveSpec,
    design: &Design,
    model: &ModelChoice,
) -> Result<Analysis, DriveError> {
    let mechanism = Mechanism::of(spec, design, model)?;
    let first = OperatingPoint::at(spec, design.clone(), model, &mechanism)?;
    let (point, search) = if model.depends_on_field() {
        operating_field::settle(design.drive.field, first, OperatingPoint::asks, |field| {
            let mut at = design.clone();
            at.drive.field = field;
            OperatingPoint::at(spec, at, model, &mechanism)
        })?
    } else {
        (first, FieldSearch::Settled)
    };
    let mut analysis = report(spec, model, &mechanism, point)?;
    if let Some(why) = search.why() {
        analysis.refuse_operating_point(why);
    }
    Ok(analysis)
}

/// The analysis of the operating point `point` through `mechanism`, with its report in lab units.
fn report(
    spec: &DriveSpec,
    model: &ModelChoice,
    mechanism: &Mechanism,
    point: OperatingPoint,
) -> Result<Analysis, DriveError> {
    let OperatingPoint {
        design,
        perf,
        system,
        per_field,
        limits,
        state,
        ..
    } = &point;
    let (actuator, wing, f) = (system.actuator, mechanism.wing, spec.frequency);
    let operating = state
        .map(|s| operating_row(system, design, perf, spec.survival, *per_field, &s))
        .transpose()?;
    let modes = match point.required {
        Some(force) => mode_rows(spec, design, model, force)?,
        None => Vec::new(),
    };
    let past_small_deflection = operating
        .as_ref()
        .and_then(|o| past_small_deflection(design, o.tip_amplitude_mm * 1e-3));
    let sweep_force = state.map_or(per_field * limits.max_signal, |s| s.force);
    let total = perf.mass + mechanism.mass;
    let unreachable = point.unreachable.clone();
    let report = DriveReport {
        drive_file: spec.source.display().to_string(),
        design: design.name.clone(),
        model: model.name().to_string(),
        drive_mode: design.drive.mode.name().to_string(),
        frequency_Hz: f,
        required_stroke_deg: spec.transmission.stroke.to_degrees(),
        reached: unreachable.is_none()
            && mechanism.unbuildable.is_none()
            && past_small_deflection.is_none(),
        unbuildable_linkage: mechanism.unbuildable.clone(),
        past_small_deflection,
        unsettled_field: None,
        resonance_Hz: system.linear_resonance(),
        resonance_at_stroke_Hz: system.resonance_at_stroke(spec.transmission.stroke, f).ok(),
        actuator: ActuatorRow {
            resonance_Hz: point.modal_frequency,
            stiffness_N_per_m: perf.stiffness,
            modal_mass_mg: actuator.mass * 1e6,
            blocked_force_per_field_mN_per_V_per_mm: per_field * 1e6,
            free_deflection_mm: perf.free_deflection * 1e3,
            loss_factor: actuator.loss_factor,
        },
        linkage: linkage_row(
            &mechanism.kinematics,
            &spec.transmission,
            mechanism.two_stage.clone().and_then(Result::ok),
            (mechanism.flexure_stiffness, mechanism.link_inertia),
        ),
        wing: WingRow {
            inertia_mg_mm2: wing.inertia * 1e12,
            added_inertia_mg_mm2: wing.added_inertia * 1e12,
            damping_nN_m_s2: wing.damping * 1e9,
            mass_mg: wing.mass * 1e6,
        },
        field_limit_V_per_mm: limits.max_signal * 1e-3,
        field_limit_binds: limits.binds.name().to_string(),
        failure_limit_V_per_mm: limits.failure_limit * 1e-3,
        depolarization_limit_V_per_mm: limits.depolarization_limit * 1e-3,
        survival_limit: spec.survival,
        operating,
        modes,
        mass: MassRow {
            actuator_mg: perf.mass * 1e6,
            transmission_mg: mechanism.mass * 1e6,
            total_mg: total * 1e6,
            budget_mg: spec.mass_budget * 1e6,
            within_budget: total <= spec.mass_budget,
        },
        unreachable,
        sweep: sweep(system, sweep_force, f),
        linkage_laminate: mechanism.laminate.as_ref().map(LinkageLaminate::report),
    };
    report.ensure_finite()?;
    Ok(Analysis {
        system: point.system,
        operating_field: point.asks(),
        state: point.state,
        report,
    })
}

/// Why a tip amplitude `deflection` (m) is past the range the linear model holds, if it is
/// (docs/physics.md §3.1).
fn past_small_deflection(design: &Design, deflection: f64) -> Option<String> {
    let (l_p, l_ext) = (
        design.planform.piezo_length(),
        design.planform.extension_length(),
    );
    let error = small_angle_error_at(deflection, l_p, l_ext);
    (error > SMALL_ANGLE_BOUND).then(|| {
        format!(
            "the tip amplitude of {:.3} mm on a {:.1} mm actuator is past the small-deflection range the model holds: the small-angle deflection is {:.1} % too large, over the {:.0} % bound; a longer actuator or a linkage with more travel per degree",
            deflection * 1e3,
            design.planform.length * 1e3,
            error * 100.0,
            SMALL_ANGLE_BOUND * 100.0
        )
    })
}
