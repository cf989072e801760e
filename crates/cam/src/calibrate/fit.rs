//! Bounded nonlinear least squares: projected Levenberg-Marquardt with a forward-difference Jacobian
//! (a parameter on a bound the step pushes against held there), several starting points, and the
//! covariance `σ² (JᵀJ)⁻¹` by SVD at the optimum.

use nalgebra::{DMatrix, DVector};

/// One fitted parameter's range and the point the search may start from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ParameterRange {
    /// Lower bound.
    pub lo: f64,
    /// Upper bound.
    pub hi: f64,
}

/// Result of a least-squares fit.
#[derive(Debug, Clone)]
pub struct FitResult {
    /// Parameter estimates.
    pub theta: Vec<f64>,
    /// Residual sum of squares.
    pub rss: f64,
    /// Number of residuals.
    pub n: usize,
    /// Residuals at the optimum.
    pub residuals: Vec<f64>,
    /// Jacobian at the optimum (n x p).
    pub jacobian: DMatrix<f64>,
}

impl FitResult {
    /// Covariance `σ² (JᵀJ)⁺` with `σ² = RSS / (n - p)` (pseudo-inverse by SVD).
    pub fn covariance(&self) -> DMatrix<f64> {
        let p = self.theta.len();
        if p == 0 {
            return DMatrix::zeros(0, 0);
        }
        if self.jacobian.iter().any(|x| !x.is_finite()) {
            // The model cannot be evaluated beside the optimum: no interval.
            return DMatrix::from_element(p, p, f64::INFINITY);
        }
        let dof = (self.n as f64 - p as f64).max(1.0);
        let sigma2 = self.rss / dof;
        let jtj = self.jacobian.transpose() * &self.jacobian;
        let svd = jtj.svd(true, true);
        let max_sv = svd.singular_values.max();
        let pinv = svd
            .pseudo_inverse(max_sv * 1e-13)
            .unwrap_or_else(|_| DMatrix::from_element(p, p, f64::INFINITY));
        pinv * sigma2
    }

    /// Leverage `h_ii` of each residual (diagonal of `J (JᵀJ)⁺ Jᵀ`).
    pub fn leverage(&self) -> Vec<f64> {
        let p = self.theta.len();
        if p == 0 || self.jacobian.iter().any(|x| !x.is_finite()) {
            return vec![0.0; self.n];
        }
        let jtj = self.jacobian.transpose() * &self.jacobian;
        let svd = jtj.svd(true, true);
        let max_sv = svd.singular_values.max();
        let Ok(pinv) = svd.pseudo_inverse(max_sv * 1e-13) else {
            return vec![0.0; self.n];
        };
        (0..self.n)
            .map(|i| {
                let row = self.jacobian.row(i);
                (row * &pinv * row.transpose())[(0, 0)]
            })
            .collect()
    }
}

/// Minimise `Σ r(θ)²` over the box `bounds` from each start; keep the best.
///
/// `residuals(θ, out)` fills `out` (same length on every call).
pub fn least_squares<F>(residuals: &F, bounds: &[ParameterRange], starts: &[Vec<f64>]) -> FitResult
where
    F: Fn(&[f64], &mut Vec<f64>),
{
    let search = |theta: &[f64], out: &mut Vec<f64>| {
        residuals(theta, out);
        None
    };
    least_squares_grouped(&search, residuals, bounds, starts)
}

/// [`least_squares`] with a shorter form of the residuals to search on: `search(θ, out)` fills `out` with
/// residuals whose sum of squares is that of `residuals` less a constant it returns (rows that share
/// every term of the model replaced by their group's mean, weighted by the root of their number; the
/// constant is the rows' spread about their means), or returns None after filling `out` with the
/// residuals themselves. The same form on every call. The result has the residuals, their sum of
/// squares and their Jacobian at the optimum.
pub fn least_squares_grouped<S, F>(
    search: &S,
    residuals: &F,
    bounds: &[ParameterRange],
    starts: &[Vec<f64>],
) -> FitResult
where
    S: Fn(&[f64], &mut Vec<f64>) -> Option<f64>,
    F: Fn(&[f64], &mut Vec<f64>),
{
    let mut best: Option<FitResult> = None;
    for start in starts {
        let fit = levenberg_marquardt(search, residuals, bounds, start);
        if best.as_ref().is_none_or(|b| fit.rss < b.rss) {
            best = Some(fit);
        }
    }
    best.unwrap_or_else(|| levenberg_marquardt(search, residuals, bounds, &[]))
}

fn clamp(theta: &mut [f64], bounds: &[ParameterRange]) {
    for (t, b) in theta.iter_mut().zip(bounds) {
        *t = t.clamp(b.lo, b.hi);
    }
}

fn rss_of(r: &[f64]) -> f64 {
    r.iter().map(|x| x * x).sum()
}

/// Fill `j` (n x p) with the forward-difference Jacobian at `theta`, whose residuals are `r0`; `r` is
/// scratch space for the shifted residuals.
fn jacobian_into<F>(
    residuals: &F,
    bounds: &[ParameterRange],
    theta: &[f64],
    r0: &[f64],
    j: &mut DMatrix<f64>,
    r: &mut Vec<f64>,
) where
    F: Fn(&[f64], &mut Vec<f64>),
{
    let n = r0.len();
    let mut shifted = theta.to_vec();
    for (k, column) in j.as_mut_slice().chunks_exact_mut(n.max(1)).enumerate() {
        let b = bounds[k];
        let scale = (b.hi - b.lo).abs().max(1e-12);
        let mut h = 1e-7 * scale.max(theta[k].abs());
        if theta[k] + h > b.hi {
            h = -h;
        }
        shifted[k] = theta[k] + h;
        residuals(&shifted, r);
        for ((x, ri), r0i) in column.iter_mut().zip(r.iter()).zip(r0) {
            *x = (ri - r0i) / h;
        }
        shifted[k] = theta[k];
    }
}

/// `Σ a_i b_i`, summed in the order of the rows.
fn dot(a: &[f64], b: &[f64]) -> f64 {
    let mut pairs = a.iter().zip(b);
    let Some((a0, b0)) = pairs.next() else {
        return 0.0;
    };
    pairs.fold(a0 * b0, |sum, (x, y)| x * y + sum)
}

/// The normal equations' `JᵀJ` and `Jᵀr`, from the columns of `j` (no transposed copy): each entry a sum
/// over the rows in their order, as a matrix product sums it.
fn normal_equations(j: &DMatrix<f64>, r: &[f64]) -> (DMatrix<f64>, DVector<f64>) {
    let (n, p) = j.shape();
    let column = |k: usize| &j.as_slice()[k * n..(k + 1) * n];
    let mut jtj = DMatrix::zeros(p, p);
    for a in 0..p {
        for b in a..p {
            let s = dot(column(a), column(b));
            jtj[(a, b)] = s;
            jtj[(b, a)] = s;
        }
    }
    let g = DVector::from_fn(p, |a, _| dot(column(a), r));
    (jtj, g)
}

/// Which parameters sit on a bound that the descent direction `-g` pushes against: the step leaves
/// them there. Clamping a step that moves them as if free spoils the step of every parameter they are
/// correlated with, and the search then creeps along the bound at a growing damping instead of
/// converging (a projected Levenberg-Marquardt step on the free parameters alone converges as the
/// unbounded one does on them).
fn held_at_bounds(theta: &[f64], g: &DVector<f64>, bounds: &[ParameterRange]) -> Vec<bool> {
    theta
        .iter()
        .zip(bounds)
        .zip(g.iter())
        .map(|((&t, b), &gk)| (t <= b.lo && gk > 0.0) || (t >= b.hi && gk < 0.0))
        .collect()
}

/// The Levenberg-Marquardt step `-(JᵀJ + λ diag(JᵀJ))⁻¹ Jᵀr` on the parameters not `held`, zero on
/// those held; None where the damped system is not positive definite.
fn damped_step(
    jtj: &DMatrix<f64>,
    g: &DVector<f64>,
    lambda: f64,
    held: &[bool],
) -> Option<DVector<f64>> {
    let p = g.len();
    let mut a = jtj.clone();
    let mut rhs = -g;
    for k in 0..p {
        if held[k] {
            // The held parameter's row and column decouple; its step solves to zero.
            for m in 0..p {
                a[(k, m)] = 0.0;
                a[(m, k)] = 0.0;
            }
            a[(k, k)] = 1.0;
            rhs[k] = 0.0;
        } else {
            a[(k, k)] += lambda * jtj[(k, k)].max(1e-12);
        }
    }
    a.cholesky().map(|c| c.solve(&rhs))
}

/// The search's residuals at `theta` in `r`, and their sum of squares with the constant they leave out;
/// whether they are grouped.
fn search_at<S>(search: &S, theta: &[f64], r: &mut Vec<f64>) -> (f64, bool)
where
    S: Fn(&[f64], &mut Vec<f64>) -> Option<f64>,
{
    let left_out = search(theta, r);
    (rss_of(r) + left_out.unwrap_or(0.0), left_out.is_some())
}

fn levenberg_marquardt<S, F>(
    search: &S,
    residuals: &F,
    bounds: &[ParameterRange],
    start: &[f64],
) -> FitResult
where
    S: Fn(&[f64], &mut Vec<f64>) -> Option<f64>,
    F: Fn(&[f64], &mut Vec<f64>),
{
    let p = bounds.len();
    let mut theta = start.to_vec();
    theta.resize(p, 0.0);
    clamp(&mut theta, bounds);
    let mut r = Vec::new();
    let (mut rss, grouped) = search_at(search, &theta, &mut r);
    let searched = |t: &[f64], out: &mut Vec<f64>| {
        search(t, out);
    };
    let mut lambda = 1e-3;
    let mut trial = vec![0.0; p];
    let mut r_trial = Vec::new();
    let mut j = DMatrix::zeros(r.len(), p);
    // Whether `j` is the Jacobian at `theta`: a search that ends without a step keeps it for the result.
    let mut j_at_theta = false;
    if p > 0 {
        for _ in 0..200 {
            jacobian_into(&searched, bounds, &theta, &r, &mut j, &mut r_trial);
            j_at_theta = true;
            let (jtj, g) = normal_equations(&j, &r);
            let held = held_at_bounds(&theta, &g, bounds);
            let mut improved = false;
            for _ in 0..30 {
                let Some(step) = damped_step(&jtj, &g, lambda, &held) else {
                    lambda *= 10.0;
                    continue;
                };
                for k in 0..p {
                    trial[k] = theta[k] + step[k];
                }
                clamp(&mut trial, bounds);
                let (rss_trial, _) = search_at(search, &trial, &mut r_trial);
                if rss_trial.is_finite() && rss_trial < rss {
                    let gain = (rss - rss_trial) / rss.max(1e-300);
                    theta.copy_from_slice(&trial);
                    std::mem::swap(&mut r, &mut r_trial);
                    rss = rss_trial;
                    j_at_theta = false;
                    lambda = (lambda / 3.0).max(1e-12);
                    improved = gain > 1e-12;
                    break;
                }
                lambda *= 4.0;
                if lambda > 1e12 {
                    break;
                }
            }
            if !improved {
                break;
            }
        }
    }
    if grouped {
        // The residuals themselves at the optimum, and their Jacobian.
        residuals(&theta, &mut r);
        rss = rss_of(&r);
        j = DMatrix::zeros(r.len(), p);
        jacobian_into(residuals, bounds, &theta, &r, &mut j, &mut r_trial);
    } else if !j_at_theta {
        jacobian_into(&searched, bounds, &theta, &r, &mut j, &mut r_trial);
    }
    FitResult {
        n: r.len(),
        theta,
        rss,
        residuals: r,
        jacobian: j,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fits_an_exponential_and_respects_bounds() {
        let xs: Vec<f64> = (0..20).map(|i| i as f64 * 0.1).collect();
        let ys: Vec<f64> = xs.iter().map(|x| 2.0 * (-1.3 * x).exp()).collect();
        let f = |t: &[f64], out: &mut Vec<f64>| {
            out.clear();
            out.extend(
                xs.iter()
                    .zip(&ys)
                    .map(|(x, y)| y - t[0] * (-t[1] * x).exp()),
            );
        };
        let b = [
            ParameterRange { lo: 0.0, hi: 10.0 },
            ParameterRange { lo: 0.0, hi: 5.0 },
        ];
        let fit = least_squares(&f, &b, &[vec![1.0, 0.1]]);
        assert!((fit.theta[0] - 2.0).abs() < 1e-6 && (fit.theta[1] - 1.3).abs() < 1e-6);
        let capped = [
            ParameterRange { lo: 0.0, hi: 10.0 },
            ParameterRange { lo: 0.0, hi: 1.0 },
        ];
        let fit = least_squares(&f, &capped, &[vec![1.0, 0.1]]);
        assert!(fit.theta[1] <= 1.0 && (fit.theta[1] - 1.0).abs() < 1e-9);
    }

    /// Two strongly correlated parameters, the unbounded optimum of one beyond its bound: the fit ends
    /// at the bounded optimum (the bound held, the other parameter's own least squares given it), as
    /// the closed form gives it, not short of it along the bound.
    #[test]
    fn a_parameter_held_at_its_bound_leaves_the_others_to_converge() {
        // y = a x + b (x + 0.05 x²) + noise-like wiggle; b's optimum is negative, its bound is 0.
        let xs: Vec<f64> = (0..30).map(|i| 1.0 + i as f64 * 0.1).collect();
        let ys: Vec<f64> = xs
            .iter()
            .enumerate()
            .map(|(i, x)| 2.0 * x - 0.5 * (x + 0.05 * x * x) + 0.01 * ((i * 7 % 5) as f64 - 2.0))
            .collect();
        let f = |t: &[f64], out: &mut Vec<f64>| {
            out.clear();
            out.extend(
                xs.iter()
                    .zip(&ys)
                    .map(|(x, y)| y - t[0] * x - t[1] * (x + 0.05 * x * x)),
            );
        };
        let b = [
            ParameterRange { lo: 0.0, hi: 10.0 },
            ParameterRange { lo: 0.0, hi: 5.0 },
        ];
        let fit = least_squares(&f, &b, &[vec![1.0, 1.0]]);
        // With b = 0, a = Σxy / Σx².
        let a = xs.iter().zip(&ys).map(|(x, y)| x * y).sum::<f64>()
            / xs.iter().map(|x| x * x).sum::<f64>();
        assert_eq!(fit.theta[1], 0.0);
        assert!((fit.theta[0] - a).abs() < 1e-10, "{} vs {a}", fit.theta[0]);
    }

    /// Rows that share every term of the model searched as their groups' weighted means give the fit
    /// of the rows themselves, with the rows' residuals and Jacobian at the optimum.
    #[test]
    fn a_grouped_search_finds_the_fit_of_the_rows() {
        // Five x values, three noisy rows at each.
        let xs: Vec<f64> = (0..5).map(|i| i as f64 * 0.4).collect();
        let noise = [0.03, -0.02, -0.01];
        let rows: Vec<(usize, f64)> = (0..15)
            .map(|k| (k / 3, 2.0 * (-1.3 * xs[k / 3]).exp() + noise[k % 3]))
            .collect();
        let model = |t: &[f64], x: f64| t[0] * (-t[1] * x).exp();
        let f = |t: &[f64], out: &mut Vec<f64>| {
            out.clear();
            out.extend(rows.iter().map(|&(i, y)| y - model(t, xs[i])));
        };
        let mean = |i: usize| rows[3 * i..3 * i + 3].iter().map(|r| r.1).sum::<f64>() / 3.0;
        let spread: f64 = rows.iter().map(|&(i, y)| (y - mean(i)).powi(2)).sum();
        let grouped = |t: &[f64], out: &mut Vec<f64>| {
            out.clear();
            out.extend((0..5).map(|i| 3f64.sqrt() * (mean(i) - model(t, xs[i]))));
            Some(spread)
        };
        let b = [
            ParameterRange { lo: 0.0, hi: 10.0 },
            ParameterRange { lo: 0.0, hi: 5.0 },
        ];
        let rows_fit = least_squares(&f, &b, &[vec![1.0, 0.1]]);
        let fit = least_squares_grouped(&grouped, &f, &b, &[vec![1.0, 0.1]]);
        for (x, y) in fit.theta.iter().zip(&rows_fit.theta) {
            assert!((x - y).abs() < 1e-9, "{x} vs {y}");
        }
        assert_eq!(fit.n, 15);
        assert!((fit.rss / rows_fit.rss - 1.0).abs() < 1e-12);
        assert_eq!(fit.jacobian.shape(), (15, 2));
        assert!((&fit.jacobian - &rows_fit.jacobian).amax() < 1e-6);
    }
}
