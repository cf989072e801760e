//! The joint criterion discovery ranks by (docs/calibration.md §3, "Discovery", "Joint ranking"): every
//! explanation scored on the masses and on the deflections and forces at once, each kind with its own
//! noise, so that a primitive that changes the stack and the mass together (a PZT plate thinner than
//! ordered) is weighed against both residuals, not against the deflections and forces on top of a
//! mass model that has already absorbed the mass deficit in another layer.
//!
//! The criterion is the Gaussian log-likelihood of the log residuals with one variance per kind,
//! profiled (each variance at its estimate `RSS_k / n_k`), penalised as the selection's AICc:
//!
//! `J = n_a ln(RSS_a / n_a) + n_m ln(RSS_m / n_m) + 2k + 2k(k + 1)/(n_a - k - 1)`,
//!
//! `a` the deflections and forces, `m` the masses, `k` every fitted parameter (the mass model's
//! included; the small-sample term on `n_a`, as the selection's), and with measured resonances a third
//! kind, `+ n_f ln(RSS_f / n_f)`, each explanation's `f1` residuals at its fitted values. Without masses
//! and resonances it is the AICc the selection ranks by; for explanations on one mass model that leave
//! the mass and the resonance alone, those terms are constants and the ranking is that AICc's.

use crate::calibrate::csv::Dataset;
use crate::calibrate::select::observations::{ActuationData, StageData};
use crate::calibrate::select::Candidate;
use crate::calibrate::stats;
use actuator_model::EffectModel;

/// The log residuals of `model` on `act`: the deflections' and forces', and the resonances' as
/// measured (without the weight the fits give them).
pub(crate) fn split(act: &ActuationData, model: &EffectModel) -> (Vec<f64>, Vec<f64>) {
    let mut r = Vec::new();
    act.residuals(model, None, &mut r);
    let w = act.resonances.weight();
    let f1 = r.split_off(act.labels().len().min(r.len()));
    (r, f1.into_iter().map(|x| x / w).collect())
}

/// The resonance term of the criterion, `n_f ln(RSS_f / n_f)`, of the log resonance residuals `f1`:
/// 0 without measured resonances, infinite where the model cannot give one.
fn resonance_term_of(f1: &[f64]) -> f64 {
    if f1.is_empty() {
        return 0.0;
    }
    profiled_term(f1.len(), f1.iter().map(|x| x * x).sum())
}

/// The resonance term of `model` on `act` ([`resonance_term_of`]).
pub(crate) fn resonance_term(act: &ActuationData, model: &EffectModel) -> f64 {
    if act.resonances.len() == 0 {
        return 0.0;
    }
    resonance_term_of(&split(act, model).1)
}

/// A selection candidate scored as the primitive fits are: its AICc and the RMS of its log residuals
/// on the deflections and forces alone, and its resonance term. The selection counts each `f1` beside
/// the rows (one more reading); the primitive fits read the rows alone, and in `J` the resonances are a
/// kind of their own, so with resonances measured the candidate is scored again on the rows.
pub(crate) fn on_the_rows(act: &ActuationData, c: &Candidate) -> (f64, f64, f64) {
    if act.resonances.len() == 0 {
        return (c.aicc, (c.rss / c.n.max(1) as f64).sqrt(), 0.0);
    }
    let (rows, f1) = split(act, &c.model);
    let rss: f64 = rows.iter().map(|x| x * x).sum();
    (
        stats::aicc(rows.len(), c.values.len(), rss),
        (rss / rows.len().max(1) as f64).sqrt(),
        resonance_term_of(&f1),
    )
}

/// `n ln(RSS / n)`: twice the negative profiled Gaussian log-likelihood of `n` residuals, up to a
/// constant; infinite for a sum that is not finite.
fn profiled_term(n: usize, rss: f64) -> f64 {
    let n = n as f64;
    if rss.is_finite() && n > 0.0 {
        n * (rss.max(1e-300) / n).ln()
    } else {
        f64::INFINITY
    }
}

/// The weighed actuators, and the weight of a log mass residual beside a log deflection or force
/// residual in a fit of both (σ_a / σ_m).
#[derive(Debug, Clone)]
pub struct Masses {
    /// (a row of the actuator, ln measured mass), one per weighed actuator.
    pub weighed: Vec<(usize, f64)>,
    /// σ_a / σ_m.
    pub weight: f64,
}

impl Masses {
    /// The weighed actuators of `data`, weighted by `sigma_a2` (the deflections' and forces' noise
    /// variance) over `sigma_m2` (the masses'); None without weighed actuators.
    pub fn of(data: &Dataset, sigma_a2: f64, sigma_m2: f64) -> Option<Masses> {
        let weighed: Vec<(usize, f64)> = (0..data.actuators())
            .filter_map(|g| Some((data.groups[g][0], data.group_mass(g)?.ln())))
            .collect();
        let w = (sigma_a2 / sigma_m2.max(1e-8)).sqrt();
        (!weighed.is_empty()).then_some(Masses {
            weighed,
            weight: if w.is_finite() && w > 0.0 { w } else { 1.0 },
        })
    }

    /// The log mass residuals (measured over model) of `model`, each times `scale`, appended to `out`;
    /// NaN where the model cannot give a mass.
    pub fn push_residuals(
        &self,
        data: &Dataset,
        model: &EffectModel,
        scale: f64,
        out: &mut Vec<f64>,
    ) {
        out.extend(self.weighed.iter().map(|&(row, ln_m)| {
            let m = model
                .mass(&data.rows[row].actuator())
                .map_or(f64::NAN, |m| m.total());
            (ln_m - m.ln()) * scale
        }));
    }

    /// The sum of squares of the log mass residuals of `model`.
    pub fn rss(&self, data: &Dataset, model: &EffectModel) -> f64 {
        let mut r = Vec::with_capacity(self.weighed.len());
        self.push_residuals(data, model, 1.0, &mut r);
        r.iter().map(|x| x * x).sum()
    }

    /// The mass term of the criterion, `n_m ln(RSS_m / n_m)`.
    pub fn term(&self, rss: f64) -> f64 {
        profiled_term(self.weighed.len(), rss)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The mass term of masses fitted to within their 1 % noise is lower than that of a 7 % deficit by
    /// `n ln 49` (the profiled Gaussian log-likelihood, twice, of 30 masses).
    #[test]
    fn the_mass_term_is_the_masses_log_likelihood() {
        let masses = Masses {
            weighed: vec![(0, 0.0); 30],
            weight: 5.0,
        };
        let noise = masses.term(30.0 * 0.01f64.powi(2));
        let deficit = masses.term(30.0 * 0.07f64.powi(2));
        assert!((deficit - noise - 30.0 * 49f64.ln()).abs() < 1e-9);
    }
}
