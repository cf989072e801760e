//! The operating point in lab units: the steady state's field and voltage in the design's mode, the
//! peak PZT stress and strain along the plate over a period, the powers, and the same force in every
//! drive mode against that mode's limits.

use super::report::OperatingRow;
use super::spec::DriveSpec;
use super::sweep::phase_deg;
use crate::design::Design;
use crate::field_limits::{self as limits, ModeRow, PolingRow};
use crate::prediction::force_per_field;
use actuator_model::drive::{Drive, DriveMode};
use actuator_model::flapping::{FlappingSystem, SteadyState};
use actuator_model::model::ModelChoice;
use actuator_model::plate::{self, PlatePeak};
use actuator_model::{ModelError, Performance, Section, Weibull};
use std::f64::consts::PI;

/// Samples a period for the peak stress and strain.
const PERIOD_SAMPLES: usize = 256;

/// The field, voltage and margins to the limits the steady force needs in each drive mode.
pub fn mode_rows(
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
pub fn operating_row(
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
