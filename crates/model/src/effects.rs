//! Physical effects the original model lacks, each a change to the physics with a null value
//! (docs/calibration.md §2). [`Effects::default`] is the original model exactly.
//!
//! | effect | change | moves |
//! |---|---|---|
//! | `d31-scale` η | `d31 → η d31` in the PZT material | δ, F_b |
//! | `field-dependent-d31` β | `d31(E) = d31 (1 + β E)` at the drive field (after Jafferis 2015, linearised) | δ, F_b |
//! | `dead-length` Δ | the root `Δ` of the PZT is not driven; it keeps its stiffness | δ, F_b |
//! | `bond-layer` t_b | a bond layer (Pyralux LF) between each PZT and the plies, in the CLT stack, with its mass | δ, F_b, m |
//! | `compliant-extension` φ | tip compliance `+= φ C44_pass l_ext³ / (3 w_tip)` (φ = 1: the bare plies) | F_b |
//! | `clamp-compliance` c_θ | tip compliance `+= c_θ l_tot²` (rotational spring at the root) | F_b |
//! | `ply-thickness` s | resin-rich plies: `t → s t`, moduli `/ s` (same fibre), density mixes in resin | m, δ, F_b |
//!
//! `stiffness_scale` (compliance `/ s_k`, no design dependence) is not an effect: it is the thesis-style
//! null model a candidate must beat.

use crate::drive::{Drive, DriveMode};
use crate::error::ModelError;
use crate::laminate::{Laminate, Layer, LayerRole};
use crate::material::Material;
use crate::performance::{evaluate, MassBreakdown, Performance};
use crate::planform::Planform;
use crate::section::Section;
use serde::{Deserialize, Serialize};

/// Density of the epoxy that resin-rich plies carry in excess, kg/m³.
pub const RESIN_DENSITY: f64 = 1200.0;

/// Built-in material of the bond layer (acrylic sheet adhesive, docs/physics.md §8).
pub const BOND_MATERIAL: &str = "Pyralux-LF";

/// Names of the library effects, in report order.
pub const EFFECT_NAMES: [&str; 7] = [
    "d31-scale",
    "field-dependent-d31",
    "dead-length",
    "bond-layer",
    "compliant-extension",
    "clamp-compliance",
    "ply-thickness",
];

/// Parameters of every effect; the default is the original model.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Effects {
    /// η: multiplies d31 (null 1).
    pub d31_scale: f64,
    /// β in `d31(E) = d31 (1 + β E)`, m/V (null 0).
    #[serde(rename = "d31_field_coefficient_m_per_V")]
    pub d31_field_coefficient: f64,
    /// Undriven length at the root of the PZT, m (null 0).
    #[serde(rename = "dead_length_m")]
    pub dead_length: f64,
    /// Thickness of the bond layer on each side of the plies, m (null 0).
    #[serde(rename = "bond_thickness_m")]
    pub bond_thickness: f64,
    /// φ: flexibility of the extension relative to the bare plies (null 0 = rigid).
    pub extension_flexibility: f64,
    /// c_θ: rotational compliance of the clamp, rad/(N·m) (null 0).
    #[serde(rename = "clamp_compliance_rad_per_N_m")]
    pub clamp_compliance: f64,
    /// s: ply thickness relative to nominal, the excess being resin (null 1).
    pub ply_thickness_scale: f64,
    /// s_k: uniform beam-stiffness factor, compliance `/ s_k` (null 1; the thesis-style null model).
    pub stiffness_scale: f64,
    /// Scales on the bond layer's material, set by declared `scale` primitives with target `bond`
    /// ([`crate::primitives::stack`]). Not a library effect: a calibrated model records them as its
    /// declared primitives, so they are not written under `[effects]`.
    #[serde(skip)]
    pub bond_scale: BondScale,
}

/// Factors on the bond layer's isotropic material (null 1 each): its modulus E (E1 = E2, with G12 kept
/// at `E / (2 (1 + ν))`), its Poisson ratio and its density.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BondScale {
    /// Factor on E.
    pub modulus: f64,
    /// Factor on ν.
    pub poisson: f64,
    /// Factor on the density.
    pub density: f64,
}

impl Default for BondScale {
    fn default() -> Self {
        BondScale {
            modulus: 1.0,
            poisson: 1.0,
            density: 1.0,
        }
    }
}

impl Default for Effects {
    fn default() -> Self {
        Effects {
            d31_scale: 1.0,
            d31_field_coefficient: 0.0,
            dead_length: 0.0,
            bond_thickness: 0.0,
            extension_flexibility: 0.0,
            clamp_compliance: 0.0,
            ply_thickness_scale: 1.0,
            stiffness_scale: 1.0,
            bond_scale: BondScale::default(),
        }
    }
}

/// Raw inputs of one actuator at one drive level, SI.
#[derive(Debug, Clone, Copy)]
pub struct Actuator<'a> {
    /// PZT material (nominal d31).
    pub pzt: &'a Material,
    /// Thickness of each PZT plate, m.
    pub pzt_thickness: f64,
    /// Passive ply material.
    pub ply: &'a Material,
    /// Nominal ply thickness, m.
    pub ply_thickness: f64,
    /// Ply angles bottom to top, degrees.
    pub layup_deg: &'a [f64],
    /// Planform.
    pub planform: Planform,
    /// Drive mode and field.
    pub drive: Drive,
}

/// What the δ/F_b physics needs of one actuator once the stack is fixed: lets a fit vary η, β, Δ, φ, c_θ
/// and s_k without re-solving the laminate. [`Effects::outputs`] applies them exactly as
/// [`Effects::predict`] does (a unit test holds the two together).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StackBasis {
    /// Free curvature with the nominal d31 at the drive field, 1/m.
    pub free_curvature: f64,
    /// Tip compliance of the tapered beam with a rigid extension, m/N.
    pub beam_compliance: f64,
    /// Extra tip compliance of an extension made of the bare plies (φ = 1), m/N.
    pub extension_compliance: f64,
    /// Drive field, V/m.
    pub field: f64,
    /// Planform.
    pub planform: Planform,
}

impl StackBasis {
    /// The same stack driven at another (positive) field of the same mode: the CLT free curvature is
    /// linear in the layer fields (`DriveMode::layer_fields`, thesis eq. 2.20's piezoelectric moment
    /// `∝ d31 E`) and the compliances do not depend on the field. Saves a stack solve per voltage.
    pub fn at_field(&self, field: f64) -> StackBasis {
        StackBasis {
            free_curvature: self.free_curvature * field / self.field,
            field,
            ..*self
        }
    }
}

impl Effects {
    /// The original model.
    pub fn null() -> Self {
        Self::default()
    }

    /// True when every effect is at its null value.
    pub fn is_null(&self) -> bool {
        *self == Self::default()
    }

    /// Check the parameters are physical.
    pub fn validate(&self) -> Result<(), ModelError> {
        let check = |name: &'static str, v: f64, ok: bool, range: &'static str| {
            if v.is_finite() && ok {
                Ok(())
            } else {
                Err(ModelError::OutOfRange {
                    name,
                    value: v,
                    range,
                })
            }
        };
        check(
            "d31_scale",
            self.d31_scale,
            self.d31_scale > 0.0,
            "(0, inf)",
        )?;
        check(
            "d31_field_coefficient",
            self.d31_field_coefficient,
            true,
            "finite",
        )?;
        check(
            "dead_length",
            self.dead_length,
            self.dead_length >= 0.0,
            "[0, l_p) m",
        )?;
        check(
            "bond_thickness",
            self.bond_thickness,
            self.bond_thickness >= 0.0,
            "[0, inf) m",
        )?;
        check(
            "extension_flexibility",
            self.extension_flexibility,
            self.extension_flexibility >= 0.0,
            "[0, inf)",
        )?;
        check(
            "clamp_compliance",
            self.clamp_compliance,
            self.clamp_compliance >= 0.0,
            "[0, inf) rad/(N m)",
        )?;
        check(
            "ply_thickness_scale",
            self.ply_thickness_scale,
            self.ply_thickness_scale > 0.25,
            "(0.25, inf)",
        )?;
        check(
            "stiffness_scale",
            self.stiffness_scale,
            self.stiffness_scale > 0.0,
            "(0, inf)",
        )
    }

    /// Factor on d31 at a drive field: `η (1 + β E)`.
    pub fn d31_factor(&self, field: f64) -> f64 {
        self.d31_scale * (1.0 + self.d31_field_coefficient * field)
    }

    /// The PZT material with d31 changed by `d31-scale` and `field-dependent-d31` at this field.
    pub fn pzt_material(&self, pzt: &Material, field: f64) -> Material {
        Material {
            d31: pzt.d31 * self.d31_factor(field),
            ..pzt.clone()
        }
    }

    /// The ply material and thickness with `ply-thickness`: the same fibre spread over `s t`, so the
    /// moduli fall as `1/s` and the density mixes in `(s - 1) t` of resin.
    pub fn ply_material(&self, ply: &Material, ply_thickness: f64) -> (Material, f64) {
        let s = self.ply_thickness_scale;
        let material = Material {
            e1: ply.e1 / s,
            e2: ply.e2 / s,
            g12: ply.g12 / s,
            density: (ply.density + (s - 1.0) * RESIN_DENSITY) / s,
            ..ply.clone()
        };
        (material, s * ply_thickness)
    }

    /// The bond layer's material: the built-in one with [`Effects::bond_scale`] applied (isotropic, so
    /// G12 follows E and ν as in `Material::isotropic`).
    fn bond_material(&self) -> Material {
        let m = Material::builtin(BOND_MATERIAL).expect("the bond material is built in");
        let k = self.bond_scale;
        let (e, nu) = (m.e1 * k.modulus, m.nu12 * k.poisson);
        Material {
            e1: e,
            e2: e,
            g12: e / (2.0 * (1.0 + nu)),
            nu12: nu,
            density: m.density * k.density,
            ..m
        }
    }

    /// The CLT stack with the stack effects (d31, plies, bond layer) applied.
    pub fn laminate(&self, a: &Actuator) -> Result<Laminate, ModelError> {
        self.validate()?;
        let pzt = self.pzt_material(a.pzt, a.drive.field);
        let (ply, t_ply) = self.ply_material(a.ply, a.ply_thickness);
        let bond = self.bond_material();
        let bond = (self.bond_thickness > 0.0).then_some((&bond, self.bond_thickness));
        Laminate::bimorph(&pzt, a.pzt_thickness, &ply, t_ply, a.layup_deg, bond)
    }

    /// Bending compliance per width of the plies alone (the extension), from CLT.
    fn passive_bending_compliance(&self, a: &Actuator) -> Result<f64, ModelError> {
        let (ply, t_ply) = self.ply_material(a.ply, a.ply_thickness);
        let layers = a
            .layup_deg
            .iter()
            .map(|&angle| Layer {
                material: ply.clone(),
                thickness: t_ply,
                angle_deg: angle,
                role: LayerRole::Passive,
            })
            .collect();
        Ok(Laminate::new(layers)?.bending_compliance())
    }

    /// Stack basis for fast re-evaluation: the stack effects of `self` are applied, η and β are not
    /// (the curvature is at the nominal d31; CLT curvature is linear in d31).
    pub fn basis(&self, a: &Actuator) -> Result<StackBasis, ModelError> {
        let nominal_d31 = Effects {
            d31_scale: 1.0,
            d31_field_coefficient: 0.0,
            ..*self
        };
        let lam = nominal_d31.laminate(a)?;
        let section = Section::new(&lam, a.drive)?;
        let pl = &a.planform;
        let l_p = pl.piezo_length();
        let beam = section.bending_compliance * l_p.powi(3) * pl.shape_factor()
            / (3.0 * pl.nominal_width());
        let extension = if pl.extension_ratio > 0.0 {
            self.passive_bending_compliance(a)? * pl.extension_length().powi(3)
                / (3.0 * pl.tip_width())
        } else {
            0.0
        };
        Ok(StackBasis {
            free_curvature: section.free_curvature,
            beam_compliance: beam,
            extension_compliance: extension,
            field: a.drive.field,
            planform: *pl,
        })
    }

    /// Free deflection and blocked force from a basis with η, β, Δ, φ, c_θ, s_k applied.
    ///
    /// Dead length Δ: curvature P acts on `[Δ, l_p]` only, so
    /// `δ = P ((L - Δ)² - l_ext²) / 2` with `L = l_p + l_ext` (Δ = 0 gives thesis eq. 2.26).
    /// Tip compliance `c = c_beam / s_k + φ c_ext + c_θ l_tot²`; `F_b = δ / c`.
    pub fn outputs(&self, b: &StackBasis) -> (f64, f64) {
        let curvature = b.free_curvature * self.d31_factor(b.field).abs();
        let pl = &b.planform;
        let l_p = pl.piezo_length();
        let l_ext = pl.extension_length();
        let tip = l_p + l_ext;
        let dead = self.dead_length.min(0.95 * l_p);
        let delta = 0.5 * curvature * ((tip - dead).powi(2) - l_ext * l_ext);
        let compliance = b.beam_compliance / self.stiffness_scale
            + self.extension_flexibility * b.extension_compliance
            + self.clamp_compliance * pl.length * pl.length;
        (delta, delta / compliance)
    }

    /// Mass by layer kind with `ply-thickness` and `bond-layer` applied, without solving the stack
    /// (same numbers as the laminate's areal masses; docs/physics.md §4).
    pub fn mass(&self, a: &Actuator) -> MassBreakdown {
        let (ply, t_ply) = self.ply_material(a.ply, a.ply_thickness);
        let pl = &a.planform;
        let a_pzt = pl.piezo_area();
        MassBreakdown {
            pzt: 2.0 * a.pzt.density * a.pzt_thickness * a_pzt,
            passive: a.layup_deg.len() as f64
                * ply.density
                * t_ply
                * (a_pzt + pl.extension_area() + pl.tab_area()),
            bond: 2.0 * self.bond_material().density * self.bond_thickness * a_pzt,
        }
    }

    /// Predict one actuator with the effects applied as physics.
    pub fn predict(&self, a: &Actuator) -> Result<Performance, ModelError> {
        let lam = self.laminate(a)?;
        let section = Section::new(&lam, a.drive)?;
        let base = evaluate(&section, &a.planform);
        let basis = self.basis(a)?;
        let (delta, force) = Effects {
            d31_scale: 1.0,
            d31_field_coefficient: 0.0,
            ..*self
        }
        .outputs(&StackBasis {
            // The scaled material's curvature, so the physical path and the fast path are checked
            // against each other by the tests rather than sharing the multiplication.
            free_curvature: section.free_curvature,
            ..basis
        });
        let mut p = base.with_outputs(delta, force, base.mass_breakdown);
        // Stresses under the changed blocked force (thesis eq. 3.3 and the CLT root moment).
        let pl = &a.planform;
        p.base_stress = 6.0 * force * pl.length / (pl.base_width * section.thickness.powi(2));
        p.peak_pzt_stress = section.peak_pzt_stress(force * pl.length / pl.base_width);
        Ok(p)
    }
}

/// Helper for callers with a drive given as a voltage.
pub fn drive_at_voltage(mode: DriveMode, voltage: f64, pzt_thickness: f64) -> Drive {
    Drive {
        mode,
        field: mode.field_from_voltage(voltage, pzt_thickness),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{predict, ModelKind};

    fn materials() -> (Material, Material) {
        (
            Material::builtin("PZT-5H").unwrap(),
            Material::builtin("CF-thesis").unwrap(),
        )
    }

    fn actuator<'a>(pzt: &'a Material, cf: &'a Material, layup: &'a [f64]) -> Actuator<'a> {
        Actuator {
            pzt,
            pzt_thickness: 191e-6,
            ply: cf,
            ply_thickness: 61.8e-6,
            layup_deg: layup,
            planform: Planform::new(40e-3, 0.6, 8e-3, 1.4, 2e-3).unwrap(),
            drive: Drive {
                mode: DriveMode::Parallel,
                field: 600e3,
            },
        }
    }

    #[test]
    fn null_effects_reproduce_the_original_model() {
        let (pzt, cf) = materials();
        let layup = [0.0, 90.0, 0.0];
        let a = actuator(&pzt, &cf, &layup);
        let lam = Laminate::bimorph(&pzt, 191e-6, &cf, 61.8e-6, &layup, None).unwrap();
        let orig = predict(ModelKind::Original, &lam, &a.planform, a.drive).unwrap();
        let p = Effects::null().predict(&a).unwrap();
        for (x, y) in [
            (p.free_deflection, orig.free_deflection),
            (p.blocked_force, orig.blocked_force),
            (p.mass, orig.mass),
        ] {
            assert!(((x - y) / y).abs() < 1e-12, "{x} vs {y}");
        }
    }

    #[test]
    fn fast_path_and_mass_shortcut_match_the_physical_path() {
        let (pzt, cf) = materials();
        let layup = [0.0, 0.0, 90.0, 0.0, 0.0];
        let a = actuator(&pzt, &cf, &layup);
        let e = Effects {
            d31_scale: 0.8,
            d31_field_coefficient: 0.5e-6,
            dead_length: 2e-3,
            bond_thickness: 20e-6,
            extension_flexibility: 0.7,
            clamp_compliance: 0.3,
            ply_thickness_scale: 1.2,
            stiffness_scale: 0.9,
            bond_scale: BondScale {
                modulus: 1.3,
                poisson: 0.9,
                density: 1.1,
            },
        };
        let p = e.predict(&a).unwrap();
        let (d, f) = e.outputs(&e.basis(&a).unwrap());
        assert!(((d - p.free_deflection) / d).abs() < 1e-10);
        assert!(((f - p.blocked_force) / f).abs() < 1e-10);
        let m = e.mass(&a);
        assert!(((m.total() - p.mass) / p.mass).abs() < 1e-12);
        assert!((m.bond - p.mass_breakdown.bond).abs() < 1e-15);
    }

    #[test]
    fn a_basis_moves_to_another_field_exactly() {
        let (pzt, cf) = materials();
        let layup = [0.0, 90.0, 0.0];
        let e = Effects {
            bond_thickness: 20e-6,
            ply_thickness_scale: 1.2,
            ..Effects::null()
        };
        for mode in DriveMode::ALL {
            let mut a = actuator(&pzt, &cf, &layup);
            a.drive.mode = mode;
            let b = e.basis(&a).unwrap();
            a.drive.field = 250e3;
            let want = e.basis(&a).unwrap();
            let got = b.at_field(250e3);
            assert!(
                ((got.free_curvature - want.free_curvature) / want.free_curvature).abs() < 1e-12
            );
            assert_eq!(got.beam_compliance, want.beam_compliance);
            assert_eq!(got.field, want.field);
        }
    }

    #[test]
    fn each_effect_moves_what_the_notes_say() {
        // docs/calibration.md §1: actuation effects move δ and F_b together; series compliances only F_b.
        let (pzt, cf) = materials();
        let layup = [0.0, 90.0, 0.0];
        let a = actuator(&pzt, &cf, &layup);
        let base = Effects::null().predict(&a).unwrap();
        let ratio = |e: Effects| {
            let p = e.predict(&a).unwrap();
            (
                p.free_deflection / base.free_deflection,
                p.blocked_force / base.blocked_force,
                p.mass / base.mass,
            )
        };
        let (d, f, m) = ratio(Effects {
            d31_scale: 0.5,
            ..Effects::null()
        });
        assert!((d - 0.5).abs() < 1e-12 && (f - 0.5).abs() < 1e-12 && m == 1.0);
        let (d, f, _) = ratio(Effects {
            dead_length: 3e-3,
            ..Effects::null()
        });
        assert!(d < 1.0 && (d - f).abs() < 1e-12);
        for e in [
            Effects {
                extension_flexibility: 1.0,
                ..Effects::null()
            },
            Effects {
                clamp_compliance: 0.5,
                ..Effects::null()
            },
        ] {
            let (d, f, m) = ratio(e);
            assert!((d - 1.0).abs() < 1e-12 && f < 0.99 && m == 1.0);
        }
        let (_, _, m) = ratio(Effects {
            ply_thickness_scale: 1.3,
            ..Effects::null()
        });
        assert!(m > 1.0);
        let (_, _, m) = ratio(Effects {
            bond_thickness: 25e-6,
            ..Effects::null()
        });
        assert!(m > 1.0);
    }

    #[test]
    fn dead_length_reduces_deflection_by_the_undriven_moment_arm() {
        // δ = P ((L-Δ)² - l_ext²)/2 against P (L² - l_ext²)/2 (module doc), rectangle without extension:
        // ratio (1 - Δ/l)².
        let (pzt, cf) = materials();
        let layup = [0.0, 90.0, 0.0];
        let mut a = actuator(&pzt, &cf, &layup);
        a.planform = Planform::new(40e-3, 0.0, 8e-3, 1.0, 0.0).unwrap();
        let base = Effects::null().predict(&a).unwrap();
        let p = Effects {
            dead_length: 4e-3,
            ..Effects::null()
        }
        .predict(&a)
        .unwrap();
        let want = (1.0f64 - 0.1).powi(2);
        assert!((p.free_deflection / base.free_deflection - want).abs() < 1e-12);
    }
}
