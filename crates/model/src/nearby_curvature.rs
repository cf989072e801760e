//! The second-order terms of the nearby modes' quotients (docs/physics.md §11.6): the Rayleigh
//! quotient on a solved beam's mode, and the static quotient on its static shape, are exact to first
//! order in the change of the beam's ratios; their second-order errors are quadratic forms in that
//! change, whose matrices follow from the solved beam alone. With them the error is third order, and
//! a cell may be wide.
//!
//! For `K = K₀ + ΔK`, `M = M₀ + ΔM` and the cell beam's mode `φ` (`φᵀM₀φ = 1`, eigenvalue `λ₀`),
//! second-order perturbation theory (Wilkinson, *The Algebraic Eigenvalue Problem*, 1965, §2.10, for
//! the pencil `K - λM`) gives `λ = R(φ) - Σ_{k≠1} (φ_kᵀ g)² / (λ_k - λ₀) + O(Δ³)`, `g = (ΔK - λ₀ΔM)φ`,
//! `R(φ)` the Rayleigh quotient. The sum is `g̃ᵀy` with `g̃ = g - M₀φ (φᵀg)` and `(K₀ - λ₀M₀) y = g̃`,
//! `y ⟂ M₀φ` (one bordered solve per part). The static compliance `fᵀK⁻¹f` with `u = K₀⁻¹f`, `c₀ = fᵀu`:
//! `fᵀK⁻¹f = c₀²/(c₀ + uᵀΔKu) + (ΔKu)ᵀ(K₀⁻¹ - uuᵀ/c₀)(ΔKu) + O(Δ³)`.

use crate::beam_element::Element;
use crate::dynamics::{assemble, ActuatorBeam, Shapes, COARSE_ELEMENTS};
use nalgebra::{DMatrix, DVector};

/// The ratios the shapes depend on, `[a_e, a_c, b_l, b_e, b_t, b_n]` over `a_w` or `b_a`
/// (`nearby_modes.rs`).
pub(crate) type Ratios = [f64; 6];

/// The quadratic forms of the second-order errors at a cell beam, per unit change of its ratios.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Curvature {
    /// The cell beam's ratios.
    center: Ratios,
    /// `G`: the eigenvalue at unit `a_w`, `b_a` is the quotient less `dᵀGd`, `d` the change of ratios.
    mode: [[f64; 6]; 6],
    /// `H`: the static compliance at unit `a_w` is the quotient plus `eᵀHe`, `e` the change of the two
    /// stiffness ratios.
    compliance: [[f64; 2]; 2],
}

impl Curvature {
    /// The terms at `beam`, a cell beam (`a_w = b_a = 1`, ratios `center`), from its held mass parts
    /// `mass` ([`mass_parts`]) and its mode and static shape on the coarse mesh.
    pub(crate) fn of(
        beam: &ActuatorBeam,
        mass: &[DMatrix<f64>; 5],
        center: Ratios,
        shapes: &Shapes,
    ) -> Self {
        let stiffness = stiffness_parts(beam);
        let [r_e, r_c, r_l, r_x, r_t, r_n] = center;
        let k0 = &stiffness[0] + &stiffness[1] * r_e + &stiffness[2] * r_c;
        let m0 = &mass[0] + &mass[1] * r_l + &mass[2] * r_x + &mass[3] * r_t + &mass[4] * r_n;
        let x = DVector::from_column_slice(&shapes.mode);
        let phi = &x / x.dot(&(&m0 * &x)).sqrt();
        let lambda = phi.dot(&(&k0 * &phi));
        let m_phi = &m0 * &phi;
        // g per unit change of each ratio, its part along M₀φ taken out.
        let parts: [DVector<f64>; 6] = [
            &stiffness[1] * &phi,
            &stiffness[2] * &phi,
            &mass[1] * &phi * -lambda,
            &mass[2] * &phi * -lambda,
            &mass[3] * &phi * -lambda,
            &mass[4] * &phi * -lambda,
        ]
        .map(|g| {
            let along = phi.dot(&g);
            g - &m_phi * along
        });
        let n = phi.len();
        let mut bordered = DMatrix::zeros(n + 1, n + 1);
        bordered
            .view_mut((0, 0), (n, n))
            .copy_from(&(&k0 - &m0 * lambda));
        bordered.view_mut((0, n), (n, 1)).copy_from(&m_phi);
        bordered
            .view_mut((n, 0), (1, n))
            .copy_from(&m_phi.transpose());
        let lu = bordered.lu();
        // A part the cell beam lacks (its ratio 0) is lacked by every beam in the cell: its change is
        // always 0, and its terms are never taken (`terms`), so they are not solved for.
        let solved: Vec<DVector<f64>> = parts
            .iter()
            .zip(center)
            .map(|(g, ratio)| {
                if ratio == 0.0 {
                    return DVector::zeros(n);
                }
                let mut rhs = DVector::zeros(n + 1);
                rhs.rows_mut(0, n).copy_from(g);
                lu.solve(&rhs)
                    .map_or_else(|| DVector::zeros(n), |y| y.rows(0, n).into_owned())
            })
            .collect();
        let mode = std::array::from_fn(|p| std::array::from_fn(|q| parts[p].dot(&solved[q])));
        let u = DVector::from_column_slice(&shapes.static_shape);
        let load_work = u.dot(&(&k0 * &u));
        let ku = [&stiffness[1] * &u, &stiffness[2] * &u];
        let k0_inv_ku = k0.cholesky().map(|c| ku.clone().map(|w| c.solve(&w)));
        let compliance = std::array::from_fn(|p| {
            std::array::from_fn(|q| match &k0_inv_ku {
                Some(z) => ku[p].dot(&z[q]) - u.dot(&ku[p]) * u.dot(&ku[q]) / load_work,
                None => 0.0,
            })
        });
        Curvature {
            center,
            mode,
            compliance,
        }
    }

    /// `dᵀGd` and `eᵀHe` at the ratios `ratios`.
    pub(crate) fn terms(&self, ratios: &Ratios) -> (f64, f64) {
        let d: [f64; 6] = std::array::from_fn(|i| ratios[i] - self.center[i]);
        // The ratios that moved (an absent part's stays 0): the others add nothing.
        let mut moved = [0; 6];
        let mut count = 0;
        for (i, di) in d.iter().enumerate() {
            if *di != 0.0 {
                moved[count] = i;
                count += 1;
            }
        }
        let moved = &moved[..count];
        let mut mode = 0.0;
        for &i in moved {
            mode += d[i] * moved.iter().map(|&j| self.mode[i][j] * d[j]).sum::<f64>();
        }
        let h = &self.compliance;
        let e = [d[0], d[1]];
        let compliance =
            e[0] * (h[0][0] * e[0] + h[0][1] * e[1]) + e[1] * (h[1][0] * e[0] + h[1][1] * e[1]);
        (mode, compliance)
    }
}

/// The held stiffness of each part at unit scalar: active region, compliant extension, clamp spring
/// (zero where the beam lacks the part).
fn stiffness_parts(beam: &ActuatorBeam) -> [DMatrix<f64>; 3] {
    let active = COARSE_ELEMENTS.0;
    let elements = unit_elements(beam);
    let part = |region: std::ops::Range<usize>| {
        beam.held_at_root(&assemble(&elements, Element::stiffness_matrix, |e| {
            region.contains(&e)
        }))
    };
    let k_w = part(0..active);
    let k_e = part(active..elements.len());
    let mut k_c = DMatrix::zeros(k_w.nrows(), k_w.ncols());
    if beam.clamp_compliance > 0.0 {
        k_c[(0, 0)] = 1.0;
    }
    [k_w, k_e, k_c]
}

/// The elements of `beam` on the coarse mesh at unit stiffness per width: `a_w = 1` on the active
/// region, `a_e = 1` on a compliant extension.
pub(crate) fn unit_elements(beam: &ActuatorBeam) -> Vec<Element> {
    let (active, extension) = COARSE_ELEMENTS;
    let unit = ActuatorBeam {
        bending_compliance: 1.0,
        stiffness_scale: 1.0,
        extension_bending_compliance: beam
            .extension_bending_compliance
            .map(|_| beam.planform.tip_width()),
        ..*beam
    };
    unit.mesh(active, extension).0
}

/// The held mass of each part at unit scalar: active areal, edge line, extension areal, tip point,
/// end point ([`ActuatorBeam::held_mass`], linear in the mass scalars). A part `beam` lacks (its scalar
/// 0) is left a zero matrix: every form and term takes it times that 0, and a beam in the same cell
/// lacks it too (`nearby_modes.rs`), so it is not assembled.
pub(crate) fn mass_parts(beam: &ActuatorBeam) -> [DMatrix<f64>; 5] {
    let (active, extension) = COARSE_ELEMENTS;
    let scalars = [
        beam.areal_mass,
        beam.edge_line_mass,
        beam.extension_areal_mass,
        beam.tip_point_mass,
        beam.end_mass,
    ];
    let part = |j: usize| {
        let unit = |part: usize| if part == j { 1.0 } else { 0.0 };
        let part = ActuatorBeam {
            areal_mass: unit(0),
            edge_line_mass: unit(1),
            extension_areal_mass: unit(2),
            tip_point_mass: unit(3),
            end_mass: unit(4),
            ..*beam
        };
        let (elements, compliant) = part.mesh(active, extension);
        part.held_mass(&elements, active, compliant).0
    };
    // The areal mass is every beam's (positive, `ActuatorBeam::check`): it sets the held size.
    let areal = part(0);
    let n = areal.nrows();
    let mut parts = std::array::from_fn(|j| match j {
        1.. if scalars[j] != 0.0 => part(j),
        _ => DMatrix::zeros(n, n),
    });
    parts[0] = areal;
    parts
}
