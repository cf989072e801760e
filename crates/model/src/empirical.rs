//! The thesis' empirical ("adjusted") corrections, `ActuatorModelAdjusted` (thesis eqs. 4.3-4.6).
//!
//! These are curve fits that "did not reflect the physics" (thesis §5.2), kept to compare against.
//! docs/physics.md §7: the printed mass factor ζ = 94.0 makes the carbon fibre 95x heavier with the
//! corrected ply density; ζ = 0.94 ([`ZETA`]) puts designs A/B/C within about 6% of thesis Table 4.14's masses.
//! Table 4.14's energy densities cannot be reproduced from the printed equations: they give 0.42x (A),
//! 0.45x (B) and 0.15x (C) of the printed D_U, and 0.026 mJ for A where §4.10 says 0.0590 mJ, so the
//! thesis' code must have differed from its text.

use crate::performance::{MassBreakdown, Performance};
use crate::planform::Planform;

/// Carbon-fibre mass factor ζ used here (printed 94.0; see the module doc).
pub const ZETA: f64 = 0.94;

/// Free-deflection factor `-0.490 l_r² + 0.204 l_r + 0.645` (thesis eq. 4.4).
pub fn deflection_factor(extension_ratio: f64) -> f64 {
    -0.490 * extension_ratio * extension_ratio + 0.204 * extension_ratio + 0.645
}

/// Blocked-force factor `0.0307 x² - 0.206 x + 0.523`, `x = w_0 t_p` in mm² (thesis eq. 4.5).
pub fn force_factor(base_width: f64, pzt_thickness: f64) -> f64 {
    // The fit variable is defined in mm² by the thesis; the conversion belongs to the fit.
    let x = (base_width * 1e3) * (pzt_thickness * 1e3);
    0.0307 * x * x - 0.206 * x + 0.523
}

/// Hysteresis in effectiveness after a peak field `E_max`: `m_δ / m_δ0 = 1.08 E_max + 1`, E_max in kV/mm
/// (thesis eq. 4.6; `field` in V/m).
pub fn hysteresis_factor(peak_field: f64) -> f64 {
    1.08 * (peak_field * 1e-6) + 1.0
}

/// Apply eqs. 4.3-4.5 to an original-model prediction: `m = m_p + m_cf (1 + ζ)`, δ and F_b scaled by the
/// fits; energy, density and stiffness follow.
pub fn adjust(original: &Performance, planform: &Planform, pzt_thickness: f64) -> Performance {
    let mass = MassBreakdown {
        pzt: original.mass_breakdown.pzt,
        passive: original.mass_breakdown.passive * (1.0 + ZETA),
        bond: original.mass_breakdown.bond,
        added: original.mass_breakdown.added,
    };
    let delta = original.free_deflection * deflection_factor(planform.extension_ratio);
    let force = original.blocked_force * force_factor(planform.base_width, pzt_thickness);
    original.with_outputs(delta, force, mass)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::drive::{Drive, DriveMode};
    use crate::laminate::Laminate;
    use crate::material::Material;
    use crate::performance::evaluate;
    use crate::section::Section;

    fn adjusted(t_p: f64, layup: &[f64], l: f64, l_r: f64, w0: f64, w_r: f64) -> Performance {
        let pzt = Material::builtin("PZT-5H").unwrap();
        let cf = Material::builtin("CF-thesis").unwrap();
        let lam = Laminate::bimorph(&pzt, t_p, &cf, 61.8e-6, layup, None).unwrap();
        let s = Section::new(&lam, Drive::new(DriveMode::Parallel, 800e3)).unwrap();
        let pl = Planform::new(l, l_r, w0, w_r, 0.0).unwrap();
        adjust(&evaluate(&s, &pl), &pl, t_p)
    }

    #[test]
    fn masses_land_near_thesis_table_4_14_with_zeta_0_94() {
        // Source: thesis Table 4.14 masses 1800, 972, 353 mg; docs/physics.md §7 says "within about 6%".
        let a = adjusted(191e-6, &[0.0, 0.0, 90.0, 0.0, 0.0], 50e-3, 0.0, 10e-3, 1.0);
        let b = adjusted(267e-6, &[0.0, 90.0, 0.0], 42.2e-3, 0.0, 5e-3, 1.0);
        let c = adjusted(267e-6, &[0.0, 90.0, 0.0], 42.2e-3, 0.833, 5e-3, 1.667);
        for (p, table_mg) in [(a, 1800.0), (b, 972.0), (c, 353.0)] {
            let gap = p.mass * 1e6 / table_mg - 1.0;
            assert!(gap.abs() < 0.07, "mass gap {gap}");
        }
    }

    #[test]
    fn energy_density_gap_to_table_4_14_is_stated() {
        // Source: Table 4.14 D_U = 0.0328, 0.0606, 0.167 J/kg for A, B, C, and §4.10's 0.0590 mJ for A.
        // The printed equations do not reproduce them (docs/physics.md §7). The gap this implementation
        // documents: D_U at 0.42x (A), 0.45x (B) and 0.15x (C) of the table; U of A 0.026 mJ, not 0.059.
        let a = adjusted(191e-6, &[0.0, 0.0, 90.0, 0.0, 0.0], 50e-3, 0.0, 10e-3, 1.0);
        let b = adjusted(267e-6, &[0.0, 90.0, 0.0], 42.2e-3, 0.0, 5e-3, 1.0);
        let c = adjusted(267e-6, &[0.0, 90.0, 0.0], 42.2e-3, 0.833, 5e-3, 1.667);
        let ratios = [
            a.energy_density / 0.0328,
            b.energy_density / 0.0606,
            c.energy_density / 0.167,
        ];
        for (r, stated) in ratios.iter().zip([0.42, 0.45, 0.15]) {
            assert!((r - stated).abs() < 0.01, "ratio {r}, documented {stated}");
        }
        assert!((a.energy * 1e3 - 0.026).abs() < 0.001, "U_A {}", a.energy);
    }

    #[test]
    fn factors_follow_the_printed_fits() {
        assert!((deflection_factor(0.0) - 0.645).abs() < 1e-15);
        assert!((deflection_factor(1.0) - 0.359).abs() < 1e-12);
        assert!(
            (force_factor(5e-3, 267e-6) - (0.0307 * 1.335f64.powi(2) - 0.206 * 1.335 + 0.523))
                .abs()
                < 1e-12
        );
        assert!((hysteresis_factor(800e3) - 1.864).abs() < 1e-12);
    }
}
