//! A power law of a residual in the design variables (docs/calibration.md §3, "Discovery"): the log
//! residual `ln(measured / model) = c + Σ a_k ln x_k`, fitted by ordinary least squares, each exponent
//! with a 95% interval `a ± t_{0.975, n-p-1} SE` and the p-value of `a = 0` (Student t, [`stats`]).
//! A log-linear fit in log variables is a power law: the residual factor goes as `Π x_k^{a_k}`.

use crate::calibrate::rounded::{six_digits, six_digits_pair};
use crate::calibrate::stats;
use nalgebra::{DMatrix, DVector};
use serde::Serialize;

/// One exponent of a power law.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Exponent {
    /// Variable (report name, as in the adequacy test).
    pub variable: &'static str,
    /// Exponent a: the residual factor goes as `x^a`.
    #[serde(serialize_with = "six_digits")]
    pub estimate: f64,
    /// 95% interval.
    #[serde(serialize_with = "six_digits_pair")]
    pub interval: (f64, f64),
    /// Two-sided p-value of `a = 0`.
    #[serde(serialize_with = "six_digits")]
    pub p: f64,
}

/// A fitted power law of one residual.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PowerLaw {
    /// Which residual: `deflection` (the gain, δ), `stiffness` (F_b/δ, the inverse compliance).
    pub residual: &'static str,
    /// Points fitted.
    pub n: usize,
    /// Exponents, in the order of the variables given.
    pub exponents: Vec<Exponent>,
    /// Share of the residual's variance the law explains.
    #[serde(serialize_with = "six_digits")]
    pub r_squared: f64,
    /// Standard deviation of what is left (log).
    #[serde(serialize_with = "six_digits")]
    pub sigma_log: f64,
}

/// Fit `y = c + Σ a_k x_k` (the x already logarithms) over the columns of `x` that vary; constant columns
/// are left out (a variable every actuator shares says nothing). `absorbed` degrees of freedom were used
/// before (data centred per actuator beyond the one intercept). None with fewer than 2 degrees of
/// freedom left, or nothing varying.
pub fn fit(
    residual: &'static str,
    names: &[&'static str],
    x: &[Vec<f64>],
    y: &[f64],
    absorbed: usize,
) -> Option<PowerLaw> {
    let n = y.len();
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len().max(1) as f64;
    let varying: Vec<usize> = (0..names.len())
        .filter(|&k| {
            let col: Vec<f64> = x.iter().map(|row| row[k]).collect();
            let m = mean(&col);
            col.iter().map(|v| (v - m).powi(2)).sum::<f64>() > 1e-12 * n as f64
        })
        .collect();
    let p = varying.len();
    if p == 0 || n < p + 3 + absorbed {
        return None;
    }
    // Centred columns and response: the intercept drops out.
    let means: Vec<f64> = varying
        .iter()
        .map(|&k| mean(&x.iter().map(|row| row[k]).collect::<Vec<_>>()))
        .collect();
    let my = mean(y);
    let a = DMatrix::from_fn(n, p, |i, j| x[i][varying[j]] - means[j]);
    let b = DVector::from_iterator(n, y.iter().map(|v| v - my));
    let ata = a.transpose() * &a;
    let svd = ata.svd(true, true);
    let tol = svd.singular_values.max() * 1e-12;
    let pinv = svd.pseudo_inverse(tol).ok()?;
    let coef = &pinv * (a.transpose() * &b);
    let fitted = &a * &coef;
    let rss: f64 = (&b - fitted).iter().map(|r| r * r).sum();
    let tss: f64 = b.iter().map(|r| r * r).sum();
    let dof = (n - p - 1 - absorbed) as f64;
    let sigma2 = rss / dof;
    let t = stats::t_quantile_two_sided(0.95, dof);
    let exponents = varying
        .iter()
        .enumerate()
        .map(|(j, &k)| {
            let se = (sigma2 * pinv[(j, j)]).max(0.0).sqrt();
            let est = coef[j];
            Exponent {
                variable: names[k],
                estimate: est,
                interval: (est - t * se, est + t * se),
                p: if se > 0.0 {
                    stats::t_two_sided_p(est / se, dof)
                } else {
                    1.0
                },
            }
        })
        .collect();
    Some(PowerLaw {
        residual,
        n,
        exponents,
        r_squared: if tss > 0.0 { 1.0 - rss / tss } else { 0.0 },
        sigma_log: sigma2.sqrt(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn recovers_exponents_of_an_exact_power_law_and_drops_constant_columns() {
        // y = 0.3 + 1.5 ln x1 - 0.5 ln x2 exactly, x3 constant.
        let xs: Vec<Vec<f64>> = (0..12)
            .map(|i| {
                let (x1, x2) = (1.0 + i as f64, 2.0 + ((i * 7) % 5) as f64);
                vec![x1.ln(), x2.ln(), 3f64.ln()]
            })
            .collect();
        let y: Vec<f64> = xs.iter().map(|r| 0.3 + 1.5 * r[0] - 0.5 * r[1]).collect();
        let law = fit("deflection", &["x1", "x2", "x3"], &xs, &y, 0).unwrap();
        assert_eq!(law.exponents.len(), 2);
        assert!((law.exponents[0].estimate - 1.5).abs() < 1e-9);
        assert!((law.exponents[1].estimate + 0.5).abs() < 1e-9);
        assert!((law.r_squared - 1.0).abs() < 1e-9);
    }

    #[test]
    fn interval_matches_the_textbook_slope_interval() {
        // One variable: SE(a) = σ / sqrt(Sxx) with σ² = RSS/(n-2) (any regression text), t_{0.975, 3}.
        let x = [0.0, 1.0, 2.0, 3.0, 4.0];
        let y = [0.1, 0.9, 2.2, 2.8, 4.1];
        let rows: Vec<Vec<f64>> = x.iter().map(|v| vec![*v]).collect();
        let law = fit("stiffness", &["x"], &rows, &y, 0).unwrap();
        let (mx, my) = (2.0, 2.02);
        let sxx: f64 = x.iter().map(|v| (v - mx) * (v - mx)).sum();
        let a = x
            .iter()
            .zip(&y)
            .map(|(u, v)| (u - mx) * (v - my))
            .sum::<f64>()
            / sxx;
        let rss: f64 = x
            .iter()
            .zip(&y)
            .map(|(u, v)| (v - my - a * (u - mx)).powi(2))
            .sum();
        let se = (rss / 3.0 / sxx).sqrt();
        let e = &law.exponents[0];
        assert!((e.estimate - a).abs() < 1e-12);
        assert!((e.interval.1 - (a + 3.182 * se)).abs() < 1e-3);
    }
}
