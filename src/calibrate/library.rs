//! The candidate effects as the fit sees them: named parameters in report units, their bounds, null values
//! and starting points, and how each sets the SI [`Effects`] of the model crate.

use actuator_model::Effects;

/// One library effect (plus the thesis-style stiffness null).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum EffectId {
    /// `d31-scale` η.
    D31Scale,
    /// `field-dependent-d31` β.
    FieldDependentD31,
    /// `dead-length` Δ.
    DeadLength,
    /// `bond-layer` t_b.
    BondLayer,
    /// `compliant-extension` φ.
    CompliantExtension,
    /// `clamp-compliance` c_θ.
    ClampCompliance,
    /// `ply-thickness` s.
    PlyThickness,
    /// Uniform stiffness scale s_k: only in the thesis-style null model.
    StiffnessScale,
}

/// Which data identify an effect.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stage {
    /// Fitted on the measured masses first, then frozen.
    Mass,
    /// Fitted on deflection and force.
    Actuation,
}

/// A fitted parameter in report units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ParamSpec {
    /// Name with unit, as in report.json.
    pub name: &'static str,
    /// Value that switches the effect off.
    pub null: f64,
    /// Lower bound.
    pub lo: f64,
    /// Upper bound.
    pub hi: f64,
    /// Starting points of the multistart search.
    pub starts: &'static [f64],
}

impl EffectId {
    /// The library, in report order.
    pub const LIBRARY: [EffectId; 7] = [
        EffectId::D31Scale,
        EffectId::FieldDependentD31,
        EffectId::DeadLength,
        EffectId::BondLayer,
        EffectId::CompliantExtension,
        EffectId::ClampCompliance,
        EffectId::PlyThickness,
    ];

    /// Issue-6 name.
    pub fn name(self) -> &'static str {
        match self {
            EffectId::D31Scale => "d31-scale",
            EffectId::FieldDependentD31 => "field-dependent-d31",
            EffectId::DeadLength => "dead-length",
            EffectId::BondLayer => "bond-layer",
            EffectId::CompliantExtension => "compliant-extension",
            EffectId::ClampCompliance => "clamp-compliance",
            EffectId::PlyThickness => "ply-thickness",
            EffectId::StiffnessScale => "stiffness-scale",
        }
    }

    /// Look an effect up by name.
    pub fn from_name(name: &str) -> Option<EffectId> {
        Self::LIBRARY
            .into_iter()
            .chain([EffectId::StiffnessScale])
            .find(|e| e.name() == name)
    }

    /// Data that identify it.
    pub fn stage(self) -> Stage {
        match self {
            EffectId::BondLayer | EffectId::PlyThickness => Stage::Mass,
            _ => Stage::Actuation,
        }
    }

    /// Its parameter (every library effect has one).
    pub fn param(self) -> ParamSpec {
        match self {
            EffectId::D31Scale => ParamSpec {
                name: "eta",
                null: 1.0,
                lo: 0.05,
                hi: 3.0,
                starts: &[1.0],
            },
            EffectId::FieldDependentD31 => ParamSpec {
                name: "beta_per_V_per_um",
                null: 0.0,
                lo: -0.4,
                hi: 3.0,
                starts: &[0.0, 1.0],
            },
            EffectId::DeadLength => ParamSpec {
                name: "dead_length_mm",
                null: 0.0,
                lo: 0.0,
                hi: 20.0,
                starts: &[0.5, 3.0],
            },
            EffectId::BondLayer => ParamSpec {
                name: "bond_thickness_um",
                null: 0.0,
                lo: 0.0,
                hi: 200.0,
                starts: &[5.0, 40.0],
            },
            EffectId::CompliantExtension => ParamSpec {
                name: "extension_flexibility",
                null: 0.0,
                lo: 0.0,
                hi: 50.0,
                starts: &[0.1, 1.0, 5.0],
            },
            EffectId::ClampCompliance => ParamSpec {
                name: "clamp_compliance_rad_per_N_m",
                null: 0.0,
                lo: 0.0,
                hi: 200.0,
                starts: &[0.05, 0.5, 5.0],
            },
            EffectId::PlyThickness => ParamSpec {
                name: "ply_thickness_scale",
                null: 1.0,
                lo: 0.5,
                hi: 3.0,
                starts: &[1.0, 1.4],
            },
            EffectId::StiffnessScale => ParamSpec {
                name: "stiffness_scale",
                null: 1.0,
                lo: 0.05,
                hi: 20.0,
                starts: &[1.0, 0.3],
            },
        }
    }

    /// Set the effect's SI parameter from its report-unit value.
    pub fn apply(self, effects: &mut Effects, value: f64) {
        match self {
            EffectId::D31Scale => effects.d31_scale = value,
            EffectId::FieldDependentD31 => effects.d31_field_coefficient = value * 1e-6,
            EffectId::DeadLength => effects.dead_length = value * 1e-3,
            EffectId::BondLayer => effects.bond_thickness = value * 1e-6,
            EffectId::CompliantExtension => effects.extension_flexibility = value,
            EffectId::ClampCompliance => effects.clamp_compliance = value,
            EffectId::PlyThickness => effects.ply_thickness_scale = value,
            EffectId::StiffnessScale => effects.stiffness_scale = value,
        }
    }

    /// Read the effect's parameter back in report units.
    pub fn value(self, effects: &Effects) -> f64 {
        match self {
            EffectId::D31Scale => effects.d31_scale,
            EffectId::FieldDependentD31 => effects.d31_field_coefficient * 1e6,
            EffectId::DeadLength => effects.dead_length * 1e3,
            EffectId::BondLayer => effects.bond_thickness * 1e6,
            EffectId::CompliantExtension => effects.extension_flexibility,
            EffectId::ClampCompliance => effects.clamp_compliance,
            EffectId::PlyThickness => effects.ply_thickness_scale,
            EffectId::StiffnessScale => effects.stiffness_scale,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_match_the_model_crate_and_nulls_give_the_original_model() {
        for (id, name) in EffectId::LIBRARY
            .iter()
            .zip(actuator_model::effects::EFFECT_NAMES)
        {
            assert_eq!(id.name(), name);
            assert_eq!(EffectId::from_name(name), Some(*id));
            let mut e = Effects::default();
            id.apply(&mut e, id.param().null);
            assert!(e.is_null());
            id.apply(&mut e, 1.7);
            assert!((id.value(&e) - 1.7).abs() < 1e-12);
        }
    }
}
