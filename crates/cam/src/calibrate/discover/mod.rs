//! Discovery when no effect explains the residual (docs/calibration.md §3,
//! "Discovery"): what the remaining residual looks like, which physical primitives would produce it, and
//! which designs would tell the leading ones apart. The user then declares the leading candidate as an
//! effect and runs `calibrate` again.
//!
//! - [`pattern`]: per residual (deflection, stiffness, mass), a power law in the design variables
//!   together and in each variable or ratio alone, with intervals ([`power_law`]).
//! - [`catalogue`] and [`primitive_fit`]: each primitive of the model crate that is not a library effect,
//!   fitted as a one-parameter effect `{η, P}`, and again beside the best library effect A, `{η, A, P}`
//!   (data where a library effect and one outside it are both present). Ranked by AICc, on the same
//!   residuals, with the selection's own fits: the library's and the declared effects `{η, A}` and the
//!   library pairs `{η, A, B}` (the cross-validated error would cost ten refits each). A combination is
//!   listed only when it gains at least the selection's margin (ΔAICc 4) over each of its parts, the rule
//!   the selection applies to an added effect: a part that only fits noise does not push the single
//!   effect down the table.
//! - [`designs`]: the designs in the data's span where the two or three leading candidates disagree most.

pub mod catalogue;
pub mod designs;
pub mod mass_fit;
pub mod pattern;
pub mod power_law;
pub mod primitive_fit;
pub mod resonance_forms;
pub mod suggest;

use crate::calibrate::csv::Dataset;
use crate::calibrate::library::{effect_names, EffectId};
use crate::calibrate::rounded::{six_digits, six_digits_pair};
use crate::calibrate::select::{actuation_data, thickness, Role, Selection, Settings};
use actuator_model::EffectModel;
use actuator_model::ModelError;
use designs::{discriminate, DiscriminatingDesign, Predictor};
use mass_fit::MassForm;
use pattern::Trend;
use power_law::PowerLaw;
use primitive_fit::{Partner, PrimitiveFit};
use rayon::prelude::*;
use serde::Serialize;

/// How many leading candidates the designs separate.
const LEADING: usize = 3;

/// What discovery found.
#[derive(Debug, Clone, Serialize)]
pub struct Discovery {
    /// Power law of each residual in the independent design variables together.
    pub power_laws: Vec<PowerLaw>,
    /// Power law of each residual in each variable or ratio alone, smallest p first.
    pub trends: Vec<Trend>,
    /// The variable the residual follows most (the first trend), as `variable (residual)`.
    pub leading_variable: Option<String>,
    /// Explanations (single effects, and combinations that gain over their parts), best first.
    pub candidates: Vec<RankedCandidate>,
    /// What the ranking is by.
    pub ranked_by: &'static str,
    /// Designs that would separate the leading candidates.
    pub designs: Vec<DiscriminatingDesign>,
    /// The mass residual's explanations, best first (empty without weighed actuators): the
    /// selection's mass models and each mass-only form ([`mass_fit`]), by AICc on the log masses.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub mass_forms: Vec<MassForm>,
    /// The forms only the resonance separates, best gain first, when the resonance residuals fail
    /// their tests ([`resonance_forms`]).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub resonance_forms: Vec<resonance_forms::ResonanceForm>,
}

/// One explanation: `{η, X}` with X a library effect, a declared effect or a primitive, or a combination
/// `{η, A, X}` (named `A + X`).
#[derive(Debug, Clone, Serialize)]
pub struct RankedCandidate {
    /// Effect or primitive name; `A + X` for a combination.
    pub name: String,
    /// Library effects only (fits from the selection), rather than a declared effect or a primitive
    /// outside the library.
    pub library: bool,
    /// The parameter of X, with the unit (library and declared: report units; primitive: SI).
    pub parameter: String,
    /// Estimate.
    #[serde(serialize_with = "six_digits")]
    pub estimate: f64,
    /// 95% interval.
    #[serde(serialize_with = "six_digits_pair")]
    pub interval: (f64, f64),
    /// The d31 scale fitted with it.
    #[serde(serialize_with = "six_digits")]
    pub eta: f64,
    /// AICc.
    #[serde(serialize_with = "six_digits")]
    pub aicc: f64,
    /// AICc above the best candidate.
    #[serde(serialize_with = "six_digits")]
    pub delta_aicc: f64,
    /// AICc below the {η} null (more than 4: a real improvement).
    #[serde(serialize_with = "six_digits")]
    pub gain_over_eta: f64,
    /// RMSE of the log residuals of δ and F_b.
    #[serde(serialize_with = "six_digits")]
    pub rmse_log: f64,
    /// The other parameters fitted with it (A's in a combination, a declared effect's further ones).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub also: Vec<AlsoFitted>,
    #[serde(skip)]
    source: Source,
    /// The single explanations it combines (empty for a single one).
    #[serde(skip)]
    parts: Vec<String>,
}

impl RankedCandidate {
    /// The primitive outside the library it declares (the last part of a combination), if it is one.
    pub fn primitive(&self) -> Option<actuator_model::primitives::Primitive> {
        match &self.source {
            Source::Primitive(f) => Some(f.primitive),
            Source::Library(_) => None,
        }
    }

    /// The library effect fitted beside the primitive, in a combination.
    pub fn partner(&self) -> Option<&str> {
        match &self.source {
            Source::Primitive(f) => f.partner.as_ref().map(|id| id.name()),
            Source::Library(_) => None,
        }
    }
}

/// A further parameter of a ranked candidate.
#[derive(Debug, Clone, Serialize)]
pub struct AlsoFitted {
    /// Name with unit.
    pub parameter: String,
    /// Estimate.
    #[serde(serialize_with = "six_digits")]
    pub estimate: f64,
    /// 95% interval.
    #[serde(serialize_with = "six_digits_pair")]
    pub interval: (f64, f64),
}

#[derive(Debug, Clone)]
enum Source {
    Library(EffectModel),
    Primitive(PrimitiveFit),
}

/// Discovery on the data a not-explained `selection` was made on.
pub fn discover(
    data: &Dataset,
    selection: &Selection,
    settings: &Settings,
) -> Result<Discovery, ModelError> {
    // The frozen mass-stage effects: what every actuation candidate was fitted on top of.
    let base = selection
        .final_mass_index
        .map_or_else(EffectModel::default, |i| {
            selection.mass_candidates[i].model.clone()
        });
    let act = actuation_data(data, &base)?;
    let mass: Vec<(usize, f64)> = (0..data.actuators())
        .filter_map(|g| {
            let m = data.group_mass(g)?;
            let model = selection
                .model
                .mass(&data.rows[data.groups[g][0]].actuator())
                .ok()?
                .total();
            Some((g, (m / model).ln()))
        })
        .collect();
    let (power_laws, trends) = pattern::describe(data, &act, &selection.model, &mass);
    let leading_variable = trends
        .first()
        .map(|t| format!("{} ({} residual)", t.exponent.variable, t.residual));

    let eta_aicc = selection
        .candidates
        .iter()
        .find(|c| c.role == Role::Null && c.effects.len() == 1)
        .map_or(f64::INFINITY, |c| c.aicc);
    let mut ranked = selection_candidates(selection, settings, eta_aicc);
    let partners = partners(data, selection);
    let stack = catalogue::Stack::of(data, &base, !selection.mass_candidates.is_empty());
    let tried = catalogue::catalogue(stack);
    let jobs: Vec<(&catalogue::Tried, Option<&Partner>)> = tried
        .iter()
        .map(|t| (t, None))
        .chain(
            partners
                .iter()
                .flat_map(|x| tried.iter().map(move |t| (t, Some(x)))),
        )
        .collect();
    let fits: Vec<PrimitiveFit> = jobs
        .par_iter()
        .filter_map(|&(t, x)| primitive_fit::fit(&act, &base, t, x))
        .collect();
    ranked.extend(fits.into_iter().map(|f| primitive_candidate(f, eta_aicc)));
    keep_gaining(&mut ranked, settings.min_delta_aicc);
    ranked.sort_by(|a, b| a.aicc.total_cmp(&b.aicc).then(a.name.cmp(&b.name)));
    let best = ranked.first().map_or(0.0, |c| c.aicc);
    for c in &mut ranked {
        c.delta_aicc = c.aicc - best;
    }
    let designs = discriminate(data, &predictors(&ranked, &base), 3);
    let resonance_forms = if selection.adequacy.resonance.is_some_and(|t| !t.passed) {
        resonance_forms::rank(&act, &selection.model)
    } else {
        Vec::new()
    };
    Ok(Discovery {
        power_laws,
        trends,
        leading_variable,
        candidates: ranked,
        ranked_by: "AICc of {eta, X} and of combinations {eta, A, X} that gain 4 over each part (same residuals)",
        designs,
        mass_forms: mass_fit::rank(data, selection),
        resonance_forms,
    })
}

/// The selection's own fits `{η, X}` and `{η, A, B}` as explanations (library and declared effects),
/// but its thickness form, which the catalogue's inactive surface layer is, fitted with the primitives.
fn selection_candidates(
    selection: &Selection,
    settings: &Settings,
    eta_aicc: f64,
) -> Vec<RankedCandidate> {
    let eta_id = EffectId::D31Scale;
    selection
        .candidates
        .iter()
        .filter(|c| c.role == Role::Candidate && c.effects.first() == Some(&eta_id))
        .filter(|c| {
            !c.effects
                .iter()
                .any(|e| thickness::is_form(e, &settings.declared))
        })
        .map(|c| {
            let ids = c.library_effects();
            let names = effect_names(&ids);
            // X: the last effect's first parameter; the rest are reported beside it.
            let last = names[names.len() - 1];
            let k = c.effects.iter().position(|e| e.name() == last).unwrap_or(1);
            let also = (1..c.effects.len())
                .filter(|&j| j != k)
                .map(|j| AlsoFitted {
                    parameter: c.effects[j].param().name.into(),
                    estimate: c.values[j],
                    interval: c.intervals[j],
                })
                .collect();
            RankedCandidate {
                name: names.join(" + "),
                // A declared effect ranks with the library's, and says it is declared.
                library: !ids.iter().any(|id| matches!(id, EffectId::Declared(_))),
                parameter: c.effects[k].param().name.into(),
                estimate: c.values[k],
                interval: c.intervals[k],
                eta: c.values[0],
                aicc: c.aicc,
                delta_aicc: 0.0,
                gain_over_eta: eta_aicc - c.aicc,
                rmse_log: (c.rss / c.n.max(1) as f64).sqrt(),
                also,
                source: Source::Library(c.model.clone()),
                parts: if names.len() > 1 {
                    names.iter().map(|n| n.to_string()).collect()
                } else {
                    Vec::new()
                },
            }
        })
        .collect()
}

/// The partners of the combinations: the library effects of the best library model with one effect
/// and of the best with two (a library effect the data hold may fit worse alone than another that
/// mimics part of the unexplained effect, as a constant clamp compliance mimics one per width).
fn partners(data: &Dataset, selection: &Selection) -> Vec<Partner> {
    let eta_id = EffectId::D31Scale;
    let l_p_min_mm = data
        .rows
        .iter()
        .map(|r| r.planform.piezo_length() * 1e3)
        .fold(f64::INFINITY, f64::min);
    let best_library = |size: usize| {
        selection
            .candidates
            .iter()
            .filter(|c| c.role == Role::Candidate && c.effects.first() == Some(&eta_id))
            .filter(|c| c.effects.len() == size + 1)
            .filter(|c| c.effects[1..].iter().all(|e| EffectId::LIBRARY.contains(e)))
            .min_by(|a, b| a.aicc.total_cmp(&b.aicc))
    };
    let mut partners: Vec<Partner> = Vec::new();
    for c in [best_library(1), best_library(2)].into_iter().flatten() {
        for (k, id) in c.effects.iter().enumerate().skip(1) {
            if partners.iter().any(|x| x.id == *id) {
                continue;
            }
            let p = id.param();
            // The selection's own cap on the dead length (docs/calibration.md §3).
            let hi = if *id == EffectId::DeadLength {
                p.hi.min(0.8 * l_p_min_mm)
            } else {
                p.hi
            };
            partners.push(Partner {
                id: id.clone(),
                lo: p.lo,
                hi,
                start: c.values[k],
            });
        }
    }
    partners
}

/// A primitive outside the library as an explanation, alone `{η, P}` or beside a library effect
/// `{η, A, P}` (named `A + P`).
fn primitive_candidate(f: PrimitiveFit, eta_aicc: f64) -> RankedCandidate {
    let single = catalogue::name(f.primitive);
    let (name, parts, also) = match &f.partner {
        Some(id) => (
            format!("{} + {single}", id.name()),
            vec![id.name().to_string(), single.clone()],
            vec![AlsoFitted {
                parameter: id.param().name.into(),
                estimate: f.theta[2],
                interval: f.intervals[2],
            }],
        ),
        None => (single, Vec::new(), Vec::new()),
    };
    RankedCandidate {
        name,
        library: false,
        parameter: catalogue::parameter(f.primitive).into(),
        estimate: f.theta[1],
        interval: f.intervals[1],
        eta: f.theta[0],
        aicc: f.aicc,
        delta_aicc: 0.0,
        gain_over_eta: eta_aicc - f.aicc,
        rmse_log: (f.rss / f.n.max(1) as f64).sqrt(),
        also,
        source: Source::Primitive(f),
        parts,
    }
}

/// Keep a combination only when it gains `min_delta_aicc` (the selection's margin) over each of its
/// parts.
fn keep_gaining(ranked: &mut Vec<RankedCandidate>, min_delta_aicc: f64) {
    let single_aicc = |name: &str| {
        ranked
            .iter()
            .find(|c| c.parts.is_empty() && c.name == name)
            .map_or(f64::INFINITY, |c| c.aicc)
    };
    let keep: Vec<bool> = ranked
        .iter()
        .map(|c| {
            c.parts
                .iter()
                .all(|p| c.aicc <= single_aicc(p) - min_delta_aicc)
        })
        .collect();
    let mut keep = keep.into_iter();
    ranked.retain(|_| keep.next().unwrap_or(false));
}

/// The predictions of the leading candidates, for the designs that separate them.
fn predictors<'a>(ranked: &[RankedCandidate], base: &'a EffectModel) -> Vec<Predictor<'a>> {
    ranked
        .iter()
        .take(LEADING)
        .map(|c| {
            let f: Predictor = match &c.source {
                Source::Library(e) => {
                    let e = e.clone();
                    (c.name.clone(), Box::new(move |a| e.predict(a)))
                }
                Source::Primitive(p) => {
                    let p = p.clone();
                    (c.name.clone(), Box::new(move |a| p.predict(base, a)))
                }
            };
            f
        })
        .collect()
}
