//! Free deflection, blocked force, energy, mass, stress and capacitance of a tapered bimorph with a rigid
//! extension (thesis eqs. 2.26, 2.35, 3.3; Wood, Steltz & Fearing 2005).

use crate::material::VACUUM_PERMITTIVITY;
use crate::planform::Planform;
use crate::section::Section;
use serde::Serialize;

/// Mass by layer kind, kg.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct MassBreakdown {
    /// Both PZT plates.
    pub pzt: f64,
    /// Passive plies under the PZT, the extension and the base tab.
    pub passive: f64,
    /// Bond layers (under the PZT only).
    pub bond: f64,
    /// Mass no layer carries (leads and solder, adhesive fillets, adhesive over the bonded area), set by
    /// the added-mass primitives ([`crate::primitives`]); 0 in the original model.
    pub added: f64,
}

impl MassBreakdown {
    /// Total mass, kg.
    pub fn total(&self) -> f64 {
        self.pzt + self.passive + self.bond + self.added
    }
}

/// Predicted performance of one actuator at one drive level, SI units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Performance {
    /// One-sided free tip deflection, m.
    pub free_deflection: f64,
    /// Blocked force at the tip of the extension, N.
    pub blocked_force: f64,
    /// Mechanical energy `U = ½ F_b δ`, J.
    pub energy: f64,
    /// Total mass, kg.
    pub mass: f64,
    /// Mass by layer kind.
    pub mass_breakdown: MassBreakdown,
    /// Energy density `U / m`, J/kg.
    pub energy_density: f64,
    /// Tip stiffness `F_b / δ`, N/m.
    pub stiffness: f64,
    /// Peak |ε_x| on a PZT surface along the active length over the stroke, free to blocked
    /// ([`crate::plate::over_stroke`]).
    pub peak_pzt_strain: f64,
    /// Where the peak strain is, `x / l_p`.
    pub peak_pzt_strain_at: f64,
    /// Peak |σ_x| on a PZT surface along the active length over the stroke, free to blocked (CLT), Pa.
    pub peak_pzt_stress: f64,
    /// Where the peak stress is, `x / l_p`.
    pub peak_pzt_stress_at: f64,
    /// Thesis base stress under blocked force, `σ = 6 F_b l_tot / (w_0 t²)` (eq. 3.3), Pa.
    pub base_stress: f64,
    /// Capacitance of one PZT plate, `ε0 K33 A / t_p`, F.
    pub capacitance: f64,
}

impl Performance {
    /// Recompute the derived outputs (energy, density, stiffness) after δ, F_b or mass changed.
    pub fn with_outputs(
        mut self,
        free_deflection: f64,
        blocked_force: f64,
        mass: MassBreakdown,
    ) -> Self {
        self.free_deflection = free_deflection;
        self.blocked_force = blocked_force;
        self.mass_breakdown = mass;
        self.mass = mass.total();
        self.energy = 0.5 * blocked_force * free_deflection;
        self.energy_density = self.energy / self.mass;
        self.stiffness = blocked_force / free_deflection;
        self
    }
}

/// Free tip deflection `δ = P l_p² (1 + 2 l_r) / 2` (thesis eq. 2.26), m. Independent of the taper.
pub fn free_deflection(section: &Section, planform: &Planform) -> f64 {
    let l_p = planform.piezo_length();
    0.5 * section.free_curvature * l_p * l_p * (1.0 + 2.0 * planform.extension_ratio)
}

/// Tip compliance of the tapered beam with a rigid extension,
/// `c = C44 l_p³ G(w_r, l_r) / (3 w_nom)` (thesis eqs. 2.29-2.34, docs/physics.md §3), m/N.
pub fn tip_compliance(section: &Section, planform: &Planform) -> f64 {
    beam_tip_compliance(section.bending_compliance, planform)
}

/// The tip compliance `c = C44 l_p³ G(w_r, l_r) / (3 w_nom)` of a beam whose section bends by `C44`
/// (1/(N·m)) under a moment per width (thesis eqs. 2.29-2.34, docs/physics.md §3), m/N:
/// `C44 ∫0..l_p (L - x)² / w(x) dx` in closed form. A section whose `∂κ/∂m` is the same along the beam
/// (the nonlinear ceramic's unloaded beam, docs/physics.md §18.3) takes it with that tangent as `C44`.
pub fn beam_tip_compliance(bending_compliance: f64, planform: &Planform) -> f64 {
    let l_p = planform.piezo_length();
    bending_compliance * l_p * l_p * l_p * planform.shape_factor()
        / (3.0 * planform.nominal_width())
}

/// The extra tip compliance `c = C44 l_ext³ / (3 w_tip)` of an extension of constant width `w_tip`
/// whose section bends by `C44` (1/(N·m)) under a moment per width, m/N: a cantilever of length `l_ext`
/// under its end load (docs/physics.md §3). 0 for a planform without an extension.
pub fn extension_tip_compliance(bending_compliance: f64, planform: &Planform) -> f64 {
    let l_ext = planform.extension_length();
    bending_compliance * l_ext * l_ext * l_ext / (3.0 * planform.tip_width())
}

/// Blocked force `F_b = δ / c = 3 P w_nom (1 + 2 l_r) / (2 C44 l_p G)` (thesis eq. 2.35), N. For a
/// rectangle this is `3 P w / (2 C44 l_p)`: the thesis' eq. 2.36 prints 4/3 in place of 3/2 (erratum,
/// docs/physics.md §3).
pub fn blocked_force(section: &Section, planform: &Planform) -> f64 {
    free_deflection(section, planform) / tip_compliance(section, planform)
}

/// Base stress under a tip force, `σ = 6 F l_tot / (w_0 t²)` (thesis eq. 3.3, docs/physics.md §6): the
/// root of a homogeneous beam of the full thickness `t` carrying the moment `F l_tot`, Pa.
pub fn base_stress(force: f64, planform: &Planform, thickness: f64) -> f64 {
    6.0 * force * planform.length / (planform.base_width * thickness * thickness)
}

/// Mass `m = 2 ρ_p t_p A_pzt + Σ ρ_ply t_ply (A_pzt + A_ext + A_tab) + bond` (docs/physics.md §4).
pub fn mass(section: &Section, planform: &Planform) -> MassBreakdown {
    let a_pzt = planform.piezo_area();
    MassBreakdown {
        pzt: section.pzt_areal_mass * a_pzt,
        passive: section.passive_areal_mass
            * (a_pzt + planform.extension_area() + planform.tab_area()),
        bond: section.bond_areal_mass * a_pzt,
        added: 0.0,
    }
}

/// Everything at once for one planform against a solved section (no allocation).
pub fn evaluate(section: &Section, planform: &Planform) -> Performance {
    let delta = free_deflection(section, planform);
    let force = blocked_force(section, planform);
    let masses = mass(section, planform);
    let plate = crate::plate::over_stroke(section, planform, force, 0.0);
    let base = Performance {
        free_deflection: 0.0,
        blocked_force: 0.0,
        energy: 0.0,
        mass: 0.0,
        mass_breakdown: MassBreakdown::default(),
        energy_density: 0.0,
        stiffness: 0.0,
        peak_pzt_strain: plate.strain,
        peak_pzt_strain_at: plate.strain_at,
        peak_pzt_stress: plate.stress,
        peak_pzt_stress_at: plate.stress_at,
        base_stress: base_stress(force, planform, section.thickness),
        capacitance: VACUUM_PERMITTIVITY * section.relative_permittivity * planform.piezo_area()
            / section.pzt_thickness,
    };
    base.with_outputs(delta, force, masses)
}

/// Energy and mass only: the optimizer's inner loop. `U = 3 P² l_p w_nom G_U / (8 C44)` is the same
/// number as `½ F_b δ` (docs/physics.md §3).
#[inline]
pub fn energy_and_mass(section: &Section, planform: &Planform) -> (f64, f64) {
    let delta = free_deflection(section, planform);
    let energy = 0.5 * delta * delta / tip_compliance(section, planform);
    (energy, mass(section, planform).total())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::drive::{Drive, DriveMode};
    use crate::laminate::Laminate;
    use crate::material::Material;

    fn thesis_section(t_p: f64, plies: usize, field: f64) -> Section {
        let layup: Vec<f64> = match plies {
            3 => vec![0.0, 90.0, 0.0],
            5 => vec![0.0, 0.0, 90.0, 0.0, 0.0],
            _ => vec![0.0, 0.0, 0.0, 90.0, 0.0, 0.0, 0.0],
        };
        let pzt = Material::builtin("PZT-5H").unwrap();
        let cf = Material::builtin("CF-thesis").unwrap();
        let lam = Laminate::bimorph(&pzt, t_p, &cf, 61.8e-6, &layup, None).unwrap();
        Section::new(&lam, Drive::new(DriveMode::Parallel, field)).unwrap()
    }

    #[test]
    #[allow(clippy::approx_constant)] // 0.5236 mm is design 21's deflection, not π/6
    fn reproduces_model_notes_reference_predictions() {
        // Source: docs/physics.md §9 (parallel drive, 800 V/mm, PZT-5H, thesis CF ply), within 0.1%.
        // design, t_p, plies, l_tot, l_r, w_0, w_r, δ mm, F_b mN, U µJ, m mg
        let rows = [
            (
                "A", 191e-6, 5, 50e-3, 0.0, 10e-3, 1.0, 0.7371, 456.00, 168.07, 1704.56,
            ),
            (
                "B", 267e-6, 3, 42.2e-3, 0.0, 5e-3, 1.0, 0.8120, 341.37, 138.59, 933.23,
            ),
            (
                "C", 267e-6, 3, 42.2e-3, 0.833, 5e-3, 1.667, 0.6443, 180.56, 58.16, 310.35,
            ),
            (
                "1", 127e-6, 5, 50e-3, 0.5, 20e-3, 1.5, 0.5471, 353.50, 96.70, 1119.15,
            ),
            (
                "7", 267e-6, 5, 50e-3, 1.0, 20e-3, 1.75, 0.5776, 682.41, 197.07, 1343.45,
            ),
            (
                "21", 127e-6, 3, 32e-3, 0.0, 15e-3, 1.0, 0.5236, 446.55, 116.90, 1074.67,
            ),
        ];
        for (name, t_p, plies, l, l_r, w0, w_r, d_mm, f_mn, u_uj, m_mg) in rows {
            let s = thesis_section(t_p, plies, 800e3);
            let p = evaluate(&s, &Planform::new(l, l_r, w0, w_r, 0.0).unwrap());
            let close = |got: f64, want: f64| ((got - want) / want).abs() < 1e-3;
            assert!(
                close(p.free_deflection * 1e3, d_mm),
                "{name} δ {}",
                p.free_deflection
            );
            assert!(
                close(p.blocked_force * 1e3, f_mn),
                "{name} F {}",
                p.blocked_force
            );
            assert!(close(p.energy * 1e6, u_uj), "{name} U {}", p.energy);
            assert!(close(p.mass * 1e6, m_mg), "{name} m {}", p.mass);
            assert!(close(p.energy_density, u_uj / m_mg), "{name} D");
        }
    }

    #[test]
    fn energy_shortcut_equals_half_force_times_deflection() {
        // Source: docs/physics.md §3, U = 3 P² l_p w_nom G_U / (8 C44) = ½ F_b δ.
        let s = thesis_section(191e-6, 5, 600e3);
        for (l_r, w_r) in [(0.0, 1.0), (0.833, 1.667), (1.2, 0.4), (0.3, 1.0 + 1e-9)] {
            let pl = Planform::new(45e-3, l_r, 8e-3, w_r, 1e-3).unwrap();
            let full = evaluate(&s, &pl);
            let (u, m) = energy_and_mass(&s, &pl);
            assert!(((u - full.energy) / u).abs() < 1e-12);
            assert!(((m - full.mass) / m).abs() < 1e-12);
            let closed = 3.0
                * s.free_curvature.powi(2)
                * pl.piezo_length()
                * pl.nominal_width()
                * crate::planform::energy_shape_factor(w_r, l_r)
                / (8.0 * s.bending_compliance);
            assert!(((u - closed) / u).abs() < 1e-12);
        }
    }

    #[test]
    fn blocked_force_is_continuous_through_unit_width_ratio() {
        let s = thesis_section(267e-6, 3, 800e3);
        for l_r in [0.0, 0.5, 1.0] {
            let at =
                |w_r: f64| blocked_force(&s, &Planform::new(42e-3, l_r, 5e-3, w_r, 0.0).unwrap());
            let centre = at(1.0);
            for e in [1e-12, 1e-9, 1e-6, 1e-3] {
                // F_b varies smoothly: a step of e in w_r moves it by O(e), never by a jump.
                assert!(((at(1.0 + e) - centre) / centre).abs() < 2.0 * e + 1e-13);
                assert!(((at(1.0 - e) - centre) / centre).abs() < 2.0 * e + 1e-13);
            }
        }
    }

    #[test]
    fn base_stress_and_capacitance_follow_their_formulas() {
        // Source: thesis eq. 3.3 and C = ε0 K33 A / t_p.
        let s = thesis_section(267e-6, 3, 800e3);
        let pl = Planform::new(42.2e-3, 0.0, 5e-3, 1.0, 0.0).unwrap();
        let p = evaluate(&s, &pl);
        let t = 2.0 * 267e-6 + 3.0 * 61.8e-6;
        assert!((p.base_stress - 6.0 * p.blocked_force * 42.2e-3 / (5e-3 * t * t)).abs() < 1e-6);
        let c = 8.854_187_812_8e-12 * 3800.0 * 42.2e-3 * 5e-3 / 267e-6;
        assert!(((p.capacitance - c) / c).abs() < 1e-12);
        assert!(p.peak_pzt_strain > 0.0 && p.peak_pzt_stress > 0.0);
    }
}
