//! What `optimize` for a wing prints and writes: the text report, the drive file of the chosen design
//! (`drive` reads it beside the design file) and the front of mass against frequency margin as CSV.

use super::flap::{FlapOutcome, Screened, FRONT_LEVELS};
use super::report::{decimal, geometry_line, layup_label};
use super::search::Problem;
use super::spec::Spec;
use crate::drive::report::DriveReport;
use crate::input::{read_toml, InputError};
use std::fmt::Write;
use std::path::Path;

/// The drive file of the chosen design: the requirement's drive file with its design and its linkage's
/// travel replaced (the wing, frequency, stroke, survival and flexures as given: the search held the
/// design's field to that survival's limits).
pub fn drive_toml(
    flap: &Path,
    spec_file: &str,
    design_file: &str,
    travel: f64,
) -> Result<String, InputError> {
    let mut table = read_toml(flap)?;
    table.insert("design".into(), toml::Value::String(design_file.into()));
    if let Some(toml::Value::Table(t)) = table.get_mut("transmission") {
        t.insert("travel_mm".into(), toml::Value::Float(travel * 1e3));
    }
    let body = toml::to_string(&table)
        .map_err(|e| InputError::invalid(flap, "(drive file)", "(table)", e.to_string()))?;
    Ok(format!(
        "# The drive of the design optimized by `actuator-cam optimize {spec_file}` for the wing of\n\
         # {}: `actuator-cam drive` on this file. travel_mm is the linkage's size the optimizer chose.\n{body}",
        flap.display()
    ))
}

/// The text report: the requirement, the chosen design, its drive as `drive` computes it, the mass
/// budget and the front.
pub fn text(
    spec: &Spec,
    file: &str,
    problem: &Problem,
    outcome: &FlapOutcome,
    drive: &DriveReport,
) -> String {
    let c = &outcome.chosen;
    let d = &c.design;
    let cand = &problem.candidates[d.candidate];
    let mut s = String::new();
    let _ = writeln!(s, "actuator-cam optimize {file}");
    let _ = writeln!(
        s,
        "requirement: flap the wing of {} ±{}° at {} Hz, {} drive within {} V/mm",
        spec.flap
            .as_deref()
            .map_or(String::new(), |p| p.display().to_string()),
        decimal(drive.required_stroke_deg, 6),
        decimal(drive.frequency_Hz, 6),
        cand.section.drive.mode.name(),
        decimal(cand.section.drive.field * 1e-3, 3),
    );
    let _ = writeln!(
        s,
        "screen: {} laminate-shape-length points, the smallest base width of each meeting the wing's energy",
        outcome.screened
    );
    let _ = writeln!(
        s,
        "optimum: t_p {:.3} mm {}, l_tot {:.4} mm, l_r {:.4}, w_0 {:.3} mm, w_r {:.4}: actuator {:.3} mg",
        cand.pzt_thickness * 1e3,
        layup_label(&cand.layup),
        d.length * 1e3,
        d.extension_ratio,
        d.base_width * 1e3,
        d.width_ratio,
        c.performance.mass * 1e6
    );
    for bound in super::report::bounds_reached(problem, d) {
        let _ = writeln!(s, "  on the search's bounds: {bound}");
    }
    let _ = writeln!(
        s,
        "  energy ½ F_b δ        {:.3} µJ (the wing needs {:.3} µJ at the actuator's resonance of {:.1} Hz)",
        c.performance.energy * 1e6,
        c.requirement.energy * 1e6,
        c.actuator_frequency
    );
    let l = &drive.linkage;
    let _ = writeln!(
        s,
        "  linkage               travel ±{:.4} mm, crank {:.3} mm, coupler {:.3} mm",
        c.travel * 1e3,
        l.crank_mm,
        l.coupler_mm
    );
    let _ = writeln!(
        s,
        "  system resonance      {:.1} Hz: {:+.1} % from the flapping frequency",
        drive.resonance_Hz,
        (drive.resonance_Hz / drive.frequency_Hz - 1.0) * 100.0
    );
    if let Some(o) = &drive.operating {
        let _ = writeln!(
            s,
            "  drive (as `drive`)    ±{:.2}° at {:.1} V {}, field {:.1} V/mm of the limit {:.1} V/mm ({} binds; margins {:.1} V/mm to the failure fit, {:.1} V/mm to depolarization)",
            o.stroke_deg,
            o.voltage_V,
            drive.drive_mode,
            o.field_V_per_mm,
            drive.field_limit_V_per_mm,
            drive.field_limit_binds,
            o.poling.failure_margin_V_per_mm,
            o.poling.depolarization_margin_V_per_mm
        );
    }
    let m = &drive.mass;
    let _ = writeln!(
        s,
        "  mass budget           actuator + transmission {:.1} + {:.1} = {:.1} mg against {:.1} mg ({})",
        m.actuator_mg,
        m.transmission_mg,
        m.total_mg,
        m.budget_mg,
        if m.within_budget { "within" } else { "OVER" }
    );
    let _ = writeln!(
        s,
        "front of mass against frequency margin (screen; the lightest design whose system resonance is at least that far above the flapping frequency):"
    );
    let _ = writeln!(s, "  margin %   actuator mg   design");
    for p in &outcome.front {
        let _ = writeln!(
            s,
            "  {:>8.1}   {:>11.3}   {}",
            p.margin * 100.0,
            p.design.mass * 1e6,
            geometry_line(problem, &p.design, 3)
        );
    }
    if outcome.front.is_empty() {
        let _ = writeln!(
            s,
            "  (no screened design resonates above the flapping frequency, levels 0 to {} %)",
            5 * FRONT_LEVELS
        );
    }
    s
}

/// The front as CSV: margin, mass and the design's variables.
pub fn front_csv(problem: &Problem, front: &[Screened]) -> String {
    let mut s = String::from(
        "margin_percent,actuator_mass_mg,pzt_thickness_mm,layup_deg,length_mm,extension_ratio,base_width_mm,width_ratio\n",
    );
    for p in front {
        let d = &p.design;
        let c = &problem.candidates[d.candidate];
        let _ = writeln!(
            s,
            "{:.3},{:.6},{},{},{:.6},{:.6},{:.6},{:.6}",
            p.margin * 100.0,
            d.mass * 1e6,
            decimal(c.pzt_thickness * 1e3, 6),
            crate::design::layup::layup_text(&c.layup),
            d.length * 1e3,
            d.extension_ratio,
            d.base_width * 1e3,
            d.width_ratio
        );
    }
    s
}
