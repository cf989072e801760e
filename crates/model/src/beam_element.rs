//! The Hermite beam element of `dynamics.rs`: a linearly tapered section between two nodes, its exact
//! stiffness from the section's flexibility and its consistent cubic-Hermite mass (docs/physics.md §11.1).

use crate::quadrature::{GAUSS4, GAUSS8};
use nalgebra::{Matrix2, Matrix4};

/// One beam element on `[a, b]` with bending stiffness `EI` and line mass `μ` linear between the ends.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Element {
    pub(crate) a: f64,
    pub(crate) b: f64,
    pub(crate) stiffness: [f64; 2],
    pub(crate) line_mass: [f64; 2],
}

impl Element {
    /// Exact stiffness from the flexibility of the element as a cantilever from `a` (docs/physics.md
    /// §11.1): `F = ∫ [(L-s)², (L-s); (L-s), 1] / EI(s) ds`, `K = Bᵀ F⁻¹ B` with `B` the end-`b`
    /// deformation relative to the rigid motion of end `a`.
    pub(crate) fn stiffness_matrix(&self) -> Matrix4<f64> {
        let len = self.b - self.a;
        #[rustfmt::skip]
        let b = nalgebra::Matrix2x4::new(
            -1.0, -len, 1.0, 0.0,
            0.0, -1.0, 0.0, 1.0,
        );
        b.transpose() * self.end_stiffness() * b
    }

    /// The stiffness of end `b` relative to the rigid motion of end `a`, `F⁻¹` of
    /// [`Element::stiffness_matrix`].
    pub(crate) fn end_stiffness(&self) -> Matrix2<f64> {
        let len = self.b - self.a;
        let [e0, e1] = self.stiffness;
        let ei = |s: f64| e0 + (e1 - e0) * s / len;
        // 1/EI varies most where EI is smallest: split the element where EI has grown by 1.2 so that
        // the 8-point rule integrates each piece to rounding.
        let ratio = e0.max(e1) / e0.min(e1);
        let pieces = ((ratio.ln() / 1.2f64.ln()).ceil() as usize).max(1);
        let at = |k: usize| {
            if pieces == 1 {
                len * k as f64
            } else {
                let target = e0 * (e1 / e0).powf(k as f64 / pieces as f64);
                len * (target - e0) / (e1 - e0)
            }
        };
        let mut f = Matrix2::<f64>::zeros();
        for p in 0..pieces {
            let (s0, s1) = (at(p), at(p + 1));
            let half = 0.5 * (s1 - s0);
            for (xi, w) in GAUSS8 {
                let s = s0 + half * (xi + 1.0);
                let arm = len - s;
                let weight = w * half / ei(s);
                f[(0, 0)] += weight * arm * arm;
                f[(0, 1)] += weight * arm;
                f[(1, 1)] += weight;
            }
        }
        f[(1, 0)] = f[(0, 1)];
        f.try_inverse().expect("a positive-definite flexibility")
    }

    /// Consistent mass of the cubic Hermite shape functions with `μ` linear (4-point Gauss, exact).
    pub(crate) fn mass_matrix(&self) -> Matrix4<f64> {
        let len = self.b - self.a;
        let [m0, m1] = self.line_mass;
        let mut m = Matrix4::<f64>::zeros();
        for (xi, w) in GAUSS4 {
            let u = 0.5 * (xi + 1.0);
            let n = [
                1.0 - 3.0 * u * u + 2.0 * u.powi(3),
                len * (u - 2.0 * u * u + u.powi(3)),
                3.0 * u * u - 2.0 * u.powi(3),
                len * (u.powi(3) - u * u),
            ];
            let mu = m0 + (m1 - m0) * u;
            let weight = 0.5 * w * len * mu;
            for r in 0..4 {
                for c in 0..4 {
                    m[(r, c)] += weight * n[r] * n[c];
                }
            }
        }
        m
    }
}
