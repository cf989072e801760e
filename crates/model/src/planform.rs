//! Planform of a tapered bimorph with a rigid extension (thesis Table 2.4, Fig. 2.14, eqs. 2.28-2.34).

use crate::error::{check_half_open, check_open, ModelError};

/// Outline of the actuator in SI units. `x` runs from the clamped base to the tip.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Planform {
    /// Total length `l_tot = l_p + l_ext`, m.
    pub length: f64,
    /// Extension ratio `l_r = l_ext / l_p`.
    pub extension_ratio: f64,
    /// Base width `w_0`, m.
    pub base_width: f64,
    /// Width ratio `w_r = w_0 / w_nom`, `0 < w_r < 2`.
    pub width_ratio: f64,
    /// Passive-only tab behind the PZT (clamp, ground wire), m; 0 for none.
    pub base_tab: f64,
}

impl Planform {
    /// Validate a planform (lengths > 0, `l_r >= 0`, `0 < w_r < 2`, tab >= 0).
    pub fn new(
        length: f64,
        extension_ratio: f64,
        base_width: f64,
        width_ratio: f64,
        base_tab: f64,
    ) -> Result<Self, ModelError> {
        check_open("length", length, 0.0, f64::INFINITY, "greater than 0 m")?;
        check_half_open(
            "extension_ratio",
            extension_ratio,
            0.0,
            f64::INFINITY,
            "at least 0",
        )?;
        check_open(
            "base_width",
            base_width,
            0.0,
            f64::INFINITY,
            "greater than 0 m",
        )?;
        check_open("width_ratio", width_ratio, 0.0, 2.0, "(0, 2)")?;
        check_half_open("base_tab", base_tab, 0.0, f64::INFINITY, "at least 0 m")?;
        Ok(Planform {
            length,
            extension_ratio,
            base_width,
            width_ratio,
            base_tab,
        })
    }

    /// Piezo length `l_p = l_tot / (1 + l_r)`.
    #[inline]
    pub fn piezo_length(&self) -> f64 {
        self.length / (1.0 + self.extension_ratio)
    }

    /// Extension length `l_ext = l_r l_p`.
    #[inline]
    pub fn extension_length(&self) -> f64 {
        self.extension_ratio * self.piezo_length()
    }

    /// Nominal (mean) width `w_nom = w_0 / w_r`.
    #[inline]
    pub fn nominal_width(&self) -> f64 {
        self.base_width / self.width_ratio
    }

    /// Tip width `w_tip = (2 - w_r) w_nom`.
    #[inline]
    pub fn tip_width(&self) -> f64 {
        (2.0 - self.width_ratio) * self.nominal_width()
    }

    /// Width at `x` along the piezo, `w(x) = w_nom (w_r + 2 (1 - w_r) x / l_p)` (thesis eq. 2.28 as
    /// corrected in docs/physics.md §1).
    pub fn width_at(&self, x: f64) -> f64 {
        self.nominal_width()
            * (self.width_ratio + 2.0 * (1.0 - self.width_ratio) * x / self.piezo_length())
    }

    /// Piezo (trapezoid) area `l_p w_nom`.
    pub fn piezo_area(&self) -> f64 {
        self.piezo_length() * self.nominal_width()
    }

    /// Outline length of one PZT plate (the trapezoid's perimeter),
    /// `w_0 + w_tip + 2 sqrt(l_p² + ((w_0 - w_tip)/2)²)`, m.
    pub fn piezo_perimeter(&self) -> f64 {
        let half_taper = 0.5 * (self.base_width - self.tip_width());
        self.base_width + self.tip_width() + 2.0 * self.piezo_length().hypot(half_taper)
    }

    /// Extension area `l_ext w_tip`.
    pub fn extension_area(&self) -> f64 {
        self.extension_length() * self.tip_width()
    }

    /// Base tab area `l_tab w_0`.
    pub fn tab_area(&self) -> f64 {
        self.base_tab * self.base_width
    }

    /// Shape factor of the tip compliance, `G(w_r, l_r)` (see [`shape_factor`]).
    pub fn shape_factor(&self) -> f64 {
        shape_factor(self.width_ratio, self.extension_ratio)
    }

    /// Shape factor of the beam clamped at `x0` (m) along the piezo, `G(w_r, l_r; x0 / l_p)` (see
    /// [`shape_factor_from`]): the tip compliance is `C44 l_p³ G / (3 w_nom)`.
    pub fn shape_factor_from(&self, x0: f64) -> f64 {
        shape_factor_from(
            self.width_ratio,
            self.extension_ratio,
            x0 / self.piezo_length(),
        )
    }

    /// `∫x0..l_p (L - x) / w(x) dx` (m), `L = l_tot`: the moment arm of the tip over the width along the
    /// piezo from `x0` (see [`arm_over_width_from`]).
    pub fn arm_over_width_from(&self, x0: f64) -> f64 {
        let l_p = self.piezo_length();
        l_p * l_p / self.nominal_width()
            * arm_over_width_from(self.width_ratio, self.extension_ratio, x0 / l_p)
    }

    /// The narrowest width of the piezo, `min(w_0, w_tip)` (the width is linear in x), m.
    #[inline]
    pub fn narrowest_width(&self) -> f64 {
        self.base_width.min(self.tip_width())
    }
}

/// Below this |1 - w_r| the closed form loses digits to cancellation; the series takes over.
const SERIES_THRESHOLD: f64 = 0.05;

/// The same for the integrals from a start `u0 > 0` ([`shape_factor_from`]).
const SERIES_THRESHOLD_FROM_START: f64 = 0.2;

/// Tip-compliance shape factor of a linearly tapered beam with a rigid extension, load at the tip:
///
/// `G(w_r, l_r) = 3 ∫0..1 (1 + l_r - u)² / (w_r + 2 (1 - w_r) u) du`
/// `            = 3 / (8 (1 - w_r)³) [K² ln((2 - w_r)/w_r) - 2 (1 - w_r)(2K - 1)]`,
/// `K = 2 (1 + l_r) - w_r (1 + 2 l_r)`.
///
/// This is the thesis' `(g_a + g_b)/g_c` (eqs. 2.32-2.34, printed `r l_r` read as `4 l_r`;
/// docs/physics.md §3). The closed form divides by `(1 - w_r)³`, so for `|1 - w_r| < 0.05` a power series in
/// `e = 1 - w_r` is used instead: with `s = 2u - 1`, `b = 1 + 2 l_r`,
/// `G = (3/8) Σ_n (-e)^n ∫-1..1 (b - s)² s^n ds`, exact term by term; it gives `G(1, l_r) = 1 + 3 l_r + 3 l_r²`.
/// It is [`shape_factor_from`] from the root.
pub fn shape_factor(width_ratio: f64, extension_ratio: f64) -> f64 {
    shape_factor_from(width_ratio, extension_ratio, 0.0)
}

/// The shape factor of the beam from `u0 = x0 / l_p` to the tip, as if clamped at `x0` (a root length
/// held rigidly in the clamp, docs/calibration.md §2 "Rigid root"):
///
/// `G(w_r, l_r; u0) = 3 ∫u0..1 (1 + l_r - u)² / (w_r + 2 (1 - w_r) u) du`
/// `                = 3 / (8 e³) [K² ln((2 - w_r)/t0) - 2 e (1 - u0)(2K - 1 - e u0)]`,
///
/// `e = 1 - w_r`, `t0 = w_r + 2 e u0` (the width at `u0` over `w_nom`), `K` as in [`shape_factor`]; with
/// `t = w_r + 2 e u` the integrand is `(K - t)² / (8 e³ t)` in `t`, and `(t1² - t0²)/2 = 2 e (1 - u0)(1 + e u0)`.
/// At `u0 = 0` it is [`shape_factor`]'s closed form operation for operation. Near `w_r = 1` (|e| < 0.05 from
/// the root, |e| < 0.2 from a start inside, where the closed form cancels more) the series
/// `(3/8) Σ_n (-e)^n ∫s0..1 (b - s)² s^n ds`, `s0 = 2 u0 - 1`. The tip compliance of the beam clamped at `x0`
/// is `C44 l_p³ G(u0) / (3 w_nom)`; for a rectangle without extension `G(1, 0; u0) = (1 - u0)³`.
pub fn shape_factor_from(width_ratio: f64, extension_ratio: f64, start: f64) -> f64 {
    taper_integral(2, width_ratio, extension_ratio, start)
}

/// The arm-over-width integral of the driven length from `u0 = x0 / l_p` to the tip:
///
/// `H(w_r, l_r; u0) = ∫u0..1 (1 + l_r - u) / (w_r + 2 (1 - w_r) u) du`
/// `                = 1 / (4 e²) [K ln((2 - w_r)/t0) - 2 e (1 - u0)]`
///
/// (`e`, `t0`, `K` as in [`shape_factor_from`]; the integrand is `(K - t) / (4 e² t)` in `t`), with the series
/// `(1/4) Σ_n (-e)^n ∫s0..1 (b - s) s^n ds` near `w_r = 1`. `l_p² H / w_nom = ∫x0..l_p (L - x) / w(x) dx`:
/// the tip deflection lost to unelectroded edge margins (docs/calibration.md §2 "Edge margin").
pub fn arm_over_width_from(width_ratio: f64, extension_ratio: f64, start: f64) -> f64 {
    taper_integral(1, width_ratio, extension_ratio, start)
}

/// `3 ∫u0..1 (1 + l_r - u)² / w du` (`power` 2) or `∫u0..1 (1 + l_r - u) / w du` (`power` 1), with
/// `w = w_r + 2 (1 - w_r) u`: closed form, or the series near `w_r = 1`.
fn taper_integral(power: u32, width_ratio: f64, extension_ratio: f64, start: f64) -> f64 {
    let e = 1.0 - width_ratio;
    let b = 1.0 + 2.0 * extension_ratio;
    // The factor in front: 3 for the compliance shape factor, 1 for the arm integral.
    let front = if power == 2 { 3.0 } else { 1.0 };
    // From a start inside the beam the closed form cancels more (its bracket is O(e³ (1 - u0)³)), so the
    // series, which converges for |e| < 1 (24 terms: 0.2^24 ≈ 2e-17), takes over up to |e| = 0.2 there.
    let threshold = if start > 0.0 {
        SERIES_THRESHOLD_FROM_START
    } else {
        SERIES_THRESHOLD
    };
    if e.abs() < threshold {
        // ∫s0..1 s^m ds = (1 - s0^(m+1)) / (m+1); from s0 = -1: 2/(m+1) for even m, 0 for odd m.
        let s0 = 2.0 * start - 1.0;
        let j = |m: u32| (1.0 - s0.powi(m as i32 + 1)) / (m as f64 + 1.0);
        let mut sum = 0.0;
        let mut power_e = 1.0; // (-e)^n
                               // |e| below the threshold (0.2 at most): 24 terms leave a remainder below 0.2^24 ≈ 2e-17.
        for n in 0..24u32 {
            sum += power_e
                * if power == 2 {
                    b * b * j(n) - 2.0 * b * j(n + 1) + j(n + 2)
                } else {
                    b * j(n) - j(n + 1)
                };
            power_e *= -e;
        }
        // (b - s)/2 = 1 + l_r - u, w = 1 + e s, du = ds/2.
        front / f64::from(1u32 << (power + 1)) * sum
    } else {
        let k = 2.0 * (1.0 + extension_ratio) - width_ratio * b;
        let t0 = width_ratio + 2.0 * e * start;
        let log = ((2.0 - width_ratio) / t0).ln();
        if power == 2 {
            front / (8.0 * e * e * e)
                * (k * k * log - 2.0 * e * (1.0 - start) * (2.0 * k - (1.0 + e * start)))
        } else {
            front / (4.0 * e * e) * (k * log - 2.0 * e * (1.0 - start))
        }
    }
}

/// Energy shape efficiency `G_U = (1 + 2 l_r)² / G` (docs/physics.md §3); `G_U <= 4/3`, with equality on
/// `w_r = 2 (1 + l_r) / (1 + 2 l_r)` (uniform strain along the piezo), and 1 for a rectangle.
pub fn energy_shape_factor(width_ratio: f64, extension_ratio: f64) -> f64 {
    let b = 1.0 + 2.0 * extension_ratio;
    b * b / shape_factor(width_ratio, extension_ratio)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Composite Gauss-Legendre quadrature of `∫u0..1 (1 + l_r - u)^power / (w_r + 2 (1 - w_r) u) du`
    /// (independent of both branches).
    fn quadrature(w_r: f64, l_r: f64, u0: f64, power: i32) -> f64 {
        // 8-point Gauss-Legendre nodes and weights on [-1, 1].
        const X: [f64; 4] = [
            0.183_434_642_495_649_8,
            0.525_532_409_916_329,
            0.796_666_477_413_626_7,
            0.960_289_856_497_536_3,
        ];
        const W: [f64; 4] = [
            0.362_683_783_378_362,
            0.313_706_645_877_887_3,
            0.222_381_034_453_374_5,
            0.101_228_536_290_376_3,
        ];
        let f = |u: f64| (1.0 + l_r - u).powi(power) / (w_r + 2.0 * (1.0 - w_r) * u);
        let panels = 400;
        let h = (1.0 - u0) / panels as f64;
        let mut sum = 0.0;
        for p in 0..panels {
            let mid = u0 + (p as f64 + 0.5) * h;
            for i in 0..4 {
                for sign in [-1.0, 1.0] {
                    sum += W[i] * f(mid + sign * X[i] * h / 2.0) * h / 2.0;
                }
            }
        }
        sum
    }

    /// The shape factor's defining integral by quadrature.
    fn g_quadrature(w_r: f64, l_r: f64) -> f64 {
        3.0 * quadrature(w_r, l_r, 0.0, 2)
    }

    #[test]
    fn matches_the_reference_table() {
        // Source: docs/physics.md §3 table of G (closed form and quadrature agree to 1e-6).
        let table = [
            (0.5, 0.0, 1.415633),
            (0.5, 0.5, 4.183347),
            (0.5, 1.0, 8.598980),
            (1.0, 0.0, 1.0),
            (1.0, 0.5, 3.25),
            (1.0, 1.0, 7.0),
            (1.5, 0.0, 0.823959),
            (1.5, 0.5, 3.000000),
            (1.5, 1.0, 6.823959),
            (1.75, 0.0, 0.774773),
            (1.75, 0.5, 3.099091),
            (1.75, 1.0, 7.369320),
        ];
        for (w_r, l_r, g) in table {
            assert!((shape_factor(w_r, l_r) - g).abs() < 1e-6, "G({w_r}, {l_r})");
        }
    }

    #[test]
    fn matches_quadrature_on_a_grid_including_near_one() {
        // Source: Gauss-Legendre quadrature of the defining integral, 1e-9 relative.
        let mut w_rs: Vec<f64> = (1..=39).map(|i| 0.05 * i as f64).collect();
        for p in 1..=12 {
            let e = 10f64.powi(-p);
            w_rs.push(1.0 - e);
            w_rs.push(1.0 + e);
        }
        w_rs.extend([1.0 - SERIES_THRESHOLD, 1.0 + SERIES_THRESHOLD, 0.95, 1.05]);
        for &w_r in &w_rs {
            for l_r in [0.0, 0.25, 0.833, 1.5, 3.0] {
                let q = g_quadrature(w_r, l_r);
                let g = shape_factor(w_r, l_r);
                assert!(
                    ((g - q) / q).abs() < 1e-9,
                    "G({w_r}, {l_r}) = {g}, quadrature {q}"
                );
            }
        }
    }

    /// The integrals from a start fraction u0 (a rigid root, edge margins from a dead length) against
    /// the same quadrature on [u0, 1], both branches, 1e-9 relative.
    #[test]
    fn integrals_from_a_start_match_quadrature() {
        let mut w_rs: Vec<f64> = (1..=39).map(|i| 0.05 * i as f64).collect();
        w_rs.extend([
            1.0 - 1e-3,
            1.0 + 1e-6,
            1.0 - SERIES_THRESHOLD,
            1.0 + SERIES_THRESHOLD,
        ]);
        for &w_r in &w_rs {
            for l_r in [0.0, 0.833, 3.0] {
                for u0 in [0.0, 0.01, 0.1, 0.37, 0.8, 0.95] {
                    let q = 3.0 * quadrature(w_r, l_r, u0, 2);
                    let g = shape_factor_from(w_r, l_r, u0);
                    assert!(
                        ((g - q) / q).abs() < 1e-9,
                        "G({w_r}, {l_r}; {u0}) = {g}, quadrature {q}"
                    );
                    let q = quadrature(w_r, l_r, u0, 1);
                    let h = arm_over_width_from(w_r, l_r, u0);
                    assert!(
                        ((h - q) / q).abs() < 1e-9,
                        "H({w_r}, {l_r}; {u0}) = {h}, quadrature {q}"
                    );
                }
            }
        }
    }

    /// Exact values a rectangle gives by hand: `G(1, 0; u0) = (1 - u0)³` (a cantilever of length
    /// `l_p - x0`: `(l_p - x0)³ / (3 w)` over `l_p³ / (3 w)`), `H(1, l_r; u0) = ((1 + l_r - u0)² - l_r²) / 2`.
    #[test]
    fn integrals_from_a_start_on_a_rectangle_are_exact() {
        for u0 in [0.0, 0.05, 0.25, 0.5, 0.9] {
            let g = shape_factor_from(1.0, 0.0, u0);
            assert!((g - (1.0 - u0).powi(3)).abs() < 1e-14, "{u0}: {g}");
            for l_r in [0.0, 0.5, 2.0] {
                let h = arm_over_width_from(1.0, l_r, u0);
                let want = 0.5 * ((1.0 + l_r - u0).powi(2) - l_r * l_r);
                assert!((h - want).abs() < 1e-14 * want.max(1.0), "{l_r}, {u0}: {h}");
            }
        }
        // The planform's lengths: the tip compliance of a 40 mm rectangle held over 4 mm is that of a
        // 36 mm cantilever.
        let p = Planform::new(40e-3, 0.0, 8e-3, 1.0, 0.0).unwrap();
        assert!((p.shape_factor_from(4e-3) - 0.9f64.powi(3)).abs() < 1e-14);
        let taper = Planform::new(40e-3, 0.5, 8e-3, 1.6, 0.0).unwrap();
        assert_eq!(taper.narrowest_width(), taper.tip_width());
    }

    #[test]
    fn continuous_through_the_series_switch() {
        for l_r in [0.0, 0.833, 2.0] {
            for side in [-1.0, 1.0] {
                let w = 1.0 + side * SERIES_THRESHOLD;
                let below = shape_factor(w - side * 1e-12, l_r);
                let above = shape_factor(w + side * 1e-12, l_r);
                assert!(((below - above) / above).abs() < 1e-10);
            }
        }
    }

    #[test]
    fn energy_shape_factor_never_exceeds_four_thirds_and_reaches_it_on_the_ridge() {
        // Source: docs/physics.md §3 (uniform-strain ridge w_r = 2(1 + l_r)/(1 + 2 l_r)).
        for i in 0..=60 {
            let l_r = 0.05 * i as f64;
            for j in 1..200 {
                let w_r = 0.01 * j as f64;
                assert!(energy_shape_factor(w_r, l_r) <= 4.0 / 3.0 + 1e-12);
            }
            let ridge = 2.0 * (1.0 + l_r) / (1.0 + 2.0 * l_r);
            if ridge < 2.0 {
                assert!(
                    (energy_shape_factor(ridge, l_r) - 4.0 / 3.0).abs() < 1e-9,
                    "l_r {l_r}"
                );
            }
        }
        assert!((energy_shape_factor(1.0, 0.0) - 1.0).abs() < 1e-15);
    }

    #[test]
    fn planform_of_thesis_design_c() {
        // Source: thesis Table 4.14 design C, l_tot 42.2 mm, l_r 0.833, w_0 5 mm, w_r 1.667.
        let p = Planform::new(42.2e-3, 0.833, 5e-3, 1.667, 0.0).unwrap();
        assert!((p.piezo_length() + p.extension_length() - 42.2e-3).abs() < 1e-15);
        assert!((p.width_at(0.0) - 5e-3).abs() < 1e-15);
        assert!((p.width_at(p.piezo_length()) - p.tip_width()).abs() < 1e-15);
        assert!(Planform::new(42.2e-3, 0.833, 5e-3, 2.5, 0.0).is_err());
        assert!(Planform::new(-1.0, 0.0, 5e-3, 1.0, 0.0).is_err());
        assert!(Planform::new(f64::NAN, 0.0, 5e-3, 1.0, 0.0).is_err());
    }
}
