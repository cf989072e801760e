//! A prediction at the file edge: the model's SI performance turned into the lab's units, as printed by
//! `predict` and embedded in cut-sheet reports.

use crate::design::Design;
use crate::field_limits::{mode_row, modes_table, ModeRow};
use crate::input::{ensure_finite, short_number, InputError};
use actuator_model::dynamics::{ActuatorBeam, Modal};
use actuator_model::effects::Actuator;
use actuator_model::model::{predict, ModelChoice, ModelKind};
use actuator_model::performance::evaluate;
use actuator_model::{Base, Drive, DriveMode, Laminate, ModelError, Performance, Section, Weibull};
use serde::Serialize;
use std::fmt::Write;

/// Mass by layer kind, mg.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct MassBreakdownMg {
    /// Both PZT plates.
    pub pzt: f64,
    /// Passive plies under the PZT, extension and tab.
    pub passive: f64,
    /// Bond layers.
    pub bond: f64,
    /// Mass no layer carries (a calibrated model's added masses); left out of the JSON when zero.
    #[serde(skip_serializing_if = "is_zero")]
    pub added: f64,
}

fn is_zero(x: &f64) -> bool {
    *x == 0.0
}

/// Predicted performance in lab units (the `predict --json` object).
#[derive(Debug, Clone, PartialEq, Serialize)]
#[allow(non_snake_case)] // the unit is part of the field name: `blocked_force_N`, `energy_mJ`
pub struct Prediction {
    pub name: String,
    pub model: String,
    pub drive_mode: String,
    pub mass_mg: f64,
    pub free_deflection_mm: f64,
    pub blocked_force_N: f64,
    pub energy_mJ: f64,
    pub energy_density_J_per_kg: f64,
    pub stiffness_N_per_m: f64,
    pub field_V_per_mm: f64,
    pub voltage_V: f64,
    pub survival: f64,
    /// Peak strain and stress along the active length from free to blocked, and where each is
    /// (`x / l_p`).
    pub peak_pzt_strain: f64,
    pub peak_pzt_strain_x_over_l_p: f64,
    /// Survival of the peak strain by the thesis' strain fit (Table 4.12).
    pub strain_survival: f64,
    pub peak_pzt_stress_MPa: f64,
    pub peak_pzt_stress_x_over_l_p: f64,
    pub base_stress_MPa: f64,
    pub capacitance_nF: f64,
    pub mass_breakdown_mg: MassBreakdownMg,
    /// First natural frequency of the bare clamped actuator (`predict` only; docs/physics.md §11).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub resonance_Hz: Option<f64>,
    /// Lumped tip mass `k / ω1²` (`predict` only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub modal_mass_mg: Option<f64>,
    /// The same free deflection in every drive mode against the limits on the plates' field at
    /// survival `DESIGN_SURVIVAL` (`predict` only; docs/physics.md §2.1).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub modes: Option<Vec<ModeRow>>,
}

/// The survival share `predict` holds each mode's failure fit to: the thesis' design point (§4.10,
/// 90 % survival).
pub const DESIGN_SURVIVAL: f64 = 0.9;

/// The actuator's raw inputs as the effects take them.
pub fn actuator(design: &Design) -> Actuator<'_> {
    Actuator {
        pzt: &design.pzt,
        pzt_thickness: design.pzt_thickness,
        ply: &design.ply,
        ply_thickness: design.ply_thickness,
        layup_deg: &design.layup_deg,
        planform: design.planform,
        drive: design.drive,
    }
}

/// The first mode of a design's bare clamped actuator under a model, with its static stiffness set to
/// the prediction's `F_b / δ` (docs/physics.md §11.3). The built-in models use the section's beam, its
/// masses scaled to the prediction's mass (the thesis-adjusted model changes the ply mass), and so does a
/// calibrated model on the nonlinear base, on its effects' laminate; a calibrated model on the original
/// base uses its effects' beam (clamp, rigid root, compliant extension, stiffness scale).
pub fn actuator_modes(
    design: &Design,
    model: &ModelChoice,
    performance: &Performance,
) -> Result<Modal, ModelError> {
    let beam = match model {
        ModelChoice::Kind(_) => section_beam(&design.laminate()?, design, performance)?,
        // The nonlinear base's effects are in its laminate (ply thickness, bond layer).
        ModelChoice::Calibrated(calibrated) if calibrated.base == Base::Nonlinear => section_beam(
            &calibrated.nonlinear_laminate(&actuator(design))?,
            design,
            performance,
        )?,
        ModelChoice::Calibrated(calibrated) => {
            let physics = calibrated.effect_model()?;
            let a = actuator(design);
            physics.beam(&physics.basis(&a)?, &physics.mass(&a)?)
        }
    };
    // A uniform stiffness factor moves k and ω1² together (§11.3).
    Ok(beam.solve()?.with_stiffness(performance.stiffness))
}

/// The beam of a laminate's section at the design's planform, its masses scaled to the prediction's
/// mass.
fn section_beam(
    laminate: &Laminate,
    design: &Design,
    performance: &Performance,
) -> Result<ActuatorBeam, ModelError> {
    let section = Section::new(laminate, design.drive)?;
    let beam = ActuatorBeam::from_section(&section, &design.planform);
    let scale = performance.mass / evaluate(&section, &design.planform).mass;
    Ok(ActuatorBeam {
        areal_mass: beam.areal_mass * scale,
        extension_areal_mass: beam.extension_areal_mass * scale,
        ..beam
    })
}

/// Blocked force per unit peak plate field of a design in a drive mode, N/(V/m) (the model is linear
/// in the field).
pub fn force_per_field(
    design: &Design,
    model: &ModelChoice,
    mode: DriveMode,
) -> Result<f64, ModelError> {
    let mut d = design.clone();
    d.drive = Drive::new(mode, design.drive.field);
    Ok(performance(&d, model)?.blocked_force / design.drive.field)
}

/// The model's performance of a design at its drive (SI): a built-in model on the design's laminate, a
/// calibrated one on its effects.
pub fn performance(design: &Design, model: &ModelChoice) -> Result<Performance, ModelError> {
    match model {
        ModelChoice::Kind(kind) => {
            predict(*kind, &design.laminate()?, &design.planform, design.drive)
        }
        ModelChoice::Calibrated(_) => model.predict(&actuator(design)),
    }
}

impl Prediction {
    /// Predict a design with one of the built-in models.
    pub fn of(design: &Design, kind: ModelKind) -> Result<Prediction, ModelError> {
        let laminate = design.laminate()?;
        let perf = predict(kind, &laminate, &design.planform, design.drive)?;
        Ok(Self::from_performance(design, kind.name(), &perf))
    }

    /// Predict a design with a built-in or a calibrated model. A calibrated model replaces the design's
    /// declared bond layer by its own fitted effects (it was fitted on built actuators, bond and all).
    pub fn with_model(design: &Design, model: &ModelChoice) -> Result<Prediction, ModelError> {
        match model {
            ModelChoice::Kind(kind) => Self::of(design, *kind),
            ModelChoice::Calibrated(_) => {
                let perf = model.predict(&actuator(design))?;
                Ok(Self::from_performance(design, model.name(), &perf))
            }
        }
    }

    /// The prediction with the bare actuator's resonance and lumped tip mass (what `predict` prints).
    pub fn with_dynamics(design: &Design, model: &ModelChoice) -> Result<Prediction, ModelError> {
        let performance = performance(design, model)?;
        let modal = actuator_modes(design, model, &performance)?;
        let mut p = Self::from_performance(design, model.name(), &performance);
        p.resonance_Hz = Some(modal.frequency);
        p.modal_mass_mg = Some(modal.modal_mass() * 1e6);
        // The modes the model covers (Euler-Bernoulli takes parallel and series only).
        let modes = DriveMode::ALL
            .into_iter()
            .filter_map(|m| force_per_field(design, model, m).ok().map(|per| (m, per)))
            .map(|(m, per)| mode_row(design, m, performance.blocked_force, per, DESIGN_SURVIVAL))
            .collect::<Result<Vec<_>, _>>()?;
        p.modes = Some(modes);
        Ok(p)
    }

    /// Convert a model performance (SI) for a design into lab units.
    pub fn from_performance(design: &Design, model: &str, p: &Performance) -> Prediction {
        let drive = design.drive;
        Prediction {
            name: design.name.clone(),
            model: model.to_string(),
            drive_mode: drive.mode.name().to_string(),
            mass_mg: p.mass * 1e6,
            free_deflection_mm: p.free_deflection * 1e3,
            blocked_force_N: p.blocked_force,
            energy_mJ: p.energy * 1e3,
            energy_density_J_per_kg: p.energy_density,
            stiffness_N_per_m: p.stiffness,
            field_V_per_mm: drive.field * 1e-3,
            voltage_V: drive
                .mode
                .voltage_from_field(drive.field, design.pzt_thickness),
            survival: drive.survival(),
            peak_pzt_strain: p.peak_pzt_strain,
            peak_pzt_strain_x_over_l_p: p.peak_pzt_strain_at,
            strain_survival: Weibull::STRAIN.survival(p.peak_pzt_strain),
            peak_pzt_stress_MPa: p.peak_pzt_stress * 1e-6,
            peak_pzt_stress_x_over_l_p: p.peak_pzt_stress_at,
            base_stress_MPa: p.base_stress * 1e-6,
            capacitance_nF: p.capacitance * 1e9,
            mass_breakdown_mg: MassBreakdownMg {
                pzt: p.mass_breakdown.pzt * 1e6,
                passive: p.mass_breakdown.passive * 1e6,
                bond: p.mass_breakdown.bond * 1e6,
                added: p.mass_breakdown.added * 1e6,
            },
            resonance_Hz: None,
            modal_mass_mg: None,
            modes: None,
        }
    }

    /// The prediction with its bond mass from the bond parts as drawn, mg (method 1's Pyralux parts
    /// are the plate inset by the template's `inset_mm`, docs/cam.md §1): the actuator's mass and its
    /// energy density follow, so the geometry's mass and the model's are the same parts. The model's
    /// stiffness keeps the bond over the whole plate: the strip a 0.15 mm inset leaves out is a film
    /// 170 times softer than the carbon beside it. A prediction with no bond mass (method 2, or a
    /// calibrated model, whose fitted effects hold the bond) is kept as it is.
    pub fn with_drawn_bond(mut self, bond_mg: f64) -> Prediction {
        if self.mass_breakdown_mg.bond <= 0.0 {
            return self;
        }
        let m = &mut self.mass_breakdown_mg;
        m.bond = bond_mg;
        let mass = m.pzt + m.passive + m.bond + m.added;
        // D = U / m (docs/physics.md §3): the same energy over the drawn mass.
        self.energy_density_J_per_kg *= self.mass_mg / mass;
        self.mass_mg = mass;
        self
    }

    /// Every number by its `--json` name, for the finite check.
    pub fn numbers(&self) -> Vec<(&'static str, f64)> {
        let mut numbers = vec![
            ("mass_mg", self.mass_mg),
            ("free_deflection_mm", self.free_deflection_mm),
            ("blocked_force_N", self.blocked_force_N),
            ("energy_mJ", self.energy_mJ),
            ("energy_density_J_per_kg", self.energy_density_J_per_kg),
            ("stiffness_N_per_m", self.stiffness_N_per_m),
            ("field_V_per_mm", self.field_V_per_mm),
            ("voltage_V", self.voltage_V),
            ("survival", self.survival),
            ("peak_pzt_strain", self.peak_pzt_strain),
            (
                "peak_pzt_strain_x_over_l_p",
                self.peak_pzt_strain_x_over_l_p,
            ),
            ("strain_survival", self.strain_survival),
            ("peak_pzt_stress_MPa", self.peak_pzt_stress_MPa),
            (
                "peak_pzt_stress_x_over_l_p",
                self.peak_pzt_stress_x_over_l_p,
            ),
            ("base_stress_MPa", self.base_stress_MPa),
            ("capacitance_nF", self.capacitance_nF),
            ("mass_breakdown_mg.pzt", self.mass_breakdown_mg.pzt),
            ("mass_breakdown_mg.passive", self.mass_breakdown_mg.passive),
            ("mass_breakdown_mg.bond", self.mass_breakdown_mg.bond),
        ];
        numbers.extend(self.resonance_Hz.map(|f| ("resonance_Hz", f)));
        numbers.extend(self.modal_mass_mg.map(|m| ("modal_mass_mg", m)));
        numbers
    }

    /// Refuse a prediction with a number that is not finite, naming the design fields that produced it
    /// (no `NaN` on screen, no `null` in JSON). `predict` calls it before printing; cut-sheet's report
    /// should call it before writing.
    pub fn ensure_finite(&self, design: &Design) -> Result<(), InputError> {
        let p = &design.planform;
        let written = format!(
            "length_mm = {}, extension_ratio = {}, base_width_mm = {}, width_ratio = {}, pzt_thickness_mm = {}, ply_thickness_mm = {}, field_V_per_mm = {}",
            short_number(p.length * 1e3),
            short_number(p.extension_ratio),
            short_number(p.base_width * 1e3),
            short_number(p.width_ratio),
            short_number(design.pzt_thickness * 1e3),
            short_number(design.ply_thickness * 1e3),
            short_number(design.drive.field * 1e-3),
        );
        ensure_finite(
            &design.source,
            "geometry, laminate, drive",
            &written,
            self.numbers(),
        )
    }

    /// A readable table, one quantity per line.
    pub fn table(&self) -> String {
        let mut rows: Vec<(&str, String, &str)> = vec![
            ("mass", format!("{:.2}", self.mass_mg), "mg"),
            (
                "  PZT plates",
                format!("{:.2}", self.mass_breakdown_mg.pzt),
                "mg",
            ),
            (
                "  passive",
                format!("{:.2}", self.mass_breakdown_mg.passive),
                "mg",
            ),
            (
                "  bond",
                format!("{:.2}", self.mass_breakdown_mg.bond),
                "mg",
            ),
            (
                "free deflection",
                format!("{:.4}", self.free_deflection_mm),
                "mm (one-sided)",
            ),
            (
                "blocked force",
                format!("{:.2}", self.blocked_force_N * 1e3),
                "mN",
            ),
            ("energy", format!("{:.4}", self.energy_mJ), "mJ"),
            (
                "energy density",
                format!("{:.4}", self.energy_density_J_per_kg),
                "J/kg",
            ),
            ("stiffness", format!("{:.1}", self.stiffness_N_per_m), "N/m"),
            ("field", format!("{:.1}", self.field_V_per_mm), "V/mm"),
            ("voltage", format!("{:.1}", self.voltage_V), "V"),
            (
                "survival (field)",
                format!("{:.3}", self.survival),
                "(thesis Table 4.12)",
            ),
            (
                "peak PZT strain",
                format!("{:.0}", self.peak_pzt_strain * 1e6),
                "µm/m (free to blocked, along the plate)",
            ),
            (
                "  at x/l_p",
                format!("{:.2}", self.peak_pzt_strain_x_over_l_p),
                "",
            ),
            (
                "  strain survival",
                format!("{:.4}", self.strain_survival),
                "(thesis Table 4.12)",
            ),
            (
                "peak PZT stress",
                format!("{:.1}", self.peak_pzt_stress_MPa),
                "MPa (free to blocked, along the plate)",
            ),
            (
                "  at x/l_p",
                format!("{:.2}", self.peak_pzt_stress_x_over_l_p),
                "",
            ),
            (
                "base stress",
                format!("{:.1}", self.base_stress_MPa),
                "MPa (thesis eq. 3.3)",
            ),
            (
                "capacitance",
                format!("{:.3}", self.capacitance_nF),
                "nF per plate",
            ),
        ];
        if let (Some(f), Some(m)) = (self.resonance_Hz, self.modal_mass_mg) {
            rows.push(("resonance", format!("{f:.1}"), "Hz (bare, clamped)"));
            rows.push(("modal mass", format!("{m:.2}"), "mg (k/ω1², at the tip)"));
        }
        let mut out = String::new();
        let _ = writeln!(
            out,
            "{} ({} model, {} drive)",
            self.name, self.model, self.drive_mode
        );
        for (label, value, unit) in rows {
            let _ = writeln!(out, "  {label:<18} {value:>12}  {unit}");
        }
        if let Some(modes) = &self.modes {
            modes_table(modes, "deflection", &mut out);
        }
        out
    }
}
