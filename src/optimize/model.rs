//! The models the optimizer can search with, in the separable form its fast search needs.
//!
//! For a laminate solved at one drive level ([`Section`]), every supported model gives energy and mass of
//! a planform without a base tab as
//!
//! `U = l_tot · w_0 · u(l_r, w_r) · g(w_0)`,  `m = l_tot · w_0 · μ(l_r, w_r)`.
//!
//! - original (lamination theory): `U = 3 P² l_p w_nom G_U / (8 C44)` with `l_p = l_tot/(1 + l_r)`,
//!   `w_nom = w_0/w_r` (MODEL-NOTES §3), and every mass term is an area `∝ l_p w_nom` (§4); `g = 1`.
//! - thesis-adjusted: δ scaled by a fit in `l_r`, F_b by a fit in `w_0 t_p` (`g`), passive mass by
//!   `1 + ζ` (thesis eqs. 4.3-4.5).
//!
//! `u`, `μ` and `g` come from the model crate evaluated at a unit planform (`l_tot = w_0 = 1 m`), so the
//! physics stays in one place; the tests check the factorisation against [`model::predict`].
//! A model that is not of this form (a calibrated one, later) needs its own search kernel or a fallback
//! that evaluates each design through [`SearchModel::performance`].

use actuator_model::performance::{energy_and_mass, evaluate};
use actuator_model::{empirical, ModelKind, Performance, Planform, Section};

/// A model the optimizer searches with.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SearchModel {
    /// Lamination theory with the tapered-beam compliance.
    Original,
    /// The thesis' empirical corrections on top of the original.
    ThesisAdjusted,
}

/// Energy and mass rates of one planform shape `(l_r, w_r)`: `U = l_tot w_0 energy g(w_0)`,
/// `m = l_tot w_0 mass` (J/m², kg/m²).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShapeRates {
    /// Energy per unit `l_tot · w_0`, before the width factor, J/m².
    pub energy: f64,
    /// Mass per unit `l_tot · w_0`, kg/m².
    pub mass: f64,
}

impl SearchModel {
    /// From the model crate's kind; the Euler-Bernoulli beam has no taper or extension to search over.
    pub fn from_kind(kind: ModelKind) -> Option<SearchModel> {
        match kind {
            ModelKind::Original => Some(SearchModel::Original),
            ModelKind::ThesisAdjusted => Some(SearchModel::ThesisAdjusted),
            ModelKind::EulerBernoulli => None,
        }
    }

    /// The model crate's kind.
    pub fn kind(self) -> ModelKind {
        match self {
            SearchModel::Original => ModelKind::Original,
            SearchModel::ThesisAdjusted => ModelKind::ThesisAdjusted,
        }
    }

    /// Command-line name.
    pub fn name(self) -> &'static str {
        self.kind().name()
    }

    /// `u(l_r, w_r)` and `μ(l_r, w_r)`: the model at `l_tot = w_0 = 1 m` without the width factor.
    pub fn shape_rates(
        self,
        section: &Section,
        extension_ratio: f64,
        width_ratio: f64,
    ) -> ShapeRates {
        let unit = unit_planform(extension_ratio, width_ratio);
        match self {
            SearchModel::Original => {
                let (energy, mass) = energy_and_mass(section, &unit);
                ShapeRates { energy, mass }
            }
            SearchModel::ThesisAdjusted => {
                let original = evaluate(section, &unit);
                let adjusted = empirical::adjust(&original, &unit, section.pzt_thickness);
                // The force fit belongs to g(w_0); take u from the original energy and the δ fit alone.
                ShapeRates {
                    energy: original.energy * empirical::deflection_factor(extension_ratio),
                    mass: adjusted.mass,
                }
            }
        }
    }

    /// `g(w_0)`: 1 for the original model, the blocked-force fit in `w_0 t_p` for the adjusted one.
    pub fn width_factor(self, section: &Section, base_width: f64) -> f64 {
        match self {
            SearchModel::Original => 1.0,
            SearchModel::ThesisAdjusted => {
                empirical::force_factor(base_width, section.pzt_thickness)
            }
        }
    }

    /// Full prediction of one planform (for reports and checks), through the model crate.
    pub fn performance(self, section: &Section, planform: &Planform) -> Performance {
        let original = evaluate(section, planform);
        match self {
            SearchModel::Original => original,
            SearchModel::ThesisAdjusted => {
                empirical::adjust(&original, planform, section.pzt_thickness)
            }
        }
    }
}

fn unit_planform(extension_ratio: f64, width_ratio: f64) -> Planform {
    Planform {
        length: 1.0,
        extension_ratio,
        base_width: 1.0,
        width_ratio,
        base_tab: 0.0,
    }
}

/// Parse a model name as the command line writes it (`original`, `thesis-adjusted`, `euler-bernoulli`).
pub fn parse_model_kind(name: &str) -> Result<ModelKind, String> {
    [
        ModelKind::Original,
        ModelKind::ThesisAdjusted,
        ModelKind::EulerBernoulli,
    ]
    .into_iter()
    .find(|k| k.name() == name)
    .ok_or_else(|| {
        format!("unknown model \"{name}\"; use original, thesis-adjusted or euler-bernoulli")
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use actuator_model::{model, Drive, DriveMode, Laminate, Material};

    #[test]
    fn factorisation_matches_the_model_crate() {
        // The search evaluates U = l w0 u g(w0), m = l w0 μ; model::predict is the reference.
        let pzt = Material::builtin("PZT-5H").unwrap();
        let cf = Material::builtin("CF-thesis").unwrap();
        let drive = Drive {
            mode: DriveMode::Parallel,
            field: 800e3,
        };
        for (t_p, layup) in [
            (127e-6, vec![0.0, 90.0, 0.0]),
            (267e-6, vec![0.0, 0.0, 0.0, 90.0, 0.0, 0.0, 0.0]),
        ] {
            let lam = Laminate::bimorph(&pzt, t_p, &cf, 61.8e-6, &layup, None).unwrap();
            let section = Section::new(&lam, drive).unwrap();
            for model in [SearchModel::Original, SearchModel::ThesisAdjusted] {
                for (l, l_r, w0, w_r) in [
                    (42.2e-3, 0.833, 5e-3, 1.667),
                    (60e-3, 0.0, 20e-3, 1.0),
                    (40e-3, 1.2, 7.3e-3, 1.93),
                    (51e-3, 0.02, 11e-3, 1.0001),
                ] {
                    let pl = Planform::new(l, l_r, w0, w_r, 0.0).unwrap();
                    let want = model::predict(model.kind(), &lam, &pl, drive).unwrap();
                    let r = model.shape_rates(&section, l_r, w_r);
                    let energy = l * w0 * r.energy * model.width_factor(&section, w0);
                    let mass = l * w0 * r.mass;
                    assert!(((energy - want.energy) / want.energy).abs() < 1e-12);
                    assert!(((mass - want.mass) / want.mass).abs() < 1e-12);
                    let p = model.performance(&section, &pl);
                    assert!(((p.energy - want.energy) / want.energy).abs() < 1e-14);
                }
            }
        }
    }

    #[test]
    fn model_names_round_trip() {
        for name in ["original", "thesis-adjusted", "euler-bernoulli"] {
            assert_eq!(parse_model_kind(name).unwrap().name(), name);
        }
        assert!(parse_model_kind("calibrated").is_err());
        assert!(SearchModel::from_kind(ModelKind::EulerBernoulli).is_none());
    }
}
