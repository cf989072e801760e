//! The models the optimizer can search with, in the form its fast search needs.
//!
//! For a laminate solved at one drive level ([`Section`]), the original and thesis-adjusted models give
//! energy and mass of a planform without a base tab as
//!
//! `U = l_tot · w_0 · u(l_r, w_r) · g(w_0)`,  `m = l_tot · w_0 · μ(l_r, w_r)`.
//!
//! - original (lamination theory): `U = 3 P² l_p w_nom G_U / (8 C44)` with `l_p = l_tot/(1 + l_r)`,
//!   `w_nom = w_0/w_r` (docs/physics.md §3), and every mass term is an area `∝ l_p w_nom` (§4); `g = 1`.
//! - thesis-adjusted: δ scaled by a fit in `l_r`, F_b by a fit in `w_0 t_p` (`g`), passive mass by
//!   `1 + ζ` (thesis eqs. 4.3-4.5).
//!
//! `u`, `μ` and `g` come from the model crate evaluated at a unit planform (`l_tot = w_0 = 1 m`), so the
//! physics stays in one place; the tests check the factorisation against [`model::predict`].
//!
//! A calibrated model (`calibrated-model.toml`) is not of this form when it carries a dead length or a
//! clamp compliance (both bring a length of their own), so its energy is not linear in `l_tot`. It keeps
//! the other half of the structure: both beam compliances scale as `l_tot³ / w_0` and the mass as
//! `l_tot w_0`, so one [`StackBasis`] per shape, from the model crate at the unit planform, gives every
//! `(l_tot, w_0)` of that shape exactly through [`EffectModel::outputs`].
//!
//! Effects a lab declared (`calibrate --effects`) keep that structure too: their stack primitives are
//! solved into the unit basis, and their boundary primitives are added at each `(l_tot, w_0)` by
//! [`EffectModel::outputs`] (a clamp compliance per width is `c_w / w_0` there; a rigid root and edge
//! margins take that planform's piezo length and widths), the function
//! [`EffectModel::predict`] is held to. Nothing is dropped: a test compares every primitive kind with the
//! exact prediction, and `tests/studies/calibrate_declared.rs` the optimizer's chosen design with `predict`.

use actuator_model::effects::StackBasis;
use actuator_model::performance::{energy_and_mass, evaluate};
use actuator_model::{
    empirical, Actuator, EffectModel, ModelChoice, ModelError, ModelKind, Performance, Planform,
    Section,
};
use std::sync::Arc;

/// A model the optimizer searches with.
#[derive(Debug, Clone, PartialEq)]
pub enum SearchModel {
    /// Lamination theory with the tapered-beam compliance.
    Original,
    /// The thesis' empirical corrections on top of the original.
    ThesisAdjusted,
    /// Lamination theory with the nonlinear ceramic of Jafferis et al. 2015 (docs/physics.md §18):
    /// separable like the original (δ ∝ l_tot², F_b ∝ w_0 / l_tot at a fixed shape, §18.2), its rates
    /// taken from the model crate at the unit planform.
    Nonlinear,
    /// The original model with the physical effects a calibration found (`--model calibrated-model.toml`),
    /// library and declared.
    Calibrated(Arc<EffectModel>),
}

/// The stack a calibrated model needs to rebuild each laminate (the effects change the materials and
/// the layers themselves, not a finished [`Section`]): an [`Actuator`] whose planform is replaced by
/// the one being evaluated.
pub type Stack<'a> = Actuator<'a>;

fn at_planform<'a>(stack: &Stack<'a>, planform: Planform) -> Actuator<'a> {
    Actuator { planform, ..*stack }
}

/// Energy and mass rates of one planform shape `(l_r, w_r)`: `U = l_tot w_0 energy g(w_0)`,
/// `m = l_tot w_0 mass` (J/m², kg/m²).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShapeRates {
    /// Energy per unit `l_tot · w_0`, before the width factor, J/m² (separable models; for a calibrated
    /// model the energy at `l_tot = w_0 = 1 m`, which is not a rate).
    pub energy: f64,
    /// Mass per unit `l_tot · w_0`, kg/m².
    pub mass: f64,
    /// Calibrated models: the stack basis at the unit planform, which [`SearchModel::energy`] scales.
    pub basis: Option<StackBasis>,
    /// The shape's peak PZT strain over the stroke when the rates' prediction gave it (the nonlinear
    /// model), else `None` ([`SearchModel::shape_strain`] computes it).
    pub peak_strain: Option<f64>,
}

impl SearchModel {
    /// From the model crate's kind; the Euler-Bernoulli beam has no taper or extension to search over.
    pub fn from_kind(kind: ModelKind) -> Option<SearchModel> {
        match kind {
            ModelKind::Original => Some(SearchModel::Original),
            ModelKind::ThesisAdjusted => Some(SearchModel::ThesisAdjusted),
            ModelKind::Nonlinear => Some(SearchModel::Nonlinear),
            ModelKind::EulerBernoulli => None,
        }
    }

    /// The model crate's kind of a built-in model (`None` for a calibrated one).
    pub fn kind(&self) -> Option<ModelKind> {
        match self {
            SearchModel::Original => Some(ModelKind::Original),
            SearchModel::ThesisAdjusted => Some(ModelKind::ThesisAdjusted),
            SearchModel::Nonlinear => Some(ModelKind::Nonlinear),
            SearchModel::Calibrated(_) => None,
        }
    }

    /// Name for reports.
    pub fn name(&self) -> &'static str {
        match self {
            SearchModel::Calibrated(_) => "calibrated",
            _ => self.kind().map_or("", ModelKind::name),
        }
    }

    /// True when `U` is linear in `l_tot` at a fixed `(w_0, l_r, w_r)`: the search then needs no length
    /// search (closed-form length, vectorised rows).
    pub fn is_separable(&self) -> bool {
        match self {
            SearchModel::Original | SearchModel::ThesisAdjusted | SearchModel::Nonlinear => true,
            // A declared primitive may bring a length or a width of its own (a margin, a clamp
            // compliance per width): such models take the general path.
            SearchModel::Calibrated(m) => {
                m.effects.dead_length == 0.0
                    && m.effects.clamp_compliance == 0.0
                    && m.effects.rigid_root == 0.0
                    && m.effects.edge_margin == 0.0
                    && m.primitives.is_empty()
            }
        }
    }

    /// `u(l_r, w_r)` and `μ(l_r, w_r)`: the model at `l_tot = w_0 = 1 m` without the width factor.
    ///
    /// `stack` is read by a calibrated model only. Fails only where the model crate does (a calibrated
    /// stack it cannot solve).
    pub fn shape_rates(
        &self,
        section: &Section,
        stack: &Stack,
        extension_ratio: f64,
        width_ratio: f64,
    ) -> Result<ShapeRates, ModelError> {
        let unit = unit_planform(extension_ratio, width_ratio);
        Ok(match self {
            SearchModel::Original => {
                let (energy, mass) = energy_and_mass(section, &unit);
                ShapeRates {
                    energy,
                    mass,
                    basis: None,
                    peak_strain: None,
                }
            }
            SearchModel::ThesisAdjusted => {
                let original = evaluate(section, &unit);
                let adjusted = empirical::adjust(&original, &unit, section.pzt_thickness);
                // The force fit belongs to g(w_0); take u from the original energy and the δ fit alone.
                ShapeRates {
                    energy: original.energy * empirical::deflection_factor(extension_ratio),
                    mass: adjusted.mass,
                    basis: None,
                    peak_strain: None,
                }
            }
            SearchModel::Nonlinear => {
                let p = nonlinear(stack, unit)?;
                ShapeRates {
                    energy: p.energy,
                    mass: p.mass,
                    basis: None,
                    peak_strain: Some(p.peak_pzt_strain),
                }
            }
            SearchModel::Calibrated(m) => {
                let a = at_planform(stack, unit);
                let basis = m.basis(&a)?;
                let (delta, force) = m.outputs(&basis);
                ShapeRates {
                    energy: 0.5 * delta * force,
                    mass: m.mass(&a)?.total(),
                    basis: Some(basis),
                    peak_strain: None,
                }
            }
        })
    }

    /// Energy of the shape `rates` at `(l_tot, w_0)`, J.
    ///
    /// Separable models: `l_tot w_0 u g(w_0)`. Calibrated: the unit basis scaled (curvature unchanged,
    /// both compliances `× l_tot³ / w_0`) and passed through [`EffectModel::outputs`], which adds the
    /// boundary effects for this planform and is held to [`EffectModel::predict`].
    pub fn energy(
        &self,
        section: &Section,
        rates: &ShapeRates,
        length: f64,
        base_width: f64,
    ) -> f64 {
        match (self, &rates.basis) {
            (SearchModel::Calibrated(m), Some(unit)) => {
                let scale = length.powi(3) / base_width;
                let basis = StackBasis {
                    beam_compliance: unit.beam_compliance * scale,
                    extension_compliance: unit.extension_compliance * scale,
                    planform: Planform {
                        length,
                        base_width,
                        ..unit.planform
                    },
                    ..*unit
                };
                let (delta, force) = m.outputs(&basis);
                0.5 * delta * force
            }
            _ => length * base_width * rates.energy * self.width_factor(section, base_width),
        }
    }

    /// `g(w_0)`: 1 for the original model, the blocked-force fit in `w_0 t_p` for the adjusted one.
    pub fn width_factor(&self, section: &Section, base_width: f64) -> f64 {
        match self {
            SearchModel::Original | SearchModel::Nonlinear | SearchModel::Calibrated(_) => 1.0,
            SearchModel::ThesisAdjusted => {
                empirical::force_factor(base_width, section.pzt_thickness)
            }
        }
    }

    /// Full prediction of one planform (for reports and checks), through the model crate.
    pub fn performance(
        &self,
        section: &Section,
        stack: &Stack,
        planform: &Planform,
    ) -> Result<Performance, ModelError> {
        match self.section_performance(section, planform) {
            Some(p) => Ok(p),
            None => match self {
                SearchModel::Calibrated(m) => m.predict(&at_planform(stack, *planform)),
                SearchModel::Nonlinear => nonlinear(stack, *planform),
                _ => unreachable!("built-in models predict from the section"),
            },
        }
    }

    /// Peak PZT strain of a shape along its plate over the stroke, free to blocked. The original model's
    /// depends on the shape alone (`M(x)/w(x)` under `F_b` is the same at every `(l_tot, w_0)`,
    /// docs/physics.md eq. 6.1), so the unit planform gives it for the whole shape; the thesis-adjusted
    /// model keeps the original's stresses; a calibrated model with a length of its own is taken at that
    /// planform too.
    pub fn shape_strain(
        &self,
        section: &Section,
        stack: &Stack,
        extension_ratio: f64,
        width_ratio: f64,
    ) -> Result<f64, ModelError> {
        let unit = unit_planform(extension_ratio, width_ratio);
        Ok(self.performance(section, stack, &unit)?.peak_pzt_strain)
    }

    /// Prediction of a built-in model from the solved section alone (`None` for a calibrated or the
    /// nonlinear model, which rebuild the stack).
    pub fn section_performance(
        &self,
        section: &Section,
        planform: &Planform,
    ) -> Option<Performance> {
        let original = evaluate(section, planform);
        match self {
            SearchModel::Original => Some(original),
            SearchModel::ThesisAdjusted => Some(empirical::adjust(
                &original,
                planform,
                section.pzt_thickness,
            )),
            SearchModel::Nonlinear | SearchModel::Calibrated(_) => None,
        }
    }
}

/// The nonlinear model's prediction of the stack at a planform: it needs the laminate, not a
/// finished [`Section`].
fn nonlinear(stack: &Stack, planform: Planform) -> Result<Performance, ModelError> {
    ModelChoice::Kind(ModelKind::Nonlinear).predict(&at_planform(stack, planform))
}

/// The planform of a shape `(l_r, w_r)` at `l_tot = w_0 = 1 m`, no base tab.
pub(crate) fn unit_planform(extension_ratio: f64, width_ratio: f64) -> Planform {
    Planform {
        length: 1.0,
        extension_ratio,
        base_width: 1.0,
        width_ratio,
        base_tab: 0.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use actuator_model::primitives::{Applied, Primitive, Property, Target};
    use actuator_model::{model, Drive, DriveMode, Laminate, Material};

    const SHAPES: [(f64, f64, f64, f64); 4] = [
        (42.2e-3, 0.833, 5e-3, 1.667),
        (60e-3, 0.0, 20e-3, 1.0),
        (40e-3, 1.2, 7.3e-3, 1.93),
        (51e-3, 0.02, 11e-3, 1.0001),
    ];

    fn stack<'a>(pzt: &'a Material, cf: &'a Material, t_p: f64, layup: &'a [f64]) -> Stack<'a> {
        Stack {
            pzt,
            pzt_thickness: t_p,
            ply: cf,
            ply_thickness: 61.8e-6,
            layup_deg: layup,
            planform: unit_planform(0.0, 1.0),
            drive: Drive::new(DriveMode::Parallel, 800e3),
        }
    }

    #[test]
    fn factorisation_matches_the_model_crate() {
        // The search evaluates U = l w0 u g(w0), m = l w0 μ; model::predict is the reference.
        let pzt = Material::builtin("PZT-5H").unwrap();
        let cf = Material::builtin("CF-thesis").unwrap();
        for (t_p, layup) in [
            (127e-6, vec![0.0, 90.0, 0.0]),
            (267e-6, vec![0.0, 0.0, 0.0, 90.0, 0.0, 0.0, 0.0]),
        ] {
            let st = stack(&pzt, &cf, t_p, &layup);
            let lam = Laminate::bimorph(&pzt, t_p, &cf, 61.8e-6, &layup, None).unwrap();
            let section = Section::new(&lam, st.drive).unwrap();
            for model in [
                SearchModel::Original,
                SearchModel::ThesisAdjusted,
                SearchModel::Nonlinear,
            ] {
                let kind = model.kind().unwrap();
                for (l, l_r, w0, w_r) in SHAPES {
                    let pl = Planform::new(l, l_r, w0, w_r, 0.0).unwrap();
                    let want = model::predict(kind, &lam, &pl, st.drive).unwrap();
                    let r = model.shape_rates(&section, &st, l_r, w_r).unwrap();
                    let energy = model.energy(&section, &r, l, w0);
                    let mass = l * w0 * r.mass;
                    // The nonlinear model's scaling is exact (docs/physics.md §18.2); its numbers
                    // carry the tolerance of its root finding.
                    let tol = if model == SearchModel::Nonlinear {
                        1e-9
                    } else {
                        1e-12
                    };
                    assert!(((energy - want.energy) / want.energy).abs() < tol);
                    assert!(((mass - want.mass) / want.mass).abs() < 1e-12);
                    let p = model.performance(&section, &st, &pl).unwrap();
                    assert!(((p.energy - want.energy) / want.energy).abs() < 1e-14);
                    // The strain along the plate is the shape's (docs/physics.md eq. 6.1, §18.2).
                    let strain = model.shape_strain(&section, &st, l_r, w_r).unwrap();
                    assert!((strain / want.peak_pzt_strain - 1.0).abs() < tol);
                }
            }
        }
    }

    #[test]
    fn calibrated_scaling_matches_the_calibrated_model() {
        // One unit basis per shape, scaled to (l_tot, w_0), against EffectModel::predict, which
        // rebuilds the stack for every actuator: every effect on, including the two with a length of
        // their own that break the linear-in-l_tot form; then the same with one declared primitive of
        // every kind on top.
        let effects = actuator_model::Effects {
            d31_scale: 0.8,
            d31_field_coefficient: 2e-7,
            dead_length: 1.5e-3,
            bond_thickness: 12e-6,
            extension_flexibility: 0.7,
            clamp_compliance: 0.4,
            ply_thickness_scale: 1.1,
            stiffness_scale: 1.0,
            ..Default::default()
        };
        let energies: Vec<f64> = [vec![], every_declared_primitive()]
            .into_iter()
            .map(|primitives| {
                let model = SearchModel::Calibrated(Arc::new(EffectModel {
                    effects,
                    primitives,
                }));
                scaled_energy_is_the_prediction(&model)
            })
            .collect();
        // The declared primitives do change the answer (the fast path could not ignore them unseen).
        assert!(
            (energies[1] / energies[0] - 1.0).abs() > 0.05,
            "{energies:?}"
        );
    }

    /// One of each primitive kind, at values that move the outputs by several per cent.
    fn every_declared_primitive() -> Vec<Applied> {
        use Primitive::*;
        let scale = |target, property, value| Applied {
            primitive: Scale { target, property },
            value,
        };
        let at = |primitive, value| Applied { primitive, value };
        vec![
            scale(Target::Passive, Property::E1, 0.7),
            scale(Target::Pzt, Property::E1, 0.9),
            scale(Target::Passive, Property::Thickness, 1.1),
            scale(Target::Pzt, Property::Density, 1.05),
            at(InsertedLayer, 10e-6),
            scale(Target::Bond, Property::E1, 1.5),
            scale(Target::Bond, Property::Thickness, 1.2),
            at(FieldDependentD31, 1e-7),
            at(ElectrodeMargin, 0.5e-3),
            at(ClampCompliance, 0.1),
            at(ClampCompliancePerWidth, 2e-3),
            at(CompliantExtension, 0.3),
            at(RigidRoot, 1e-3),
            at(EdgeMargin, 0.2e-3),
            at(InactiveSurfaceLayer, 10e-6),
            at(D31ThicknessPower, 0.2),
        ]
    }

    /// The fast path (one unit basis per shape, scaled) against the exact prediction, which rebuilds the
    /// stack for every actuator. Returns the energy of the first shape.
    fn scaled_energy_is_the_prediction(model: &SearchModel) -> f64 {
        let pzt = Material::builtin("PZT-5H").unwrap();
        let cf = Material::builtin("CF-thesis").unwrap();
        assert!(!model.is_separable());
        let layup = [0.0, 90.0, 0.0];
        let st = stack(&pzt, &cf, 191e-6, &layup);
        let lam = Laminate::bimorph(&pzt, 191e-6, &cf, 61.8e-6, &layup, None).unwrap();
        let section = Section::new(&lam, st.drive).unwrap();
        for (l, l_r, w0, w_r) in SHAPES {
            let r = model.shape_rates(&section, &st, l_r, w_r).unwrap();
            let pl = Planform::new(l, l_r, w0, w_r, 0.0).unwrap();
            let want = model.performance(&section, &st, &pl).unwrap();
            let energy = model.energy(&section, &r, l, w0);
            assert!(
                ((energy - want.energy) / want.energy).abs() < 1e-12,
                "{energy} vs {}",
                want.energy
            );
            assert!(((l * w0 * r.mass - want.mass) / want.mass).abs() < 1e-12);
            // The calibrated effects do change the answer (the check above is not original = original).
            let original = model::predict(ModelKind::Original, &lam, &pl, st.drive).unwrap();
            assert!((want.energy / original.energy - 1.0).abs() > 0.05);
        }
        let (l, l_r, w0, w_r) = SHAPES[0];
        let r = model.shape_rates(&section, &st, l_r, w_r).unwrap();
        model.energy(&section, &r, l, w0)
    }

    #[test]
    fn the_beam_has_no_search_model() {
        assert!(SearchModel::from_kind(ModelKind::EulerBernoulli).is_none());
    }
}
