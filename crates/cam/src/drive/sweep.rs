//! The frequency response the report plots: stroke and phase over frequency at the operating force.

use super::report::SweepPoint;
use actuator_model::flapping::FlappingSystem;

/// Points of the frequency sweep.
pub const SWEEP_POINTS: usize = 61;

/// Phase of the stroke behind the force in degrees, in [-90, 270).
pub fn phase_deg(phase: f64) -> f64 {
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
