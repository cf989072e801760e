//! Two-parameter Weibull reliability (thesis eqs. 2.39, 2.40, 3.2, Table 4.12).

use crate::error::ModelError;

/// A Weibull distribution with scale λ (units of the variable) and shape k.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Weibull {
    /// Scale λ.
    pub scale: f64,
    /// Shape (modulus) k.
    pub shape: f64,
}

impl Weibull {
    /// Maximum drive field, simultaneous drive, V/m (thesis Table 4.12: λ = 1040 V/mm, k = 4.85).
    pub const FIELD_SIMULTANEOUS: Weibull = Weibull {
        scale: 1040e3,
        shape: 4.85,
    };
    /// Maximum drive field, parallel drive, V/m (thesis Table 4.12: λ = 923 V/mm, k = 21.8).
    pub const FIELD_PARALLEL: Weibull = Weibull {
        scale: 923e3,
        shape: 21.8,
    };
    /// Failure strain, dimensionless (thesis Table 4.12: λ = 1400 µm/m, k = 4.356).
    pub const STRAIN: Weibull = Weibull {
        scale: 1400e-6,
        shape: 4.356,
    };
    /// Failure stress at the base, Pa (thesis Table 4.12: λ = 5.72 MPa, k = 1.925).
    pub const STRESS: Weibull = Weibull {
        scale: 5.72e6,
        shape: 1.925,
    };

    /// Failure probability `F(x) = 1 - exp(-(x/λ)^k)` (thesis eq. 2.39).
    pub fn cdf(&self, x: f64) -> f64 {
        if x <= 0.0 {
            0.0
        } else {
            -(-(x / self.scale).powf(self.shape)).exp_m1()
        }
    }

    /// Survival `S(x) = exp(-(x/λ)^k)` (thesis eq. 2.40).
    pub fn survival(&self, x: f64) -> f64 {
        if x <= 0.0 {
            1.0
        } else {
            (-(x / self.scale).powf(self.shape)).exp()
        }
    }

    /// Level survived by a share `S` of the population, `x_S = λ (-ln S)^(1/k)` (thesis eq. 3.2).
    pub fn threshold(&self, survival: f64) -> Result<f64, ModelError> {
        if !(survival > 0.0 && survival < 1.0) {
            return Err(ModelError::OutOfRange {
                name: "survival",
                value: survival,
                range: "(0, 1)",
            });
        }
        Ok(self.scale * (-survival.ln()).powf(1.0 / self.shape))
    }

    /// Maximum-likelihood fit to failure values (all > 0): k solves the profile equation
    /// `1/k + mean(ln x) - Σ x^k ln x / Σ x^k = 0` (Newton with bisection safeguard), then
    /// `λ = (Σ x^k / n)^(1/k)` (Cohen 1965; docs/physics.md §6: not a probability-plot regression).
    pub fn fit_mle(samples: &[f64]) -> Result<Weibull, ModelError> {
        if samples.len() < 2 {
            return Err(ModelError::Fit(format!(
                "a Weibull fit needs at least 2 failure values, got {}",
                samples.len()
            )));
        }
        if let Some(bad) = samples.iter().find(|x| !(x.is_finite() && **x > 0.0)) {
            return Err(ModelError::Fit(format!(
                "failure value {bad} is not a positive finite number"
            )));
        }
        // Scale by the largest value so x^k stays finite for large k.
        let top = samples.iter().cloned().fold(0.0, f64::max);
        let logs: Vec<f64> = samples.iter().map(|x| (x / top).ln()).collect();
        if logs.iter().all(|l| (l - logs[0]).abs() < 1e-15) {
            return Err(ModelError::Fit(
                "all failure values are equal: the Weibull shape is unbounded".into(),
            ));
        }
        let n = logs.len() as f64;
        let mean_log = logs.iter().sum::<f64>() / n;
        // g(k) is strictly decreasing in k; g(0+) = +inf, g(inf) = mean_log - max_log < 0.
        let g = |k: f64| {
            let (mut s0, mut s1, mut s2) = (0.0, 0.0, 0.0);
            for &l in &logs {
                let w = (k * l).exp();
                s0 += w;
                s1 += w * l;
                s2 += w * l * l;
            }
            let value = 1.0 / k + mean_log - s1 / s0;
            let slope = -1.0 / (k * k) - (s2 / s0 - (s1 / s0).powi(2));
            (value, slope)
        };
        let (mut lo, mut hi) = (1e-3, 1.0);
        while g(hi).0 > 0.0 {
            lo = hi;
            hi *= 2.0;
            if hi > 1e6 {
                return Err(ModelError::Fit("the Weibull shape did not converge".into()));
            }
        }
        let mut k = 0.5 * (lo + hi);
        for _ in 0..200 {
            let (value, slope) = g(k);
            if value > 0.0 {
                lo = k;
            } else {
                hi = k;
            }
            let newton = k - value / slope;
            k = if newton > lo && newton < hi {
                newton
            } else {
                0.5 * (lo + hi)
            };
            if (hi - lo) < 1e-14 * k || value.abs() < 1e-15 {
                break;
            }
        }
        let mean_pow = logs.iter().map(|l| (k * l).exp()).sum::<f64>() / n;
        Ok(Weibull {
            scale: top * mean_pow.powf(1.0 / k),
            shape: k,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    #[test]
    fn reproduces_thesis_table_4_12_thresholds() {
        // Source: thesis Table 4.12 (values printed to 3 significant figures).
        let rows: [(Weibull, f64, [f64; 3]); 4] = [
            (Weibull::FIELD_SIMULTANEOUS, 1e3, [654.0, 805.0, 965.0]),
            (Weibull::FIELD_PARALLEL, 1e3, [833.0, 872.0, 908.0]),
            (Weibull::STRAIN, 1e-6, [860.0, 1100.0, 1300.0]),
            (Weibull::STRESS, 1e6, [1.78, 2.99, 4.72]),
        ];
        for (w, unit, expect) in rows {
            for (s, e) in [0.9, 0.75, 0.5].into_iter().zip(expect) {
                let x = w.threshold(s).unwrap() / unit;
                // The thesis rounds to 3 significant figures (strain to 2): allow half a unit of the last one.
                let tol = if unit == 1e-6 { 50.0 } else { 0.005 * e };
                assert!((x - e).abs() <= tol, "{w:?} at {s}: {x} vs {e}");
            }
        }
    }

    #[test]
    fn survival_and_cdf_are_complementary() {
        let w = Weibull::FIELD_PARALLEL;
        for x in [1e5, 8e5, 9.23e5, 1.2e6] {
            assert!((w.cdf(x) + w.survival(x) - 1.0).abs() < 1e-15);
        }
        assert!((w.survival(w.threshold(0.9).unwrap()) - 0.9).abs() < 1e-12);
        assert!(w.threshold(1.0).is_err() && w.threshold(f64::NAN).is_err());
    }

    #[test]
    fn mle_recovers_parameters_from_2000_samples() {
        // λ and k within 3% from 2,000 seeded samples (inverse-CDF sampling).
        for truth in [Weibull::FIELD_PARALLEL, Weibull::STRESS, Weibull::STRAIN] {
            let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(2013);
            let samples: Vec<f64> = (0..2000)
                .map(|_| {
                    let u: f64 = rng.gen_range(f64::EPSILON..1.0);
                    truth.scale * (-u.ln()).powf(1.0 / truth.shape)
                })
                .collect();
            let fit = Weibull::fit_mle(&samples).unwrap();
            assert!(
                (fit.scale / truth.scale - 1.0).abs() < 0.03,
                "{fit:?} vs {truth:?}"
            );
            assert!(
                (fit.shape / truth.shape - 1.0).abs() < 0.03,
                "{fit:?} vs {truth:?}"
            );
        }
    }

    #[test]
    fn mle_rejects_bad_data() {
        assert!(Weibull::fit_mle(&[1.0]).is_err());
        assert!(Weibull::fit_mle(&[1.0, -2.0, 3.0]).is_err());
        assert!(Weibull::fit_mle(&[1.0, f64::NAN]).is_err());
        assert!(Weibull::fit_mle(&[2.0, 2.0, 2.0]).is_err());
    }
}
