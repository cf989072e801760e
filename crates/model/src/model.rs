//! Choice of model for a prediction: original lamination theory, the thesis' adjusted fits, the
//! nonlinear ceramic, or the Euler-Bernoulli beam.

use crate::calibrated_base::{self, Base};
use crate::ceramic::Ceramic;
use crate::drive::Drive;
use crate::dynamics::{ActuatorBeam, Modal};
use crate::effects::{Actuator, BondScale, Effects, StackBasis, StackSection};
use crate::empirical;
use crate::error::ModelError;
use crate::euler_bernoulli::BeamBimorph;
use crate::laminate::Laminate;
use crate::nonlinear;
use crate::performance::{evaluate, MassBreakdown, Performance};
use crate::planform::Planform;
use crate::primitives::{self, Applied, Link};
use crate::section::Section;
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// Which model predicts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ModelKind {
    /// Classical lamination theory with the tapered-beam compliance (thesis ch. 2, Wood 2005).
    Original,
    /// Original with the thesis' empirical corrections, eqs. 4.3-4.5 ([`crate::empirical`]).
    ThesisAdjusted,
    /// Euler-Bernoulli beam, eqs. 2.11-2.15; rectangular designs only.
    EulerBernoulli,
    /// Lamination theory with the PZT's field-dependent stress coefficient and bimodular modulus of
    /// Jafferis, Smith & Wood 2015 ([`crate::nonlinear`], docs/physics.md §18).
    Nonlinear,
}

impl ModelKind {
    /// Command-line name.
    pub fn name(self) -> &'static str {
        match self {
            ModelKind::Original => "original",
            ModelKind::ThesisAdjusted => "thesis-adjusted",
            ModelKind::EulerBernoulli => "euler-bernoulli",
            ModelKind::Nonlinear => "nonlinear",
        }
    }
}

/// Predict one actuator with the chosen model.
pub fn predict(
    kind: ModelKind,
    laminate: &Laminate,
    planform: &Planform,
    drive: Drive,
) -> Result<Performance, ModelError> {
    let section = Section::new(laminate, drive)?;
    let original = evaluate(&section, planform);
    match kind {
        ModelKind::Original => Ok(original),
        ModelKind::Nonlinear => {
            let pzt = &laminate.layers()[laminate.piezo_layer(0)].material;
            nonlinear::predict(laminate, planform, drive, Ceramic::of(pzt)?)
        }
        ModelKind::ThesisAdjusted => Ok(empirical::adjust(
            &original,
            planform,
            section.pzt_thickness,
        )),
        ModelKind::EulerBernoulli => {
            if planform.extension_ratio != 0.0 || (planform.width_ratio - 1.0).abs() > 1e-12 {
                return Err(ModelError::OutOfRange {
                    name: "width_ratio/extension_ratio",
                    value: planform.width_ratio,
                    range: "the Euler-Bernoulli model covers rectangles only (w_r = 1, l_r = 0)",
                });
            }
            // The beam's plates move by ±E (docs/physics.md §2); the biased mode's bias bends nothing.
            use crate::drive::DriveMode::{Biased, Parallel, Series};
            if ![Parallel, Series, Biased].contains(&drive.mode) {
                return Err(ModelError::NotCovered {
                    name: "drive mode",
                    value: drive.mode.name(),
                    allowed: "the Euler-Bernoulli model covers parallel, series and biased drive",
                });
            }
            let beam = BeamBimorph::from_laminate(laminate, planform.length, planform.base_width)?;
            let r = beam.response(drive.field);
            Ok(original.with_outputs(r.free_deflection, r.blocked_force, original.mass_breakdown))
        }
    }
}

/// The original model with effects applied as physics: the library's [`Effects`] and any primitives a
/// lab declared, at their values (docs/calibration.md §2). The primitives sit on top of the effects:
/// stack primitives change the materials and layers before the stack is solved, boundary and field
/// primitives add to the effects ([`primitives::compose`]).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct EffectModel {
    /// The library effects.
    pub effects: Effects,
    /// Declared primitives at their values.
    pub primitives: Vec<Applied>,
}

impl From<Effects> for EffectModel {
    fn from(effects: Effects) -> Self {
        EffectModel {
            effects,
            primitives: Vec::new(),
        }
    }
}

impl EffectModel {
    /// Predict one actuator.
    pub fn predict(&self, a: &Actuator) -> Result<Performance, ModelError> {
        primitives::compose(&self.primitives, &self.effects, a)
    }

    /// True when a declared primitive changes the stack, so a [`StackBasis`] must be solved per
    /// parameter value rather than once.
    pub fn changes_stack(&self) -> bool {
        self.primitives.iter().any(|x| x.primitive.changes_stack())
    }

    /// True when δ and F_b are proportional to the drive field under this model: no field-dependent d31,
    /// neither as an effect nor as a primitive ([`primitives::Primitive::linear_in_field`]).
    pub fn linear_in_field(&self) -> bool {
        self.effects.d31_field_coefficient == 0.0
            && self
                .primitives
                .iter()
                .all(|x| x.primitive.linear_in_field())
    }

    /// The stack basis of an actuator with the stack effects and stack primitives applied (η, β and the
    /// boundary primitives are left to [`EffectModel::outputs`]).
    pub fn basis(&self, a: &Actuator) -> Result<StackBasis, ModelError> {
        self.stack_section(a)?.basis(&a.planform)
    }

    /// The planform-free part of [`EffectModel::basis`] ([`StackSection`]): the same for every actuator
    /// of the same stack (materials, thicknesses, layup), drive field and presence of an extension, since
    /// the stack primitives act on the stack's inputs alone.
    pub fn stack_section(&self, a: &Actuator) -> Result<StackSection, ModelError> {
        // No primitive: the effects' own section, without copying the materials into a stack.
        if self.primitives.is_empty() {
            return self.effects.stack_section(a);
        }
        let s = primitives::stack(&self.primitives, &self.effects, a)?;
        s.effects.stack_section(&s.actuator(a))
    }

    /// Free deflection and blocked force from a basis of [`EffectModel::basis`] (the same numbers as
    /// [`EffectModel::predict`]; a test holds them together). The boundary primitives use the basis'
    /// planform (clamp compliance per width).
    pub fn outputs(&self, b: &StackBasis) -> (f64, f64) {
        self.boundary_effects(&b.planform).outputs(b)
    }

    /// The effects with the declared boundary and field primitives added for this planform (stack
    /// primitives need [`EffectModel::basis`]).
    pub fn boundary_effects(&self, planform: &Planform) -> Effects {
        primitives::boundary(&self.primitives, &self.effects, planform)
    }

    /// True when [`EffectModel::boundary_effects`] are the same for every planform
    /// ([`primitives::boundary_is_uniform`]).
    pub fn boundary_is_uniform(&self) -> bool {
        primitives::boundary_is_uniform(&self.primitives)
    }

    /// Mass by layer kind.
    pub fn mass(&self, a: &Actuator) -> Result<MassBreakdown, ModelError> {
        primitives::mass(&self.primitives, &self.effects, a)
    }

    /// The actuator's beam under these effects (docs/physics.md §11.4): the stack from `basis`
    /// ([`EffectModel::basis`]), the boundary effects and the masses with the declared primitives
    /// applied ([`primitives::boundary`], [`primitives::masses`]), the added masses where
    /// [`ActuatorBeam::from_effects`] puts them (a tip mass at the tip).
    pub fn beam(&self, basis: &StackBasis, mass: &MassBreakdown) -> ActuatorBeam {
        let effects = primitives::masses(&self.primitives, &self.boundary_effects(&basis.planform));
        ActuatorBeam::from_effects(&effects, basis, mass)
    }

    /// True when `self` and `other` give every actuator the same mass, beam and statics' tip stiffness
    /// on the same [`StackBasis`] ([`EffectModel::mass`], [`EffectModel::beam`],
    /// [`EffectModel::tip_stiffness`]), to the bit: the same primitives in the same order, and the same
    /// values but for what acts on the drive alone (d31 and its field dependence, the undriven root and
    /// edge strips, a dead surface layer; [`primitives::Primitive::changes_beam`]), whose differing
    /// values are finite, as the mass asks of every primitive value ([`primitives::stack`]).
    pub fn same_beam(&self, other: &EffectModel) -> bool {
        let same = |a: f64, b: f64| a.to_bits() == b.to_bits();
        let (mine, theirs) = (self.beam_values(), other.beam_values());
        mine.iter().zip(&theirs).all(|(&a, &b)| same(a, b))
            && self.primitives.len() == other.primitives.len()
            && self.primitives.iter().zip(&other.primitives).all(|(a, b)| {
                a.primitive == b.primitive
                    && (same(a.value, b.value)
                        || (!a.primitive.changes_beam()
                            && a.value.is_finite()
                            && b.value.is_finite()))
            })
    }

    /// A hash of what [`EffectModel::same_beam`] compares: models with the same beam have the same
    /// digest, so a cache of beams compares models in full only where their digests agree.
    pub fn beam_digest(&self) -> u64 {
        let primitives = self.primitives.iter().map(|x| {
            if x.primitive.changes_beam() {
                x.value
            } else {
                0.0
            }
        });
        self.beam_values()
            .into_iter()
            .chain(primitives)
            .fold(self.primitives.len() as u64, |h, v| {
                (h.rotate_left(5) ^ v.to_bits()).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95)
            })
    }

    /// The effects' values the beam, the mass and the statics' tip stiffness read: all but what acts on
    /// the drive alone (d31 and its field dependence, the undriven root and edge strips, a dead surface
    /// layer). Every field named, so that a field added to the effects is classed here.
    fn beam_values(&self) -> [f64; 13] {
        let Effects {
            d31_scale: _,
            d31_field_coefficient: _,
            dead_length: _,
            edge_margin: _,
            inactive_surface: _,
            bond_thickness,
            extension_flexibility,
            clamp_compliance,
            ply_thickness_scale,
            stiffness_scale,
            bond_scale,
            rigid_root,
            added_mass,
            added_mass_per_length,
            added_mass_per_area,
            tip_mass,
        } = self.effects;
        let BondScale {
            modulus,
            poisson,
            density,
        } = bond_scale;
        [
            bond_thickness,
            extension_flexibility,
            clamp_compliance,
            ply_thickness_scale,
            stiffness_scale,
            modulus,
            poisson,
            density,
            rigid_root,
            added_mass,
            added_mass_per_length,
            added_mass_per_area,
            tip_mass,
        ]
    }

    /// The first mode of the bare clamped actuator, what `predict` reports as `resonance_Hz` and
    /// `calibrate` fits to a measured one: the beam's mode ([`EffectModel::beam`]) with its stiffness
    /// scaled to the statics' `k = F_b / δ` of `basis` ([`Modal::with_stiffness`]).
    pub fn modes(&self, basis: &StackBasis, mass: &MassBreakdown) -> Result<Modal, ModelError> {
        Ok(self
            .beam(basis, mass)
            .solve()?
            .with_stiffness(self.tip_stiffness(basis)))
    }

    /// The statics' tip stiffness `k = F_b / δ` of a basis, N/m (at any drive, even one that gives no
    /// deflection).
    pub fn tip_stiffness(&self, basis: &StackBasis) -> f64 {
        1.0 / self.boundary_effects(&basis.planform).tip_compliance(basis)
    }
}

/// One parameter of an effect a lab declared (`calibrate --effects FILE`) as the calibrated model
/// records it: the primitives it drives and its fitted value. An effect with several parameters is
/// recorded as one entry per parameter under the effect's name.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DeclaredEffect {
    /// The name it was declared under.
    pub name: String,
    /// Its parameter's name.
    pub parameter: String,
    /// The fitted value (the primitives' unit, SI).
    pub value: f64,
    /// The value that switches it off.
    pub null: f64,
    /// The primitives it drives and how the parameter sets each.
    pub primitives: Vec<Link>,
}

impl DeclaredEffect {
    /// Its primitives at its value. Fails on a map that needs the ply ([`primitives::Map::ResinDensity`],
    /// library-only) or a non-finite value.
    pub fn applied(&self) -> Result<Vec<Applied>, ModelError> {
        self.primitives
            .iter()
            .map(|l| match l.map.of(self.value) {
                // A scale on a property its target lacks (a bond's d31) is refused by the stack.
                _ if !l.primitive.is_defined() => Err(ModelError::OutOfRange {
                    name: "declared bond scale",
                    value: self.value,
                    range: "a property the bond layer has: E1, nu12, density or thickness",
                }),
                Some(value) if l.primitive.allows(value) => Ok(Applied {
                    primitive: l.primitive,
                    value,
                }),
                _ => Err(ModelError::OutOfRange {
                    name: "declared effect value",
                    value: self.value,
                    range:
                        "inside its primitive's physical range, with an identity or reciprocal map",
                }),
            })
            .collect()
    }
}

/// A calibrated model: the effects found in measured data and what the calibration concluded.
/// Written as `calibrated-model.toml` by `actuator-cam calibrate`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CalibratedModel {
    /// Always "calibrated"; lets a reader reject other files.
    pub model: String,
    /// The model the effects sit on ([`calibrated_base`]); a file without `base` is on the original.
    #[serde(default, skip_serializing_if = "Base::is_original")]
    pub base: Base,
    /// The calibration verdict (`no-effect`, `explained`, `ambiguous`, `not-explained`).
    pub verdict: String,
    /// Names of the effects the calibration selected.
    pub selected_effects: Vec<String>,
    /// Parameters of every library effect (null values where not selected).
    pub effects: Effects,
    /// Declared effects the calibration selected, with their compositions and fitted values.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub declared: Vec<DeclaredEffect>,
    /// The structural loss factor from the measured quality factors, when the data carried them.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub loss: Option<MeasuredLoss>,
}

/// The structural loss factor of the measured actuators: `η = 1/Q` of each actuator's first resonance
/// (hysteretic damping `k (1 + i η)` has `Q = 1/η` at resonance), their mean and its 95 % interval.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MeasuredLoss {
    /// Mean `η = 1/Q` over the actuators.
    pub loss_factor: f64,
    /// 95 % interval of the mean (Student t over the actuators).
    pub interval: [f64; 2],
    /// How many actuators carried a quality factor.
    pub actuators: usize,
}

impl CalibratedModel {
    /// The physics of this model: library effects and the declared effects' primitives.
    pub fn effect_model(&self) -> Result<EffectModel, ModelError> {
        let mut primitives = Vec::new();
        for d in &self.declared {
            primitives.extend(d.applied()?);
        }
        Ok(EffectModel {
            effects: self.effects,
            primitives,
        })
    }

    /// Check every value is physical, and that the base takes the effects.
    pub fn validate(&self) -> Result<(), ModelError> {
        self.effects.validate()?;
        if self.base == Base::Nonlinear {
            calibrated_base::check_nonlinear(&self.effects, !self.declared.is_empty())?;
        }
        if let Some(loss) = &self.loss {
            let [lo, hi] = loss.interval;
            let inside = |v: f64| v.is_finite() && v > 0.0 && v <= 1.0;
            if !(inside(loss.loss_factor) && inside(lo) && inside(hi) && lo <= hi) {
                return Err(ModelError::OutOfRange {
                    name: "loss.loss_factor",
                    value: loss.loss_factor,
                    range: "(0, 1], inside its interval (0, 1]",
                });
            }
        }
        self.effect_model().map(|_| ())
    }

    /// The laminate the nonlinear base solves: the actuator's stack with the ply-thickness and
    /// bond-layer effects applied ([`calibrated_base::check_nonlinear`] refuses the others).
    pub fn nonlinear_laminate(&self, a: &Actuator) -> Result<Laminate, ModelError> {
        calibrated_base::check_nonlinear(&self.effects, !self.declared.is_empty())?;
        self.effects.laminate(a)
    }

    /// Predict one actuator: the effects' physics on the original base, the nonlinear model of the
    /// effects' laminate on the nonlinear base ([`CalibratedModel::nonlinear_laminate`]).
    pub fn predict(&self, a: &Actuator) -> Result<Performance, ModelError> {
        match self.base {
            Base::Original => self.effect_model()?.predict(a),
            Base::Nonlinear => {
                let lam = self.nonlinear_laminate(a)?;
                nonlinear::predict(&lam, &a.planform, a.drive, Ceramic::of(a.pzt)?)
            }
        }
    }
}

/// A model as the command line chooses it: one of the built-in kinds, or a calibrated model read from
/// `calibrated-model.toml` (`--model FILE`). [`ModelKind`] stays `Copy`; this carries the parameters.
#[derive(Debug, Clone)]
pub enum ModelChoice {
    /// A built-in model.
    Kind(ModelKind),
    /// The original model with calibrated physical effects ([`crate::effects`]).
    Calibrated(Arc<CalibratedModel>),
}

impl From<ModelKind> for ModelChoice {
    fn from(kind: ModelKind) -> Self {
        ModelChoice::Kind(kind)
    }
}

impl ModelChoice {
    /// Name for reports.
    pub fn name(&self) -> &'static str {
        match self {
            ModelChoice::Kind(k) => k.name(),
            ModelChoice::Calibrated(_) => "calibrated",
        }
    }

    /// True when the model's stiffness and blocked force per field change with the field (the
    /// nonlinear ceramic, docs/physics.md §18): a drive then predicts at its operating field.
    pub fn depends_on_field(&self) -> bool {
        match self {
            ModelChoice::Kind(kind) => *kind == ModelKind::Nonlinear,
            ModelChoice::Calibrated(model) => model.base == Base::Nonlinear,
        }
    }

    /// Predict one actuator from its raw inputs (the calibrated effects change the stack itself, so they
    /// need the materials and thicknesses, not a finished laminate).
    pub fn predict(&self, a: &Actuator) -> Result<Performance, ModelError> {
        match self {
            ModelChoice::Kind(kind) => {
                let lam = Laminate::bimorph(
                    a.pzt,
                    a.pzt_thickness,
                    a.ply,
                    a.ply_thickness,
                    a.layup_deg,
                    None,
                )?;
                predict(*kind, &lam, &a.planform, a.drive)
            }
            ModelChoice::Calibrated(model) => model.predict(a),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::primitives::tests::with;
    use crate::primitives::{Map, Primitive, Property, Target};

    #[test]
    fn null_effects_reproduce_the_original_model() {
        let pzt = crate::material::Material::builtin("PZT-5H").unwrap();
        let cf = crate::material::Material::builtin("CF-thesis").unwrap();
        let layup = [0.0, 90.0, 0.0];
        let a = Actuator {
            pzt: &pzt,
            pzt_thickness: 191e-6,
            ply: &cf,
            ply_thickness: 61.8e-6,
            layup_deg: &layup,
            planform: Planform::new(40e-3, 0.6, 8e-3, 1.4, 2e-3).unwrap(),
            drive: Drive::new(crate::drive::DriveMode::Parallel, 600e3),
        };
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

    fn declared(name: &str, value: f64, null: f64, links: &[(Primitive, Map)]) -> DeclaredEffect {
        DeclaredEffect {
            name: name.into(),
            parameter: "p".into(),
            value,
            null,
            primitives: links
                .iter()
                .map(|&(primitive, map)| Link { primitive, map })
                .collect(),
        }
    }

    #[test]
    fn the_basis_path_of_declared_primitives_is_the_prediction() {
        // EffectModel::basis + outputs (what the fit and the optimizer use) against EffectModel::predict
        // (the stack rebuilt with every primitive), with library effects underneath.
        with(|a| {
            let soft = Primitive::Scale {
                target: Target::Passive,
                property: Property::E1,
            };
            let model = CalibratedModel {
                model: "calibrated".into(),
                base: Base::Original,
                verdict: "explained".into(),
                selected_effects: vec![],
                effects: Effects {
                    d31_scale: 0.85,
                    dead_length: 1e-3,
                    clamp_compliance: 0.2,
                    ..Effects::default()
                },
                declared: vec![
                    declared("soft", 0.7, 1.0, &[(soft, Map::Identity)]),
                    declared(
                        "resin",
                        1.2,
                        1.0,
                        &[(
                            Primitive::Scale {
                                target: Target::Passive,
                                property: Property::G12,
                            },
                            Map::Reciprocal,
                        )],
                    ),
                    declared(
                        "clamp",
                        4e-3,
                        0.0,
                        &[
                            (Primitive::ClampCompliancePerWidth, Map::Identity),
                            (Primitive::InsertedLayer, Map::Identity),
                        ],
                    ),
                    declared(
                        "held",
                        1.5e-3,
                        0.0,
                        &[(Primitive::RigidRoot, Map::Identity)],
                    ),
                    declared(
                        "edges",
                        0.3e-3,
                        0.0,
                        &[(Primitive::EdgeMargin, Map::Identity)],
                    ),
                    declared(
                        "skin",
                        12e-6,
                        0.0,
                        &[(Primitive::InactiveSurfaceLayer, Map::Identity)],
                    ),
                ],
                loss: None,
            };
            let m = model.effect_model().unwrap();
            assert_eq!(m.primitives.len(), 7);
            assert!((m.primitives[1].value - 1.0 / 1.2).abs() < 1e-15);
            let p = model.predict(a).unwrap();
            let (d, f) = m.outputs(&m.basis(a).unwrap());
            assert!(
                ((d - p.free_deflection) / d).abs() < 1e-10,
                "{d} vs {}",
                p.free_deflection
            );
            assert!(
                ((f - p.blocked_force) / f).abs() < 1e-10,
                "{f} vs {}",
                p.blocked_force
            );
            let mass = m.mass(a).unwrap().total();
            assert!(((mass - p.mass) / mass).abs() < 1e-12);
            // Without the declared effects the numbers differ (the check above is not vacuous).
            let library_only = model.effects.predict(a).unwrap();
            assert!((library_only.blocked_force / p.blocked_force - 1.0).abs() > 0.05);
            assert!(library_only.mass < p.mass, "the inserted layer has mass");
            // Each of the last three moves the prediction by itself.
            for k in 4..7 {
                let mut without = m.clone();
                without.primitives.remove(k);
                let q = without.predict(a).unwrap();
                assert!(
                    (q.blocked_force / p.blocked_force - 1.0).abs() > 1e-3,
                    "{:?}",
                    m.primitives[k]
                );
            }
        });
    }

    #[test]
    fn the_mass_primitives_reach_the_beam_through_the_effects() {
        // The beam reads the declared masses from the effects, as the library's own (docs/physics.md
        // §11.4): the tip mass at the tip, the fillets and the adhesive along the active region.
        with(|a| {
            let applied = |primitive, value| Applied { primitive, value };
            let m = EffectModel {
                effects: Effects::default(),
                primitives: vec![
                    applied(Primitive::TipMass, 2e-6),
                    applied(Primitive::AddedMassPerLength, 1e-4),
                    applied(Primitive::AddedMassPerArea, 1e-3),
                ],
            };
            let (basis, mass) = (m.basis(a).unwrap(), m.mass(a).unwrap());
            let effects = Effects {
                tip_mass: 2e-6,
                added_mass_per_length: 1e-4,
                added_mass_per_area: 1e-3,
                ..Effects::default()
            };
            let beam = m.beam(&basis, &mass);
            assert_eq!(beam, ActuatorBeam::from_effects(&effects, &basis, &mass));
            assert_eq!(beam.end_mass, 2e-6);
            // Only the beam sees the tip mass: f1 falls, the weighed mass does not move.
            let no_tip = EffectModel {
                primitives: m.primitives[1..].to_vec(),
                ..m.clone()
            };
            assert_eq!(no_tip.mass(a).unwrap(), mass);
            let f1 = |m: &EffectModel| m.modes(&basis, &mass).unwrap().frequency;
            assert!(f1(&m) < 0.99 * f1(&no_tip), "{} vs {}", f1(&m), f1(&no_tip));
        });
    }

    #[test]
    fn a_declared_value_outside_its_primitive_is_refused() {
        let soft = Primitive::Scale {
            target: Target::Passive,
            property: Property::E1,
        };
        for bad in [0.0, -0.5, f64::NAN] {
            let model = CalibratedModel {
                model: "calibrated".into(),
                base: Base::Original,
                verdict: "explained".into(),
                selected_effects: vec![],
                effects: Effects::default(),
                declared: vec![declared("soft", bad, 1.0, &[(soft, Map::Identity)])],
                loss: None,
            };
            assert!(model.validate().is_err(), "{bad}");
        }
    }
}
