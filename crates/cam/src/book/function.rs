//! The functional check that closes every build book: each actuator weighed, its plates' capacitance
//! measured, and its bend at a low voltage seen and measured, each against the prediction with the
//! band a good actuator falls in (docs/cam.md §6, "The functional check").

use super::DesignFacts;
use crate::design::Design;
use crate::markdown;
use crate::prediction::Prediction;
use actuator_model::capacitance::plate_capacitance;
use actuator_model::model::ModelKind;

/// The field of the low-voltage check, V/mm: a third of the 0.3 kV/mm at which PZT-5H begins to
/// depolarise against its poling (docs/physics.md §8), so the plate driven against its poling
/// (parallel drive) keeps it.
pub const LOW_FIELD_V_PER_MM: f64 = 100.0;

/// ζ of the thesis' mass equation (eq. 4.3, docs/physics.md §7): its built actuators carried 0.94 of
/// the carbon's mass again, in resin the model does not count.
pub const RESIN_ZETA: f64 = 0.94;

/// The capacitance band, ± of the prediction: an assumption, the supplier's K33 being a typical
/// value and not a bound; a lab narrows it from its own good plates.
const CAPACITANCE_BAND: f64 = 0.2;

/// What the check compares each design's actuators with: the original model's prediction at the
/// design's drive, and the PZT's permittivity the capacitance comes from.
#[derive(Debug, Clone, PartialEq)]
pub struct Expected {
    /// PZT material name, as the design names it.
    pub pzt: String,
    /// Its relative permittivity K33.
    pub k33: f64,
    /// Plate thickness, mm.
    pub pzt_thickness_mm: f64,
    /// Model mass of one actuator, mg, and of its passive layer.
    pub mass_mg: f64,
    pub passive_mass_mg: f64,
    /// Free deflection at the design's field, mm, and that field and voltage.
    pub free_deflection_mm: f64,
    pub field_v_per_mm: f64,
    pub voltage_v: f64,
    /// Extension ratio l_r (the thesis' deflection factor, eq. 4.4, depends on it).
    pub extension_ratio: f64,
    /// Drive mode name.
    pub drive_mode: String,
}

impl Expected {
    /// The original model's prediction of `design` (none if the model refuses it), its bond mass the
    /// bond parts as drawn, `bond_mg`, when the build cuts them.
    pub fn of(design: &Design, bond_mg: Option<f64>) -> Option<Expected> {
        let p = Prediction::of(design, ModelKind::Original).ok()?;
        let p = match bond_mg {
            Some(b) => p.with_drawn_bond(b),
            None => p,
        };
        Some(Expected {
            pzt: design.pzt.name.clone(),
            k33: design.pzt.relative_permittivity,
            pzt_thickness_mm: design.pzt_thickness * 1e3,
            mass_mg: p.mass_mg,
            passive_mass_mg: p.mass_breakdown_mg.passive,
            free_deflection_mm: p.free_deflection_mm,
            field_v_per_mm: p.field_V_per_mm,
            voltage_v: p.voltage_V,
            extension_ratio: design.planform.extension_ratio,
            drive_mode: design.drive.mode.name().to_string(),
        })
    }

    /// One plate's capacitance, nF, for a drawn plate of `area_mm2`: `C = ε0 K33 A / t_p`.
    pub fn capacitance_nf(&self, area_mm2: f64) -> f64 {
        plate_capacitance(self.k33, area_mm2 * 1e-6, self.pzt_thickness_mm * 1e-3) * 1e9
    }
}

/// The thesis' measured share of the original model's free deflection at extension ratio `l_r`
/// (eq. 4.4, docs/physics.md §7), at least 0.
pub fn thesis_deflection_factor(l_r: f64) -> f64 {
    (-0.490 * l_r * l_r + 0.204 * l_r + 0.645).max(0.0)
}

/// The capacitance step of `d`, whose drawn plate has `area_mm2`.
pub(super) fn capacitance_step(d: &DesignFacts, area_mm2: f64) -> String {
    let name = markdown::text(&d.name);
    let Some(e) = &d.expected else {
        return format!(
            "{name}: measure each PZT layer's capacitance, outer face to the carbon, on an LCR meter \
             at 1 kHz. Well below the other plates' value, the plate is cracked or unbonded (thesis \
             §4.9.1-2)."
        );
    };
    let c = e.capacitance_nf(area_mm2);
    format!(
        "{name}: measure each PZT layer's capacitance, outer face to the carbon, on an LCR meter at \
         1 kHz. Expected {c:.2} nF per plate, {:.2} to {:.2} nF: C = ε0 K33 A / t_p (docs/physics.md \
         §10) with the plate as drawn, A = {area_mm2:.2} mm², t_p = {} mm, and K33 = {} of {} \
         (docs/physics.md §8), a typical value and not a bound: ±{:.0} % (an assumption, to be \
         narrowed from a lab's good plates). Well below it, the plate is cracked or unbonded \
         (thesis §4.9.1-2).",
        c * (1.0 - CAPACITANCE_BAND),
        c * (1.0 + CAPACITANCE_BAND),
        e.pzt_thickness_mm,
        e.k33,
        markdown::text(&e.pzt),
        CAPACITANCE_BAND * 100.0,
    )
}

/// The weighing of each design's actuators, released and trimmed, before the wires go on.
pub(super) fn weigh_steps(designs: &[DesignFacts]) -> Vec<String> {
    designs
        .iter()
        .filter_map(|d| {
            let e = d.expected.as_ref()?;
            Some(format!(
                "{}: weigh each actuator before the wires go on: the model's {:.2} mg to {:.2} mg \
                 (the thesis' built actuators carried {RESIN_ZETA} of the carbon's {:.2} mg again in \
                 resin, eq. 4.3, docs/physics.md §7). Lighter, a plate is chipped or a part short; \
                 heavier, squeeze-out or silver epoxy is left on.",
                markdown::text(&d.name),
                e.mass_mg,
                e.mass_mg + RESIN_ZETA * e.passive_mass_mg,
                e.passive_mass_mg
            ))
        })
        .collect()
}

/// The functional check of each design's actuators, wired: polarity, bend and free deflection at a
/// low voltage, then the record of every check against its band.
pub(super) fn function_steps(designs: &[DesignFacts]) -> Vec<String> {
    let mut steps = Vec::new();
    for d in designs {
        let Some(e) = &d.expected else { continue };
        let field = LOW_FIELD_V_PER_MM.min(e.field_v_per_mm);
        let scale = field / e.field_v_per_mm;
        let volts = e.voltage_v * scale;
        let delta = e.free_deflection_mm * scale;
        let factor = thesis_deflection_factor(e.extension_ratio);
        let toward = if e.drive_mode == "parallel" {
            " toward the dotted face (the upper plate, driven along its poling, shortens)"
        } else {
            ""
        };
        steps.push(format!(
            "{}: polarity, bend and poling at a low voltage: clamp the actuator by its base and \
             drive it in its {} mode at {volts:.1} V ({field:.0} V/mm, a third of the 0.3 kV/mm \
             where PZT-5H begins to depolarise, docs/physics.md §8), + on the red wire. The tip must \
             bend{toward}; the other way, the wires or a plate are reversed. Its free deflection, \
             under a microscope or a displacement sensor: {:.4} to {:.4} mm, from the share of the \
             original model the thesis' built actuators reached, {factor:.3} at l_r = {} (eq. 4.4, \
             docs/physics.md §7), to the model's own {delta:.4} mm (linear in the field, \
             docs/physics.md §3). Less, with the capacitance right, is a plate depoled in the cure \
             or unbonded.",
            markdown::text(&d.name),
            e.drive_mode,
            delta * factor,
            delta,
            e.extension_ratio,
        ));
    }
    steps.push(
        "Record each actuator's mass, capacitances and free deflection beside its number: one \
         outside its band is set aside, not built into a flight part."
            .into(),
    );
    steps
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_thesis_deflection_factor_is_eq_4_4_and_never_negative() {
        // Thesis eq. 4.4 at l_r = 0: 0.645; at l_r = 0.5: -0.1225 + 0.102 + 0.645 = 0.6245.
        assert!((thesis_deflection_factor(0.0) - 0.645).abs() < 1e-12);
        assert!((thesis_deflection_factor(0.5) - 0.6245).abs() < 1e-12);
        // Past its root near l_r = 1.38 the fit would go negative: no lower bound then.
        assert_eq!(thesis_deflection_factor(2.0), 0.0);
    }
}
