//! Symmetric matrices of half-bandwidth 3, the stiffness and mass of a beam cut into two-degree-of-freedom
//! Hermite elements (each element couples the four degrees of freedom of its two nodes): product,
//! Cholesky factor and solve in `O(n)` rather than the dense `O(n³)`, as the calibration's modal solve
//! needs them for every resonance at every evaluation (Golub & Van Loan, Matrix Computations, 4th ed.,
//! Algorithm 4.3.5, band Cholesky).

use nalgebra::DMatrix;

/// Half-bandwidth: entry `(i, j)` may be non-zero only where `|i - j| <= HALF_BAND`.
pub const HALF_BAND: usize = 3;
const WIDTH: usize = HALF_BAND + 1;

/// The lower band of a symmetric matrix: row `i` holds `(i, j)` for `j` in `i-3..=i` at index
/// `j + 3 - i` (entries before column 0 are zero).
#[derive(Debug, Clone)]
pub struct Band {
    rows: Vec<[f64; WIDTH]>,
}

/// A Cholesky factor `L` in the band, with the inverses of its diagonal (a solve multiplies by them
/// rather than dividing).
#[derive(Debug, Clone)]
pub struct Factor {
    l: Band,
    inverse_diagonal: Vec<f64>,
}

/// `a · b`.
pub fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

impl Band {
    /// The band of the symmetric `a`; None when `a` has a non-zero entry outside it.
    pub fn from_dense(a: &DMatrix<f64>) -> Option<Band> {
        let n = a.nrows();
        let mut rows = vec![[0.0; WIDTH]; n];
        for (i, row) in rows.iter_mut().enumerate() {
            for j in 0..n {
                let v = a[(i, j)];
                if i.abs_diff(j) > HALF_BAND {
                    if v != 0.0 {
                        return None;
                    }
                } else if j <= i {
                    row[j + HALF_BAND - i] = v;
                }
            }
        }
        Some(Band { rows })
    }

    fn len(&self) -> usize {
        self.rows.len()
    }

    /// Entry `(i, j)`, `j <= i <= j + 3`.
    fn at(&self, i: usize, j: usize) -> f64 {
        self.rows[i][j + HALF_BAND - i]
    }

    /// The columns `j <= i` of row `i` inside the band.
    fn start(i: usize) -> usize {
        i.saturating_sub(HALF_BAND)
    }

    /// `out = A x` for the symmetric matrix.
    pub fn mul(&self, x: &[f64], out: &mut [f64]) {
        let n = self.len();
        for (i, o) in out.iter_mut().enumerate().take(n) {
            let mut s = 0.0;
            for (j, xj) in x.iter().enumerate().take(i + 1).skip(Band::start(i)) {
                s += self.at(i, j) * xj;
            }
            for (j, xj) in x.iter().enumerate().take(n.min(i + WIDTH)).skip(i + 1) {
                s += self.at(j, i) * xj;
            }
            *o = s;
        }
    }

    /// The Cholesky factor `L` (`A = L Lᵀ`, `L` lower, in the same band); None when `A` is not
    /// positive definite.
    pub fn cholesky(&self) -> Option<Factor> {
        let n = self.len();
        let mut l = Band {
            rows: vec![[0.0; WIDTH]; n],
        };
        for i in 0..n {
            for j in Band::start(i)..=i {
                let mut s = self.at(i, j);
                for k in Band::start(i)..j {
                    s -= l.at(i, k) * l.at(j, k);
                }
                let v = if i == j {
                    // Not positive (or NaN): not positive definite.
                    if s.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
                        return None;
                    }
                    s.sqrt()
                } else {
                    s / l.at(j, j)
                };
                l.rows[i][j + HALF_BAND - i] = v;
            }
        }
        let inverse_diagonal = (0..n).map(|i| 1.0 / l.at(i, i)).collect();
        Some(Factor {
            l,
            inverse_diagonal,
        })
    }
}

impl Factor {
    /// `b` replaced by `(L Lᵀ)⁻¹ b`.
    pub fn solve_in_place(&self, b: &mut [f64]) {
        let (l, d) = (&self.l, &self.inverse_diagonal);
        let n = l.len();
        for i in 0..n {
            let start = Band::start(i);
            let s: f64 = (start..i)
                .zip(&b[start..i])
                .map(|(k, bk)| l.at(i, k) * bk)
                .sum();
            b[i] = (b[i] - s) * d[i];
        }
        for i in (0..n).rev() {
            let end = n.min(i + WIDTH);
            let s: f64 = (i + 1..end)
                .zip(&b[i + 1..end])
                .map(|(k, bk)| l.at(k, i) * bk)
                .sum();
            b[i] = (b[i] - s) * d[i];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::DVector;

    /// A symmetric positive-definite matrix of half-bandwidth 3 (diagonally dominant).
    fn banded(n: usize) -> DMatrix<f64> {
        DMatrix::from_fn(n, n, |i, j| match i.abs_diff(j) {
            0 => 10.0 + i as f64,
            d if d <= HALF_BAND => 1.0 / (1.0 + (i + j) as f64 + d as f64),
            _ => 0.0,
        })
    }

    #[test]
    fn band_solve_and_product_match_the_dense_ones() {
        for n in [1, 2, 4, 7, 25] {
            let a = banded(n);
            let band = Band::from_dense(&a).unwrap();
            let b = DVector::from_fn(n, |i, _| (i as f64 * 0.7).sin() + 0.1);
            let mut x: Vec<f64> = b.iter().copied().collect();
            band.cholesky().unwrap().solve_in_place(&mut x);
            let dense = a.clone().cholesky().unwrap().solve(&b);
            let mut ax = vec![0.0; n];
            band.mul(b.as_slice(), &mut ax);
            let dense_ax = &a * &b;
            for i in 0..n {
                assert!((x[i] - dense[i]).abs() < 1e-14 * dense.amax(), "n {n}");
                assert!(
                    (ax[i] - dense_ax[i]).abs() < 1e-14 * dense_ax.amax(),
                    "n {n}"
                );
            }
        }
    }

    #[test]
    fn an_entry_outside_the_band_or_an_indefinite_matrix_is_refused() {
        let mut a = banded(6);
        a[(5, 0)] = 1e-9;
        a[(0, 5)] = 1e-9;
        assert!(Band::from_dense(&a).is_none());
        let mut b = banded(6);
        b[(3, 3)] = -1.0;
        assert!(Band::from_dense(&b).unwrap().cholesky().is_none());
    }
}
