//! Discovery when no effect explains the residual (issue 17 item 5; docs/calibration.md §3,
//! "Discovery"): what the remaining residual looks like, which physical primitives would produce it, and
//! which designs would tell the leading ones apart. The user then declares the leading candidate as an
//! effect and runs `calibrate` again.
//!
//! - [`pattern`]: per residual (deflection, stiffness, mass), a power law in the design variables
//!   together and in each variable or ratio alone, with intervals ([`power_law`]).
//! - [`catalogue`] and [`primitive_fit`]: each primitive of the model crate that is not a library effect,
//!   fitted as a one-parameter effect `{η, P}`; ranked with the library's own single-effect fits
//!   `{η, A}` by AICc (every one has two parameters, on the same residuals: AICc orders them as the
//!   residual sum of squares does; the cross-validated error would cost ten refits each).
//! - [`designs`]: the designs in the data's span where the two or three leading candidates disagree most.

pub mod catalogue;
pub mod designs;
pub mod pattern;
pub mod power_law;
pub mod primitive_fit;

use crate::calibrate::csv::Dataset;
use crate::calibrate::library::EffectId;
use crate::calibrate::rounded::{six_digits, six_digits_pair};
use crate::calibrate::select::{actuation_data, Role, Selection};
use actuator_model::EffectModel;
use actuator_model::ModelError;
use designs::{discriminate, DiscriminatingDesign, Predictor};
use pattern::Trend;
use power_law::PowerLaw;
use primitive_fit::PrimitiveFit;
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
    /// Single-effect explanations, best first.
    pub candidates: Vec<RankedCandidate>,
    /// What the ranking is by.
    pub ranked_by: &'static str,
    /// Designs that would separate the leading candidates.
    pub designs: Vec<DiscriminatingDesign>,
}

/// One single-effect explanation `{η, X}`, X a library effect or a primitive.
#[derive(Debug, Clone, Serialize)]
pub struct RankedCandidate {
    /// Effect or primitive name.
    pub name: String,
    /// A library effect (its fit from the selection) rather than a primitive outside the library.
    pub library: bool,
    /// Its parameter, with the unit (library: report units; primitive: SI).
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
    #[serde(skip)]
    source: Source,
}

#[derive(Debug, Clone)]
enum Source {
    Library(EffectModel),
    Primitive(PrimitiveFit),
}

/// Discovery on the data a not-explained `selection` was made on.
pub fn discover(data: &Dataset, selection: &Selection) -> Result<Discovery, ModelError> {
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
        .find(|c| c.role == Role::Null && c.effects.len() - c.carried == 1)
        .map_or(f64::INFINITY, |c| c.aicc);
    let mut ranked: Vec<RankedCandidate> = selection
        .candidates
        .iter()
        .filter(|c| c.role == Role::Candidate && c.effects.len() - c.carried == 2)
        .filter_map(|c| {
            let id = *c.own_effects().first()?;
            let k = c.effects.iter().position(|e| *e == id)?;
            let eta = c.values[c.effects.iter().position(|e| *e == EffectId::D31Scale)?];
            Some(RankedCandidate {
                name: id.name().into(),
                // A declared effect ranks with the library's, and says it is declared.
                library: !matches!(id, EffectId::Declared(_)),
                parameter: id.param().name.into(),
                estimate: c.values[k],
                interval: c.intervals[k],
                eta,
                aicc: c.aicc,
                delta_aicc: 0.0,
                gain_over_eta: eta_aicc - c.aicc,
                rmse_log: (c.rss / c.n.max(1) as f64).sqrt(),
                source: Source::Library(c.model.clone()),
            })
        })
        .collect();
    let fits: Vec<PrimitiveFit> = catalogue::catalogue()
        .par_iter()
        .filter_map(|t| primitive_fit::fit(data, &act, &base, t))
        .collect();
    ranked.extend(fits.into_iter().map(|f| RankedCandidate {
        name: catalogue::name(f.primitive),
        library: false,
        parameter: catalogue::parameter(f.primitive).into(),
        estimate: f.theta[1],
        interval: f.interval,
        eta: f.theta[0],
        aicc: f.aicc,
        delta_aicc: 0.0,
        gain_over_eta: eta_aicc - f.aicc,
        rmse_log: (f.rss / f.n.max(1) as f64).sqrt(),
        source: Source::Primitive(f),
    }));
    ranked.sort_by(|a, b| a.aicc.total_cmp(&b.aicc).then(a.name.cmp(&b.name)));
    let best = ranked.first().map_or(0.0, |c| c.aicc);
    for c in &mut ranked {
        c.delta_aicc = c.aicc - best;
    }
    let predictors: Vec<Predictor> = ranked
        .iter()
        .take(LEADING)
        .map(|c| {
            let f: Predictor = match &c.source {
                Source::Library(e) => {
                    let e = e.clone();
                    (c.name.clone(), Box::new(move |a| e.predict(a)))
                }
                Source::Primitive(p) => {
                    let (p, base) = (p.clone(), &base);
                    (c.name.clone(), Box::new(move |a| p.predict(base, a)))
                }
            };
            f
        })
        .collect();
    let designs = discriminate(data, &predictors, 3);
    Ok(Discovery {
        power_laws,
        trends,
        leading_variable,
        candidates: ranked,
        ranked_by: "AICc of {eta, X} (two parameters each, same residuals)",
        designs,
    })
}
