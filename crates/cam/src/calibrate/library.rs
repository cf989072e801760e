//! The candidate effects as the fit sees them: named parameters in report units, their bounds, null values
//! and starting points, and how each sets the SI [`EffectModel`] of the model crate. The library's seven
//! are built in; a lab adds its own compositions of primitives (`calibrate --effects FILE`,
//! [`DeclaredSpec`], read by `crate::calibrate::effects_file`), which the selection treats as it treats the seven.

use actuator_model::primitives::{Applied, Link};
use actuator_model::{DeclaredEffect, EffectModel};
use std::hash::{Hash, Hasher};
use std::sync::Arc;

/// One parameter of a declared effect: the primitives it drives, its bounds and null value (validated
/// by the input layer: `lo < hi`, `lo <= null <= hi`, every primitive value inside its physical range
/// over the bounds, every primitive at its own null value at `null`).
#[derive(Debug, Clone, PartialEq)]
pub struct DeclaredParameter {
    /// Parameter name with its unit, as report.json shows it.
    pub name: String,
    /// Value that switches its primitives off.
    pub null: f64,
    /// Lower bound.
    pub lo: f64,
    /// Upper bound.
    pub hi: f64,
    /// The primitives and how the parameter sets each (identity or reciprocal).
    pub primitives: Vec<Link>,
}

impl DeclaredParameter {
    /// Its primitives at parameter value `p`.
    pub fn applied(&self, p: f64) -> impl Iterator<Item = Applied> + '_ {
        self.primitives.iter().map(move |l| Applied {
            primitive: l.primitive,
            // The input layer admits only the maps that need no ply.
            value: l.map.of(p).unwrap_or(f64::NAN),
        })
    }

    /// Fitted on the measured masses (like `ply-thickness`) when any of its primitives changes the mass.
    pub fn stage(&self) -> Stage {
        if self.primitives.iter().any(|l| l.primitive.changes_mass()) {
            Stage::Mass
        } else {
            Stage::Actuation
        }
    }
}

/// An effect a lab declared: a composition of primitives driven by one or more parameters, each with its
/// own bounds and null value. Each parameter is fitted on the data that identify it (`Stage`): the
/// parameters of one effect on the same stage are fitted together, as one candidate.
#[derive(Debug, Clone, PartialEq)]
pub struct DeclaredSpec {
    /// Name (not a library effect's name).
    pub name: String,
    /// Its parameters, in the declared order.
    pub parameters: Vec<DeclaredParameter>,
}

/// A declared effect's parameter as the selection holds it: one id per parameter like the library's
/// effects, so a candidate's effect list stays a list of ids with one parameter each (an effect with
/// two parameters is two ids under one name). Cloning it shares the declaration; two ids are equal when
/// they are the same parameter of equal declarations, wherever each was read (the same declaration read
/// twice gives equal ids).
#[derive(Debug, Clone)]
pub struct Declared(Arc<SharedParameter>);

/// One parameter of a declaration the parameters' ids share, with its starting points.
#[derive(Debug)]
struct SharedParameter {
    spec: Arc<DeclaredSpec>,
    /// Which of its parameters.
    k: usize,
    /// Starting points of the multistart search.
    starts: Vec<f64>,
}

impl Declared {
    /// The ids of a declared effect's parameters, in the declared order.
    pub fn all(spec: DeclaredSpec) -> Vec<Declared> {
        let spec = Arc::new(spec);
        (0..spec.parameters.len())
            .map(|k| {
                let p = &spec.parameters[k];
                // Starts: the null value and the midpoints towards each bound.
                let mut starts = vec![p.null];
                for x in [0.5 * (p.lo + p.null), 0.5 * (p.null + p.hi)] {
                    if !starts.contains(&x) {
                        starts.push(x);
                    }
                }
                Declared(Arc::new(SharedParameter {
                    spec: Arc::clone(&spec),
                    k,
                    starts,
                }))
            })
            .collect()
    }

    /// The declaration this parameter belongs to.
    pub fn spec(&self) -> &DeclaredSpec {
        &self.0.spec
    }

    /// The parameter.
    pub fn parameter(&self) -> &DeclaredParameter {
        &self.0.spec.parameters[self.0.k]
    }

    /// As the calibrated model records it, at value `value`: one entry per parameter, under the
    /// effect's name.
    pub fn record(&self, value: f64) -> DeclaredEffect {
        let p = self.parameter();
        DeclaredEffect {
            name: self.0.spec.name.clone(),
            parameter: p.name.clone(),
            value,
            null: p.null,
            primitives: p.primitives.clone(),
        }
    }
}

impl PartialEq for Declared {
    fn eq(&self, other: &Self) -> bool {
        let (a, b) = (&self.0, &other.0);
        Arc::ptr_eq(a, b) || (a.k == b.k && (Arc::ptr_eq(&a.spec, &b.spec) || a.spec == b.spec))
    }
}
// The input layer admits no NaN in a declaration, so equal declarations compare equal.
impl Eq for Declared {}
impl Hash for Declared {
    fn hash<H: Hasher>(&self, state: &mut H) {
        self.0.spec.name.hash(state);
        self.0.k.hash(state);
    }
}

/// The effect names of a list of ids, in order, each once (the parameters of one declared effect share
/// its name).
pub fn effect_names(ids: &[EffectId]) -> Vec<&str> {
    let mut names: Vec<&str> = Vec::new();
    for id in ids {
        if !names.contains(&id.name()) {
            names.push(id.name());
        }
    }
    names
}

/// One library effect (plus the thesis-style stiffness null), or a declared one.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
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
    /// An effect a lab declared.
    Declared(Declared),
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
pub struct ParamSpec<'a> {
    /// Name with unit, as in report.json.
    pub name: &'a str,
    /// Value that switches the effect off.
    pub null: f64,
    /// Lower bound.
    pub lo: f64,
    /// Upper bound.
    pub hi: f64,
    /// Starting points of the multistart search.
    pub starts: &'a [f64],
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

    /// The name used in the reports, calibrated-model.toml and effects.toml.
    pub fn name(&self) -> &str {
        match self {
            EffectId::D31Scale => "d31-scale",
            EffectId::FieldDependentD31 => "field-dependent-d31",
            EffectId::DeadLength => "dead-length",
            EffectId::BondLayer => "bond-layer",
            EffectId::CompliantExtension => "compliant-extension",
            EffectId::ClampCompliance => "clamp-compliance",
            EffectId::PlyThickness => "ply-thickness",
            EffectId::StiffnessScale => "stiffness-scale",
            EffectId::Declared(d) => &d.spec().name,
        }
    }

    /// Look a library effect up by name.
    pub fn from_name(name: &str) -> Option<EffectId> {
        Self::LIBRARY
            .into_iter()
            .chain([EffectId::StiffnessScale])
            .find(|e| e.name() == name)
    }

    /// Data that identify it.
    pub fn stage(&self) -> Stage {
        match self {
            EffectId::BondLayer | EffectId::PlyThickness => Stage::Mass,
            EffectId::Declared(d) => d.parameter().stage(),
            _ => Stage::Actuation,
        }
    }

    /// Its parameter (every library effect has one).
    pub fn param(&self) -> ParamSpec<'_> {
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
            EffectId::Declared(d) => {
                let p = d.parameter();
                ParamSpec {
                    name: &p.name,
                    null: p.null,
                    lo: p.lo,
                    hi: p.hi,
                    starts: &d.0.starts,
                }
            }
        }
    }

    /// Set the effect's SI parameter from its report-unit value (a declared parameter adds its
    /// primitives: apply each id once).
    pub fn apply(&self, model: &mut EffectModel, value: f64) {
        let effects = &mut model.effects;
        match self {
            EffectId::D31Scale => effects.d31_scale = value,
            EffectId::FieldDependentD31 => effects.d31_field_coefficient = value * 1e-6,
            EffectId::DeadLength => effects.dead_length = value * 1e-3,
            EffectId::BondLayer => effects.bond_thickness = value * 1e-6,
            EffectId::CompliantExtension => effects.extension_flexibility = value,
            EffectId::ClampCompliance => effects.clamp_compliance = value,
            EffectId::PlyThickness => effects.ply_thickness_scale = value,
            EffectId::StiffnessScale => effects.stiffness_scale = value,
            EffectId::Declared(d) => model.primitives.extend(d.parameter().applied(value)),
        }
    }

    /// True when the effect keeps δ and F_b proportional to the field at every value of its parameter:
    /// all but a field-dependent d31, as the library's effect or among a declared effect's primitives
    /// ([`actuator_model::primitives::Primitive::linear_in_field`]).
    pub fn linear_in_field(&self) -> bool {
        match self {
            EffectId::FieldDependentD31 => false,
            EffectId::Declared(d) => d
                .parameter()
                .primitives
                .iter()
                .all(|l| l.primitive.linear_in_field()),
            _ => true,
        }
    }

    /// Read a library effect's parameter back in report units (`None` for a declared one, whose
    /// primitives do not name it).
    pub fn value(&self, model: &EffectModel) -> Option<f64> {
        let effects = &model.effects;
        Some(match self {
            EffectId::D31Scale => effects.d31_scale,
            EffectId::FieldDependentD31 => effects.d31_field_coefficient * 1e6,
            EffectId::DeadLength => effects.dead_length * 1e3,
            EffectId::BondLayer => effects.bond_thickness * 1e6,
            EffectId::CompliantExtension => effects.extension_flexibility,
            EffectId::ClampCompliance => effects.clamp_compliance,
            EffectId::PlyThickness => effects.ply_thickness_scale,
            EffectId::StiffnessScale => effects.stiffness_scale,
            EffectId::Declared(_) => return None,
        })
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
            assert_eq!(EffectId::from_name(name), Some(id.clone()));
            let mut e = EffectModel::default();
            id.apply(&mut e, id.param().null);
            assert!(e.effects.is_null() && e.primitives.is_empty());
            id.apply(&mut e, 1.7);
            assert!((id.value(&e).unwrap() - 1.7).abs() < 1e-12);
        }
    }

    fn glue(name: &str, hi: f64) -> DeclaredSpec {
        let parameter = |name: &str| DeclaredParameter {
            name: name.into(),
            null: 0.0,
            lo: 0.0,
            hi,
            primitives: Vec::new(),
        };
        DeclaredSpec {
            name: name.into(),
            parameters: vec![parameter("a_um"), parameter("b_um")],
        }
    }

    #[test]
    fn equal_declarations_read_apart_give_equal_ids() {
        let first = Declared::all(glue("glue", 10.0));
        let again = Declared::all(glue("glue", 10.0));
        assert_eq!(first, again);
        // One id per parameter, each its own.
        assert_ne!(first[0], first[1]);
        assert_eq!(first[1].parameter().name, "b_um");
        // Another bound or another name is another declaration.
        assert_ne!(first, Declared::all(glue("glue", 20.0)));
        assert_ne!(first, Declared::all(glue("paste", 10.0)));
        let id = EffectId::Declared(again[0].clone());
        assert_eq!(id, EffectId::Declared(first[0].clone()));
        assert_eq!((id.name(), id.param().name), ("glue", "a_um"));
        assert_eq!(id.param().starts, [0.0, 5.0]);
    }
}
