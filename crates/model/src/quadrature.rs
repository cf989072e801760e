//! Gauss-Legendre rules on [-1, 1] as (abscissa, weight) pairs, for the integrals of the model that
//! have no closed form (Abramowitz & Stegun, Handbook of Mathematical Functions, 1964, Table 25.4): an
//! `n`-point rule is exact for polynomials up to degree `2n - 1`.

/// 4 points (exact to degree 7).
pub(crate) const GAUSS4: [(f64, f64); 4] = [
    (-0.861_136_311_594_052_6, 0.347_854_845_137_453_85),
    (-0.339_981_043_584_856_3, 0.652_145_154_862_546_2),
    (0.339_981_043_584_856_3, 0.652_145_154_862_546_2),
    (0.861_136_311_594_052_6, 0.347_854_845_137_453_85),
];

/// 5 points (exact to degree 9).
pub(crate) const GAUSS5: [(f64, f64); 5] = [
    (-0.906_179_845_938_664, 0.236_926_885_056_189_1),
    (-0.538_469_310_105_683, 0.478_628_670_499_366_5),
    (0.0, 0.568_888_888_888_888_9),
    (0.538_469_310_105_683, 0.478_628_670_499_366_5),
    (0.906_179_845_938_664, 0.236_926_885_056_189_1),
];

/// 8 points (exact to degree 15).
pub(crate) const GAUSS8: [(f64, f64); 8] = [
    (-0.960_289_856_497_536_3, 0.101_228_536_290_376_26),
    (-0.796_666_477_413_626_7, 0.222_381_034_453_374_47),
    (-0.525_532_409_916_329, 0.313_706_645_877_887_3),
    (-0.183_434_642_495_649_8, 0.362_683_783_378_362),
    (0.183_434_642_495_649_8, 0.362_683_783_378_362),
    (0.525_532_409_916_329, 0.313_706_645_877_887_3),
    (0.796_666_477_413_626_7, 0.222_381_034_453_374_47),
    (0.960_289_856_497_536_3, 0.101_228_536_290_376_26),
];

#[cfg(test)]
mod tests {
    use super::*;

    /// Each rule integrates the monomials up to its degree exactly: `∫ x^k dx` over [-1, 1] is
    /// `2/(k+1)` for even `k` and 0 for odd.
    fn exact_to(rule: &[(f64, f64)], degree: i32) {
        for k in 0..=degree {
            let got: f64 = rule.iter().map(|(x, w)| w * x.powi(k)).sum();
            let want = if k % 2 == 0 {
                2.0 / (k + 1) as f64
            } else {
                0.0
            };
            assert!(
                (got - want).abs() < 1e-14,
                "{} points, degree {k}: {got}",
                rule.len()
            );
        }
    }

    #[test]
    fn each_rule_is_exact_to_its_degree() {
        exact_to(&GAUSS4, 7);
        exact_to(&GAUSS5, 9);
        exact_to(&GAUSS8, 15);
    }
}
