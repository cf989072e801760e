//! The primitives discovery tries (docs/calibration.md §3, "Discovery"): every primitive of the model
//! crate that changes the deflection or the force and is not already a library effect on its own, with
//! the range and starting points of its parameter (SI, as [`Applied`] takes it).

use actuator_model::effects::EFFECT_NAMES;
use actuator_model::primitives::{library_composition, Map, Primitive, Property, Target};

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
/// the mass only, the permittivity on nothing this model predicts). An exhaustive match: a primitive
/// added to the model crate must be given its range here.
fn range(p: Primitive) -> Option<(f64, f64, &'static [f64])> {
    Some(match p {
        Primitive::Scale {
            property: Property::Density | Property::Permittivity,
            ..
        } => return None,
        Primitive::Scale { .. } => (0.2, 3.0, &[0.7, 1.4]),
        Primitive::InsertedLayer => (0.0, 200e-6, &[5e-6, 40e-6]),
        Primitive::FieldDependentD31 => (-0.4e-6, 3e-6, &[0.0, 1e-6]),
        Primitive::ElectrodeMargin => (0.0, 20e-3, &[0.5e-3, 3e-3]),
        Primitive::ClampCompliance => (0.0, 200.0, &[0.05, 0.5, 5.0]),
        // c_θ = c_w / w_0 with w_0 from 0.5 mm up: the constant clamp's range times a typical width.
        Primitive::ClampCompliancePerWidth => (0.0, 2.0, &[4e-4, 4e-3, 4e-2]),
        Primitive::CompliantExtension => (0.0, 50.0, &[0.1, 1.0, 5.0]),
    })
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

/// Every primitive that could move δ or F_b and that no library effect already is, in a fixed order.
pub fn catalogue() -> Vec<Tried> {
    let mut all: Vec<Primitive> = TARGETS
        .iter()
        .flat_map(|&target| {
            PROPERTIES
                .iter()
                .map(move |&property| Primitive::Scale { target, property })
        })
        .collect();
    all.extend([
        Primitive::InsertedLayer,
        Primitive::FieldDependentD31,
        Primitive::ElectrodeMargin,
        Primitive::ClampCompliance,
        Primitive::ClampCompliancePerWidth,
        Primitive::CompliantExtension,
    ]);
    all.into_iter()
        .filter(|p| library_name(*p).is_none())
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
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_catalogue_leaves_out_library_effects_and_what_cannot_move_deflection_or_force() {
        let names: Vec<String> = catalogue().iter().map(|t| name(t.primitive)).collect();
        // d31 of the PZT is d31-scale, the clamp compliance, margin, bond and extension are library effects.
        for gone in [
            "pzt-d31-scale",
            "clamp-compliance",
            "electrode-margin",
            "inserted-layer",
            "compliant-extension",
            "field-dependent-d31",
            "pzt-density-scale",
            "passive-permittivity-scale",
        ] {
            assert!(!names.iter().any(|n| n == gone), "{gone} in {names:?}");
        }
        for kept in [
            "passive-E1-scale",
            "passive-thickness-scale",
            "pzt-E1-scale",
            "clamp-compliance-per-width",
        ] {
            assert!(names.iter().any(|n| n == kept), "{kept} missing");
        }
        assert_eq!(
            library_name(Primitive::ElectrodeMargin),
            Some("dead-length")
        );
    }
}
