//! The laminate stack and its `[A B; B D]` matrix (thesis eqs. 2.20-2.23, the thesis' `CFMatrixCalc`), with
//! per-layer piezoelectric loads and the free response to any set of layer fields.

use crate::error::ModelError;
use crate::lamina::{reduced_stiffness, rotated_stiffness};
use crate::material::Material;
use nalgebra::{Matrix3, Matrix6, Vector3, Vector6};

/// What a layer does in the actuator.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LayerRole {
    /// An active piezoceramic plate (or its driven part).
    Piezo,
    /// Piezoceramic that is not driven: the inactive surface layer of a plate
    /// ([`Laminate::bimorph_with_surface`]). Elastic and massive as the PZT, with no piezoelectric load;
    /// it belongs to the plate of the driven layer next to it ([`Laminate::piezo_plate`]).
    InactivePiezo,
    /// A passive ply (carbon fibre, glass, steel).
    Passive,
    /// An adhesive or bond layer (Pyralux, epoxy).
    Bond,
}

/// One layer of the stack.
#[derive(Debug, Clone, PartialEq)]
pub struct Layer {
    /// Material of the layer.
    pub material: Material,
    /// Thickness, m.
    pub thickness: f64,
    /// Angle of the material 1-axis from the actuator axis, degrees.
    pub angle_deg: f64,
    /// Role in the actuator.
    pub role: LayerRole,
}

/// A solved laminate: stiffness, compliance and the unit response of each piezo layer.
///
/// Built once per stack; every later query is a few multiplications, so the optimizer can evaluate
/// millions of planforms against one laminate without inverting anything again.
#[derive(Debug, Clone)]
pub struct Laminate {
    layers: Vec<Layer>,
    /// Interface heights from the geometric midplane, bottom to top (`layers.len() + 1` values).
    z: Vec<f64>,
    qbar: Vec<Matrix3<f64>>,
    abd: Matrix6<f64>,
    compliance: Matrix6<f64>,
    piezo: Vec<usize>,
    /// Midplane strain and curvature `[ε0; κ]` per unit `E3 p` (V/m) in each piezo layer.
    unit_response: Vec<Vector6<f64>>,
}

impl Laminate {
    /// Solve a stack given bottom to top.
    pub fn new(layers: Vec<Layer>) -> Result<Self, ModelError> {
        if layers.is_empty() {
            return Err(ModelError::Laminate("no layers".into()));
        }
        for l in &layers {
            if !(l.thickness.is_finite() && l.thickness > 0.0) {
                return Err(ModelError::Laminate(format!(
                    "layer of {} has thickness {} m; it must be > 0",
                    l.material.name, l.thickness
                )));
            }
            if !l.angle_deg.is_finite() {
                return Err(ModelError::Laminate(format!(
                    "layer of {} has a non-finite angle",
                    l.material.name
                )));
            }
        }
        let total: f64 = layers.iter().map(|l| l.thickness).sum();
        let mut z = Vec::with_capacity(layers.len() + 1);
        let mut acc = -total / 2.0;
        z.push(acc);
        for l in &layers {
            acc += l.thickness;
            z.push(acc);
        }
        let qbar: Vec<Matrix3<f64>> = layers
            .iter()
            .map(|l| rotated_stiffness(&reduced_stiffness(&l.material), l.angle_deg))
            .collect();
        // A = Σ Q̄ (z1 - z0), B = ½ Σ Q̄ (z1² - z0²), D = ⅓ Σ Q̄ (z1³ - z0³)  (thesis eq. 2.21)
        let (mut a, mut b, mut d) = (Matrix3::zeros(), Matrix3::zeros(), Matrix3::zeros());
        for (k, q) in qbar.iter().enumerate() {
            let (z0, z1) = (z[k], z[k + 1]);
            a += q * (z1 - z0);
            b += q * (0.5 * (z1 * z1 - z0 * z0));
            d += q * ((z1 * z1 * z1 - z0 * z0 * z0) / 3.0);
        }
        let mut abd = Matrix6::zeros();
        abd.fixed_view_mut::<3, 3>(0, 0).copy_from(&a);
        abd.fixed_view_mut::<3, 3>(0, 3).copy_from(&b);
        abd.fixed_view_mut::<3, 3>(3, 0).copy_from(&b);
        abd.fixed_view_mut::<3, 3>(3, 3).copy_from(&d);
        let compliance = abd
            .try_inverse()
            .ok_or_else(|| ModelError::Laminate("[A B; B D] is singular".into()))?;
        let piezo: Vec<usize> = layers
            .iter()
            .enumerate()
            .filter(|(_, l)| l.role == LayerRole::Piezo)
            .map(|(k, _)| k)
            .collect();
        let unit_response = piezo
            .iter()
            .map(|&k| compliance * piezo_load(&layers[k], &qbar[k], z[k], z[k + 1], 1.0))
            .collect();
        Ok(Laminate {
            layers,
            z,
            qbar,
            abd,
            compliance,
            piezo,
            unit_response,
        })
    }

    /// The bimorph stack: PZT (t_p), passive plies in layup order, PZT (t_p); optional bond layer of
    /// thickness `t_b` between each PZT and the passive core.
    pub fn bimorph(
        pzt: &Material,
        pzt_thickness: f64,
        ply: &Material,
        ply_thickness: f64,
        layup_deg: &[f64],
        bond: Option<(&Material, f64)>,
    ) -> Result<Self, ModelError> {
        Self::bimorph_with_surface(pzt, pzt_thickness, ply, ply_thickness, layup_deg, bond, 0.0)
    }

    /// [`Laminate::bimorph`] with the outer `t_s` of each PZT plate piezoelectrically dead (an inactive
    /// surface layer, docs/calibration.md §2): each plate is split into an [`LayerRole::InactivePiezo`]
    /// layer of `t_s` on the outside (the PZT material with d31 = 0) and a driven layer of `t_p - t_s`
    /// inside. The plate keeps its thickness, stiffness and mass; `0 <= t_s < t_p` (0: the plain bimorph).
    pub fn bimorph_with_surface(
        pzt: &Material,
        pzt_thickness: f64,
        ply: &Material,
        ply_thickness: f64,
        layup_deg: &[f64],
        bond: Option<(&Material, f64)>,
        inactive_surface: f64,
    ) -> Result<Self, ModelError> {
        if layup_deg.is_empty() {
            return Err(ModelError::Laminate("the layup has no plies".into()));
        }
        // (0 leaves the plain bimorph's own checks to Laminate::new.)
        if inactive_surface != 0.0 && !(inactive_surface > 0.0 && inactive_surface < pzt_thickness)
        {
            return Err(ModelError::Laminate(format!(
                "an inactive surface layer of {inactive_surface} m on a PZT plate of {pzt_thickness} m; it must be >= 0 and thinner than the plate"
            )));
        }
        let split = inactive_surface != 0.0;
        let driven = Layer {
            material: pzt.clone(),
            thickness: if split {
                pzt_thickness - inactive_surface
            } else {
                pzt_thickness
            },
            angle_deg: 0.0,
            role: LayerRole::Piezo,
        };
        let dead = split.then(|| Layer {
            material: Material {
                d31: 0.0,
                ..pzt.clone()
            },
            thickness: inactive_surface,
            angle_deg: 0.0,
            role: LayerRole::InactivePiezo,
        });
        let bond_layer = bond.map(|(m, t)| Layer {
            material: m.clone(),
            thickness: t,
            angle_deg: 0.0,
            role: LayerRole::Bond,
        });
        let mut layers: Vec<Layer> = dead.iter().cloned().collect();
        layers.push(driven.clone());
        layers.extend(bond_layer.clone());
        layers.extend(layup_deg.iter().map(|&angle| Layer {
            material: ply.clone(),
            thickness: ply_thickness,
            angle_deg: angle,
            role: LayerRole::Passive,
        }));
        layers.extend(bond_layer);
        layers.push(driven);
        layers.extend(dead);
        Self::new(layers)
    }

    /// The layers, bottom to top.
    pub fn layers(&self) -> &[Layer] {
        &self.layers
    }

    /// Interface heights from the midplane, bottom to top, m.
    pub fn interfaces(&self) -> &[f64] {
        &self.z
    }

    /// `[A B; B D]` (N/m, N, N·m per unit width).
    pub fn abd(&self) -> &Matrix6<f64> {
        &self.abd
    }

    /// `C = [A B; B D]⁻¹`.
    pub fn compliance(&self) -> &Matrix6<f64> {
        &self.compliance
    }

    /// Bending compliance `C44` (1-based, thesis eq. 2.25), 1/(N·m).
    pub fn bending_compliance(&self) -> f64 {
        self.compliance[(3, 3)]
    }

    /// Total thickness, m.
    pub fn thickness(&self) -> f64 {
        self.z[self.z.len() - 1] - self.z[0]
    }

    /// Areal mass of the layers with a given role, kg/m².
    pub fn areal_mass(&self, role: LayerRole) -> f64 {
        self.layers
            .iter()
            .filter(|l| l.role == role)
            .map(|l| l.material.density * l.thickness)
            // fold from +0.0: an empty f64 sum is -0.0, which would print as "-0.00 mg".
            .fold(0.0, |acc, m| acc + m)
    }

    /// Number of piezo layers (2 for a bimorph).
    pub fn piezo_count(&self) -> usize {
        self.piezo.len()
    }

    /// Index into `layers()` of the i-th piezo layer from the bottom.
    pub fn piezo_layer(&self, i: usize) -> usize {
        self.piezo[i]
    }

    /// Indices into `layers()` of the i-th PZT plate from the bottom: its driven layer and the
    /// [`LayerRole::InactivePiezo`] layers next to it, bottom to top.
    pub fn piezo_plate(&self, i: usize) -> std::ops::RangeInclusive<usize> {
        let k = self.piezo[i];
        let inactive = |j: usize| self.layers[j].role == LayerRole::InactivePiezo;
        let mut first = k;
        while first > 0 && inactive(first - 1) {
            first -= 1;
        }
        let mut last = k;
        while last + 1 < self.layers.len() && inactive(last + 1) {
            last += 1;
        }
        first..=last
    }

    /// Midplane strain and curvature `[ε0x, ε0y, γ0xy, κx, κy, κxy]` for the given `E3 p` per piezo
    /// layer (V/m, bottom to top; missing entries are 0): `C [N_p; M_p]` (thesis eqs. 2.22-2.24).
    pub fn free_response(&self, fields: &[f64]) -> Vector6<f64> {
        self.unit_response
            .iter()
            .zip(fields)
            .fold(Vector6::zeros(), |acc, (r, f)| acc + r * *f)
    }

    /// Free curvature `P = C41 N1 + C42 N2 + C44 M1 + C45 M2` (thesis eq. 2.24), 1/m.
    pub fn free_curvature(&self, fields: &[f64]) -> f64 {
        self.free_response(fields)[3]
    }

    /// Response to an external bending moment `M_x` per unit width (N·m/m): `C [0; M]`.
    pub fn moment_response(&self, moment_x: f64) -> Vector6<f64> {
        self.compliance.column(3) * moment_x
    }

    /// In-plane strain `ε = ε0 + z κ` at height z for a response `[ε0; κ]` (thesis eq. 2.18).
    pub fn strain_at(response: &Vector6<f64>, z: f64) -> Vector3<f64> {
        Vector3::new(
            response[0] + z * response[3],
            response[1] + z * response[4],
            response[2] + z * response[5],
        )
    }

    /// Stress in layer k at height z (inside it): `σ = Q̄ (ε - d E3 p)` with `d = [d31, d31, 0]`; the
    /// piezo term only for piezo layers (`fields` as in [`Self::free_response`]).
    pub fn stress_at(
        &self,
        k: usize,
        z: f64,
        response: &Vector6<f64>,
        fields: &[f64],
    ) -> Vector3<f64> {
        let strain = Self::strain_at(response, z);
        let field = self
            .piezo
            .iter()
            .position(|&p| p == k)
            .and_then(|i| fields.get(i))
            .copied()
            .unwrap_or(0.0);
        let d31 = self.layers[k].material.d31;
        let free = Vector3::new(d31 * field, d31 * field, 0.0);
        self.qbar[k] * (strain - free)
    }
}

/// Piezoelectric force and moment resultants of one layer at field `E3 p` (thesis eq. 2.23):
/// `N_p = Q̄ d (z1 - z0) E3 p`, `M_p = ½ Q̄ d (z1² - z0²) E3 p`.
fn piezo_load(layer: &Layer, qbar: &Matrix3<f64>, z0: f64, z1: f64, field: f64) -> Vector6<f64> {
    let d31 = layer.material.d31;
    let qd = qbar * Vector3::new(d31, d31, 0.0) * field;
    let n = qd * (z1 - z0);
    let m = qd * (0.5 * (z1 * z1 - z0 * z0));
    Vector6::new(n[0], n[1], n[2], m[0], m[1], m[2])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn thesis_b() -> Laminate {
        let pzt = Material::builtin("PZT-5H").unwrap();
        let cf = Material::builtin("CF-thesis").unwrap();
        Laminate::bimorph(&pzt, 267e-6, &cf, 61.8e-6, &[0.0, 90.0, 0.0], None).unwrap()
    }

    #[test]
    fn symmetric_stack_has_no_coupling() {
        // Source: a midplane-symmetric laminate has B = 0 (Jones §4.3).
        let lam = thesis_b();
        let b = lam.abd().fixed_view::<3, 3>(0, 3).into_owned();
        assert!(b.norm() < 1e-9 * lam.abd()[(0, 0)] * lam.thickness());
        assert!((lam.thickness() - (2.0 * 267e-6 + 3.0 * 61.8e-6)).abs() < 1e-15);
    }

    #[test]
    fn homogeneous_plate_matches_plate_theory() {
        // Source: for one isotropic layer, D11 = E t³ / (12 (1 - ν²)).
        let steel = Material::builtin("stainless-steel").unwrap();
        let t = 1e-3;
        let lam = Laminate::new(vec![Layer {
            material: steel.clone(),
            thickness: t,
            angle_deg: 0.0,
            role: LayerRole::Passive,
        }])
        .unwrap();
        let d11 = steel.e1 * t.powi(3) / (12.0 * (1.0 - 0.09));
        assert!((lam.abd()[(3, 3)] - d11).abs() < 1e-12 * d11);
    }

    #[test]
    fn opposite_fields_bend_and_equal_fields_stretch() {
        let lam = thesis_b();
        let bend = lam.free_response(&[1e5, -1e5]);
        let stretch = lam.free_response(&[1e5, 1e5]);
        assert!(bend[3].abs() > 0.0 && bend[0].abs() < 1e-12 * bend[3].abs());
        assert!(stretch[3].abs() < 1e-12 && stretch[0].abs() > 0.0);
    }

    #[test]
    fn rejects_zero_thickness_and_nan_angle() {
        let pzt = Material::builtin("PZT-5H").unwrap();
        let cf = Material::builtin("CF-thesis").unwrap();
        assert!(Laminate::bimorph(&pzt, 0.0, &cf, 61.8e-6, &[0.0], None).is_err());
        assert!(Laminate::bimorph(&pzt, 1e-4, &cf, 61.8e-6, &[f64::NAN], None).is_err());
        assert!(Laminate::bimorph(&pzt, 1e-4, &cf, 61.8e-6, &[], None).is_err());
    }
}
