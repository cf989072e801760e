//! Discovery when no effect explains the residual (docs/calibration.md §3,
//! "Discovery"): what the remaining residual looks like, which physical primitives would produce it, and
//! which designs would tell the leading ones apart. The user then declares the leading candidate as an
//! effect and runs `calibrate` again.
//!
//! - [`pattern`]: per residual (deflection, stiffness, mass), a power law in the design variables
//!   together and in each variable or ratio alone, with intervals ([`power_law`]).
//! - [`catalogue`] and [`primitive_fit`]: each primitive of the model crate that is not a library effect,
//!   fitted as a one-parameter effect `{η, P}`, and again beside the best library effect A, `{η, A, P}`
//!   (data where a library effect and one outside it are both present). A primitive that changes the
//!   mass is fitted on the masses too, and again in place of the chosen mass model. Ranked by the joint
//!   criterion of [`joint`] (masses, deflections, forces and resonances, each kind by its own noise) with the
//!   selection's own fits: the library's and the declared effects `{η, A}` and the
//!   library pairs `{η, A, B}` (the cross-validated error would cost ten refits each). A combination is
//!   listed only when it gains at least the selection's margin (ΔAICc 4) over each of its parts, the rule
//!   the selection applies to an added effect: a part that only fits noise does not push the single
//!   effect down the table.
//! - [`designs`]: the designs in the data's span where the two or three leading candidates disagree most.

pub mod catalogue;
pub mod designs;
pub mod joint;
pub mod mass_fit;
pub mod pattern;
pub mod power_law;
pub mod primitive_fit;
pub mod resonance_forms;
pub mod suggest;

use crate::calibrate::csv::Dataset;
use crate::calibrate::library::{effect_names, EffectId};
use crate::calibrate::rounded::{six_digits, six_digits_pair};
use crate::calibrate::select::observations::ActuationData;
use crate::calibrate::select::{actuation_data, adequacy, thickness, Role, Selection, Settings};
use actuator_model::ModelError;
use actuator_model::{EffectModel, Effects};
use designs::{discriminate, DiscriminatingDesign, Predictor};
use joint::Masses;
use mass_fit::MassForm;
use pattern::Trend;
use power_law::PowerLaw;
use primitive_fit::{Partner, PrimitiveFit};
use rayon::prelude::*;
use serde::Serialize;

/// How many leading candidates the designs separate.
const LEADING: usize = 3;

/// How far above the best mass form's mass term a fit's own may be and still explain the masses: the
/// selection's acceptance margin.
const MASS_MARGIN: f64 = 4.0;

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
    /// AICc of the deflections and forces.
    #[serde(serialize_with = "six_digits")]
    pub aicc: f64,
    /// The joint criterion ranked by ([`joint`]): the AICc with the masses' log-likelihood.
    #[serde(serialize_with = "six_digits")]
    pub joint: f64,
    /// Fitted on the masses too, and fitting them as well as the best mass form (within
    /// [`MASS_MARGIN`] of its mass term).
    pub explains_masses: bool,
    /// Joint criterion above the best candidate.
    #[serde(serialize_with = "six_digits")]
    pub delta_aicc: f64,
    /// Joint criterion below the {η} null on the chosen mass model (more than 4: a real improvement).
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

    let mass_forms = mass_fit::rank(data, selection);
    let scoring = Scoring::of(data, &act, &base, selection, &mass_forms);
    let eta_joint = selection
        .candidates
        .iter()
        .find(|c| c.role == Role::Null && c.effects.len() == 1)
        .map_or(f64::INFINITY, |c| {
            let (aicc, _, resonance) = joint::on_the_rows(&act, c);
            aicc + scoring.base_term + resonance
        });
    let mut ranked = selection_candidates(data, &act, selection, settings, &scoring, eta_joint);
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
    let masses_of = |t: &catalogue::Tried| {
        scoring
            .masses
            .as_ref()
            .filter(|_| catalogue::mass_counts(t.primitive))
    };
    let mut fits: Vec<PrimitiveFit> = jobs
        .par_iter()
        .filter_map(|&(t, x)| primitive_fit::fit(&act, &base, t, x, masses_of(t)))
        .collect();
    if let Some(masses) = scoring
        .masses
        .as_ref()
        .filter(|_| scoring.replaced.is_some())
    {
        fits.extend(in_place(data, masses)?);
    }
    ranked.extend(
        fits.into_par_iter()
            .map(|f| primitive_candidate(f, &act, eta_joint, &scoring))
            .collect::<Vec<_>>(),
    );
    keep_gaining(&mut ranked, settings.min_delta_aicc);
    ranked.sort_by(|a, b| a.joint.total_cmp(&b.joint).then(a.name.cmp(&b.name)));
    let best = ranked.first().map_or(0.0, |c| c.joint);
    for c in &mut ranked {
        c.delta_aicc = c.joint - best;
    }
    let designs = discriminate(data, &predictors(&ranked), 3);
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
        ranked_by:
            "the joint AICc of deflections, forces, masses and resonances, each kind with its own variance, of \
                    {eta, X} and of combinations {eta, A, X} that gain 4 over each part",
        designs,
        mass_forms,
        resonance_forms,
    })
}

/// The primitives that change the mass fitted again in place of the mass model the masses chose, on the
/// original model, on the masses and the stack together: a mass deficit the chosen model put into
/// another layer is then not one discovery must undo.
fn in_place(data: &Dataset, masses: &Masses) -> Result<Vec<PrimitiveFit>, ModelError> {
    let original = EffectModel::default();
    let act = actuation_data(data, &original)?;
    let tried: Vec<catalogue::Tried> =
        catalogue::catalogue(catalogue::Stack::of(data, &original, true))
            .into_iter()
            .filter(|t| catalogue::mass_counts(t.primitive))
            .collect();
    Ok(tried
        .par_iter()
        .filter_map(|t| primitive_fit::fit(&act, &original, t, None, Some(masses)))
        .collect())
}

/// What the joint criterion ([`joint`]) needs beside each fit: the weighed masses, the mass term and
/// parameter count of the chosen mass model, and that model's label when it has effects (the primitives
/// that change the mass are then also fitted in its place).
struct Scoring {
    masses: Option<Masses>,
    /// `n_m ln(RSS_m / n_m)` of the chosen mass model, plus 2 per mass parameter (0 without masses).
    base_term: f64,
    /// 2 per parameter of the chosen mass model.
    base_penalty: f64,
    replaced: Option<String>,
    /// The mass term of the best mass form: a fit whose own is within the margin explains the masses.
    best_mass_term: f64,
}

impl Scoring {
    fn of(
        data: &Dataset,
        act: &ActuationData,
        base: &EffectModel,
        selection: &Selection,
        mass_forms: &[MassForm],
    ) -> Scoring {
        let chosen = selection
            .final_mass_index
            .map(|i| &selection.mass_candidates[i])
            .filter(|c| !c.effects.is_empty());
        let base_penalty = 2.0 * chosen.map_or(0, |c| c.values.len()) as f64;
        // The deflections' and forces' noise from the sweeps' pure error, else their spread under {η};
        // the masses' from the best mass form (what the masses show at best).
        let sigma_a2 = adequacy::pure_error_variance(act, base).unwrap_or_else(|| {
            selection
                .candidates
                .iter()
                .find(|c| c.role == Role::Null && c.effects.len() == 1)
                .map_or(1.0, |c| c.rss / c.n.max(1) as f64)
        });
        let sigma_m2 = mass_forms
            .iter()
            .map(|f| f.rmse_log * f.rmse_log)
            .fold(f64::INFINITY, f64::min);
        let masses = (!selection.mass_candidates.is_empty())
            .then(|| Masses::of(data, sigma_a2, sigma_m2))
            .flatten();
        let (base_term, best_mass_term) = masses.as_ref().map_or((0.0, 0.0), |m| {
            let n = m.weighed.len() as f64;
            (
                m.term(m.rss(data, base)) + base_penalty,
                m.term(sigma_m2 * n),
            )
        });
        Scoring {
            replaced: chosen.map(|c| c.label()),
            masses,
            base_term,
            base_penalty,
            best_mass_term,
        }
    }

    /// The mass part of a fit's criterion: its own mass term when the masses were fitted with it
    /// (`rss_mass`), else the chosen mass model's; with the mass model's parameters on `base_of`
    /// (false: fitted in its place).
    fn mass_part(&self, rss_mass: Option<f64>, on_chosen: bool) -> f64 {
        let penalty = if on_chosen { self.base_penalty } else { 0.0 };
        match (&self.masses, rss_mass) {
            (Some(m), Some(rss)) => m.term(rss) + penalty,
            _ => self.base_term,
        }
    }
}

/// The selection's own fits `{η, X}` and `{η, A, B}` as explanations (library and declared effects),
/// but its thickness form, which the catalogue's inactive surface layer is, fitted with the primitives.
fn selection_candidates(
    data: &Dataset,
    act: &ActuationData,
    selection: &Selection,
    settings: &Settings,
    scoring: &Scoring,
    eta_joint: f64,
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
            // The carried mass parameters refitted beside it: the mass term at its own values.
            let (aicc, rmse_log, resonance) = joint::on_the_rows(act, c);
            let joint =
                aicc + match (&scoring.masses, c.carried.is_empty()) {
                    (Some(m), false) => m.term(m.rss(data, &c.model)) + scoring.base_penalty,
                    _ => scoring.base_term,
                } + resonance;
            RankedCandidate {
                name: names.join(" + "),
                // A declared effect ranks with the library's, and says it is declared.
                library: !ids.iter().any(|id| matches!(id, EffectId::Declared(_))),
                parameter: c.effects[k].param().name.into(),
                estimate: c.values[k],
                interval: c.intervals[k],
                eta: c.values[0],
                aicc,
                joint,
                explains_masses: false,
                delta_aicc: 0.0,
                gain_over_eta: eta_joint - joint,
                rmse_log,
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
fn primitive_candidate(
    f: PrimitiveFit,
    act: &ActuationData,
    eta_joint: f64,
    scoring: &Scoring,
) -> RankedCandidate {
    let single = catalogue::name(f.primitive);
    // Fitted in place of the chosen mass model: on the original model.
    let in_place = f.base.primitives.is_empty() && f.base.effects == Effects::default();
    let on_chosen = !in_place || scoring.replaced.is_none();
    let joint =
        f.aicc + scoring.mass_part(f.rss_mass, on_chosen) + joint::resonance_term(act, &f.model());
    let explains_masses = match (&scoring.masses, f.rss_mass) {
        (Some(m), Some(rss)) => m.term(rss) < scoring.best_mass_term + MASS_MARGIN,
        _ => false,
    };
    let single = match (&scoring.replaced, on_chosen) {
        (Some(label), false) => format!("{single} in place of {label}"),
        _ => single,
    };
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
        joint,
        explains_masses,
        delta_aicc: 0.0,
        gain_over_eta: eta_joint - joint,
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
            .map_or(f64::INFINITY, |c| c.joint)
    };
    let keep: Vec<bool> = ranked
        .iter()
        .map(|c| {
            c.parts
                .iter()
                .all(|p| c.joint <= single_aicc(p) - min_delta_aicc)
        })
        .collect();
    let mut keep = keep.into_iter();
    ranked.retain(|_| keep.next().unwrap_or(false));
}

/// The predictions of the leading candidates, for the designs that separate them.
fn predictors(ranked: &[RankedCandidate]) -> Vec<Predictor<'static>> {
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
                    (c.name.clone(), Box::new(move |a| p.predict(a)))
                }
            };
            f
        })
        .collect()
}
