//! The few distribution functions the selection needs (Student t, F), written out rather than pulling a
//! statistics crate with its own nalgebra. Incomplete beta by Lentz's continued fraction (Numerical
//! Recipes §6.4); ln Γ by Lanczos (g = 7, n = 9).

/// ln Γ(x), x > 0.
pub fn ln_gamma(x: f64) -> f64 {
    const G: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    if x < 0.5 {
        let pi = std::f64::consts::PI;
        return (pi / (pi * x).sin()).ln() - ln_gamma(1.0 - x);
    }
    let x = x - 1.0;
    let mut a = G[0];
    let t = x + 7.5;
    for (i, g) in G.iter().enumerate().skip(1) {
        a += g / (x + i as f64);
    }
    0.5 * (2.0 * std::f64::consts::PI).ln() + (x + 0.5) * t.ln() - t + a.ln()
}

/// Regularised incomplete beta I_x(a, b).
pub fn incomplete_beta(x: f64, a: f64, b: f64) -> f64 {
    if x <= 0.0 {
        return 0.0;
    }
    if x >= 1.0 {
        return 1.0;
    }
    let front =
        (ln_gamma(a + b) - ln_gamma(a) - ln_gamma(b) + a * x.ln() + b * (1.0 - x).ln()).exp();
    if x < (a + 1.0) / (a + b + 2.0) {
        front * beta_fraction(x, a, b) / a
    } else {
        1.0 - front * beta_fraction(1.0 - x, b, a) / b
    }
}

fn beta_fraction(x: f64, a: f64, b: f64) -> f64 {
    const TINY: f64 = 1e-300;
    let (qab, qap, qam) = (a + b, a + 1.0, a - 1.0);
    let mut c = 1.0;
    let mut d = 1.0 - qab * x / qap;
    if d.abs() < TINY {
        d = TINY;
    }
    d = 1.0 / d;
    let mut h = d;
    for m in 1..300 {
        let m = m as f64;
        let m2 = 2.0 * m;
        let aa = m * (b - m) * x / ((qam + m2) * (a + m2));
        d = 1.0 + aa * d;
        if d.abs() < TINY {
            d = TINY;
        }
        c = 1.0 + aa / c;
        if c.abs() < TINY {
            c = TINY;
        }
        d = 1.0 / d;
        h *= d * c;
        let aa = -(a + m) * (qab + m) * x / ((a + m2) * (qap + m2));
        d = 1.0 + aa * d;
        if d.abs() < TINY {
            d = TINY;
        }
        c = 1.0 + aa / c;
        if c.abs() < TINY {
            c = TINY;
        }
        d = 1.0 / d;
        let del = d * c;
        h *= del;
        if (del - 1.0).abs() < 1e-14 {
            break;
        }
    }
    h
}

/// Two-sided p-value of Student's t with `df` degrees of freedom.
pub fn t_two_sided_p(t: f64, df: f64) -> f64 {
    incomplete_beta(df / (df + t * t), 0.5 * df, 0.5)
}

/// Quantile `t` with `P(|T| < t) = level`.
pub fn t_quantile_two_sided(level: f64, df: f64) -> f64 {
    let (mut lo, mut hi) = (0.0, 1e3);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if t_two_sided_p(mid, df) > 1.0 - level {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// Upper tail `P(F > f)` of the F distribution with (d1, d2) degrees of freedom.
pub fn f_upper_p(f: f64, d1: f64, d2: f64) -> f64 {
    if f <= 0.0 {
        return 1.0;
    }
    incomplete_beta(d2 / (d2 + d1 * f), 0.5 * d2, 0.5 * d1)
}

/// p-value of Pearson's r from n pairs (t test with n - 2 degrees of freedom).
pub fn correlation_p(r: f64, n: usize) -> f64 {
    if n < 3 {
        return 1.0;
    }
    let df = (n - 2) as f64;
    let r = r.clamp(-0.999_999_999, 0.999_999_999);
    t_two_sided_p(r * (df / (1.0 - r * r)).sqrt(), df)
}

/// Pearson correlation; `None` when either variable is constant.
pub fn pearson(x: &[f64], y: &[f64]) -> Option<f64> {
    weighted_pearson(x, y, &vec![1.0; x.len()])
}

/// Pearson correlation with weights `w`; `None` when either variable is constant. With `w_i`
/// proportional to `1 / var(y_i)`, `r_w √((n-2)/(1-r_w²))` is the t statistic of the slope of the
/// weighted least-squares line of y on x (Draper & Smith, Applied Regression Analysis, 3rd ed. 1998,
/// §9.2), so [`correlation_p`] of it keeps its level when the y are means of different numbers of
/// readings; unweighted, the few noisier means pull the correlation as far as the precise ones.
pub fn weighted_pearson(x: &[f64], y: &[f64], w: &[f64]) -> Option<f64> {
    if x.len() < 3 {
        return None;
    }
    let total: f64 = w.iter().sum();
    let mx = x.iter().zip(w).map(|(a, w)| w * a).sum::<f64>() / total;
    let my = y.iter().zip(w).map(|(b, w)| w * b).sum::<f64>() / total;
    let (mut sxy, mut sxx, mut syy) = (0.0, 0.0, 0.0);
    for ((a, b), w) in x.iter().zip(y).zip(w) {
        sxy += w * (a - mx) * (b - my);
        sxx += w * (a - mx) * (a - mx);
        syy += w * (b - my) * (b - my);
    }
    let scale = 1e-12 * (mx.abs() + 1.0).powi(2) * total;
    if sxx <= scale || syy <= 1e-30 {
        return None;
    }
    Some(sxy / (sxx * syy).sqrt())
}

/// Corrected Akaike information criterion of a least-squares fit with `k` parameters, `n` residuals and
/// residual sum of squares `rss` (docs/calibration.md §3): `n ln(RSS/n) + 2k + 2k(k+1)/(n-k-1)`; infinite
/// when `n <= k + 1`.
pub fn aicc(n: usize, k: usize, rss: f64) -> f64 {
    if n <= k + 1 {
        return f64::INFINITY;
    }
    let (nf, kf) = (n as f64, k as f64);
    nf * (rss.max(1e-300) / nf).ln() + 2.0 * kf + 2.0 * kf * (kf + 1.0) / (nf - kf - 1.0)
}

/// Holm step-down adjusted p-values, in the input order.
pub fn holm(p: &[f64]) -> Vec<f64> {
    let m = p.len();
    let mut order: Vec<usize> = (0..m).collect();
    order.sort_by(|&a, &b| p[a].total_cmp(&p[b]));
    let mut adjusted = vec![1.0; m];
    let mut running: f64 = 0.0;
    for (rank, &i) in order.iter().enumerate() {
        running = running.max(((m - rank) as f64 * p[i]).min(1.0));
        adjusted[i] = running;
    }
    adjusted
}

/// Upper tail `P(χ² > x)` of the chi-square distribution with `df` degrees of freedom: the regularised
/// upper incomplete gamma `Q(df/2, x/2)`, by its series below `a + 1` and Lentz's continued fraction
/// above (Press et al., Numerical Recipes, 3rd ed., §6.2, eqs. 6.2.5 and 6.2.7).
pub fn chi_square_upper_p(x: f64, df: f64) -> f64 {
    if x <= 0.0 {
        return 1.0;
    }
    let (a, x) = (0.5 * df, 0.5 * x);
    let front = (-x + a * x.ln() - ln_gamma(a)).exp();
    if x < a + 1.0 {
        // P(a, x) = e^-x x^a / Γ(a) Σ x^n / (a (a+1) … (a+n)).
        let (mut term, mut sum, mut ap) = (1.0 / a, 1.0 / a, a);
        for _ in 0..1000 {
            ap += 1.0;
            term *= x / ap;
            sum += term;
            if term.abs() < sum.abs() * 1e-15 {
                break;
            }
        }
        return (1.0 - sum * front).clamp(0.0, 1.0);
    }
    let tiny = 1e-300;
    let mut b = x + 1.0 - a;
    let mut c = 1.0 / tiny;
    let mut d = 1.0 / b;
    let mut h = d;
    for i in 1..1000 {
        let an = -(i as f64) * (i as f64 - a);
        b += 2.0;
        d = an * d + b;
        if d.abs() < tiny {
            d = tiny;
        }
        c = b + an / c;
        if c.abs() < tiny {
            c = tiny;
        }
        d = 1.0 / d;
        let step = d * c;
        h *= step;
        if (step - 1.0).abs() < 1e-15 {
            break;
        }
    }
    (front * h).clamp(0.0, 1.0)
}

/// A standard normal draw (Box-Muller), for the tests that measure a test's level on simulated noise.
#[cfg(test)]
pub(crate) fn standard_normal(rng: &mut impl rand::Rng) -> f64 {
    let (u, v): (f64, f64) = (rng.gen::<f64>().max(1e-300), rng.gen());
    (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_tabulated_quantiles() {
        // Source: standard tables: t_{0.975, 10} = 2.228, t_{0.975, 1e6} ≈ 1.960; F_{0.95}(2, 20) = 3.49.
        assert!((t_quantile_two_sided(0.95, 10.0) - 2.228).abs() < 1e-3);
        assert!((t_quantile_two_sided(0.95, 1e6) - 1.960).abs() < 1e-3);
        assert!((f_upper_p(3.49, 2.0, 20.0) - 0.05).abs() < 1e-3);
        assert!((ln_gamma(5.0) - 24f64.ln()).abs() < 1e-12);
    }

    #[test]
    fn holm_is_monotone_and_capped() {
        let a = holm(&[0.01, 0.04, 0.03, 0.5]);
        assert_eq!(a, vec![0.04, 0.09, 0.09, 0.5]);
    }

    #[test]
    fn chi_square_tails_are_the_tabled_ones() {
        // Upper 5 % and 1 % points (e.g. Abramowitz & Stegun, Table 26.8): df 1: 3.841, 6.635;
        // df 10: 18.307, 23.209; df 30: 43.773, 50.892. And df 2 is exactly e^(-x/2).
        for (x, df, p) in [
            (3.841_459, 1.0, 0.05),
            (6.634_897, 1.0, 0.01),
            (18.307_04, 10.0, 0.05),
            (23.209_25, 10.0, 0.01),
            (43.772_97, 30.0, 0.05),
            (50.892_18, 30.0, 0.01),
        ] {
            let got = chi_square_upper_p(x, df);
            assert!((got / p - 1.0).abs() < 1e-4, "df {df}, x {x}: {got}");
        }
        for x in [0.5, 2.0, 9.0] {
            assert!((chi_square_upper_p(x, 2.0) - (-x / 2.0f64).exp()).abs() < 1e-12);
        }
        assert_eq!(chi_square_upper_p(0.0, 5.0), 1.0);
    }

    #[test]
    fn a_weighted_correlation_is_the_weighted_least_squares_slope_test() {
        let x = [1.0, 2.0, 4.0, 5.0, 7.0, 8.0];
        let y = [0.3, -0.1, 0.4, 0.2, 0.9, 0.5];
        // Equal weights are no weights; a zero weight drops its point; a weight of 2 counts its point twice.
        let plain = pearson(&x, &y).unwrap();
        assert!((weighted_pearson(&x, &y, &[3.0; 6]).unwrap() - plain).abs() < 1e-14);
        let w0 = [1.0, 1.0, 1.0, 1.0, 1.0, 0.0];
        let dropped = pearson(&x[..5], &y[..5]).unwrap();
        assert!((weighted_pearson(&x, &y, &w0).unwrap() - dropped).abs() < 1e-14);
        let w2 = [2.0, 1.0, 1.0, 1.0, 1.0, 1.0];
        let twice = pearson(
            &[1.0, 1.0, 2.0, 4.0, 5.0, 7.0, 8.0],
            &[0.3, 0.3, -0.1, 0.4, 0.2, 0.9, 0.5],
        );
        assert!((weighted_pearson(&x, &y, &w2).unwrap() - twice.unwrap()).abs() < 1e-14);
    }

    #[test]
    fn weighted_correlations_of_means_of_unequal_counts_keep_their_level() {
        // Thirty actuators' mean residuals under no effect: a third measured at two voltages (their
        // means twice as noisy) and at the extremes of the design variable. The weighted test rejects
        // at its 1 % within the binomial scatter of 10,000 draws; the plain one rejects at more than 1.5 %.
        use rand::SeedableRng;
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(59_310);
        let n = 30;
        let x: Vec<f64> = (0..n).map(|k| k as f64).collect();
        let readings: Vec<f64> = (0..n)
            .map(|k| if !(5..25).contains(&k) { 2.0 } else { 4.0 })
            .collect();
        let (mut weighted, mut plain) = (0, 0);
        let draws = 10_000;
        for _ in 0..draws {
            let y: Vec<f64> = readings
                .iter()
                .map(|m| standard_normal(&mut rng) / m.sqrt())
                .collect();
            let rw = weighted_pearson(&x, &y, &readings).unwrap();
            let r = pearson(&x, &y).unwrap();
            weighted += (correlation_p(rw, n) < 0.01) as usize;
            plain += (correlation_p(r, n) < 0.01) as usize;
        }
        // 100 ± 26 (the binomial 99 % bounds, 2.6 standard deviations of 9.95) of 10,000.
        assert!((74..=126).contains(&weighted), "{weighted}");
        assert!(plain > 150, "{plain}");
    }
}
