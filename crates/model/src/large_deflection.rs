//! Geometric nonlinearity of the free deflection (docs/calibration.md §2, "Not candidates"): the model's tip
//! deflection uses the small-angle form; this is the exact one for the same curvature, to measure how much
//! the approximation costs over the design ranges before deciding whether it is an effect worth adding.
//!
//! Only the free deflection is concerned: at the blocked force the tip is held at zero deflection.

/// Tip deflection of a cantilever bent to a uniform curvature `P` over `l_p`, then a rigid extension
/// `l_ext`, without the small-angle approximation: the root section turns by `θ = P l_p`, so
/// `δ = (1 - cos θ) / P + l_ext sin θ` (circular arc, then a straight tangent). Its small-angle limit is
/// docs/physics.md §3's `P l_p² / 2 + P l_p l_ext`.
pub fn exact_tip_deflection(curvature: f64, l_p: f64, l_ext: f64) -> f64 {
    let theta = curvature * l_p;
    if theta.abs() < 1e-12 {
        return curvature * l_p * (0.5 * l_p + l_ext);
    }
    (1.0 - theta.cos()) / curvature + l_ext * theta.sin()
}

/// Relative overestimate of the small-angle deflection: `δ_linear / δ_exact - 1`.
pub fn small_angle_error(curvature: f64, l_p: f64, l_ext: f64) -> f64 {
    let linear = curvature * l_p * (0.5 * l_p + l_ext);
    linear / exact_tip_deflection(curvature, l_p, l_ext) - 1.0
}

/// The largest small-angle overestimate of the tip deflection the linear model is trusted to: 1 %.
/// For a plate without extension it is reached at a root-to-tip rotation of 0.35 rad, `δ / l_p ≈ 0.17`
/// (docs/physics.md §3.1).
pub const SMALL_ANGLE_BOUND: f64 = 0.01;

/// The small-angle overestimate at a linear tip deflection `deflection` of a plate `l_p` with a rigid
/// extension `l_ext`, taking the curvature as uniform: `P = δ / (l_p (l_p/2 + l_ext))` (docs/physics.md §3).
pub fn small_angle_error_at(deflection: f64, l_p: f64, l_ext: f64) -> f64 {
    let curvature = deflection / (l_p * (0.5 * l_p + l_ext));
    small_angle_error(curvature, l_p, l_ext)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::effects::{Actuator, Effects};
    use crate::{Drive, DriveMode, Material, Planform};

    #[test]
    fn the_small_angle_bound_is_reached_near_a_fifth_of_the_plate() {
        // Closed form for a uniform arc without extension: δ_lin/δ_exact - 1 = (θ²/2)/(1 - cos θ) - 1
        // ≈ θ²/12, so 1 % at θ ≈ 0.346 rad, δ/l_p = θ/2 ≈ 0.173.
        let l_p = 0.04;
        let at = |ratio: f64| small_angle_error_at(ratio * l_p, l_p, 0.0);
        assert!(at(0.17) < SMALL_ANGLE_BOUND && at(0.177) > SMALL_ANGLE_BOUND);
        let theta: f64 = 0.3;
        let want = (theta * theta / 2.0) / (1.0 - theta.cos()) - 1.0;
        assert!((at(theta / 2.0) - want).abs() < 1e-12);
    }

    #[test]
    fn matches_the_series_of_the_arc() {
        // Without extension: linear/exact = (θ²/2) / (1 - cos θ) = 1 + θ²/12 + θ⁴/240 + … (Taylor series).
        for theta in [0.01f64, 0.05, 0.1] {
            let e = small_angle_error(theta / 0.02, 0.02, 0.0);
            let series = theta.powi(2) / 12.0 + theta.powi(4) / 240.0;
            assert!((e - series).abs() < 1e-3 * series, "{e} vs {series}");
        }
        // A rigid extension only: δ = l_ext sin θ against l_ext θ, error ≈ θ²/6.
        let e = small_angle_error(0.1 / 1e-9, 1e-9, 0.02);
        assert!((e - 0.01 / 6.0).abs() < 1e-5, "{e}");
    }

    /// The measurement behind leaving it out of the library: the largest small-angle error over the
    /// design ranges of the calibration study (l_tot 20-50 mm, l_r 0-1, t_p 127/191/267 µm, 3/5/7 plies of
    /// CF-thesis, PZT-5H) at the drive fields measured (up to 800 V/mm) and at twice that.
    #[test]
    fn geometric_nonlinearity_over_the_design_ranges() {
        let pzt = Material::builtin("PZT-5H").unwrap();
        let cf = Material::builtin("CF-thesis").unwrap();
        let layups: [&[f64]; 3] = [
            &[0.0, 90.0, 0.0],
            &[0.0, 0.0, 90.0, 0.0, 0.0],
            &[0.0, 0.0, 0.0, 90.0, 0.0, 0.0, 0.0],
        ];
        let mut worst = [(0.0f64, 0.0f64); 2];
        for (k, field) in [800e3, 1600e3].into_iter().enumerate() {
            for layup in layups {
                for t_p in [127e-6, 191e-6, 267e-6] {
                    for l_tot in [20e-3, 35e-3, 50e-3] {
                        for l_r in [0.0, 0.5, 1.0] {
                            let planform = Planform::new(l_tot, l_r, 8e-3, 1.0, 0.0).unwrap();
                            let a = Actuator {
                                pzt: &pzt,
                                pzt_thickness: t_p,
                                ply: &cf,
                                ply_thickness: 61.8e-6,
                                layup_deg: layup,
                                planform,
                                drive: Drive::new(DriveMode::Parallel, field),
                            };
                            let b = Effects::null().basis(&a).unwrap();
                            let l_p = planform.piezo_length();
                            let l_ext = planform.extension_length();
                            let e = small_angle_error(b.free_curvature, l_p, l_ext);
                            let slope = exact_tip_deflection(b.free_curvature, l_p, l_ext) / l_tot;
                            if e > worst[k].0 {
                                worst[k] = (e, slope);
                            }
                        }
                    }
                }
            }
        }
        println!(
            "largest small-angle error: {:.3} % at 800 V/mm (δ/L = {:.3}), {:.3} % at 1600 V/mm (δ/L = {:.3})",
            100.0 * worst[0].0,
            worst[0].1,
            100.0 * worst[1].0,
            worst[1].1
        );
        // The figures stated in docs/calibration.md §2 (rounded up from this measurement).
        assert!(worst[0].0 < 0.0005 && worst[1].0 < 0.002, "{worst:?}");
    }
}
