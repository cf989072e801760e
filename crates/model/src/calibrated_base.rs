//! The base model a calibrated model's effects sit on (`base` in `calibrated-model.toml`): the original
//! lamination theory, or the nonlinear ceramic of Jafferis, Smith & Wood 2015 (docs/physics.md §18;
//! docs/calibration.md, "The model file").
//!
//! On the nonlinear base the effects must act on the stack the nonlinear solver takes, a laminate: the
//! ply-thickness and bond-layer effects change the layers and are solved through exactly as the
//! original's are. Every other library effect acts on the linear section (a d31 scale or slope on the
//! linear coefficient the ceramic replaces, a length or a compliance added to the linear beam's tip
//! compliance, a stiffness scale on it) and the declared primitives are composed on the linear basis;
//! those are refused on the nonlinear base rather than approximated.

use crate::effects::Effects;
use crate::error::ModelError;
use serde::{Deserialize, Serialize};

/// The base model of a calibrated model.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Base {
    /// Classical lamination theory with the tapered-beam compliance, the effects' own physics.
    #[default]
    Original,
    /// Lamination theory with the nonlinear ceramic ([`crate::nonlinear`]).
    Nonlinear,
}

/// The values `base` takes, as a file writes them.
pub const BASE_NAMES: &str = "\"original\" or \"nonlinear\"";

/// The library effects the nonlinear base takes, as the file names them.
pub const NONLINEAR_BASE_EFFECTS: &str = "ply_thickness_scale and bond_thickness_m";

impl Base {
    /// The name in the file.
    pub fn name(self) -> &'static str {
        match self {
            Base::Original => "original",
            Base::Nonlinear => "nonlinear",
        }
    }

    /// The base of a file's `base` value, if it is one.
    pub fn parse(text: &str) -> Option<Base> {
        [Base::Original, Base::Nonlinear]
            .into_iter()
            .find(|b| b.name() == text)
    }

    /// True for the original base (the file leaves `base` out).
    pub fn is_original(&self) -> bool {
        *self == Base::Original
    }
}

/// The first library effect of `effects` that is on but acts on the linear section, as
/// `(file key, value)`: what the nonlinear base cannot take.
pub fn linear_only_effect(effects: &Effects) -> Option<(&'static str, f64)> {
    let null = Effects::default();
    [
        ("d31_scale", effects.d31_scale, null.d31_scale),
        (
            "d31_field_coefficient_m_per_V",
            effects.d31_field_coefficient,
            null.d31_field_coefficient,
        ),
        ("dead_length_m", effects.dead_length, null.dead_length),
        (
            "extension_flexibility",
            effects.extension_flexibility,
            null.extension_flexibility,
        ),
        (
            "clamp_compliance_rad_per_N_m",
            effects.clamp_compliance,
            null.clamp_compliance,
        ),
        (
            "stiffness_scale",
            effects.stiffness_scale,
            null.stiffness_scale,
        ),
    ]
    .into_iter()
    .find(|&(_, value, off)| value != off)
    .map(|(key, value, _)| (key, value))
}

/// Refuse effects the nonlinear base cannot take: a library effect on the linear section
/// ([`linear_only_effect`]) or any declared effect (`declared`, their primitives compose on the linear
/// basis).
pub fn check_nonlinear(effects: &Effects, declared: bool) -> Result<(), ModelError> {
    if linear_only_effect(effects).is_some() || declared {
        return Err(ModelError::NotCovered {
            name: "base",
            value: "nonlinear",
            allowed: "the nonlinear base takes the effects ply_thickness_scale and bond_thickness_m only, no declared effect (the others act on the linear section)",
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_nonlinear_base_takes_the_stack_effects_and_refuses_the_others() {
        let on = |effects: Effects, declared| check_nonlinear(&effects, declared).is_ok();
        assert!(on(Effects::default(), false));
        assert!(on(
            Effects {
                ply_thickness_scale: 1.3,
                bond_thickness: 20e-6,
                ..Effects::default()
            },
            false
        ));
        assert!(!on(Effects::default(), true), "a declared effect");
        for (effects, key) in [
            (
                Effects {
                    d31_scale: 0.9,
                    ..Effects::default()
                },
                "d31_scale",
            ),
            (
                Effects {
                    d31_field_coefficient: 1e-7,
                    ..Effects::default()
                },
                "d31_field_coefficient_m_per_V",
            ),
            (
                Effects {
                    dead_length: 1e-3,
                    ..Effects::default()
                },
                "dead_length_m",
            ),
            (
                Effects {
                    extension_flexibility: 0.5,
                    ..Effects::default()
                },
                "extension_flexibility",
            ),
            (
                Effects {
                    clamp_compliance: 0.1,
                    ..Effects::default()
                },
                "clamp_compliance_rad_per_N_m",
            ),
            (
                Effects {
                    stiffness_scale: 0.8,
                    ..Effects::default()
                },
                "stiffness_scale",
            ),
        ] {
            assert_eq!(linear_only_effect(&effects).map(|(k, _)| k), Some(key));
            assert!(!on(effects, false), "{key}");
        }
    }

    #[test]
    fn a_base_parses_from_its_name_only() {
        for base in [Base::Original, Base::Nonlinear] {
            assert_eq!(Base::parse(base.name()), Some(base));
        }
        assert_eq!(Base::parse("Nonlinear"), None);
        assert_eq!(Base::default(), Base::Original);
    }
}
