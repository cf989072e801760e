//! The polycrystalline ceramic as Jafferis, Smith & Wood measured it (*Smart Mater. Struct.* 24 (2015)
//! 065023; docs/physics.md §18): a stress coefficient that rises with the field along a logistic, and a
//! modulus that is lower in tension than in compression. Both are one-dimensional laws along the
//! actuator's axis; [`crate::nonlinear`] puts them into the laminate.

use crate::error::ModelError;
use crate::material::Material;

/// The ceramic's law along the actuator axis: the internal stress per unit field
/// `f31(ξ, ε) = (1 + b ε) [f_min + (f_max (1 - d |ξ|) - f_min) S(c (|ξ| - ξ0))]` and the elastic stress
/// `σ_e(ε) = E_t ε - (E_c - E_t)/a [ln(1 + e^{a(ε0 - ε)}) - ln(1 + e^{a ε0})]`, whose tangent is
/// `E_t + (E_c - E_t) S(a (ε0 - ε))`, with `S` the logistic `1/(1 + e^{-x})` (Jafferis et al. 2015;
/// docs/physics.md eqs. 18.1-18.3). Compressive strain is negative.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ceramic {
    /// `f_min`, the stress coefficient at low field, Pa·m/V.
    pub coefficient_low: f64,
    /// `f_max`, the stress coefficient at high field before the high-field fall, Pa·m/V.
    pub coefficient_high: f64,
    /// `ξ0`, the field at the middle of the rise, V/m.
    pub switching_field: f64,
    /// `c`, the logistic's steepness in the field, m/V (its width is `1/c`).
    pub field_steepness: f64,
    /// `d`, the fall of `f_max` with the field, m/V.
    pub high_field_fall: f64,
    /// `b`, the change of the coefficient with the axial strain (dimensionless).
    pub strain_factor: f64,
    /// `E_t`, the modulus in tension, Pa.
    pub modulus_tension: f64,
    /// `E_c`, the modulus in compression, Pa.
    pub modulus_compression: f64,
    /// `ε0`, the strain at the middle of the modulus' change (compressive, negative).
    pub switching_strain: f64,
    /// `a`, the logistic's steepness in the strain (its width is `1/a`).
    pub strain_steepness: f64,
}

/// The logistic `S(x) = 1/(1 + e^{-x})`, without overflow for either sign.
fn logistic(x: f64) -> f64 {
    if x >= 0.0 {
        1.0 / (1.0 + (-x).exp())
    } else {
        let e = x.exp();
        e / (1.0 + e)
    }
}

/// `ln(1 + e^x)`, without overflow for large x.
fn softplus(x: f64) -> f64 {
    x.max(0.0) + (-x.abs()).exp().ln_1p()
}

impl Ceramic {
    /// PZT-5H (Piezo Systems T-series plates, 135 µm) as fitted by Jafferis, Smith & Wood (2015):
    /// `f_min = 14`, `f_max = 29` Pa·m/V, `ξ0 = 0.4` V/µm, `c = 10⁻⁵` m/V (width 0.1 V/µm),
    /// `d = 69` nm/V, `b = -230`; `E_t = 38.5`, `E_c = 81` GPa, `ε0 = -470` µm/m, `a = 8000`.
    /// Every number is the paper's fit; docs/physics.md §18 states which are read from the lab's
    /// published code rather than the paper's text.
    pub const JAFFERIS_2015: Ceramic = Ceramic {
        coefficient_low: 14.0,
        coefficient_high: 29.0,
        switching_field: 0.4e6,
        field_steepness: 1e-5,
        high_field_fall: 69e-9,
        strain_factor: -230.0,
        modulus_tension: 38.5e9,
        modulus_compression: 81e9,
        switching_strain: -4.7e-4,
        strain_steepness: 8000.0,
    };

    /// The ceramic of a laminate's PZT: the paper's fit, which is PZT-5H's, for a PZT with PZT-5H's
    /// small-signal constants (`E` = 62 GPa, `d31` = -320 pm/V, docs/physics.md §8); any other PZT is
    /// refused rather than given PZT-5H's law.
    pub fn of(pzt: &Material) -> Result<Ceramic, ModelError> {
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-9 * b.abs();
        let fitted =
            Material::builtin("PZT-5H").filter(|h| close(pzt.e1, h.e1) && close(pzt.d31, h.d31));
        if fitted.is_some() {
            Ok(Self::JAFFERIS_2015)
        } else {
            Err(ModelError::NotCovered {
                name: "nonlinear ceramic",
                value: "PZT",
                allowed: "the fit of Jafferis et al. 2015 is PZT-5H's: the PZT must have E = 62 GPa and d31 = -320 pm/V",
            })
        }
    }

    /// A linear ceramic: one modulus `E` and one stress coefficient `e = E |d31|` at every field and
    /// strain (the original model's PZT along the axis).
    pub fn linear(modulus: f64, coefficient: f64) -> Ceramic {
        Ceramic {
            coefficient_low: coefficient,
            coefficient_high: coefficient,
            high_field_fall: 0.0,
            strain_factor: 0.0,
            modulus_tension: modulus,
            modulus_compression: modulus,
            ..Self::JAFFERIS_2015
        }
    }

    /// The stress coefficient at zero strain, `f31(ξ, 0)`, Pa·m/V (docs/physics.md eq. 18.1). The paper
    /// measured it along the poling; a field against the poling takes the coefficient of its magnitude
    /// (an assumption, §18).
    pub fn stress_coefficient(&self, field: f64) -> f64 {
        let xi = field.abs();
        let s = logistic(self.field_steepness * (xi - self.switching_field));
        let high = self.coefficient_high * (1.0 - self.high_field_fall * xi);
        self.coefficient_low + (high - self.coefficient_low) * s
    }

    /// The internal (piezoelectric) stress magnitude `f31(ξ, ε) ξ` and its strain derivative,
    /// `(1 + b ε) f31(ξ, 0) ξ` and `b f31(ξ, 0) ξ` (docs/physics.md eq. 18.1), Pa. Positive for a field
    /// along the poling; the sign of the stress on the plate is the material's (`-sign(d31)`).
    pub fn internal_stress(&self, field: f64, strain: f64) -> (f64, f64) {
        let f = self.stress_coefficient(field) * field;
        (
            (1.0 + self.strain_factor * strain) * f,
            self.strain_factor * f,
        )
    }

    /// The elastic stress `σ_e(ε)` and its tangent modulus (docs/physics.md eqs. 18.2, 18.3), Pa.
    pub fn elastic_stress(&self, strain: f64) -> (f64, f64) {
        let (lo, hi) = (self.modulus_tension, self.modulus_compression);
        let a = self.strain_steepness;
        let shift =
            softplus(a * (self.switching_strain - strain)) - softplus(a * self.switching_strain);
        let stress = lo * strain - (hi - lo) / a * shift;
        let tangent = lo + (hi - lo) * logistic(a * (self.switching_strain - strain));
        (stress, tangent)
    }

    /// Check the parameters describe a ceramic: moduli and coefficients positive, steepnesses positive,
    /// every number finite. Returns the first that is not, with its name.
    pub fn check(&self) -> Result<(), (&'static str, f64)> {
        let positive = [
            ("coefficient_low", self.coefficient_low),
            ("coefficient_high", self.coefficient_high),
            ("field_steepness", self.field_steepness),
            ("modulus_tension", self.modulus_tension),
            ("modulus_compression", self.modulus_compression),
            ("strain_steepness", self.strain_steepness),
        ];
        let finite = [
            ("switching_field", self.switching_field),
            ("high_field_fall", self.high_field_fall),
            ("strain_factor", self.strain_factor),
            ("switching_strain", self.switching_strain),
        ];
        for (name, v) in positive {
            if !(v.is_finite() && v > 0.0) {
                return Err((name, v));
            }
        }
        for (name, v) in finite {
            if !v.is_finite() {
                return Err((name, v));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const J: Ceramic = Ceramic::JAFFERIS_2015;

    #[test]
    fn the_coefficient_rises_from_f_min_to_f_max_around_the_switching_field() {
        // Source: Jafferis, Smith & Wood 2015, the logistic fit of f31(ξ): f_min = 14 and f_max = 29
        // Pa·m/V about ξ0 = 0.4 V/µm, width 0.1 V/µm, f_max falling by d = 69 nm/V.
        // At zero field the logistic is S(-4) = 0.01799: f = 14 + 15 × 0.01799.
        assert!((J.stress_coefficient(0.0) - (14.0 + 15.0 * 0.017_986_2)).abs() < 1e-5);
        // At ξ0 it is half way between f_min and f_max (1 - d ξ0).
        let mid = 0.5 * (14.0 + 29.0 * (1.0 - 69e-9 * 0.4e6));
        assert!((J.stress_coefficient(0.4e6) - mid).abs() < 1e-12);
        // Well above, f_max (1 - d ξ): 29 × (1 - 0.138) at 2 V/µm (S(16) = 1 - 1.1e-7).
        let high = J.stress_coefficient(2e6);
        assert!((high - 29.0 * (1.0 - 0.138)).abs() < 1e-5, "{high}");
        // Monotone through the rise (above about 0.7 V/µm the fall d takes over).
        let mut last = 0.0;
        for i in 0..=60 {
            let f = J.stress_coefficient(i as f64 * 1e4);
            assert!(f > last);
            last = f;
        }
        // Even in the field (the assumption for fields against the poling, docs/physics.md §18).
        assert_eq!(J.stress_coefficient(-0.3e6), J.stress_coefficient(0.3e6));
    }

    #[test]
    fn the_modulus_is_38_5_gpa_in_tension_and_81_gpa_in_compression() {
        // Source: Jafferis, Smith & Wood 2015, the fit of the PZT's modulus against strain: E_min =
        // 38.5 GPa in tension, E_max = 81 GPa in compression, switching at -470 µm/m, a = 8000.
        let (_, tension) = J.elastic_stress(2e-3);
        let (_, compression) = J.elastic_stress(-3e-3);
        assert!((tension / 38.5e9 - 1.0).abs() < 1e-6, "{tension}");
        assert!((compression / 81e9 - 1.0).abs() < 1e-6, "{compression}");
        let (_, mid) = J.elastic_stress(-4.7e-4);
        assert!((mid - 0.5 * (38.5e9 + 81e9)).abs() < 1.0);
        // The stress is zero at zero strain, and its tangent is the derivative of the stress.
        assert_eq!(J.elastic_stress(0.0).0, 0.0);
        for eps in [-2e-3, -6e-4, -4.7e-4, 0.0, 3e-4, 1.5e-3] {
            let h = 1e-9;
            let slope = (J.elastic_stress(eps + h).0 - J.elastic_stress(eps - h).0) / (2.0 * h);
            let (_, tangent) = J.elastic_stress(eps);
            assert!((slope / tangent - 1.0).abs() < 1e-5, "{eps}");
        }
    }

    #[test]
    fn the_internal_stress_grows_under_compression_by_b() {
        // Source: Jafferis et al. 2015, f31 scaled by (1 + b ε) with b = -230.
        let (s0, slope) = J.internal_stress(1e6, 0.0);
        let (s1, _) = J.internal_stress(1e6, -1e-3);
        assert!((s1 / s0 - 1.23).abs() < 1e-12);
        assert!((slope / s0 + 230.0).abs() < 1e-9);
    }

    #[test]
    fn a_linear_ceramic_is_one_modulus_and_one_coefficient_everywhere() {
        let c = Ceramic::linear(62e9, 19.84);
        for xi in [-3e5, 0.0, 4e5, 2e6] {
            assert_eq!(c.stress_coefficient(xi), 19.84);
        }
        for eps in [-2e-3, -4.7e-4, 0.0, 1e-3] {
            let (s, t) = c.elastic_stress(eps);
            assert!((s - 62e9 * eps).abs() < 1e-6 && t == 62e9, "{eps}");
        }
        assert!(c.check().is_ok() && J.check().is_ok());
        // The paper's fit belongs to PZT-5H; PZT-5A is refused.
        assert_eq!(Ceramic::of(&Material::builtin("PZT-5H").unwrap()), Ok(J));
        assert!(Ceramic::of(&Material::builtin("PZT-5A").unwrap()).is_err());
        // docs/physics.md §18.1: a user PZT that differs from PZT-5H in its depolarization field alone
        // takes the fit.
        assert_eq!(
            Ceramic::of(&Material {
                depolarization_field: 500e3,
                ..Material::builtin("PZT-5H").unwrap()
            }),
            Ok(J)
        );
        let bad = Ceramic {
            modulus_tension: -1.0,
            ..J
        };
        assert_eq!(bad.check(), Err(("modulus_tension", -1.0)));
    }
}
