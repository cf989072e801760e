//! The primitives discovery tries (docs/calibration.md §3, "Discovery"): every primitive of the model
//! crate that changes the deflection or the force of the stack at hand and is not already fitted on
//! them as a library effect, with the range and starting points of its parameter (SI, as [`Applied`]
//! takes it).
//!
//! The bond layer's primitives depend on the stack. With a bond (the mass stage chose `bond-layer`, or a
//! declared effect inserts one), its thickness is scaled: a bond thicker or thinner in the stack than
//! its mass says (an adhesive lighter or denser than its datasheet). Without one, and without masses to
//! fit (the library's `bond-layer` is fitted on the masses only), a bond is inserted and fitted here on
//! deflection and force. With masses fitted, a bond that moves δ or F_b by the 5 % noise (about 10 µm)
//! adds 0.5 to 1 % to the mass, which the mass stage sees with 30 actuators at 1 % noise, so it is not
//! tried again. The bond's modulus and ν12 are left out: in the
//! perfectly bonded stack of the model the bond is a spacer, and its modulus × 0.2 to × 3 or its ν12 up
//! to the isotropic limit 0.5 move δ and F_b by under 1 % (a unit test below holds this), nearly the same
//! for every design, so η takes it up and no data at the thesis' noise could tell the fit from {η}.

use crate::calibrate::csv::Dataset;
use actuator_model::effects::EFFECT_NAMES;
use actuator_model::primitives::{library_composition, stack, Map, Primitive, Property, Target};
use actuator_model::EffectModel;

/// A primitive's parameter as the fit sees it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tried {
    /// The primitive.
    pub primitive: Primitive,
    /// Lower bound (SI).
    pub lo: f64,
    /// Upper bound (SI).
    pub hi: f64,
    /// Starting points of the multistart search.
    pub starts: &'static [f64],
}

/// What discovery needs to know of the stack it tries primitives on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Stack {
    /// The base model has a bond layer between each PZT and the plies.
    pub bond: bool,
    /// The masses were fitted (the mass stage ran), so a bond would have shown there.
    pub masses_fitted: bool,
    /// Some passive ply is piezoelectric (otherwise a scale on the plies' d31 scales zero).
    pub piezoelectric_plies: bool,
}

impl Stack {
    /// The stack of the data's actuators under `base` (the frozen mass-stage model), with or without
    /// the masses fitted. The bond is the same for every actuator (an effect, not a design variable), so
    /// the first row tells.
    pub fn of(data: &Dataset, base: &EffectModel, masses_fitted: bool) -> Stack {
        let bond = data.rows.first().is_some_and(|r| {
            stack(&base.primitives, &base.effects, &r.actuator())
                .is_ok_and(|s| s.effects.bond_thickness > 0.0)
        });
        Stack {
            bond,
            masses_fitted,
            piezoelectric_plies: data.rows.iter().any(|r| r.ply.is_piezoelectric()),
        }
    }
}

const TARGETS: [Target; 2] = [Target::Pzt, Target::Passive];
const PROPERTIES: [Property; 8] = [
    Property::E1,
    Property::E2,
    Property::G12,
    Property::Nu12,
    Property::D31,
    Property::Permittivity,
    Property::Density,
    Property::Thickness,
];

/// Range and starts of a primitive's parameter, or None when it cannot move δ or F_b (density acts on
/// the mass only, a tip mass on `f1` only, the permittivity on nothing this model predicts). An
/// exhaustive match: a primitive added to the model crate must be given its range here.
fn range(p: Primitive) -> Option<(f64, f64, &'static [f64])> {
    Some(match p {
        Primitive::Scale {
            property: Property::Density | Property::Permittivity,
            ..
        }
        | Primitive::AddedMass
        | Primitive::AddedMassPerLength
        | Primitive::AddedMassPerArea
        | Primitive::TipMass => return None,
        Primitive::Scale { .. } => (0.2, 3.0, &[0.7, 1.4]),
        Primitive::InsertedLayer => (0.0, 200e-6, &[5e-6, 40e-6]),
        Primitive::FieldDependentD31 => (-0.4e-6, 3e-6, &[0.0, 1e-6]),
        Primitive::ElectrodeMargin => (0.0, 20e-3, &[0.5e-3, 3e-3]),
        Primitive::ClampCompliance => (0.0, 200.0, &[0.05, 0.5, 5.0]),
        // c_θ = c_w / w_0 with w_0 from 0.5 mm up: the constant clamp's range times a typical width.
        Primitive::ClampCompliancePerWidth => (0.0, 2.0, &[4e-4, 4e-3, 4e-2]),
        Primitive::CompliantExtension => (0.0, 50.0, &[0.1, 1.0, 5.0]),
        // As the electrode margin (the model clips both at 0.95 l_p).
        Primitive::RigidRoot => (0.0, 20e-3, &[0.5e-3, 3e-3]),
        // Up to 3 mm a side: the model clips 2m at 0.95 of the narrowest width (3 mm wide bases and
        // narrower tips in the design ranges).
        Primitive::EdgeMargin => (0.0, 3e-3, &[0.1e-3, 0.5e-3]),
        // Below the thinnest plate of the design ranges (127 µm); a value at or above an actuator's
        // plate is refused by the model, which the fit treats as no fit there.
        Primitive::InactiveSurfaceLayer => (0.0, 100e-6, &[5e-6, 30e-6]),
        // The selection's thickness form (select/thickness.rs) bounds it the same way: a d31 that
        // changes by up to the plates' ratio over the 127-267 µm plates.
        Primitive::D31ThicknessPower => (-1.0, 1.0, &[-0.2, 0.2]),
    })
}

/// The physical bounds discovery fits a primitive within (SI), for a primitive that moves δ or F_b or
/// one of the mass forms.
pub fn bounds(p: Primitive) -> Option<(f64, f64)> {
    mass_catalogue()
        .into_iter()
        .find(|t| t.primitive == p)
        .map(|t| (t.lo, t.hi))
        .or_else(|| range(p).map(|(lo, hi, _)| (lo, hi)))
}

/// The primitive a library effect is, when it is exactly one primitive at its parameter.
fn library_single(name: &str) -> Option<Primitive> {
    match library_composition(name)?.as_slice() {
        [link] if link.map == Map::Identity => Some(link.primitive),
        _ => None,
    }
}

/// The library effect that is exactly this primitive, if any.
pub fn library_name(p: Primitive) -> Option<&'static str> {
    EFFECT_NAMES
        .into_iter()
        .find(|name| library_single(name) == Some(p))
}

/// Whether the library's fits on deflection and force already cover the primitive: a library effect
/// that is exactly it, except the bond layer, which the library fits on the masses alone.
fn fitted_by_library(p: Primitive) -> bool {
    library_name(p).is_some() && p != Primitive::InsertedLayer
}

/// Every primitive that could move δ or F_b of `stack` and that the library does not already fit on
/// them, in a fixed order.
pub fn catalogue(stack: Stack) -> Vec<Tried> {
    let mut all: Vec<Primitive> = TARGETS
        .iter()
        .flat_map(|&target| {
            PROPERTIES
                .iter()
                .map(move |&property| Primitive::Scale { target, property })
        })
        .filter(|p| {
            stack.piezoelectric_plies
                || *p
                    != Primitive::Scale {
                        target: Target::Passive,
                        property: Property::D31,
                    }
        })
        .collect();
    if stack.bond {
        // The one bond property that moves δ or F_b (the module's comment says why not the others).
        all.push(Primitive::Scale {
            target: Target::Bond,
            property: Property::Thickness,
        });
    } else if !stack.masses_fitted {
        all.push(Primitive::InsertedLayer);
    }
    all.extend([
        Primitive::FieldDependentD31,
        Primitive::ElectrodeMargin,
        Primitive::ClampCompliance,
        Primitive::ClampCompliancePerWidth,
        Primitive::CompliantExtension,
        Primitive::RigidRoot,
        Primitive::EdgeMargin,
        Primitive::InactiveSurfaceLayer,
    ]);
    all.into_iter()
        .filter(|p| !fitted_by_library(*p))
        .filter_map(|primitive| {
            range(primitive).map(|(lo, hi, starts)| Tried {
                primitive,
                lo,
                hi,
                starts,
            })
        })
        .collect()
}

/// Whether discovery fits the primitive on the masses as well as on δ and F_b ([`super::joint`]): a
/// thickness scale of the PZT or of the plies changes the mass with the stack, and an inserted layer
/// carries its own mass. The bond's thickness scale is tried with its mass held: its meaning here is a
/// bond thicker or thinner in the stack than its mass says (module comment).
pub fn mass_counts(p: Primitive) -> bool {
    matches!(
        p,
        Primitive::Scale {
            target: Target::Pzt | Target::Passive,
            property: Property::Thickness,
        } | Primitive::InsertedLayer
    )
}

/// Report name of a primitive, e.g. `passive-E1-scale`, `clamp-compliance-per-width`.
pub fn name(p: Primitive) -> String {
    match p {
        Primitive::Scale { target, property } => {
            let t = match target {
                Target::Pzt => "pzt",
                Target::Passive => "passive",
                Target::Bond => "bond",
            };
            let q = match property {
                Property::E1 => "E1",
                Property::E2 => "E2",
                Property::G12 => "G12",
                Property::Nu12 => "nu12",
                Property::D31 => "d31",
                Property::Permittivity => "permittivity",
                Property::Density => "density",
                Property::Thickness => "thickness",
            };
            format!("{t}-{q}-scale")
        }
        Primitive::InsertedLayer => "inserted-layer".into(),
        Primitive::FieldDependentD31 => "field-dependent-d31".into(),
        Primitive::ElectrodeMargin => "electrode-margin".into(),
        Primitive::ClampCompliance => "clamp-compliance".into(),
        Primitive::ClampCompliancePerWidth => "clamp-compliance-per-width".into(),
        Primitive::CompliantExtension => "compliant-extension".into(),
        Primitive::RigidRoot => "rigid-root".into(),
        Primitive::EdgeMargin => "edge-margin".into(),
        Primitive::InactiveSurfaceLayer => "inactive-surface-layer".into(),
        Primitive::D31ThicknessPower => "d31-thickness-power".into(),
        Primitive::AddedMass => "added-mass".into(),
        Primitive::AddedMassPerLength => "added-mass-per-length".into(),
        Primitive::AddedMassPerArea => "added-mass-per-area".into(),
        Primitive::TipMass => "tip-mass".into(),
    }
}

/// Name of a primitive's parameter with its unit.
pub fn parameter(p: Primitive) -> &'static str {
    match p {
        Primitive::Scale { .. } => "factor",
        Primitive::InsertedLayer => "thickness_m",
        Primitive::FieldDependentD31 => "beta_m_per_V",
        Primitive::ElectrodeMargin => "length_m",
        Primitive::ClampCompliance => "rad_per_N_m",
        Primitive::ClampCompliancePerWidth => "rad_m_per_N_m",
        Primitive::CompliantExtension => "flexibility",
        Primitive::RigidRoot => "held_root_m",
        Primitive::EdgeMargin => "edge_margin_m",
        Primitive::InactiveSurfaceLayer => "inactive_thickness_m",
        Primitive::D31ThicknessPower => "d31_thickness_exponent",
        Primitive::AddedMass => "added_mass_kg",
        Primitive::AddedMassPerLength => "mass_per_length_kg_per_m",
        Primitive::AddedMassPerArea => "mass_per_area_kg_per_m2",
        Primitive::TipMass => "tip_mass_kg",
    }
}

/// The forms a mass residual is ranked by (docs/calibration.md §3, "Discovery"): every primitive that
/// changes the mass and nothing else, with its range (SI). A scale on a layer's density, or a mass no
/// layer carries: per actuator (leads, solder; up to 100 mg), per length of the PZT outline (adhesive
/// fillets; up to 1 mg per mm) or per bonded area (adhesive under the PZT; up to 0.5 kg/m², a 400 µm
/// epoxy film). Each is affine in its parameter, so its fit needs the mass at two values only.
pub fn mass_catalogue() -> Vec<Tried> {
    let density = |target| Tried {
        primitive: Primitive::Scale {
            target,
            property: Property::Density,
        },
        lo: 0.2,
        hi: 3.0,
        starts: &[1.0],
    };
    let added = |primitive, hi| Tried {
        primitive,
        lo: 0.0,
        hi,
        starts: &[0.0],
    };
    vec![
        density(Target::Pzt),
        density(Target::Passive),
        added(Primitive::AddedMass, 1e-4),
        added(Primitive::AddedMassPerLength, 1e-3),
        added(Primitive::AddedMassPerArea, 0.5),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use actuator_model::effects::{drive_at_voltage, Actuator};
    use actuator_model::primitives::{compose, Applied};
    use actuator_model::{DriveMode, Effects, Material, Planform};

    const BARE: Stack = Stack {
        bond: false,
        masses_fitted: false,
        piezoelectric_plies: false,
    };
    const BONDED: Stack = Stack {
        bond: true,
        masses_fitted: true,
        piezoelectric_plies: false,
    };

    fn names(stack: Stack) -> Vec<String> {
        catalogue(stack).iter().map(|t| name(t.primitive)).collect()
    }

    #[test]
    fn the_catalogue_leaves_out_library_effects_and_what_cannot_move_deflection_or_force() {
        for stack in [BARE, BONDED] {
            let names = names(stack);
            // d31 of the PZT is d31-scale, the clamp compliance, margin and extension are library effects
            // fitted on deflection and force; the plies' d31 is zero here.
            for gone in [
                "pzt-d31-scale",
                "clamp-compliance",
                "electrode-margin",
                "compliant-extension",
                "field-dependent-d31",
                "pzt-density-scale",
                "passive-permittivity-scale",
                "passive-d31-scale",
                "bond-E1-scale",
                "bond-nu12-scale",
                "bond-density-scale",
            ] {
                assert!(!names.iter().any(|n| n == gone), "{gone} in {names:?}");
            }
            for kept in [
                "passive-E1-scale",
                "passive-thickness-scale",
                "pzt-E1-scale",
                "clamp-compliance-per-width",
                "rigid-root",
                "edge-margin",
                "inactive-surface-layer",
            ] {
                assert!(names.iter().any(|n| n == kept), "{kept} missing");
            }
        }
        assert_eq!(
            library_name(Primitive::ElectrodeMargin),
            Some("dead-length")
        );
        // A piezoelectric ply's d31 is tried.
        let piezo = names(Stack {
            piezoelectric_plies: true,
            ..BARE
        });
        assert!(piezo.iter().any(|n| n == "passive-d31-scale"), "{piezo:?}");
    }

    /// The bond is scaled when the stack has one, and inserted when it has none and no masses were
    /// fitted (the library's `bond-layer` is fitted on the masses only).
    #[test]
    fn the_bond_is_scaled_when_the_stack_has_one_and_inserted_when_not() {
        let bare = names(BARE);
        assert!(bare.iter().any(|n| n == "inserted-layer"), "{bare:?}");
        assert!(!bare.iter().any(|n| n.starts_with("bond-")), "{bare:?}");
        let weighed = names(Stack {
            masses_fitted: true,
            ..BARE
        });
        assert!(
            !weighed
                .iter()
                .any(|n| n == "inserted-layer" || n.starts_with("bond-")),
            "{weighed:?}"
        );
        let bonded = names(BONDED);
        assert!(!bonded.iter().any(|n| n == "inserted-layer"), "{bonded:?}");
        assert!(
            bonded.iter().any(|n| n == "bond-thickness-scale"),
            "{bonded:?}"
        );
        // Every bond primitive tried is one the model accepts.
        assert!(catalogue(BONDED).iter().all(|t| t.primitive.is_defined()));
    }

    /// Why the bond's modulus and ν12 are not tried: its modulus × 0.2 to × 3 and its ν12 from the
    /// datasheet's 0.35 to the isotropic limit 0.5 move δ and F_b by under 1 % at the corners of the
    /// design ranges (20-50 mm, 127-267 µm PZT, 3-7 plies, a 30 µm bond), where doubling the bond's
    /// thickness moves them by more than 5 %.
    #[test]
    fn the_bonds_modulus_and_poisson_ratio_barely_move_deflection_or_force() {
        let pzt = Material::builtin("PZT-5H").unwrap();
        let cf = Material::builtin("CF-thesis").unwrap();
        let bonded = Effects {
            bond_thickness: 30e-6,
            ..Effects::default()
        };
        let bond = |property, value| Applied {
            primitive: Primitive::Scale {
                target: Target::Bond,
                property,
            },
            value,
        };
        for layup in [
            vec![0.0, 90.0, 0.0],
            vec![0.0, 0.0, 0.0, 90.0, 0.0, 0.0, 0.0],
        ] {
            for t_p in [127e-6, 267e-6] {
                for length in [20e-3, 50e-3] {
                    let a = Actuator {
                        pzt: &pzt,
                        pzt_thickness: t_p,
                        ply: &cf,
                        ply_thickness: 61.8e-6,
                        layup_deg: &layup,
                        planform: Planform::new(length, 0.5, 6e-3, 1.0, 0.0).unwrap(),
                        drive: drive_at_voltage(DriveMode::Parallel, 0.4e6 * t_p, t_p),
                    };
                    let plain = bonded.predict(&a).unwrap();
                    let change = |x: Applied| {
                        let p = compose(&[x], &bonded, &a).unwrap();
                        let d = (p.free_deflection / plain.free_deflection).ln().abs();
                        let f = (p.blocked_force / plain.blocked_force).ln().abs();
                        d.max(f)
                    };
                    for (property, value) in [
                        (Property::E1, 0.2),
                        (Property::E1, 3.0),
                        (Property::Nu12, 0.5 / 0.35),
                    ] {
                        let moved = change(bond(property, value));
                        assert!(moved < 1e-2, "{property:?} x {value}: {moved}");
                    }
                    let thicker = change(bond(Property::Thickness, 2.0));
                    assert!(thicker > 0.05, "thickness: {thicker}");
                }
            }
        }
    }
}
