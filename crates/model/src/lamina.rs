//! Plane-stress lamina stiffness `Q` and its rotation `Q̄` (thesis eqs. 2.17-2.19; Jones, Mechanics of
//! Composite Materials, §2.6).

use crate::material::Material;
use nalgebra::Matrix3;

/// Reduced stiffness in the material axes (thesis eq. 2.17):
/// `Q11 = E1/(1-ν12ν21)`, `Q12 = ν12 E2/(1-ν12ν21)`, `Q22 = E2/(1-ν12ν21)`, `Q66 = G12`.
pub fn reduced_stiffness(m: &Material) -> Matrix3<f64> {
    let denom = 1.0 - m.nu12 * m.nu21();
    let q11 = m.e1 / denom;
    let q12 = m.nu12 * m.e2 / denom;
    let q22 = m.e2 / denom;
    Matrix3::new(q11, q12, 0.0, q12, q22, 0.0, 0.0, 0.0, m.g12)
}

/// Transformed reduced stiffness `Q̄` of a ply whose 1-axis is turned `angle_deg` from the laminate x axis
/// (thesis eq. 2.19, Jones eq. 2.85).
pub fn rotated_stiffness(q: &Matrix3<f64>, angle_deg: f64) -> Matrix3<f64> {
    let (s, c) = angle_deg.to_radians().sin_cos();
    let (c2, s2) = (c * c, s * s);
    let (c4, s4, c2s2) = (c2 * c2, s2 * s2, c2 * s2);
    let (q11, q12, q22, q66) = (q[(0, 0)], q[(0, 1)], q[(1, 1)], q[(2, 2)]);
    let b11 = q11 * c4 + 2.0 * (q12 + 2.0 * q66) * c2s2 + q22 * s4;
    let b12 = (q11 + q22 - 4.0 * q66) * c2s2 + q12 * (c4 + s4);
    let b22 = q11 * s4 + 2.0 * (q12 + 2.0 * q66) * c2s2 + q22 * c4;
    let b16 = (q11 - q12 - 2.0 * q66) * c2 * c * s + (q12 - q22 + 2.0 * q66) * c * s2 * s;
    let b26 = (q11 - q12 - 2.0 * q66) * c * s2 * s + (q12 - q22 + 2.0 * q66) * c2 * c * s;
    let b66 = (q11 + q22 - 2.0 * q12 - 2.0 * q66) * c2s2 + q66 * (c4 + s4);
    Matrix3::new(b11, b12, b16, b12, b22, b26, b16, b26, b66)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cf() -> Material {
        Material::builtin("CF-thesis").unwrap()
    }

    #[test]
    fn zero_rotation_is_identity() {
        let q = reduced_stiffness(&cf());
        assert!((rotated_stiffness(&q, 0.0) - q).norm() < 1e-6 * q.norm());
    }

    #[test]
    fn ninety_degrees_swaps_the_axes() {
        // Source: a 90° ply has Q̄11 = Q22, Q̄22 = Q11, Q̄16 = 0 (Jones §2.6).
        let q = reduced_stiffness(&cf());
        let r = rotated_stiffness(&q, 90.0);
        assert!((r[(0, 0)] - q[(1, 1)]).abs() < 1e-6 * q[(0, 0)]);
        assert!((r[(1, 1)] - q[(0, 0)]).abs() < 1e-6 * q[(0, 0)]);
        assert!(r[(0, 2)].abs() < 1e-6 * q[(0, 0)]);
    }

    #[test]
    fn isotropic_material_is_rotation_invariant() {
        let q = reduced_stiffness(&Material::builtin("PZT-5H").unwrap());
        let r = rotated_stiffness(&q, 37.0);
        assert!((r - q).norm() < 1e-9 * q.norm());
    }
}
