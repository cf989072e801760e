//! Capacitance of one PZT plate between its electrodes: a parallel-plate capacitor,
//! `C = ε0 K33 A / t_p` (docs/physics.md §10), the value a lab's LCR meter checks a built plate against.

use crate::material::VACUUM_PERMITTIVITY;

/// `C = ε0 K33 A / t_p`, F, for a plate of electrode area `area` (m²) and thickness `thickness` (m)
/// of relative permittivity `k33` (docs/physics.md §10; the parallel-plate capacitor with the field
/// only through the thickness, fringing left out: `A ≫ t_p²` for every plate the geometry ranges allow).
pub fn plate_capacitance(k33: f64, area: f64, thickness: f64) -> f64 {
    VACUUM_PERMITTIVITY * k33 * area / thickness
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_square_centimetre_of_pzt_5h_at_267_um() {
        // ε0 · 3800 · 1e-4 m² / 267e-6 m, written out: 8.8541878128e-12 × 3800 = 3.364591e-8 F/m,
        // × 1e-4 / 2.67e-4 = 1.260147e-8 F, 12.6 nF.
        let c = plate_capacitance(3800.0, 1e-4, 267e-6);
        assert!((c - 1.260_147e-8).abs() < 1e-13, "{c}");
        // Twice as thick, half the capacitance.
        assert!((plate_capacitance(3800.0, 1e-4, 534e-6) - c / 2.0).abs() < 1e-20);
    }
}
