//! Euler-Bernoulli bimorph model for a rectangular actuator with an isotropic passive layer
//! (thesis eqs. 2.7-2.16).

use crate::error::ModelError;
use crate::laminate::{Laminate, Layer, LayerRole};

/// Inputs of the beam model, SI.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BeamBimorph {
    /// PZT Young's modulus E_p, Pa.
    pub pzt_modulus: f64,
    /// PZT d31, m/V.
    pub d31: f64,
    /// Thickness of one PZT plate t_p, m.
    pub pzt_thickness: f64,
    /// Passive layer modulus E_m, Pa.
    pub passive_modulus: f64,
    /// Passive layer thickness t_m, m.
    pub passive_thickness: f64,
    /// Beam length l, m.
    pub length: f64,
    /// Beam width w, m.
    pub width: f64,
}

/// Beam-model outputs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BeamResponse {
    /// Curvature magnitude κ, 1/m.
    pub curvature: f64,
    /// Free tip deflection, m.
    pub free_deflection: f64,
    /// Blocked force, N.
    pub blocked_force: f64,
}

impl BeamBimorph {
    /// The beam equivalent of a laminate: E_m is the bending modulus of the passive core alone,
    /// `E_m = 12 / (t_m³ d11)` with `d = D⁻¹` of the core (exact for an isotropic core with ν = 0).
    pub fn from_laminate(laminate: &Laminate, length: f64, width: f64) -> Result<Self, ModelError> {
        let layers = laminate.layers();
        let core: Vec<Layer> = layers
            .iter()
            .filter(|l| !matches!(l.role, LayerRole::Piezo | LayerRole::InactivePiezo))
            .cloned()
            .collect();
        let t_m: f64 = core.iter().map(|l| l.thickness).sum();
        let core_laminate = Laminate::new(core)?;
        let d11 = core_laminate.compliance()[(3, 3)];
        let pzt = &layers[laminate.piezo_layer(0)];
        Ok(BeamBimorph {
            pzt_modulus: pzt.material.e1,
            d31: pzt.material.d31,
            pzt_thickness: pzt.thickness,
            passive_modulus: 12.0 / (t_m * t_m * t_m * d11),
            passive_thickness: t_m,
            length,
            width,
        })
    }

    /// Response at plate field `E3` (V/m, parallel drive).
    ///
    /// Curvature from the moment balance of thesis eq. 2.11 with M = 0:
    /// `κ = 6 E_p d31 E3 (t_m t_p + t_p²) / (E_p (3 t_m² t_p + 6 t_m t_p² + 4 t_p³) + E_m t_m³ / 2)`.
    /// The thesis' eq. 2.12 prints `E_m t_m³` without the ½, which contradicts its own eqs. 2.11 and 2.14;
    /// eq. 2.14 (`δ = 6 E_p d31 E3 (t_m t_p + t_p²) l² / (2 E_p (…) + E_m t_m³)`) agrees with this form.
    /// Deflection `δ = κ l² / 2` (eq. 2.13); blocked force `F_b = 3 M_p / (2 l)` with
    /// `M_p = w E_p d31 E3 (t_m t_p + t_p²)` (eq. 2.15; the printed eq. 2.16 simplifies to `2 t_m t_p + t_p²`,
    /// a typo, docs/physics.md §5). F_b does not depend on E_m.
    pub fn response(&self, field: f64) -> BeamResponse {
        let (e_p, t_p, e_m, t_m) = (
            self.pzt_modulus,
            self.pzt_thickness,
            self.passive_modulus,
            self.passive_thickness,
        );
        let drive = (e_p * self.d31 * field * (t_m * t_p + t_p * t_p)).abs();
        let stiffness = e_p * (3.0 * t_m * t_m * t_p + 6.0 * t_m * t_p * t_p + 4.0 * t_p.powi(3))
            + 0.5 * e_m * t_m.powi(3);
        let curvature = 6.0 * drive / stiffness;
        BeamResponse {
            curvature,
            free_deflection: 0.5 * curvature * self.length * self.length,
            blocked_force: 3.0 * self.width * drive / (2.0 * self.length),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::drive::{Drive, DriveMode};
    use crate::material::Material;
    use crate::performance::evaluate;
    use crate::planform::Planform;
    use crate::section::Section;

    #[test]
    fn agrees_with_lamination_theory_for_an_isotropic_core_with_zero_poisson() {
        // CLT with ν = 0 everywhere and EB agree to 1e-9 relative (δ and F_b).
        let mut pzt = Material::builtin("PZT-5H").unwrap();
        pzt.nu12 = 0.0;
        pzt.g12 = pzt.e1 / 2.0;
        let mut core = Material::builtin("stainless-steel").unwrap();
        core.nu12 = 0.0;
        core.g12 = core.e1 / 2.0;
        for (t_p, t_m, l, w, field) in [
            (127e-6, 100e-6, 30e-3, 5e-3, 500e3),
            (267e-6, 185e-6, 42.2e-3, 5e-3, 800e3),
            (191e-6, 400e-6, 60e-3, 20e-3, 300e3),
        ] {
            let lam = Laminate::bimorph(&pzt, t_p, &core, t_m, &[0.0], None).unwrap();
            let section = Section::new(&lam, Drive::new(DriveMode::Parallel, field)).unwrap();
            let clt = evaluate(&section, &Planform::new(l, 0.0, w, 1.0, 0.0).unwrap());
            let beam = BeamBimorph::from_laminate(&lam, l, w).unwrap();
            assert!((beam.passive_modulus / core.e1 - 1.0).abs() < 1e-12);
            let eb = beam.response(field);
            let rel = |a: f64, b: f64| ((a - b) / b).abs();
            assert!(
                rel(eb.free_deflection, clt.free_deflection) < 1e-9,
                "δ {eb:?} {clt:?}"
            );
            assert!(
                rel(eb.blocked_force, clt.blocked_force) < 1e-9,
                "F {eb:?} {clt:?}"
            );
        }
    }
}
