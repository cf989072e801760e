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
//!
//! Three more changes are primitives only ([`crate::primitives`], docs/calibration.md §2), set by declared
//! or discovered primitives and not written under `[effects]`:
//!
//! | primitive | change | moves |
//! |---|---|---|
//! | `rigid-root` h | the root `h` of the PZT held rigidly in the clamp: neither bends nor drives there | δ, F_b |
//! | `edge-margin` m | unelectroded strips of width `m` along both long edges: free curvature `P (1 - 2m/w(x))` | δ, F_b |
//! | `inactive-surface-layer` t_s | the outer `t_s` of each PZT plate has no d31, in the CLT stack | δ, F_b |
//! | `added-mass` m_a | a mass per actuator no layer carries (leads, solder): `m += m_a` | m |
//! | `added-mass-per-length` λ | a mass along the outline of each PZT plate (adhesive fillets): `m += 2 λ P_pzt` | m |
//! | `added-mass-per-area` μ | a mass over each bonded face (adhesive under the PZT): `m += 2 μ A_pzt` | m |

use crate::drive::{Drive, DriveMode};
use crate::error::ModelError;
use crate::laminate::{Laminate, Layer, LayerRole};
use crate::material::Material;
use crate::performance::{evaluate, MassBreakdown, Performance};
use crate::planform::Planform;
use crate::section::Section;
use serde::{Deserialize, Serialize};

mod stack;
pub use stack::{PlanformTerms, StackBasis, StackSection};

/// Density of the epoxy that resin-rich plies carry in excess, kg/m³.
pub const RESIN_DENSITY: f64 = 1200.0;

/// Built-in material of the bond layer (acrylic sheet adhesive, docs/physics.md §8).
pub const BOND_MATERIAL: &str = "Pyralux-LF";

/// The built-in bond material, looked up once: the library is built anew on every lookup.
fn bond_builtin() -> &'static Material {
    static BOND: std::sync::OnceLock<Material> = std::sync::OnceLock::new();
    BOND.get_or_init(|| Material::builtin(BOND_MATERIAL).expect("the bond material is built in"))
}

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
    /// Root length of the PZT held rigidly inside the clamp, m (null 0; the `rigid-root` primitive): on
    /// `[0, h]` the beam neither bends nor drives. Recorded as a declared primitive, not under `[effects]`.
    #[serde(skip)]
    pub rigid_root: f64,
    /// Width of the unelectroded strip along each long edge of each PZT plate, m (null 0; the
    /// `edge-margin` primitive). Recorded as a declared primitive, not under `[effects]`.
    #[serde(skip)]
    pub edge_margin: f64,
    /// Thickness of the piezoelectrically dead outer layer of each PZT plate, m (null 0; the
    /// `inactive-surface-layer` primitive; below the plate's thickness). Recorded as a declared
    /// primitive, not under `[effects]`.
    #[serde(skip)]
    pub inactive_surface: f64,
    /// Mass per actuator that no layer carries, kg (null 0; the `added-mass` primitive). Recorded as a
    /// declared primitive, not under `[effects]`.
    #[serde(skip)]
    pub added_mass: f64,
    /// Mass per unit length of the outline of each PZT plate, kg/m (null 0; the `added-mass-per-length`
    /// primitive: adhesive fillets). Recorded as a declared primitive.
    #[serde(skip)]
    pub added_mass_per_length: f64,
    /// Mass per unit bonded area, kg/m², over both PZT-to-ply faces (null 0; the `added-mass-per-area`
    /// primitive: adhesive with no stiffness in the stack). Recorded as a declared primitive.
    #[serde(skip)]
    pub added_mass_per_area: f64,
    /// Point mass at the actuator's tip fitted after it was weighed, kg (null 0; the `tip-mass`
    /// primitive): in the beam alone, not in [`Effects::added_mass`]. Recorded as a declared primitive.
    #[serde(skip)]
    pub tip_mass: f64,
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
            rigid_root: 0.0,
            edge_margin: 0.0,
            inactive_surface: 0.0,
            added_mass: 0.0,
            added_mass_per_length: 0.0,
            added_mass_per_area: 0.0,
            tip_mass: 0.0,
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
            "greater than 0",
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
            "at least 0 m",
        )?;
        check(
            "extension_flexibility",
            self.extension_flexibility,
            self.extension_flexibility >= 0.0,
            "at least 0",
        )?;
        check(
            "clamp_compliance",
            self.clamp_compliance,
            self.clamp_compliance >= 0.0,
            "at least 0 rad/(N m)",
        )?;
        check(
            "ply_thickness_scale",
            self.ply_thickness_scale,
            self.ply_thickness_scale > 0.25,
            "greater than 0.25",
        )?;
        check(
            "stiffness_scale",
            self.stiffness_scale,
            self.stiffness_scale > 0.0,
            "greater than 0",
        )?;
        check(
            "rigid_root",
            self.rigid_root,
            self.rigid_root >= 0.0,
            "[0, l_p) m",
        )?;
        check(
            "edge_margin",
            self.edge_margin,
            self.edge_margin >= 0.0,
            "[0, w/2) m",
        )?;
        check(
            "inactive_surface",
            self.inactive_surface,
            self.inactive_surface >= 0.0,
            "[0, t_p) m",
        )?;
        check(
            "added_mass",
            self.added_mass,
            self.added_mass >= 0.0,
            "at least 0 kg",
        )?;
        check(
            "added_mass_per_length",
            self.added_mass_per_length,
            self.added_mass_per_length >= 0.0,
            "at least 0 kg/m",
        )?;
        check(
            "added_mass_per_area",
            self.added_mass_per_area,
            self.added_mass_per_area >= 0.0,
            "at least 0 kg/m2",
        )?;
        check(
            "tip_mass",
            self.tip_mass,
            self.tip_mass >= 0.0,
            "at least 0 kg",
        )
    }

    /// The mass no layer carries: `m_a + 2 λ P_pzt + 2 μ A_pzt` over both plates
    /// ([`Planform::piezo_perimeter`], [`Planform::piezo_area`]), kg.
    pub fn added_mass(&self, planform: &Planform) -> f64 {
        // A term whose parameter is zero adds exactly zero: skipped, since a calibration asks for the
        // mass of every actuator at every step of every fit and the perimeter costs a square root.
        let mut m = self.added_mass;
        if self.added_mass_per_length != 0.0 {
            m += 2.0 * self.added_mass_per_length * planform.piezo_perimeter();
        }
        if self.added_mass_per_area != 0.0 {
            m += 2.0 * self.added_mass_per_area * planform.piezo_area();
        }
        m
    }

    /// Factor on d31 at a drive field: `η (1 + β E)`.
    #[inline]
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
        let m = bond_builtin().clone();
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

    /// The CLT stack with the stack effects (d31, plies, bond layer, an inactive surface layer of the
    /// PZT) applied.
    pub fn laminate(&self, a: &Actuator) -> Result<Laminate, ModelError> {
        // (An inactive surface layer at or above the plate's thickness is refused by the laminate.)
        self.validate()?;
        let pzt = self.pzt_material(a.pzt, a.drive.field);
        let (ply, t_ply) = self.ply_material(a.ply, a.ply_thickness);
        let bond = self.bond_material();
        let bond = (self.bond_thickness > 0.0).then_some((&bond, self.bond_thickness));
        Laminate::bimorph_with_surface(
            &pzt,
            a.pzt_thickness,
            &ply,
            t_ply,
            a.layup_deg,
            bond,
            self.inactive_surface,
        )
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
        self.stack_section(a)?.basis(&a.planform)
    }

    /// The planform-free part of [`Effects::basis`]: the stack with the stack effects of `self` applied
    /// (η and β not) solved at the drive, and the plies alone when the planform has an extension.
    pub fn stack_section(&self, a: &Actuator) -> Result<StackSection, ModelError> {
        let nominal_d31 = Effects {
            d31_scale: 1.0,
            d31_field_coefficient: 0.0,
            ..*self
        };
        let lam = nominal_d31.laminate(a)?;
        let section = Section::new(&lam, a.drive)?;
        let passive = if a.planform.extension_ratio > 0.0 {
            Some(self.passive_bending_compliance(a)?)
        } else {
            None
        };
        Ok(StackSection {
            free_curvature: section.free_curvature,
            bending_compliance: section.bending_compliance,
            passive_bending_compliance: passive,
            field: a.drive.field,
        })
    }

    /// The rigid root's length as the beam uses it: clipped at 0.95 `l_p`, as the dead length is, so a
    /// free length always remains (docs/calibration.md §2).
    #[inline]
    fn held_root(&self, pl: &Planform) -> f64 {
        self.rigid_root.min(0.95 * pl.piezo_length())
    }

    /// Free deflection and blocked force from a basis with η, β, Δ, h, m, φ, c_θ, s_k applied
    /// (docs/calibration.md §2).
    ///
    /// Dead length Δ and rigid root h: curvature P acts on `[x0, l_p]` only, `x0 = max(Δ, h)` (each
    /// clipped at 0.95 `l_p`), so `δ = P ((L - x0)² - l_ext²) / 2` with `L = l_p + l_ext` (x0 = 0 gives
    /// thesis eq. 2.26).
    ///
    /// Edge margin m: the actuation moment acts on `w(x) - 2m` of the width and the stiffness on all of it,
    /// so the free curvature is `P (1 - 2m / w(x))` and `δ = P [∫x0..l_p (L - x) dx - 2m ∫x0..l_p (L - x)/w dx]`
    /// ([`Planform::arm_over_width_from`]); `2m` is clipped at 0.95 of the narrowest width.
    ///
    /// Rigid root h: the beam is clamped at h, so its tip compliance is the tapered-beam integral from h,
    /// `c_beam(h) = c_beam G(w_r, l_r; h/l_p) / G(w_r, l_r)` ([`Planform::shape_factor_from`]).
    /// Tip compliance `c = c_beam(h) / s_k + φ c_ext + c_θ l_tot²`; `F_b = δ / c`.
    pub fn outputs(&self, b: &StackBasis) -> (f64, f64) {
        let curvature = b.free_curvature * self.d31_factor(b.field).abs();
        let pl = &b.planform;
        let l_ext = pl.extension_length();
        let tip = pl.piezo_length() + l_ext;
        let start = self.driven_start(pl);
        let mut delta = 0.5 * curvature * ((tip - start).powi(2) - l_ext * l_ext);
        if self.edge_margin > 0.0 {
            delta -= curvature * self.edge_margins(pl) * pl.arm_over_width_from(start);
        }
        (delta, delta / self.tip_compliance(b))
    }

    /// Where the driven part of the PZT begins, `x0 = max(Δ, h)`, each clipped at 0.95 `l_p`
    /// ([`Effects::outputs`]), m.
    #[inline]
    fn driven_start(&self, pl: &Planform) -> f64 {
        let dead = self.dead_length.min(0.95 * pl.piezo_length());
        dead.max(self.held_root(pl))
    }

    /// Both edge margins together, `2m` clipped at 0.95 of the narrowest width, m.
    #[inline]
    fn edge_margins(&self, pl: &Planform) -> f64 {
        (2.0 * self.edge_margin).min(0.95 * pl.narrowest_width())
    }

    /// The free deflection per unit of driving curvature, m²: `δ / P` of [`Effects::outputs`] with the
    /// curvature `P` at the nominal d31 times `|η (1 + β E)|`, i.e.
    /// `((L - x0)² - l_ext²) / 2 - 2m ∫x0..l_p (L - x)/w dx`. It depends on the planform and the boundary
    /// effects alone, not on the field, so an actuator's voltages share it: `δ = P a` and
    /// `F_b = P a / c` ([`Effects::tip_compliance`]).
    #[inline]
    pub fn deflection_arm(&self, pl: &Planform) -> f64 {
        let l_ext = pl.extension_length();
        let tip = pl.piezo_length() + l_ext;
        let start = self.driven_start(pl);
        let mut arm = 0.5 * ((tip - start).powi(2) - l_ext * l_ext);
        if self.edge_margin > 0.0 {
            arm -= self.edge_margins(pl) * pl.arm_over_width_from(start);
        }
        arm
    }

    /// True when [`Effects::deflection_arm`] is the planform's own, `(L² - l_ext²) / 2`, as in the original
    /// model: no dead length, rigid root or edge margin.
    #[inline]
    pub fn drives_whole_pzt(&self) -> bool {
        self.dead_length == 0.0 && self.rigid_root == 0.0 && self.edge_margin == 0.0
    }

    /// True when [`Effects::tip_compliance`] is the beam's alone, `c_beam / s_k`: no rigid root, compliant
    /// extension or clamp compliance.
    #[inline]
    pub fn compliance_is_beam(&self) -> bool {
        self.rigid_root == 0.0 && self.extension_flexibility == 0.0 && self.clamp_compliance == 0.0
    }

    /// Tip compliance `c = c_beam(h) / s_k + φ c_ext + c_θ l_tot²` of a basis, m/N: `δ / F_b` of
    /// [`Effects::outputs`], whatever the drive.
    #[inline]
    pub fn tip_compliance(&self, b: &StackBasis) -> f64 {
        let pl = &b.planform;
        let held = self.held_root(pl);
        let beam = if held > 0.0 {
            b.beam_compliance * pl.shape_factor_from(held) / pl.shape_factor()
        } else {
            b.beam_compliance
        };
        beam / self.stiffness_scale
            + self.extension_flexibility * b.extension_compliance
            + self.clamp_compliance * pl.length * pl.length
    }

    /// Mass by layer kind with `ply-thickness` and `bond-layer` applied, without solving the stack
    /// (same numbers as the laminate's areal masses; docs/physics.md §4).
    pub fn mass(&self, a: &Actuator) -> MassBreakdown {
        // The densities alone, as `ply_material` and `bond_material` give them: a calibration evaluates
        // the mass of every actuator at every step of every fit, and the whole materials are not needed.
        let s = self.ply_thickness_scale;
        let ply_density = (a.ply.density + (s - 1.0) * RESIN_DENSITY) / s;
        let t_ply = s * a.ply_thickness;
        let pl = &a.planform;
        let a_pzt = pl.piezo_area();
        MassBreakdown {
            pzt: 2.0 * a.pzt.density * a.pzt_thickness * a_pzt,
            passive: a.layup_deg.len() as f64
                * ply_density
                * t_ply
                * (a_pzt + pl.extension_area() + pl.tab_area()),
            bond: 2.0
                * (bond_builtin().density * self.bond_scale.density)
                * self.bond_thickness
                * a_pzt,
            added: self.added_mass(pl),
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
        let masses = MassBreakdown {
            added: self.added_mass(&a.planform),
            ..base.mass_breakdown
        };
        let mut p = base.with_outputs(delta, force, masses);
        // Stresses under the changed blocked force (thesis eq. 3.3, and the CLT stress and strain along
        // the plate; with a rigid root the beam's root is at h, where the moment is F (L - h) over w(h)).
        let pl = &a.planform;
        p.base_stress = crate::performance::base_stress(force, pl, section.thickness);
        let plate = crate::plate::over_stroke(&section, pl, force, self.held_root(pl));
        p.peak_pzt_strain = plate.strain;
        p.peak_pzt_strain_at = plate.strain_at;
        p.peak_pzt_stress = plate.stress;
        p.peak_pzt_stress_at = plate.stress_at;
        Ok(p)
    }
}

/// Helper for callers with a drive given as a voltage.
pub fn drive_at_voltage(mode: DriveMode, voltage: f64, pzt_thickness: f64) -> Drive {
    Drive::new(mode, mode.field_from_voltage(voltage, pzt_thickness))
}

#[cfg(test)]
mod tests {
    use super::*;

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
            drive: Drive::new(DriveMode::Parallel, 600e3),
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
            rigid_root: 1.5e-3,
            edge_margin: 0.3e-3,
            inactive_surface: 12e-6,
            added_mass: 1e-6,
            added_mass_per_length: 5e-6,
            added_mass_per_area: 0.01,
            tip_mass: 2e-6,
        };
        let p = e.predict(&a).unwrap();
        let (d, f) = e.outputs(&e.basis(&a).unwrap());
        assert!(((d - p.free_deflection) / d).abs() < 1e-10);
        assert!(((f - p.blocked_force) / f).abs() < 1e-10);
        let m = e.mass(&a);
        assert!(((m.total() - p.mass) / p.mass).abs() < 1e-12);
        assert!((m.bond - p.mass_breakdown.bond).abs() < 1e-15);
        assert!((m.added - p.mass_breakdown.added).abs() < 1e-15 && m.added > 1e-6);
        // The tip mass is fitted after weighing and moves f1 alone (docs/physics.md §11.4): the
        // statics and the mass are those without it.
        let no_tip = Effects { tip_mass: 0.0, ..e };
        assert_eq!(no_tip.predict(&a).unwrap(), p);
        assert_eq!(no_tip.mass(&a), m);
        // Each of the primitive-only fields moves the outputs (the agreement above is not vacuous).
        for off in [
            Effects {
                rigid_root: 0.0,
                ..e
            },
            Effects {
                edge_margin: 0.0,
                ..e
            },
            Effects {
                inactive_surface: 0.0,
                ..e
            },
        ] {
            let q = off.predict(&a).unwrap();
            assert!((q.blocked_force / p.blocked_force - 1.0).abs() > 1e-3);
        }
    }

    /// A bond layer and plies 20 % thicker: effects that change the stack.
    fn bonded_thick_plies() -> Effects {
        Effects {
            bond_thickness: 20e-6,
            ply_thickness_scale: 1.2,
            ..Effects::null()
        }
    }

    /// The stack section does not depend on the planform: solved on one actuator, it gives another
    /// planform's basis exactly; solved without an extension, it refuses a planform with one.
    #[test]
    fn a_stack_section_serves_every_planform_of_its_stack() {
        let (pzt, cf) = materials();
        let layup = [0.0, 90.0, 0.0];
        let e = bonded_thick_plies();
        let a = actuator(&pzt, &cf, &layup);
        let section = e.stack_section(&a).unwrap();
        let mut b = a;
        b.planform = Planform::new(25e-3, 0.3, 5e-3, 0.7, 0.0).unwrap();
        assert_eq!(section.basis(&b.planform).unwrap(), e.basis(&b).unwrap());
        let mut bare = a;
        bare.planform = Planform::new(25e-3, 0.0, 5e-3, 0.7, 0.0).unwrap();
        let without = e.stack_section(&bare).unwrap();
        assert!(without.passive_bending_compliance.is_none());
        assert_eq!(
            without.basis(&bare.planform).unwrap(),
            e.basis(&bare).unwrap()
        );
        assert!(without.basis(&a.planform).is_err());
    }

    #[test]
    fn a_basis_moves_to_another_field_exactly() {
        let (pzt, cf) = materials();
        let layup = [0.0, 90.0, 0.0];
        let e = bonded_thick_plies();
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

    /// Composite Simpson's rule on [a, b] with 20 000 intervals: the test's own integration, independent
    /// of the closed forms in planform.rs.
    fn simpson(f: impl Fn(f64) -> f64, a: f64, b: f64) -> f64 {
        let n = 20_000;
        let h = (b - a) / n as f64;
        let inner: f64 = (1..n)
            .map(|i| f(a + i as f64 * h) * if i % 2 == 1 { 4.0 } else { 2.0 })
            .sum();
        (f(a) + inner + f(b)) * h / 3.0
    }

    /// C44 of the actuator's stack (the section the model solves), 1/(N·m).
    fn c44(e: &Effects, a: &Actuator) -> f64 {
        Section::new(&e.laminate(a).unwrap(), a.drive)
            .unwrap()
            .bending_compliance
    }

    /// Rigid root h (docs/calibration.md §2): a cantilever clamped at h. On a rectangle without extension
    /// the tip compliance is exactly `C44 (l - h)³ / (3 w)` and δ shrinks as `((l - h)/l)²`; on a tapered
    /// beam with an extension the compliance is `C44 ∫h..l_p (L - x)²/w(x) dx` by Simpson's rule, and δ is
    /// `P ((L - h)² - l_ext²)/2`.
    #[test]
    fn a_rigid_root_is_a_cantilever_clamped_at_its_end() {
        let (pzt, cf) = materials();
        let layup = [0.0, 90.0, 0.0];
        let mut a = actuator(&pzt, &cf, &layup);
        let held = Effects {
            rigid_root: 4e-3,
            ..Effects::null()
        };
        a.planform = Planform::new(40e-3, 0.0, 8e-3, 1.0, 0.0).unwrap();
        let base = Effects::null().predict(&a).unwrap();
        let p = held.predict(&a).unwrap();
        let c = c44(&held, &a) * (36e-3f64).powi(3) / (3.0 * 8e-3);
        let got = p.free_deflection / p.blocked_force;
        assert!(((got - c) / c).abs() < 1e-12, "{got} vs {c}");
        assert!((p.free_deflection / base.free_deflection - 0.81).abs() < 1e-12);
        // A taper with an extension.
        a.planform = Planform::new(40e-3, 0.6, 8e-3, 1.4, 0.0).unwrap();
        let pl = a.planform;
        let (l_p, tip, l_ext) = (pl.piezo_length(), pl.length, pl.extension_length());
        let h = 4e-3;
        let p = held.predict(&a).unwrap();
        let base = Effects::null().predict(&a).unwrap();
        let beam = c44(&held, &a) * simpson(|x| (tip - x).powi(2) / pl.width_at(x), h, l_p);
        let got = p.free_deflection / p.blocked_force;
        assert!(((got - beam) / beam).abs() < 1e-9, "{got} vs {beam}");
        let curvature = 2.0 * base.free_deflection / (tip * tip - l_ext * l_ext);
        let want = 0.5 * curvature * ((tip - h).powi(2) - l_ext * l_ext);
        assert!(((p.free_deflection - want) / want).abs() < 1e-12);
        // With a dead length too, the curvature is zero up to the longer of the two; the dead length
        // keeps the compliance, the rigid root does not.
        for (dead, root) in [(3e-3, 2e-3), (2e-3, 3e-3)] {
            let both = Effects {
                dead_length: dead,
                rigid_root: root,
                ..Effects::null()
            }
            .predict(&a)
            .unwrap();
            let longer = 0.5 * curvature * ((tip - 3e-3f64).powi(2) - l_ext * l_ext);
            assert!(((both.free_deflection - longer) / longer).abs() < 1e-12);
            let clamped = Effects {
                rigid_root: root,
                ..Effects::null()
            }
            .predict(&a)
            .unwrap();
            let c = both.free_deflection / both.blocked_force;
            let want = clamped.free_deflection / clamped.blocked_force;
            assert!(((c - want) / want).abs() < 1e-12);
        }
        assert_eq!(p.mass, base.mass);
    }

    /// Edge margins m (docs/calibration.md §2): on a rectangle δ and F_b fall by exactly `1 - 2m/w` and the
    /// compliance is unchanged; on a taper with a dead length, δ is `P ∫Δ..l_p (1 - 2m/w(x)) (L - x) dx`
    /// by Simpson's rule; 2m is clipped at 0.95 of the narrowest width.
    #[test]
    fn edge_margins_scale_the_local_curvature_by_the_electroded_share() {
        let (pzt, cf) = materials();
        let layup = [0.0, 90.0, 0.0];
        let mut a = actuator(&pzt, &cf, &layup);
        a.planform = Planform::new(30e-3, 0.5, 6e-3, 1.0, 0.0).unwrap();
        let m = 0.4e-3;
        let margin = Effects {
            edge_margin: m,
            ..Effects::null()
        };
        let base = Effects::null().predict(&a).unwrap();
        let p = margin.predict(&a).unwrap();
        let k = 1.0 - 2.0 * m / 6e-3;
        assert!((p.free_deflection / base.free_deflection - k).abs() < 1e-12);
        assert!((p.blocked_force / base.blocked_force - k).abs() < 1e-12);
        a.planform = Planform::new(40e-3, 0.6, 8e-3, 1.7, 0.0).unwrap();
        let pl = a.planform;
        let (l_p, tip, l_ext) = (pl.piezo_length(), pl.length, pl.extension_length());
        let dead = 2e-3;
        let base = Effects::null().predict(&a).unwrap();
        let curvature = 2.0 * base.free_deflection / (tip * tip - l_ext * l_ext);
        let both = Effects {
            dead_length: dead,
            ..margin
        }
        .predict(&a)
        .unwrap();
        let want = curvature * simpson(|x| (1.0 - 2.0 * m / pl.width_at(x)) * (tip - x), dead, l_p);
        assert!(
            ((both.free_deflection - want) / want).abs() < 1e-9,
            "{} vs {want}",
            both.free_deflection
        );
        let stiffness = base.blocked_force / base.free_deflection;
        let dead_only = Effects {
            dead_length: dead,
            ..Effects::null()
        }
        .predict(&a)
        .unwrap();
        assert!(((both.stiffness - stiffness) / stiffness).abs() < 1e-12);
        assert!(both.free_deflection < dead_only.free_deflection);
        // Margins wider than the tip (w_tip = 0.3 w_nom here) are clipped, not a negative deflection.
        let wide = Effects {
            edge_margin: 5e-3,
            ..Effects::null()
        }
        .predict(&a)
        .unwrap();
        let clipped = 0.95 * pl.narrowest_width();
        let want = curvature * simpson(|x| (1.0 - clipped / pl.width_at(x)) * (tip - x), 0.0, l_p);
        assert!(((wide.free_deflection - want) / want).abs() < 1e-9);
        assert!(wide.free_deflection > 0.0);
    }

    /// An inactive surface layer t_s (docs/calibration.md §2). With plies of the PZT's own elastic
    /// properties the beam is homogeneous and Euler-Bernoulli gives the free curvature by hand:
    /// `κ = M_p / (E I) = 12 |d31| E_3 [(H/2 - t_s)² - (H/2 - t_p)²] / H³` (the piezoelectric moment of the
    /// two driven parts, `∫ E d31 E_3 z dz`, over `E H³/12`; E and ν cancel for an equibiaxial free strain).
    /// On the real stack the moment ratio `((H/2 - t_s)² - z_i²) / ((H/2)² - z_i²)`, `z_i = H/2 - t_p`, is the
    /// deflection ratio (the stiffness is unchanged), and it lies below the first-order `1 - t_s/t_p` and
    /// above `1 - 2 t_s/t_p` (a sanity bound, not the reference). The mass is unchanged; t_s → 0 is the
    /// original model; t_s >= t_p is refused.
    #[test]
    fn an_inactive_surface_layer_drives_only_the_inner_part_of_each_plate() {
        let (pzt, cf) = materials();
        let dead_ply = Material {
            name: "PZT-as-ply".into(),
            d31: 0.0,
            ..pzt.clone()
        };
        let layup = [0.0, 90.0, 0.0];
        let (t_p, t_s) = (191e-6, 15e-6);
        let surface = Effects {
            inactive_surface: t_s,
            ..Effects::null()
        };
        let mut a = actuator(&pzt, &dead_ply, &layup);
        a.planform = Planform::new(40e-3, 0.0, 8e-3, 1.0, 0.0).unwrap();
        let h = 2.0 * t_p + 3.0 * 61.8e-6;
        let e3 = a.drive.field;
        for t in [t_s, 0.0] {
            let kappa =
                12.0 * pzt.d31.abs() * e3 * ((h / 2.0 - t).powi(2) - (h / 2.0 - t_p).powi(2))
                    / h.powi(3);
            let p = Effects {
                inactive_surface: t,
                ..Effects::null()
            }
            .predict(&a)
            .unwrap();
            let want = 0.5 * kappa * 40e-3 * 40e-3;
            assert!(
                ((p.free_deflection - want) / want).abs() < 1e-9,
                "t_s {t}: {} vs {want}",
                p.free_deflection
            );
        }
        // Stresses in free deflection, by hand on the homogeneous beam: σ = E/(1-ν) (z κ - d31 E_3) in a
        // driven part (equibiaxial strain), E/(1-ν) z κ in the dead one; the peak is the largest over both
        // sides of each layer of the plate.
        let lam = surface.laminate(&a).unwrap();
        let section = Section::new(&lam, a.drive).unwrap();
        let kappa = section.free_curvature;
        let q = pzt.e1 / (1.0 - pzt.nu12);
        // Bottom plate (field +E_3; the curvature's sign makes the driven part's stresses add as below).
        let z = [-h / 2.0, -h / 2.0 + t_s, -h / 2.0 + t_p];
        let signed = Laminate::bimorph(&pzt, t_p, &dead_ply, 61.8e-6, &layup, None)
            .unwrap()
            .free_curvature(&a.drive.mode.layer_fields(e3));
        let kz = |z: f64| z * kappa * signed.signum();
        let free = pzt.d31 * e3;
        let want = [
            q * kz(z[0]),
            q * kz(z[1]),
            q * (kz(z[1]) - free),
            q * (kz(z[2]) - free),
        ]
        .into_iter()
        .map(f64::abs)
        .fold(0.0, f64::max);
        let got = section.peak_pzt_stress(0.0);
        assert!(((got - want) / want).abs() < 1e-9, "{got} vs {want}");
        assert!((section.pzt_thickness - t_p).abs() < 1e-18);
        assert!((section.voltage - e3 * t_p).abs() < 1e-9);
        // The real stack: the moment ratio, and the sanity bounds.
        let a = actuator(&pzt, &cf, &[0.0, 0.0, 90.0, 0.0, 0.0]);
        let base = Effects::null().predict(&a).unwrap();
        let p = surface.predict(&a).unwrap();
        let h = 2.0 * t_p + 5.0 * 61.8e-6;
        let z_i = h / 2.0 - t_p;
        let want = ((h / 2.0 - t_s).powi(2) - z_i * z_i) / ((h / 2.0).powi(2) - z_i * z_i);
        let ratio = p.free_deflection / base.free_deflection;
        assert!((ratio - want).abs() < 1e-9, "{ratio} vs {want}");
        assert!((p.blocked_force / base.blocked_force - want).abs() < 1e-9);
        assert!(ratio < 1.0 - t_s / t_p && ratio > 1.0 - 2.0 * t_s / t_p);
        assert!(((p.mass - base.mass) / base.mass).abs() < 1e-12);
        let thin = Effects {
            inactive_surface: 1e-12,
            ..Effects::null()
        }
        .predict(&a)
        .unwrap();
        assert!((thin.free_deflection / base.free_deflection - 1.0).abs() < 1e-7);
        assert!(Effects {
            inactive_surface: t_p,
            ..Effects::null()
        }
        .predict(&a)
        .is_err());
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

    /// The shortcuts a calibration takes per actuator: with no dead length, rigid root or edge margin the
    /// arm is the original model's bit for bit, and with no rigid root, extension flexibility or clamp
    /// compliance the tip compliance is `c_beam / s_k`; each of those effects alone moves them.
    #[test]
    fn the_arm_and_the_compliance_keep_their_original_form_without_their_effects() {
        let (pzt, cf) = materials();
        let layup = [0.0, 90.0, 0.0];
        let a = actuator(&pzt, &cf, &layup);
        let b = Effects::null().basis(&a).unwrap();
        let pl = &a.planform;
        let kept = Effects {
            d31_scale: 0.8,
            d31_field_coefficient: 1e-6,
            stiffness_scale: 0.9,
            ply_thickness_scale: 1.2,
            bond_thickness: 20e-6,
            ..Effects::null()
        };
        assert!(kept.drives_whole_pzt() && kept.compliance_is_beam());
        assert_eq!(kept.deflection_arm(pl), Effects::null().deflection_arm(pl));
        assert_eq!(kept.tip_compliance(&b), b.beam_compliance / 0.9);
        let arm_movers = [
            Effects {
                dead_length: 2e-3,
                ..kept
            },
            Effects {
                rigid_root: 2e-3,
                ..kept
            },
            Effects {
                edge_margin: 0.2e-3,
                ..kept
            },
        ];
        for e in arm_movers {
            assert!(!e.drives_whole_pzt());
            assert_ne!(e.deflection_arm(pl), kept.deflection_arm(pl));
        }
        let compliance_movers = [
            Effects {
                rigid_root: 2e-3,
                ..kept
            },
            Effects {
                extension_flexibility: 1.0,
                ..kept
            },
            Effects {
                clamp_compliance: 0.3,
                ..kept
            },
        ];
        for e in compliance_movers {
            assert!(!e.compliance_is_beam());
            assert_ne!(e.tip_compliance(&b), kept.tip_compliance(&b));
        }
    }
}
