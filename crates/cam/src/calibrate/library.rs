//! The candidate effects as the fit sees them: named parameters in report units, their bounds, null values
//! and starting points, and how each sets the SI [`EffectModel`] of the model crate. The library's seven
//! are built in; a lab adds its own compositions of primitives (`calibrate --effects FILE`,
//! [`DeclaredSpec`], read by `crate::calibrate::effects_file`), which the selection treats as it treats the seven.

use actuator_model::primitives::{Applied, Link};
use actuator_model::{DeclaredEffect, EffectModel};
use std::cmp::Ordering;
use std::hash::{Hash, Hasher};
use std::sync::Mutex;

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
/// own bounds and null value. Each parameter is fitted on the data that identify it ([`Stage`]): the
/// parameters of one effect on the same stage are fitted together, as one candidate.
#[derive(Debug, Clone, PartialEq)]
pub struct DeclaredSpec {
    /// Name (not a library effect's name).
    pub name: String,
    /// Its parameters, in the declared order.
    pub parameters: Vec<DeclaredParameter>,
}

/// A declared effect's parameter as the selection holds it: `Copy` like the library's effects, so a
/// candidate's effect list stays a list of ids with one parameter each (an effect with two parameters is
/// two ids under one name). The specs are interned for the life of the process (a handful, read once
/// per run; the same declaration read twice gives the same ids), which gives the `&'static` names the
/// reports borrow.
#[derive(Debug, Clone, Copy)]
pub struct Declared {
    index: usize,
    spec: &'static Interned,
}

#[derive(Debug)]
struct Interned {
    spec: DeclaredSpec,
    /// Which of its parameters.
    k: usize,
    name: &'static str,
    parameter: &'static str,
    starts: &'static [f64],
}

static DECLARED: Mutex<Vec<&'static Interned>> = Mutex::new(Vec::new());

impl Declared {
    /// The ids of a declared effect's parameters, in the declared order.
    pub fn all(spec: DeclaredSpec) -> Vec<Declared> {
        let mut all = DECLARED.lock().unwrap_or_else(|e| e.into_inner());
        (0..spec.parameters.len())
            .map(|k| {
                if let Some(index) = all.iter().position(|i| i.spec == spec && i.k == k) {
                    return Declared {
                        index,
                        spec: all[index],
                    };
                }
                let p = &spec.parameters[k];
                // Starts: the null value and the midpoints towards each bound.
                let mut starts = vec![p.null];
                for x in [0.5 * (p.lo + p.null), 0.5 * (p.null + p.hi)] {
                    if !starts.contains(&x) {
                        starts.push(x);
                    }
                }
                let interned: &'static Interned = Box::leak(Box::new(Interned {
                    name: Box::leak(spec.name.clone().into_boxed_str()),
                    parameter: Box::leak(p.name.clone().into_boxed_str()),
                    starts: Box::leak(starts.into_boxed_slice()),
                    k,
                    spec: spec.clone(),
                }));
                all.push(interned);
                Declared {
                    index: all.len() - 1,
                    spec: interned,
                }
            })
            .collect()
    }

    /// The declaration this parameter belongs to.
    pub fn spec(&self) -> &'static DeclaredSpec {
        &self.spec.spec
    }

    /// The parameter.
    pub fn parameter(&self) -> &'static DeclaredParameter {
        &self.spec.spec.parameters[self.spec.k]
    }

    /// As the calibrated model records it, at value `value`: one entry per parameter, under the
    /// effect's name.
    pub fn record(&self, value: f64) -> DeclaredEffect {
        let p = self.parameter();
        DeclaredEffect {
            name: self.spec.spec.name.clone(),
            parameter: p.name.clone(),
            value,
            null: p.null,
            primitives: p.primitives.clone(),
        }
    }
}

/// The effect names of a list of ids, in order, each once (the parameters of one declared effect share
/// its name).
pub fn effect_names(ids: &[EffectId]) -> Vec<&'static str> {
    let mut names: Vec<&'static str> = Vec::new();
    for id in ids {
        if !names.contains(&id.name()) {
            names.push(id.name());
        }
    }
    names
}

impl PartialEq for Declared {
    fn eq(&self, other: &Self) -> bool {
        self.index == other.index
    }
}
impl Eq for Declared {}
impl PartialOrd for Declared {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Declared {
    fn cmp(&self, other: &Self) -> Ordering {
        self.index.cmp(&other.index)
    }
}
impl Hash for Declared {
    fn hash<H: Hasher>(&self, state: &mut H) {
        self.index.hash(state);
    }
}

/// One library effect (plus the thesis-style stiffness null), or a declared one.
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

    /// The name used in the reports, calibrated-model.toml and effects.toml.
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
            EffectId::Declared(d) => d.spec.name,
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
    pub fn stage(self) -> Stage {
        match self {
            EffectId::BondLayer | EffectId::PlyThickness => Stage::Mass,
            EffectId::Declared(d) => d.parameter().stage(),
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
            EffectId::Declared(d) => {
                let p = d.parameter();
                ParamSpec {
                    name: d.spec.parameter,
                    null: p.null,
                    lo: p.lo,
                    hi: p.hi,
                    starts: d.spec.starts,
                }
            }
        }
    }

    /// Set the effect's SI parameter from its report-unit value (a declared parameter adds its
    /// primitives: apply each id once).
    pub fn apply(self, model: &mut EffectModel, value: f64) {
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

    /// Read a library effect's parameter back in report units (`None` for a declared one, whose
    /// primitives do not name it).
    pub fn value(self, model: &EffectModel) -> Option<f64> {
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
            assert_eq!(EffectId::from_name(name), Some(*id));
            let mut e = EffectModel::default();
            id.apply(&mut e, id.param().null);
            assert!(e.effects.is_null() && e.primitives.is_empty());
            id.apply(&mut e, 1.7);
            assert!((id.value(&e).unwrap() - 1.7).abs() < 1e-12);
        }
    }
}
