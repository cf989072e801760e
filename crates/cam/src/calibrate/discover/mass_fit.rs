//! The mass residual on its own (docs/calibration.md §3, "Discovery"): each mass-only form of
//! [`mass_catalogue`] fitted to the measured masses, alone on the original model and on top of the mass
//! model the selection chose, and ranked with the selection's own mass models by AICc on the same
//! `ln m` residuals. A mass that grows with the perimeter (adhesive fillets), a fixed one (leads and
//! solder) and one that grows with the bonded area are told apart here by their shapes across the
//! designs, which no stiffness or actuation effect can mimic.
//!
//! Every form is affine in its parameter (`m(p) = m(null) + (p - null) dm`), so each actuator's mass is
//! computed at two values and the fit costs no model evaluation.

use super::catalogue::{self, mass_catalogue, Tried};
use crate::calibrate::csv::Dataset;
use crate::calibrate::fit::{least_squares, ParameterRange};
use crate::calibrate::rounded::{six_digits, six_digits_pair};
use crate::calibrate::select::fitter::intervals;
use crate::calibrate::select::{Role, Selection};
use crate::calibrate::stats;
use actuator_model::primitives::Applied;
use actuator_model::EffectModel;
use serde::Serialize;

/// One explanation of the mass residual.
#[derive(Debug, Clone, Serialize)]
pub struct MassForm {
    /// The form's name (`chosen + form` on top of the selection's mass model), or a selection's mass
    /// model (`{ply-thickness}`, `original`).
    pub name: String,
    /// A mass model of the selection (library or declared effects) rather than a mass-only form.
    pub library: bool,
    /// The form's parameter with its unit (SI); empty for the selection's models.
    pub parameter: String,
    /// Estimate.
    #[serde(serialize_with = "six_digits")]
    pub estimate: f64,
    /// 95% interval.
    #[serde(serialize_with = "six_digits_pair")]
    pub interval: (f64, f64),
    /// AICc on the log masses.
    #[serde(serialize_with = "six_digits")]
    pub aicc: f64,
    /// AICc above the best form.
    #[serde(serialize_with = "six_digits")]
    pub delta_aicc: f64,
    /// AICc below the mass model the selection chose (more than 4: a real improvement).
    #[serde(serialize_with = "six_digits")]
    pub gain_over_chosen: f64,
    /// RMSE of the log mass residuals.
    #[serde(serialize_with = "six_digits")]
    pub rmse_log: f64,
    /// The primitive and its bounds (SI), for a mass-only form.
    #[serde(skip)]
    pub primitive: Option<Tried>,
}

impl MassForm {
    /// Whether its 95 % interval excludes the primitive's null value.
    pub fn excludes_null(&self) -> bool {
        let null = self.primitive.map_or(f64::NAN, |t| t.primitive.null());
        self.interval.0 > null || self.interval.1 < null
    }
}

/// Rank the mass forms on `data`'s weighed actuators; empty when the selection fitted no masses.
pub fn rank(data: &Dataset, selection: &Selection) -> Vec<MassForm> {
    if selection.mass_candidates.is_empty() {
        return Vec::new();
    }
    let weighed: Vec<(usize, f64)> = (0..data.actuators())
        .filter_map(|g| Some((data.groups[g][0], data.group_mass(g)?.ln())))
        .collect();
    let chosen = selection
        .final_mass_index
        .map(|i| &selection.mass_candidates[i]);
    let chosen_aicc = chosen.map_or_else(
        || {
            selection
                .mass_candidates
                .iter()
                .find(|c| c.role == Role::Original)
                .map_or(f64::INFINITY, |c| c.aicc)
        },
        |c| c.aicc,
    );
    let mut forms: Vec<MassForm> = selection
        .mass_candidates
        .iter()
        .map(|c| MassForm {
            name: c.label(),
            library: true,
            parameter: String::new(),
            estimate: f64::NAN,
            interval: (f64::NAN, f64::NAN),
            aicc: c.aicc,
            delta_aicc: 0.0,
            gain_over_chosen: chosen_aicc - c.aicc,
            rmse_log: (c.rss / c.n.max(1) as f64).sqrt(),
            primitive: None,
        })
        .collect();
    let mut bases: Vec<(String, EffectModel, usize)> =
        vec![(String::new(), EffectModel::default(), 0)];
    if let Some(c) = chosen.filter(|c| !c.effects.is_empty()) {
        bases.push((format!("{} + ", c.label()), c.model.clone(), c.values.len()));
    }
    for (prefix, base, frozen) in &bases {
        for tried in mass_catalogue() {
            if let Some(form) = fit(data, &weighed, base, tried, *frozen) {
                forms.push(MassForm {
                    name: format!("{prefix}{}", catalogue::name(tried.primitive)),
                    gain_over_chosen: chosen_aicc - form.aicc,
                    ..form
                });
            }
        }
    }
    forms.sort_by(|a, b| a.aicc.total_cmp(&b.aicc).then(a.name.cmp(&b.name)));
    let best = forms.first().map_or(0.0, |f| f.aicc);
    for f in &mut forms {
        f.delta_aicc = f.aicc - best;
    }
    forms
}

/// Fit one form on top of `base` (whose `frozen` parameters count in the AICc).
fn fit(
    data: &Dataset,
    weighed: &[(usize, f64)],
    base: &EffectModel,
    tried: Tried,
    frozen: usize,
) -> Option<MassForm> {
    let null = tried.primitive.null();
    let probe = if null == 0.0 { tried.hi } else { 2.0 };
    let mass_at = |row: usize, value: f64| -> Option<f64> {
        let mut m = base.clone();
        m.primitives.push(Applied {
            primitive: tried.primitive,
            value,
        });
        Some(m.mass(&data.rows[row].actuator()).ok()?.total())
    };
    // (ln measured, mass at null, dm per unit of the parameter)
    let affine: Vec<(f64, f64, f64)> = weighed
        .iter()
        .map(|&(row, ln_m)| {
            let m0 = mass_at(row, null)?;
            Some((ln_m, m0, (mass_at(row, probe)? - m0) / (probe - null)))
        })
        .collect::<Option<_>>()?;
    if affine.iter().all(|a| a.2 == 0.0) {
        return None;
    }
    let residuals = |theta: &[f64], out: &mut Vec<f64>| {
        out.clear();
        out.extend(
            affine
                .iter()
                .map(|&(ln_m, m0, dm)| ln_m - (m0 + (theta[0] - null) * dm).max(1e-30).ln()),
        );
    };
    let bounds = [ParameterRange {
        lo: tried.lo,
        hi: tried.hi,
    }];
    let starts = [vec![null], vec![0.5 * (tried.lo + tried.hi)]];
    let result = least_squares(&residuals, &bounds, &starts);
    let (_, ci) = intervals(&result, &result.covariance());
    let aicc = stats::aicc(result.n, frozen + 1, result.rss);
    Some(MassForm {
        name: String::new(),
        library: false,
        parameter: catalogue::parameter(tried.primitive).into(),
        estimate: result.theta[0],
        interval: ci[0],
        aicc,
        delta_aicc: 0.0,
        gain_over_chosen: 0.0,
        rmse_log: (result.rss / result.n.max(1) as f64).sqrt(),
        primitive: Some(tried),
    })
}
