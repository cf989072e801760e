//! `drive`: will this actuator flap this wing to the required stroke at the flapping frequency, at
//! what voltage, with what margin to the field limit, through which linkage and at what mass
//! (docs/physics.md §15). The design's lumped tip model (§11.3), the transmission (§12) and the wing
//! (§13) make the flapping system of §14, whose harmonic balance gives the blocked-force amplitude,
//! and so the field, that holds the required stroke.

pub mod linkage_row;
pub mod operating_field;
pub mod report;
pub mod spec;
pub mod stages;

use crate::design::transmission::TransmissionSpec;
use crate::design::Design;
use crate::field_limits::{self as limits, ModeRow, PolingRow};
use crate::input::fixed;
use crate::input::InputError;
use crate::linkage::LinkageLaminate;
use crate::prediction::{actuator_modes, force_per_field, performance};
use crate::process::template::Template;
use actuator_model::drive::{Drive, DriveMode};
use actuator_model::dynamics::LumpedActuator;
use actuator_model::flapping::{FlappingSystem, SteadyState};
use actuator_model::large_deflection::{small_angle_error_at, SMALL_ANGLE_BOUND};
use actuator_model::model::ModelChoice;
use actuator_model::plate::{self, PlatePeak};
use actuator_model::poling::{Binding, FieldCheck};
use actuator_model::{ModelError, Performance, Section, Weibull};
use report::{ActuatorRow, DriveReport, MassRow, OperatingRow, SweepPoint, Unreachable, WingRow};
use spec::{DriveSpec, LinkageSpec};
use stages::{kinematics, linkage};
use std::f64::consts::PI;

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

/// Points of the frequency sweep.
pub const SWEEP_POINTS: usize = 61;

/// Samples a period for the peak stress and strain.
const PERIOD_SAMPLES: usize = 256;

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

/// The linkage laminate of a drive file for its design's process (docs/cam.md §7): the flexures the
/// file gives, or the shortest the film allows at the template's width when it gives none.
pub fn linkage_laminate(
    spec: &DriveSpec,
    design: &Design,
    model: &ModelChoice,
) -> Result<LinkageLaminate, DriveError> {
    let template = Template::resolve(&design.process, &design.source)?;
    linkage_laminate_in(&spec.transmission, &spec.source, design, model, &template)
}

/// The linkage laminate of the transmission `spec` (given in the file `source`, which refusals name)
/// with the materials and rules of `template`'s `[linkage]` (a batch's template, whose kerf is the
/// larger of the linkage's and the prepreg sheet's when the carbon shares the prepreg sheets).
pub fn linkage_laminate_in(
    spec: &TransmissionSpec,
    source: &std::path::Path,
    design: &Design,
    model: &ModelChoice,
    template: &Template,
) -> Result<LinkageLaminate, DriveError> {
    if let Some(refusal) = no_drawing(spec, source) {
        return Err(refusal.into());
    }
    let perf = performance(design, model)?;
    let Some(process) = template.linkage.as_ref() else {
        return Err(InputError::invalid(
            &template.source,
            "linkage",
            "(missing)",
            "a [linkage] table (materials of the flexure linkage laminate, docs/cam.md §7)",
        )
        .into());
    };
    Ok(LinkageLaminate::design(
        linkage(&spec.linkage, &perf)?,
        spec.end_angles(),
        &spec.flexures.clone().unwrap_or_default(),
        process,
        source,
        &template.source,
    )?)
}

/// Why no linkage drawing is made of a transmission: a ratio alone has no lengths, and the two-stage
/// linkage's flexures are checked by `drive` but its layer files are not drawn.
fn no_drawing(spec: &TransmissionSpec, source: &std::path::Path) -> Option<InputError> {
    let (field, value, why) = match (spec.linkage, spec.four_bar) {
        (LinkageSpec::Ratio(law), _) => (
            "transmission.ratio_rad_per_m",
            fixed(law.ratio, 0),
            "link lengths to draw: no linkage drawing can be made from a ratio alone (give coupler_ratio for the slider-crank of that ratio)",
        ),
        (_, Some(_)) => (
            "transmission.four_bar",
            "(given)".to_string(),
            "a one-stage slider-crank to draw: drive checks the two-stage linkage's flexures, but no layer files are drawn of it",
        ),
        _ => return None,
    };
    Some(InputError::invalid(source, field, value, why))
}

/// Why the linkage of a drive file that gives no flexures cannot be built with its design's process
/// (the flexure rules cut-sheet applies: the film's fatigue strain, the gap against the links beside it,
/// the carbon left bonded), or `None` when it can, or when the process has no `[linkage]` to build it with.
fn unbuildable_linkage(spec: &DriveSpec, design: &Design, model: &ModelChoice) -> Option<String> {
    // A ratio alone or a two-stage linkage is not drawn; the two-stage's flexures are checked apart.
    no_drawing(&spec.transmission, &spec.source)
        .is_none()
        .then_some(())?;
    let template = Template::resolve(&design.process, &design.source).ok()?;
    template.linkage.as_ref()?;
    let refusal =
        linkage_laminate_in(&spec.transmission, &spec.source, design, model, &template).err()?;
    // The refusal's field is the flexure request the file leaves out; what is wrong is its text.
    let why = match refusal {
        DriveError::Input(e) => e.expected,
        e => e.to_string(),
    };
    Some(format!(
        "{why}; to build it: a longer crank (a larger travel_mm), a thinner film (film_thickness_um), or a second stage"
    ))
}

/// Analyse a drive file's design (already built for its process) under a model. With flexures in the
/// file, the transmission's stiffness, inertia and mass are the drawn linkage's. A model whose
/// stiffness and blocked force per field depend on the field (the nonlinear ceramic) is predicted at
/// the field its operating point needs: the design is predicted again at that field until the field
/// settles (docs/physics.md §18.5), and a field that does not settle is reported, not drawn on.
pub fn analyse(
    spec: &DriveSpec,
    design: &Design,
    model: &ModelChoice,
) -> Result<Analysis, DriveError> {
    let analysis = analyse_at(spec, design, model)?;
    if !model.depends_on_field() {
        return Ok(analysis);
    }
    // The linkage stays the one sized from the design's free deflection at its own field.
    let mut spec = spec.clone();
    if let LinkageSpec::Solve { travel, .. } = &mut spec.transmission.linkage {
        travel.get_or_insert(analysis.report.actuator.free_deflection_mm * 1e-3);
    }
    let (mut analysis, search) = operating_field::settle(
        design.drive.field,
        analysis,
        |a: &Analysis| a.operating_field,
        |field| {
            let mut at = design.clone();
            at.drive.field = field;
            analyse_at(&spec, &at, model)
        },
    )?;
    if let Some(why) = search.why() {
        analysis.refuse_operating_point(why);
    }
    Ok(analysis)
}

/// [`analyse`] with the model predicted at the design's own field.
fn analyse_at(
    spec: &DriveSpec,
    design: &Design,
    model: &ModelChoice,
) -> Result<Analysis, DriveError> {
    let perf = performance(design, model)?;
    let modal = actuator_modes(design, model, &perf)?;
    let actuator = LumpedActuator::new(perf.stiffness, &modal, spec.loss_factor(model));
    let wing = spec.wing.wing();
    let linkage = kinematics(&spec.transmission, &perf)?;
    let laminate = match spec.transmission.flexures {
        Some(_) => Some(linkage_laminate(spec, design, model)?),
        None => None,
    };
    // A linkage given by its stiffness alone is still drawn, as cut-sheet would draw it, to check that
    // its flexures can be built at all.
    let template = Template::resolve(&design.process, &design.source).ok();
    let two_stage = stages::two_stage_flexures(&linkage, &spec.transmission, template.as_ref());
    let unbuildable = match (&laminate, &two_stage) {
        (_, Some(checked)) => checked.clone().err(),
        (Some(_), None) => None,
        (None, None) => unbuildable_linkage(spec, design, model),
    };
    let (flexure_stiffness, link_inertia, transmission_mass) = match &laminate {
        Some(l) => (l.flexure_stiffness(), l.link_inertia(), l.mass()),
        None => (
            spec.transmission.flexure_stiffness,
            spec.transmission.link_inertia,
            spec.transmission.transmission_mass,
        ),
    };
    let system = FlappingSystem {
        actuator,
        linkage,
        flexure_stiffness,
        inertia: wing.inertia + link_inertia,
        damping: wing.damping,
    };
    let mode = design.drive.mode;
    let per_field = force_per_field(design, model, mode)?;
    let limits = limits::check(design, &design.drive, spec.survival)?;
    let limit_field = limits.max_signal;
    let force_limit = per_field * limit_field;
    let f = spec.frequency;

    let (state, unreachable, required) = steady_state(spec, &system, design, per_field, &limits);

    let operating = state
        .map(|s| operating_row(&system, design, &perf, spec.survival, per_field, &s))
        .transpose()?;
    let modes = match required {
        Some(force) => mode_rows(spec, design, model, force)?,
        None => Vec::new(),
    };
    let past_small_deflection = operating
        .as_ref()
        .and_then(|o| past_small_deflection(design, o.tip_amplitude_mm * 1e-3));
    let sweep_force = state.map_or(force_limit, |s| s.force);
    let sweep = sweep(&system, sweep_force, f);
    let actuator_mass = perf.mass;
    let total = actuator_mass + transmission_mass;
    let report = DriveReport {
        drive_file: spec.source.display().to_string(),
        design: design.name.clone(),
        model: model.name().to_string(),
        drive_mode: mode.name().to_string(),
        frequency_Hz: f,
        required_stroke_deg: spec.transmission.stroke.to_degrees(),
        reached: unreachable.is_none() && unbuildable.is_none() && past_small_deflection.is_none(),
        unbuildable_linkage: unbuildable,
        past_small_deflection,
        unsettled_field: None,
        resonance_Hz: system.linear_resonance(),
        resonance_at_stroke_Hz: system.resonance_at_stroke(spec.transmission.stroke, f).ok(),
        actuator: ActuatorRow {
            resonance_Hz: modal.frequency,
            stiffness_N_per_m: perf.stiffness,
            modal_mass_mg: actuator.mass * 1e6,
            blocked_force_per_field_mN_per_V_per_mm: per_field * 1e6,
            free_deflection_mm: perf.free_deflection * 1e3,
            loss_factor: actuator.loss_factor,
        },
        linkage: stages::linkage_row(
            &linkage,
            &spec.transmission,
            two_stage.and_then(Result::ok),
            (flexure_stiffness, link_inertia),
        ),
        wing: WingRow {
            inertia_mg_mm2: wing.inertia * 1e12,
            added_inertia_mg_mm2: wing.added_inertia * 1e12,
            damping_nN_m_s2: wing.damping * 1e9,
            mass_mg: wing.mass * 1e6,
        },
        field_limit_V_per_mm: limit_field * 1e-3,
        field_limit_binds: limits.binds.name().to_string(),
        failure_limit_V_per_mm: limits.failure_limit * 1e-3,
        depolarization_limit_V_per_mm: limits.depolarization_limit * 1e-3,
        survival_limit: spec.survival,
        operating,
        modes,
        mass: MassRow {
            actuator_mg: actuator_mass * 1e6,
            transmission_mg: transmission_mass * 1e6,
            total_mg: total * 1e6,
            budget_mg: spec.mass_budget * 1e6,
            within_budget: total <= spec.mass_budget,
        },
        unreachable,
        sweep,
        linkage_laminate: laminate.as_ref().map(LinkageLaminate::report),
    };
    report.ensure_finite()?;
    Ok(Analysis {
        system,
        operating_field: state.map(|s| s.force / per_field),
        state,
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

/// The steady state at the required stroke, when the field limits allow it; else the best one within
/// them, and why the stroke is out of reach. Also the force amplitude the required stroke takes at any
/// field, where it has a steady state.
fn steady_state(
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
    let change = format!(
        "the stroke needs {:.0} V/mm in {} drive (field survival {}) against the limit of {:.0} V/mm ({}): it takes {:.2} times the blocked force per volt at this stiffness (a wider, longer or thinner-plated actuator), {}, a smaller stroke, or a flapping frequency nearer the resonance ({:.1} Hz)",
        field * 1e-3,
        design.drive.mode.name(),
        fixed(Drive { field, ..design.drive }.survival(), 4),
        limits.max_signal * 1e-3,
        limits.binds.name(),
        s.force / force_limit,
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

/// The field, voltage and margins to the limits the steady force needs in each drive mode.
fn mode_rows(
    spec: &DriveSpec,
    design: &Design,
    model: &ModelChoice,
    force: f64,
) -> Result<Vec<ModeRow>, ModelError> {
    DriveMode::ALL
        .into_iter()
        .map(|m| {
            let per = force_per_field(design, model, m)?;
            limits::mode_row(design, m, force, per, spec.survival)
        })
        .collect()
}

/// The operating point in lab units: field and voltage of the force, peak PZT stress and strain along
/// the plate over a period and the strain's Weibull survival, power into the wing and reactive power through the plates.
fn operating_row(
    system: &FlappingSystem,
    design: &Design,
    perf: &Performance,
    survival: f64,
    per_field: f64,
    s: &SteadyState,
) -> Result<OperatingRow, ModelError> {
    let mode = design.drive.mode;
    let field = s.force / per_field;
    let drive = Drive {
        field,
        ..design.drive
    };
    let check = limits::check(design, &drive, survival)?;
    let section = Section::new(&design.laminate()?, drive)?;
    let omega = 2.0 * PI * s.frequency;
    let mut peak = PlatePeak::default();
    for i in 0..PERIOD_SAMPLES {
        let phase = 2.0 * PI * i as f64 / PERIOD_SAMPLES as f64;
        let angle = s.angle_at(phase);
        let x = system.linkage.travel(angle).unwrap_or(0.0);
        // The tip load: what holds the tip back from its free motion (`F sin ωt - k x`), along the
        // whole plate (docs/physics.md §15).
        let load = s.force * phase.sin() - system.actuator.stiffness * x;
        peak = peak.max(plate::peak(
            &section,
            &design.planform,
            phase.sin(),
            load,
            0.0,
        ));
    }
    // ½ ω C V² per plate at the plate's AC field amplitude.
    let reactive: f64 = mode
        .layer_fields(field)
        .iter()
        .map(|e| 0.5 * omega * perf.capacitance * (e * design.pzt_thickness).powi(2))
        .sum();
    Ok(OperatingRow {
        stroke_deg: s.stroke_amplitude.to_degrees(),
        mean_angle_deg: s.mean_angle.to_degrees(),
        phase_deg: phase_deg(s.phase),
        tip_amplitude_mm: s.displacement_amplitude * 1e3,
        force_amplitude_N: s.force,
        field_V_per_mm: field * 1e-3,
        voltage_V: mode.voltage_from_field(field, design.pzt_thickness),
        survival: drive.survival(),
        peak_pzt_stress_MPa: peak.stress * 1e-6,
        peak_pzt_stress_x_over_l_p: peak.stress_at,
        peak_pzt_strain: peak.strain,
        peak_pzt_strain_x_over_l_p: peak.strain_at,
        strain_survival: Weibull::STRAIN.survival(peak.strain),
        peak_tip_load_N: s.peak_tip_load,
        mechanical_power_mW: s.aero_power * 1e3,
        reactive_power_mW: reactive * 1e3,
        poling: PolingRow::new(design, &drive, &check),
    })
}

/// Phase of the stroke behind the force in degrees, in [-90, 270).
/// The resonance a user should move the flapping frequency towards: the one at the required stroke,
/// or the small-stroke one where the stroke has no steady state to resonate at.
fn nearest_resonance(system: &FlappingSystem, stroke: f64) -> f64 {
    system
        .resonance_at_stroke(stroke, system.linear_resonance())
        .unwrap_or_else(|_| system.linear_resonance())
}

fn phase_deg(phase: f64) -> f64 {
    let d = phase.to_degrees().rem_euclid(360.0);
    if d >= 270.0 {
        d - 360.0
    } else {
        d
    }
}

/// The stroke and phase over frequency at one force amplitude: harmonic balance continued from point to
/// point; a frequency without a steady stroke within the linkage's reach is left out.
pub fn sweep(system: &FlappingSystem, force: f64, frequency: f64) -> Vec<SweepPoint> {
    let resonance = system.linear_resonance();
    let lo = 0.25 * frequency.min(resonance);
    let hi = 1.75 * frequency.max(resonance);
    let mut start = None;
    let mut points = Vec::with_capacity(SWEEP_POINTS);
    for i in 0..SWEEP_POINTS {
        let f = lo + (hi - lo) * i as f64 / (SWEEP_POINTS - 1) as f64;
        match system.harmonic_balance(force, f, start.as_ref()) {
            Ok(s) => {
                start = Some(s);
                points.push(SweepPoint {
                    frequency_Hz: f,
                    stroke_deg: s.stroke_amplitude.to_degrees(),
                    phase_deg: phase_deg(s.phase),
                });
            }
            Err(_) => start = None,
        }
    }
    points
}
