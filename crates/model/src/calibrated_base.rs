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

/// True when `effects` turns on a library effect that acts on the linear section: anything but the
/// ply-thickness scale and the bond layer, which change the laminate the nonlinear solver takes.
pub fn acts_on_linear_section(effects: &Effects) -> bool {
    let stack_only = Effects {
        ply_thickness_scale: effects.ply_thickness_scale,
        bond_thickness: effects.bond_thickness,
        ..Effects::default()
    };
    *effects != stack_only
}

/// Refuse effects the nonlinear base cannot take: a library effect on the linear section
/// ([`acts_on_linear_section`]) or any declared effect (`declared`, their primitives compose on the
/// linear basis).
pub fn check_nonlinear(effects: &Effects, declared: bool) -> Result<(), ModelError> {
    if acts_on_linear_section(effects) || declared {
        return Err(ModelError::NotCovered {
            name: "base",
            value: "nonlinear",
            allowed: "the nonlinear base takes the ply-thickness and bond-layer effects only, no declared effect (the others act on the linear section)",
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
        let linear = [
            Effects {
                d31_scale: 0.9,
                ..Effects::default()
            },
            Effects {
                d31_field_coefficient: 1e-7,
                ..Effects::default()
            },
            Effects {
                dead_length: 1e-3,
                ..Effects::default()
            },
            Effects {
                extension_flexibility: 0.5,
                ..Effects::default()
            },
            Effects {
                clamp_compliance: 0.1,
                ..Effects::default()
            },
            Effects {
                stiffness_scale: 0.8,
                ..Effects::default()
            },
        ];
        for effects in linear {
            assert!(acts_on_linear_section(&effects), "{effects:?}");
            assert!(!on(effects, false), "{effects:?}");
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
