//! Physical primitives an effect is composed of (docs/calibration.md §2, "Primitives"): each
//! changes the inputs of the physics — a material property, a layer of the stack, a boundary condition, the
//! field — never an output. [`compose`] applies a list of them to an actuator and predicts it with the model
//! of [`Effects`]; the seven library effects are named compositions of them ([`library_composition`]), and a
//! test holds each composition to the effect's own prediction.

use crate::effects::{Actuator, Effects, RESIN_DENSITY};
use crate::error::ModelError;
use crate::material::Material;
use crate::performance::{MassBreakdown, Performance};
use crate::planform::Planform;
use serde::{Deserialize, Serialize};

/// A layer kind of the bimorph stack whose material a primitive changes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Target {
    /// Both PZT plates.
    Pzt,
    /// Every passive ply (and the extension made of them).
    Passive,
    /// The bond layer between each PZT and the plies, where the model has one (the library's
    /// `bond-layer` or an inserted layer applied before this primitive); isotropic, so it scales E1
    /// (its modulus E), ν12, density and thickness ([`Target::scalable`]).
    Bond,
}

impl Target {
    /// Whether a `scale` primitive on this target can act on `property`: every property for the PZT
    /// and the plies; for the bond layer E1 (its one modulus), ν12, density and thickness. `Err` says
    /// why not and what is allowed.
    pub fn scalable(self, property: Property) -> Result<(), &'static str> {
        match (self, property) {
            (Target::Pzt | Target::Passive, _) => Ok(()),
            (
                Target::Bond,
                Property::E1 | Property::Nu12 | Property::Density | Property::Thickness,
            ) => Ok(()),
            (Target::Bond, Property::E2 | Property::G12) => Err(
                "the bond layer is isotropic: scale its modulus as E1 (E2 and G12 follow); allowed for the bond: E1, nu12, density, thickness",
            ),
            (Target::Bond, Property::D31 | Property::Permittivity) => Err(
                "the model's bond layer has no such property (it is not piezoelectric); allowed for the bond: E1, nu12, density, thickness",
            ),
        }
    }
}

/// A material property a primitive scales.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Property {
    /// Longitudinal modulus E1.
    E1,
    /// Transverse modulus E2.
    E2,
    /// Shear modulus G12.
    G12,
    /// Major Poisson ratio ν12.
    Nu12,
    /// Piezoelectric coefficient d31.
    D31,
    /// Relative permittivity ε (no effect on δ or F_b in this model; kept for drive-power studies).
    Permittivity,
    /// Density.
    Density,
    /// Layer thickness.
    Thickness,
}

/// One physical primitive with one parameter.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
pub enum Primitive {
    /// Multiply a property of a material by the parameter (null 1).
    Scale {
        /// Which layers.
        target: Target,
        /// Which property.
        property: Property,
    },
    /// Insert a bond layer (built-in `Pyralux-LF`) of the parameter's thickness, m, between each PZT and the
    /// plies, in the CLT stack and the mass (null 0).
    InsertedLayer,
    /// `d31(E) = d31 (1 + β E)`, β in m/V (null 0).
    FieldDependentD31,
    /// An undriven root of the PZT of the parameter's length, m (no electrode there; it keeps its stiffness;
    /// null 0).
    ElectrodeMargin,
    /// Rotational compliance of the clamp, rad/(N·m) (null 0).
    ClampCompliance,
    /// Rotational compliance of the clamp per unit clamped width: `c_θ = c_w / w_0`, rad·m/(N·m) (null 0).
    ClampCompliancePerWidth,
    /// Extension flexibility relative to the bare plies (null 0 = rigid).
    CompliantExtension,
    /// A root length of the PZT held rigidly inside the clamp, m (null 0): on `[0, h]` the beam neither
    /// bends nor drives, so the deflection is that of an undriven root and the tip compliance is the
    /// tapered-beam integral from h ([`Effects::outputs`]).
    RigidRoot,
    /// An unelectroded strip of the parameter's width, m, along both long edges of each PZT plate over its
    /// whole length (null 0): free curvature `P (1 - 2m/w(x))`, stiffness unchanged ([`Effects::outputs`]).
    EdgeMargin,
    /// A piezoelectrically dead outer layer of each PZT plate, of the parameter's thickness, m (null 0;
    /// below the plate's thickness): same elastic properties and density, d31 = 0, in the CLT stack
    /// ([`crate::laminate::Laminate::bimorph_with_surface`]).
    InactiveSurfaceLayer,
    /// A d31 that follows a power of the PZT plate's thickness, `d31 (t_p / t_ref)^a` with
    /// `t_ref` = [`D31_REFERENCE_THICKNESS`]; the parameter is the exponent `a` (null 0). A thickness
    /// trend in either direction (docs/calibration.md §2): where a dead surface layer can only cost a thin
    /// plate more, `a < 0` is a thick plate driven less (poled less through its thickness).
    D31ThicknessPower,
    /// A mass per actuator that no layer carries (leads, solder), kg (null 0): the mass only.
    AddedMass,
    /// A mass per unit length of the outline of each PZT plate (adhesive fillets), kg/m (null 0): the
    /// mass only, `2 λ P_pzt` over both plates.
    AddedMassPerLength,
    /// A mass per unit bonded area (adhesive under each PZT with no stiffness in the stack), kg/m²
    /// (null 0): the mass only, `2 μ A_pzt` over both PZT-to-ply faces.
    AddedMassPerArea,
    /// A point mass at the actuator's tip (a glue blob, a wing hinge) fitted after the actuator was
    /// weighed, kg (null 0): it moves with the tip in the first mode and nothing else, so δ, F_b, the
    /// stack and the weighed mass are untouched and only `f1` falls (docs/physics.md §11.4).
    TipMass,
}

impl Primitive {
    /// False for a scale on a property its target does not have ([`Target::scalable`]).
    pub fn is_defined(self) -> bool {
        match self {
            Primitive::Scale { target, property } => target.scalable(property).is_ok(),
            _ => true,
        }
    }

    /// The parameter value that leaves the physics unchanged.
    pub fn null(self) -> f64 {
        match self {
            Primitive::Scale { .. } => 1.0,
            _ => 0.0,
        }
    }

    /// True when the primitive changes the CLT stack (a material or an inserted layer), so a
    /// [`crate::effects::StackBasis`] solved without it no longer holds. Boundary and field primitives
    /// act on a solved stack.
    pub fn changes_stack(self) -> bool {
        matches!(
            self,
            Primitive::Scale { .. }
                | Primitive::InsertedLayer
                | Primitive::InactiveSurfaceLayer
                | Primitive::D31ThicknessPower
        )
    }

    /// True when δ and F_b stay proportional to the drive field with the primitive applied: CLT's free
    /// curvature is linear in the piezoelectric strain `d31 E` and nothing else in the model depends on
    /// the field, so every primitive but the field-dependent d31, whose `d31 (1 + β E)` adds a term in E²
    /// (a test holds each primitive to this). A calibration evaluates one field of an actuator and
    /// scales its other voltages.
    pub fn linear_in_field(self) -> bool {
        !matches!(self, Primitive::FieldDependentD31)
    }

    /// True when the primitive changes the mass (a density, a thickness, an inserted layer or an added
    /// mass).
    pub fn changes_mass(self) -> bool {
        matches!(
            self,
            Primitive::Scale {
                property: Property::Density | Property::Thickness,
                ..
            } | Primitive::InsertedLayer
        ) || self.is_added_mass()
    }

    /// True when the primitive can change an actuator's beam, mass or statics' tip stiffness on a given
    /// stack basis, so its first mode ([`crate::EffectModel::modes`]): everything but what acts on the
    /// drive alone (d31 and its field or thickness dependence, the permittivity, an undriven root or
    /// edge strip, a dead surface layer), which moves the free curvature and nothing the mode reads
    /// (docs/physics.md §11.1).
    pub fn changes_beam(self) -> bool {
        !matches!(
            self,
            Primitive::Scale {
                property: Property::D31 | Property::Permittivity,
                ..
            } | Primitive::FieldDependentD31
                | Primitive::ElectrodeMargin
                | Primitive::EdgeMargin
                | Primitive::InactiveSurfaceLayer
                | Primitive::D31ThicknessPower
        )
    }

    /// True for the primitives that change the mass alone (an added mass per actuator, per outline
    /// length or per bonded area): δ, F_b and the stack are untouched.
    pub fn is_added_mass(self) -> bool {
        matches!(
            self,
            Primitive::AddedMass | Primitive::AddedMassPerLength | Primitive::AddedMassPerArea
        )
    }

    /// The values the parameter may physically take, as (lower, lower inclusive, upper): scales and
    /// thicknesses are positive, lengths and compliances non-negative, the field coefficient any finite
    /// number. A declared effect's bounds must lie inside. (An inactive surface layer must also be thinner
    /// than the PZT plate, and a rigid root or edge margins are clipped as a dead length is, but those
    /// limits depend on the actuator: the model checks them per actuator.)
    pub fn physical_range(self) -> (f64, bool, f64) {
        match self {
            Primitive::Scale { .. } => (0.0, false, f64::INFINITY),
            Primitive::FieldDependentD31 | Primitive::D31ThicknessPower => {
                (f64::NEG_INFINITY, false, f64::INFINITY)
            }
            _ => (0.0, true, f64::INFINITY),
        }
    }

    /// True when `v` is finite and inside [`Primitive::physical_range`].
    pub fn allows(self, v: f64) -> bool {
        let (lo, lo_inclusive, hi) = self.physical_range();
        v.is_finite() && v < hi && (v > lo || (lo_inclusive && v == lo))
    }
}

/// The plate thickness at which [`Primitive::D31ThicknessPower`] leaves d31 unchanged: the middle of the
/// commercial plates the thesis built with (127, 191 and 267 µm), so that a d31 scale fitted beside the
/// exponent is the scale at a typical plate and the two are not strongly correlated over those plates.
pub const D31_REFERENCE_THICKNESS: f64 = 191e-6;

/// How a composition's one parameter sets a primitive's value.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Map {
    #[default]
    /// The parameter itself.
    Identity,
    /// Its reciprocal (moduli of a ply spread over `s` times its thickness).
    Reciprocal,
    /// A millionth of the parameter: a parameter in µm for a primitive in m (a layer thickness as the
    /// reports show it).
    Micro,
    /// The passive density of a ply `s` times as thick whose excess is resin:
    /// `(ρ + (s - 1) ρ_resin) / (s ρ)` as a factor on ρ.
    ResinDensity,
}

impl Map {
    /// The primitive's value at parameter `p`; `None` for [`Map::ResinDensity`], which needs the ply
    /// ([`at`]) and is the library's `ply-thickness` alone.
    pub fn of(self, p: f64) -> Option<f64> {
        match self {
            Map::Identity => Some(p),
            Map::Reciprocal => Some(1.0 / p),
            // Divided by the exact 1e6, so that 15 gives the double nearest 15e-6.
            Map::Micro => Some(p / 1e6),
            Map::ResinDensity => None,
        }
    }
}

/// A primitive in a composition, with how the composition's parameter sets it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Link {
    /// The primitive.
    pub primitive: Primitive,
    /// How the parameter sets it.
    #[serde(default)]
    pub map: Map,
}

/// A primitive at a value.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Applied {
    /// The primitive.
    pub primitive: Primitive,
    /// Its value (SI).
    pub value: f64,
}

/// The primitives a one-parameter composition applies at parameter `p` on an actuator whose passive
/// material is `ply`.
pub fn at(links: &[Link], p: f64, ply: &Material) -> Vec<Applied> {
    links
        .iter()
        .map(|l| Applied {
            primitive: l.primitive,
            value: match l.map {
                Map::Identity => p,
                Map::Reciprocal => 1.0 / p,
                Map::Micro => p / 1e6,
                Map::ResinDensity => (ply.density + (p - 1.0) * RESIN_DENSITY) / (p * ply.density),
            },
        })
        .collect()
}

fn scale(m: &mut Material, thickness: &mut f64, property: Property, v: f64) {
    match property {
        Property::E1 => m.e1 *= v,
        Property::E2 => m.e2 *= v,
        Property::G12 => m.g12 *= v,
        Property::Nu12 => m.nu12 *= v,
        Property::D31 => m.d31 *= v,
        Property::Permittivity => m.relative_permittivity *= v,
        Property::Density => m.density *= v,
        Property::Thickness => *thickness *= v,
    }
}

/// An actuator's stack with the stack primitives applied ([`Primitive::changes_stack`]): its materials
/// and thicknesses, and the effects with an inserted layer added.
#[derive(Debug, Clone)]
pub struct Stacked {
    /// `base` with the inserted layers added.
    pub effects: Effects,
    /// The PZT material.
    pub pzt: Material,
    /// PZT plate thickness, m.
    pub pzt_thickness: f64,
    /// The passive ply material.
    pub ply: Material,
    /// Ply thickness, m.
    pub ply_thickness: f64,
}

impl Stacked {
    /// `a` with this stack.
    pub fn actuator<'s>(&'s self, a: &Actuator<'s>) -> Actuator<'s> {
        Actuator {
            pzt: &self.pzt,
            pzt_thickness: self.pzt_thickness,
            ply: &self.ply,
            ply_thickness: self.ply_thickness,
            ..*a
        }
    }
}

/// Apply the stack primitives of `applied` to an actuator's stack on top of `base`; every value must be
/// finite.
pub fn stack(applied: &[Applied], base: &Effects, a: &Actuator) -> Result<Stacked, ModelError> {
    let mut s = Stacked {
        effects: *base,
        pzt: a.pzt.clone(),
        pzt_thickness: a.pzt_thickness,
        ply: a.ply.clone(),
        ply_thickness: a.ply_thickness,
    };
    for x in applied {
        stack_effects(&mut s.effects, x)?;
        let v = x.value;
        match x.primitive {
            Primitive::Scale {
                target: Target::Pzt,
                property,
            } => scale(&mut s.pzt, &mut s.pzt_thickness, property, v),
            Primitive::Scale {
                target: Target::Passive,
                property,
            } => scale(&mut s.ply, &mut s.ply_thickness, property, v),
            // The designed plate (`a`), not one a thickness scale in `applied` has changed: the trend is
            // over the plates as bought.
            Primitive::D31ThicknessPower => {
                s.pzt.d31 *= (a.pzt_thickness / D31_REFERENCE_THICKNESS).powf(v)
            }
            _ => {}
        }
    }
    // Not the stack, but the mass the stacked effects report.
    s.effects = masses(applied, &s.effects);
    Ok(s)
}

/// Add the mass primitives of `applied` (added mass, per length, per area, tip mass) to `effects`:
/// what the effects' mass ([`Effects::added_mass`]) and the beam ([`crate::dynamics::ActuatorBeam::from_effects`],
/// docs/physics.md §11.4) read of them. Neither the stack nor the boundary does.
pub fn masses<'x>(applied: impl IntoIterator<Item = &'x Applied>, effects: &Effects) -> Effects {
    let mut e = *effects;
    for x in applied {
        let v = x.value;
        match x.primitive {
            Primitive::AddedMass => e.added_mass += v,
            Primitive::AddedMassPerLength => e.added_mass_per_length += v,
            Primitive::AddedMassPerArea => e.added_mass_per_area += v,
            Primitive::TipMass => e.tip_mass += v,
            _ => {}
        }
    }
    e
}

/// The part of [`stack`] that acts on the effects (a bond scale, an inserted or inactive layer), after
/// checking that the value is finite; the materials are left to [`stack`].
fn stack_effects(effects: &mut Effects, x: &Applied) -> Result<(), ModelError> {
    let v = x.value;
    if !v.is_finite() {
        return Err(ModelError::OutOfRange {
            name: "primitive value",
            value: v,
            range: "finite",
        });
    }
    match x.primitive {
        Primitive::Scale {
            target: Target::Bond,
            property,
        } => {
            if let Err(range) = Target::Bond.scalable(property) {
                return Err(ModelError::OutOfRange {
                    name: "bond scale primitive",
                    value: v,
                    range,
                });
            }
            let k = &mut effects.bond_scale;
            match property {
                Property::Thickness => effects.bond_thickness *= v,
                Property::Density => k.density *= v,
                Property::Nu12 => k.poisson *= v,
                _ => k.modulus *= v,
            }
        }
        Primitive::InsertedLayer => effects.bond_thickness += v,
        Primitive::InactiveSurfaceLayer => effects.inactive_surface += v,
        _ => {}
    }
    Ok(())
}

/// Add the boundary and field primitives of `applied` to `effects` for an actuator of this planform
/// (the clamp compliance per width becomes `c_w / w_0` here). Stack primitives are left to [`stack`].
pub fn boundary<'x>(
    applied: impl IntoIterator<Item = &'x Applied>,
    effects: &Effects,
    planform: &Planform,
) -> Effects {
    let mut e = *effects;
    for x in applied {
        let v = x.value;
        match x.primitive {
            Primitive::FieldDependentD31 => e.d31_field_coefficient += v,
            Primitive::ElectrodeMargin => e.dead_length += v,
            Primitive::ClampCompliance => e.clamp_compliance += v,
            Primitive::ClampCompliancePerWidth => e.clamp_compliance += v / planform.base_width,
            Primitive::CompliantExtension => e.extension_flexibility += v,
            Primitive::RigidRoot => e.rigid_root += v,
            Primitive::EdgeMargin => e.edge_margin += v,
            Primitive::Scale { .. }
            | Primitive::InsertedLayer
            | Primitive::InactiveSurfaceLayer
            | Primitive::D31ThicknessPower
            | Primitive::AddedMass
            | Primitive::AddedMassPerLength
            | Primitive::AddedMassPerArea
            | Primitive::TipMass => {}
        }
    }
    e
}

/// True when [`boundary`] gives the same effects for every planform: none of `applied` is a clamp
/// compliance per width (the one boundary primitive that reads the planform).
pub fn boundary_is_uniform<'x>(applied: impl IntoIterator<Item = &'x Applied>) -> bool {
    applied
        .into_iter()
        .all(|x| x.primitive != Primitive::ClampCompliancePerWidth)
}

/// Predict an actuator with the primitives applied on top of `base` (the model's own effects; the
/// original model for `Effects::default()`). Material primitives change the stack's inputs; boundary and
/// field primitives add to the corresponding effect of `base`.
pub fn compose(
    applied: &[Applied],
    base: &Effects,
    a: &Actuator,
) -> Result<Performance, ModelError> {
    let s = stack(applied, base, a)?;
    boundary(applied, &s.effects, &a.planform).predict(&s.actuator(a))
}

/// Mass by layer kind with the primitives applied on top of `base`.
pub fn mass(
    applied: &[Applied],
    base: &Effects,
    a: &Actuator,
) -> Result<MassBreakdown, ModelError> {
    // Nothing applied: the base effects' mass, without copying the materials into a stack (a
    // calibration asks for the mass of every actuator at every step of every fit).
    if applied.is_empty() {
        return Ok(base.mass(a));
    }
    // The mass reads the plates' and plies' densities and thicknesses alone: where no primitive scales
    // them, the stacked effects weigh the actuator's own materials, which are not copied.
    let weighed_as_built = applied.iter().all(|x| {
        !matches!(
            x.primitive,
            Primitive::Scale {
                target: Target::Pzt | Target::Passive,
                property: Property::Density | Property::Thickness,
            }
        )
    });
    if weighed_as_built {
        let mut effects = *base;
        for x in applied {
            stack_effects(&mut effects, x)?;
        }
        return Ok(masses(applied, &effects).mass(a));
    }
    let s = stack(applied, base, a)?;
    Ok(s.effects.mass(&s.actuator(a)))
}

/// The seven library effects as compositions of primitives (names as in [`crate::effects::EFFECT_NAMES`]).
pub fn library_composition(name: &str) -> Option<Vec<Link>> {
    let id = |primitive| Link {
        primitive,
        map: Map::Identity,
    };
    let passive = |property, map| Link {
        primitive: Primitive::Scale {
            target: Target::Passive,
            property,
        },
        map,
    };
    Some(match name {
        "d31-scale" => vec![id(Primitive::Scale {
            target: Target::Pzt,
            property: Property::D31,
        })],
        "field-dependent-d31" => vec![id(Primitive::FieldDependentD31)],
        "dead-length" => vec![id(Primitive::ElectrodeMargin)],
        "bond-layer" => vec![id(Primitive::InsertedLayer)],
        "compliant-extension" => vec![id(Primitive::CompliantExtension)],
        "clamp-compliance" => vec![id(Primitive::ClampCompliance)],
        // Resin-rich plies: the same fibre over s times the thickness (moduli / s), the excess resin.
        "ply-thickness" => vec![
            passive(Property::Thickness, Map::Identity),
            passive(Property::E1, Map::Reciprocal),
            passive(Property::E2, Map::Reciprocal),
            passive(Property::G12, Map::Reciprocal),
            passive(Property::Density, Map::ResinDensity),
        ],
        _ => return None,
    })
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::effects::EFFECT_NAMES;
    use crate::{Drive, DriveMode, Planform};

    /// A thesis-like actuator (also the model module's test fixture).
    pub(crate) fn with<R>(f: impl FnOnce(&Actuator) -> R) -> R {
        let pzt = Material::builtin("PZT-5H").unwrap();
        let cf = Material::builtin("CF-thesis").unwrap();
        let layup = [0.0, 0.0, 90.0, 0.0, 0.0];
        let a = Actuator {
            pzt: &pzt,
            pzt_thickness: 191e-6,
            ply: &cf,
            ply_thickness: 61.8e-6,
            layup_deg: &layup,
            planform: Planform::new(40e-3, 0.6, 8e-3, 1.4, 2e-3).unwrap(),
            drive: Drive::new(DriveMode::Parallel, 600e3),
        };
        f(&a)
    }

    /// Each library effect at a non-null value, in SI as `Effects` holds it.
    fn effect(name: &str) -> (f64, Effects) {
        let e = Effects::default();
        match name {
            "d31-scale" => (
                0.7,
                Effects {
                    d31_scale: 0.7,
                    ..e
                },
            ),
            "field-dependent-d31" => (
                0.8e-6,
                Effects {
                    d31_field_coefficient: 0.8e-6,
                    ..e
                },
            ),
            "dead-length" => (
                3e-3,
                Effects {
                    dead_length: 3e-3,
                    ..e
                },
            ),
            "bond-layer" => (
                30e-6,
                Effects {
                    bond_thickness: 30e-6,
                    ..e
                },
            ),
            "compliant-extension" => (
                1.5,
                Effects {
                    extension_flexibility: 1.5,
                    ..e
                },
            ),
            "clamp-compliance" => (
                0.5,
                Effects {
                    clamp_compliance: 0.5,
                    ..e
                },
            ),
            "ply-thickness" => (
                1.3,
                Effects {
                    ply_thickness_scale: 1.3,
                    ..e
                },
            ),
            _ => unreachable!(),
        }
    }

    #[test]
    fn every_library_effect_is_its_composition_of_primitives() {
        with(|a| {
            for name in EFFECT_NAMES {
                let (p, effects) = effect(name);
                let want = effects.predict(a).unwrap();
                let links = library_composition(name).unwrap();
                let got = compose(&at(&links, p, a.ply), &Effects::default(), a).unwrap();
                for (x, y) in [
                    (got.free_deflection, want.free_deflection),
                    (got.blocked_force, want.blocked_force),
                    (got.mass, want.mass),
                ] {
                    assert!(((x - y) / y).abs() < 1e-12, "{name}: {x} vs {y}");
                }
                // At the null value the composition is the original model.
                let null = compose(
                    &at(&links, links[0].primitive.null(), a.ply),
                    &Effects::default(),
                    a,
                )
                .unwrap();
                let orig = Effects::default().predict(a).unwrap();
                assert!(
                    ((null.blocked_force - orig.blocked_force) / orig.blocked_force).abs() < 1e-12
                );
            }
        });
    }

    /// A scale on the bond layer acts on the bond the model has: its thickness as an inserted layer of
    /// the scaled thickness, its modulus as a laminate built by hand with the stiffer isotropic bond
    /// (`Laminate::bimorph`, independent of the primitive code); a property the bond lacks is refused.
    #[test]
    fn bond_scales_act_on_the_models_bond_layer() {
        use crate::laminate::Laminate;
        use crate::section::Section;
        with(|a| {
            let bonded = Effects {
                bond_thickness: 20e-6,
                ..Effects::default()
            };
            let bond = |property, value| Applied {
                primitive: Primitive::Scale {
                    target: Target::Bond,
                    property,
                },
                value,
            };
            let thicker = compose(&[bond(Property::Thickness, 1.5)], &bonded, a).unwrap();
            let want = Effects {
                bond_thickness: 30e-6,
                ..Effects::default()
            }
            .predict(a)
            .unwrap();
            for (x, y) in [
                (thicker.free_deflection, want.free_deflection),
                (thicker.blocked_force, want.blocked_force),
                (thicker.mass, want.mass),
            ] {
                assert!(((x - y) / y).abs() < 1e-12, "{x} vs {y}");
            }
            // A stiffer bond: the free curvature of the hand-built stack.
            let stiff = compose(&[bond(Property::E1, 2.0)], &bonded, a).unwrap();
            let glue = Material::builtin(crate::effects::BOND_MATERIAL).unwrap();
            let e = 2.0 * glue.e1;
            let glue = Material {
                e1: e,
                e2: e,
                g12: e / (2.0 * (1.0 + glue.nu12)),
                ..glue
            };
            let lam = Laminate::bimorph(
                a.pzt,
                a.pzt_thickness,
                a.ply,
                a.ply_thickness,
                a.layup_deg,
                Some((&glue, 20e-6)),
            )
            .unwrap();
            let plain = bonded.predict(a).unwrap();
            let section = Section::new(&lam, a.drive).unwrap();
            let plain_section = Section::new(&bonded.laminate(a).unwrap(), a.drive).unwrap();
            let ratio = section.free_curvature / plain_section.free_curvature;
            assert!((ratio - 1.0).abs() > 1e-4, "the bond modulus must matter");
            assert!(
                (stiff.free_deflection / plain.free_deflection - ratio).abs() < 1e-12,
                "{} vs {ratio}",
                stiff.free_deflection / plain.free_deflection
            );
            assert_eq!(stiff.mass, plain.mass);
            // Without a bond layer the bond's modulus changes nothing.
            let none = compose(&[bond(Property::E1, 2.0)], &Effects::default(), a).unwrap();
            assert_eq!(
                none.blocked_force,
                Effects::default().predict(a).unwrap().blocked_force
            );
            assert!(compose(&[bond(Property::D31, 0.5)], &bonded, a).is_err());
            assert!(!Primitive::Scale {
                target: Target::Bond,
                property: Property::G12
            }
            .is_defined());
        });
    }

    /// The rigid root, the edge margins and the inactive surface layer through [`compose`]: what each
    /// moves by its physics (docs/calibration.md §2; the exact values are held in effects.rs' tests).
    #[test]
    fn root_edge_and_surface_primitives_move_what_their_physics_says() {
        with(|a| {
            let one = |primitive, value| {
                compose(&[Applied { primitive, value }], &Effects::default(), a).unwrap()
            };
            let rel = |x: f64, y: f64| ((x - y) / y).abs();
            let orig = Effects::default().predict(a).unwrap();
            // A held root deflects as an undriven root of the same length, but the beam is stiffer: the
            // held part no longer bends.
            let dead = Effects {
                dead_length: 2e-3,
                ..Effects::default()
            }
            .predict(a)
            .unwrap();
            let root = one(Primitive::RigidRoot, 2e-3);
            assert!(rel(root.free_deflection, dead.free_deflection) < 1e-12);
            assert!(root.stiffness > dead.stiffness * 1.01);
            assert_eq!(root.mass, orig.mass);
            // Edge margins: less actuation, the same stiffness and mass.
            let edge = one(Primitive::EdgeMargin, 0.3e-3);
            assert!(edge.free_deflection < 0.95 * orig.free_deflection);
            assert!(rel(edge.stiffness, orig.stiffness) < 1e-12);
            // An inactive surface layer: less actuation, the same stiffness (same elastic properties) and
            // mass (same density); it changes the stack.
            let surface = one(Primitive::InactiveSurfaceLayer, 15e-6);
            assert!(surface.free_deflection < 0.95 * orig.free_deflection);
            assert!(rel(surface.stiffness, orig.stiffness) < 1e-9);
            assert!(rel(surface.mass, orig.mass) < 1e-12);
            assert!(Primitive::InactiveSurfaceLayer.changes_stack());
            assert!(
                !Primitive::RigidRoot.changes_stack() && !Primitive::EdgeMargin.changes_stack()
            );
            for p in [
                Primitive::RigidRoot,
                Primitive::EdgeMargin,
                Primitive::InactiveSurfaceLayer,
            ] {
                assert!(!p.changes_mass() && p.is_defined() && p.null() == 0.0);
                assert!(p.allows(0.0) && !p.allows(-1e-6));
            }
            // The layer acts on the plate the stack primitives before it leave: on a PZT thinned to
            // 9.5 µm, 15 µm is refused.
            let thinned = compose(
                &[
                    Applied {
                        primitive: Primitive::Scale {
                            target: Target::Pzt,
                            property: Property::Thickness,
                        },
                        value: 0.05,
                    },
                    Applied {
                        primitive: Primitive::InactiveSurfaceLayer,
                        value: 15e-6,
                    },
                ],
                &Effects::default(),
                a,
            );
            assert!(thinned.is_err());
        });
    }

    /// A d31 power of the plate thickness (docs/calibration.md §2): δ and F_b times `(t_p / t_ref)^a`
    /// exactly (the CLT free curvature is linear in d31), the stiffness and mass unchanged, nothing at
    /// the reference plate, and the designed plate is the one that counts.
    #[test]
    fn a_d31_thickness_power_scales_actuation_by_the_plate_ratio() {
        with(|a| {
            // A thin plate, off the reference.
            let a = &Actuator {
                pzt_thickness: 127e-6,
                ..*a
            };
            let rel = |x: f64, y: f64| ((x - y) / y).abs();
            let orig = Effects::default().predict(a).unwrap();
            for exponent in [-0.4, 0.25] {
                let power = Applied {
                    primitive: Primitive::D31ThicknessPower,
                    value: exponent,
                };
                let p = compose(&[power], &Effects::default(), a).unwrap();
                let want = (a.pzt_thickness / D31_REFERENCE_THICKNESS).powf(exponent);
                assert!(
                    (want - 1.0).abs() > 0.01,
                    "the test plate is off the reference"
                );
                assert!(rel(p.free_deflection / orig.free_deflection, want) < 1e-12);
                assert!(rel(p.blocked_force / orig.blocked_force, want) < 1e-12);
                assert!(rel(p.stiffness, orig.stiffness) < 1e-12);
                assert_eq!(p.mass, orig.mass);
                let at_reference = Actuator {
                    pzt_thickness: D31_REFERENCE_THICKNESS,
                    ..*a
                };
                let plain = Effects::default().predict(&at_reference).unwrap();
                let same = compose(&[power], &Effects::default(), &at_reference).unwrap();
                assert!(rel(same.free_deflection, plain.free_deflection) < 1e-12);
                // A thickness scale before it changes the stack, not the trend's plate.
                let thick = Applied {
                    primitive: Primitive::Scale {
                        target: Target::Pzt,
                        property: Property::Thickness,
                    },
                    value: 1.5,
                };
                let scaled = compose(&[thick], &Effects::default(), a).unwrap();
                let both = compose(&[thick, power], &Effects::default(), a).unwrap();
                assert!(rel(both.free_deflection / scaled.free_deflection, want) < 1e-12);
            }
            let p = Primitive::D31ThicknessPower;
            assert!(p.changes_stack() && !p.changes_mass() && !p.is_added_mass());
            assert!(p.null() == 0.0 && p.allows(-0.5) && p.allows(0.5) && !p.allows(f64::NAN));
        });
    }

    /// The added masses move the mass alone, by `m_a`, `2 λ P_pzt` and `2 μ A_pzt` (the trapezoid's
    /// perimeter worked by hand for this planform: l_p = 25 mm, w_nom = 5.714 mm, w_0 = 8 mm,
    /// w_tip = 3.429 mm).
    #[test]
    fn added_masses_change_the_mass_alone() {
        with(|a| {
            let orig = Effects::default().predict(a).unwrap();
            let l_p: f64 = 40e-3 / 1.6;
            let w_nom = 8e-3 / 1.4;
            let w_tip: f64 = (2.0 - 1.4) * w_nom;
            let perimeter =
                8e-3 + w_tip + 2.0 * (l_p * l_p + (0.5 * (8e-3 - w_tip)).powi(2)).sqrt();
            assert!((a.planform.piezo_perimeter() - perimeter).abs() < 1e-15);
            for (primitive, value, want) in [
                (Primitive::AddedMass, 2e-6, 2e-6),
                (Primitive::AddedMassPerLength, 1e-5, 2.0 * 1e-5 * perimeter),
                (Primitive::AddedMassPerArea, 0.02, 2.0 * 0.02 * l_p * w_nom),
            ] {
                let applied = [Applied { primitive, value }];
                let p = compose(&applied, &Effects::default(), a).unwrap();
                assert!(
                    ((p.mass - orig.mass) - want).abs() < 1e-12 * orig.mass,
                    "{primitive:?}"
                );
                assert_eq!(p.free_deflection, orig.free_deflection);
                assert_eq!(p.blocked_force, orig.blocked_force);
                let m = mass(&applied, &Effects::default(), a).unwrap();
                assert!((m.total() - p.mass).abs() < 1e-15 && (m.added - want).abs() < 1e-18);
                assert!(primitive.changes_mass() && primitive.is_added_mass());
                assert!(!primitive.changes_stack() && primitive.null() == 0.0);
            }
        });
    }

    #[test]
    fn new_primitives_move_what_their_physics_says() {
        with(|a| {
            let orig = Effects::default().predict(a).unwrap();
            // A clamp compliance per width c_w acts as c_θ = c_w / w_0.
            let per_width = compose(
                &[Applied {
                    primitive: Primitive::ClampCompliancePerWidth,
                    value: 0.5 * 8e-3,
                }],
                &Effects::default(),
                a,
            )
            .unwrap();
            let constant = Effects {
                clamp_compliance: 0.5,
                ..Effects::default()
            }
            .predict(a)
            .unwrap();
            assert!(
                ((per_width.blocked_force - constant.blocked_force) / constant.blocked_force).abs()
                    < 1e-12
            );
            // Softer passive fibres (E1 of the plies x 0.6): a more compliant beam (lower stiffness) and a
            // larger free curvature, as CLT gives for a softer core; mass unchanged.
            let soft = compose(
                &[Applied {
                    primitive: Primitive::Scale {
                        target: Target::Passive,
                        property: Property::E1,
                    },
                    value: 0.6,
                }],
                &Effects::default(),
                a,
            )
            .unwrap();
            assert!(soft.stiffness < orig.stiffness);
            assert!(soft.free_deflection > orig.free_deflection);
            assert_eq!(soft.mass, orig.mass);
            // A denser PZT changes the mass only.
            let dense = compose(
                &[Applied {
                    primitive: Primitive::Scale {
                        target: Target::Pzt,
                        property: Property::Density,
                    },
                    value: 1.1,
                }],
                &Effects::default(),
                a,
            )
            .unwrap();
            assert!(dense.mass > orig.mass);
            assert_eq!(dense.free_deflection, orig.free_deflection);
        });
    }

    /// Every primitive at a value away from its null, for the tests that go through all of them (a
    /// new variant fails to compile here until it is given one).
    fn every_primitive() -> Vec<Applied> {
        let sample = |primitive: Primitive| Applied {
            primitive,
            value: match primitive {
                Primitive::Scale { .. } => 1.1,
                Primitive::InsertedLayer => 20e-6,
                Primitive::FieldDependentD31 => 0.8e-6,
                Primitive::ElectrodeMargin | Primitive::RigidRoot => 2e-3,
                Primitive::ClampCompliance => 0.5,
                Primitive::ClampCompliancePerWidth => 0.5 * 8e-3,
                Primitive::CompliantExtension => 2.0,
                Primitive::EdgeMargin => 0.3e-3,
                Primitive::InactiveSurfaceLayer => 10e-6,
                Primitive::D31ThicknessPower => -0.8,
                Primitive::AddedMass => 5e-6,
                Primitive::AddedMassPerLength => 1e-4,
                Primitive::AddedMassPerArea => 1e-3,
                Primitive::TipMass => 2e-6,
            },
        };
        let properties = [
            Property::E1,
            Property::E2,
            Property::G12,
            Property::Nu12,
            Property::D31,
            Property::Permittivity,
            Property::Density,
            Property::Thickness,
        ];
        let mut all: Vec<Primitive> = [Target::Pzt, Target::Passive, Target::Bond]
            .into_iter()
            .flat_map(|target| properties.map(|property| Primitive::Scale { target, property }))
            .filter(|p| p.is_defined())
            .collect();
        all.extend([
            Primitive::InsertedLayer,
            Primitive::FieldDependentD31,
            Primitive::ElectrodeMargin,
            Primitive::ClampCompliance,
            Primitive::ClampCompliancePerWidth,
            Primitive::CompliantExtension,
            Primitive::RigidRoot,
            Primitive::EdgeMargin,
            Primitive::InactiveSurfaceLayer,
            Primitive::D31ThicknessPower,
            Primitive::AddedMass,
            Primitive::AddedMassPerLength,
            Primitive::AddedMassPerArea,
            Primitive::TipMass,
        ]);
        all.into_iter().map(sample).collect()
    }

    /// The field enters δ and F_b only through the piezoelectric strain `d31 E` (CLT, thesis eq. 2.20:
    /// the free curvature is linear in the layer fields): with each primitive flagged linear, twice the
    /// field gives exactly twice δ and F_b, the stack solved at each field (parallel and series drive,
    /// a bond layer under the bond scales); the field-dependent d31 gives `2 (1 + 2βE) / (1 + βE)`.
    /// And the factoring a calibration evaluates per actuator: `δ = P a` and `F_b = P a / c`
    /// ([`Effects::deflection_arm`], [`Effects::tip_compliance`]), `P` the basis' curvature times
    /// `|η (1 + β E)|`.
    #[test]
    fn every_primitive_but_the_field_dependent_d31_is_linear_in_the_field() {
        let bond = Effects {
            bond_thickness: 20e-6,
            ..Effects::default()
        };
        for mode in [DriveMode::Parallel, DriveMode::Series] {
            with(|a| {
                for x in every_primitive() {
                    let model = crate::EffectModel {
                        effects: bond,
                        primitives: vec![x],
                    };
                    let at = |field: f64| Actuator {
                        drive: Drive::new(mode, field),
                        ..*a
                    };
                    let (e1, e2) = (300e3, 600e3);
                    let (p1, p2) = (model.predict(&at(e1)), model.predict(&at(e2)));
                    let (p1, p2) = (p1.unwrap(), p2.unwrap());
                    let beta = if x.primitive.linear_in_field() {
                        0.0
                    } else {
                        x.value
                    };
                    let want = 2.0 * (1.0 + beta * e2) / (1.0 + beta * e1);
                    for (y1, y2) in [
                        (p1.free_deflection, p2.free_deflection),
                        (p1.blocked_force, p2.blocked_force),
                    ] {
                        assert!(
                            (y2 / y1 / want - 1.0).abs() < 1e-12,
                            "{x:?} {mode:?}: {}",
                            y2 / y1
                        );
                    }
                    assert_eq!(x.primitive.linear_in_field(), beta == 0.0);
                    assert_eq!(model.linear_in_field(), beta == 0.0);
                    // The factoring, on the basis at the higher field.
                    let b = model.basis(&at(e2)).unwrap();
                    let e = model.boundary_effects(&b.planform);
                    let p = b.free_curvature * e.d31_factor(e2).abs();
                    let delta = p * e.deflection_arm(&b.planform);
                    let force = delta / e.tip_compliance(&b);
                    let (d, f) = model.outputs(&b);
                    assert!((delta / d - 1.0).abs() < 1e-14, "{x:?}");
                    assert!((force / f - 1.0).abs() < 1e-14, "{x:?}");
                }
            });
        }
    }

    /// A primitive that acts on the drive alone ([`Primitive::changes_beam`] false) leaves an actuator's
    /// mass, beam and statics' tip stiffness on a given basis as they were, to the bit, and
    /// [`crate::EffectModel::same_beam`] holds; it tells every other primitive apart, and a drive-alone
    /// value that is not finite (the mass refuses it). The first mode is a function of these three
    /// (docs/physics.md §11.1): a calibration keeps each actuator's `f1` on this.
    #[test]
    fn what_acts_on_the_drive_alone_leaves_the_beam_to_the_bit() {
        let base = Effects {
            bond_thickness: 20e-6,
            clamp_compliance: 0.2,
            extension_flexibility: 0.5,
            ..Effects::default()
        };
        with(|a| {
            let model = crate::EffectModel {
                effects: base,
                primitives: every_primitive(),
            };
            let basis = model.basis(a).unwrap();
            let state = |m: &crate::EffectModel| {
                let mass = m.mass(a).unwrap();
                let tip = m.tip_stiffness(&basis);
                format!("{mass:?} {:?} {tip:?}", m.beam(&basis, &mass))
            };
            let before = state(&model);
            for (i, x) in model.primitives.iter().enumerate() {
                let mut moved = model.clone();
                moved.primitives[i].value *= 1.5;
                let drive_alone = !x.primitive.changes_beam();
                assert_eq!(moved.same_beam(&model), drive_alone, "{x:?}");
                // The digest agrees where the beams do, and here tells the others apart.
                let same_digest = moved.beam_digest() == model.beam_digest();
                assert_eq!(same_digest, drive_alone, "{x:?}");
                if drive_alone {
                    assert_eq!(state(&moved), before, "{x:?}");
                    moved.primitives[i].value = f64::NAN;
                    assert!(!moved.same_beam(&model) && moved.mass(a).is_err(), "{x:?}");
                }
            }
            type Move = fn(&mut Effects);
            let effects: [(&str, Move, bool); 16] = [
                ("d31_scale", |e| e.d31_scale = 0.8, true),
                ("d31_field", |e| e.d31_field_coefficient = 1e-7, true),
                ("dead_length", |e| e.dead_length = 1e-3, true),
                ("edge_margin", |e| e.edge_margin = 1e-4, true),
                ("inactive_surface", |e| e.inactive_surface = 5e-6, true),
                ("bond_thickness", |e| e.bond_thickness = 30e-6, false),
                ("extension", |e| e.extension_flexibility = 0.7, false),
                ("clamp", |e| e.clamp_compliance = 0.3, false),
                ("ply", |e| e.ply_thickness_scale = 1.2, false),
                ("stiffness", |e| e.stiffness_scale = 0.9, false),
                ("bond_scale", |e| e.bond_scale.density = 1.1, false),
                ("rigid_root", |e| e.rigid_root = 1e-3, false),
                ("added_mass", |e| e.added_mass = 1e-6, false),
                ("per_length", |e| e.added_mass_per_length = 1e-5, false),
                ("per_area", |e| e.added_mass_per_area = 1e-4, false),
                ("tip_mass", |e| e.tip_mass = 1e-6, false),
            ];
            for (name, set, drive_alone) in effects {
                let mut moved = model.clone();
                set(&mut moved.effects);
                assert_eq!(moved.same_beam(&model), drive_alone, "{name}");
                let same_digest = moved.beam_digest() == model.beam_digest();
                assert_eq!(same_digest, drive_alone, "{name}");
                if drive_alone {
                    assert_eq!(state(&moved), before, "{name}");
                }
            }
        });
    }

    /// The mass of a stack whose materials keep their densities and thicknesses is weighed without
    /// copying them: the same bits as the mass of the whole stack, for each primitive alone and for all
    /// of them.
    #[test]
    fn the_mass_of_a_stack_is_that_of_its_materials_to_the_bit() {
        let base = Effects {
            ply_thickness_scale: 1.2,
            bond_thickness: 20e-6,
            ..Effects::default()
        };
        with(|a| {
            let all = every_primitive();
            for applied in all.iter().map(std::slice::from_ref).chain([&all[..]]) {
                let s = stack(applied, &base, a).unwrap();
                let whole = s.effects.mass(&s.actuator(a));
                let weighed = mass(applied, &base, a).unwrap();
                assert_eq!(format!("{weighed:?}"), format!("{whole:?}"), "{applied:?}");
            }
        });
    }

    /// `boundary_is_uniform` is what a calibration relies on to add the boundary primitives once per
    /// evaluation rather than once per actuator: it holds exactly when two planforms of different
    /// widths, lengths and tapers get the same effects.
    #[test]
    fn only_a_clamp_compliance_per_width_makes_the_boundary_depend_on_the_planform() {
        let narrow = Planform::new(40e-3, 0.6, 8e-3, 1.4, 2e-3).unwrap();
        let wide = Planform::new(25e-3, 0.0, 12e-3, 0.7, 0.0).unwrap();
        for x in every_primitive() {
            let same = boundary([&x], &Effects::default(), &narrow)
                == boundary([&x], &Effects::default(), &wide);
            assert_eq!(boundary_is_uniform([&x]), same, "{x:?}");
        }
    }
}
