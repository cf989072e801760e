//! Fit one effect set on one stage: multi-start bounded least squares, then the information criteria,
//! covariance intervals and the cross-validated error that the selection compares.

use super::candidate::{Candidate, Role};
use super::cross_validation;
use super::identifiability;
use super::observations::StageData;
use crate::calibrate::fit::{least_squares, Bounds, FitResult};
use crate::calibrate::library::{EffectId, Stage};
use crate::calibrate::stats;
use actuator_model::EffectModel;
use nalgebra::DMatrix;

/// Every combination of the parameters' start values, clamped to their bounds.
fn starts(specs: &[(f64, f64, &'static [f64])]) -> Vec<Vec<f64>> {
    let mut out = vec![Vec::new()];
    for &(lo, hi, s) in specs {
        out = out
            .into_iter()
            .flat_map(|prefix| {
                s.iter().map(move |&v| {
                    let mut p = prefix.clone();
                    p.push(v.clamp(lo, hi));
                    p
                })
            })
            .collect();
    }
    out
}

/// Standard errors and 95% intervals (estimate ± t_{0.975, n-p} · SE) of a fit's parameters, from its
/// covariance `cov` (docs/calibration.md §3, "Intervals and identifiability").
pub(crate) fn intervals(fit: &FitResult, cov: &DMatrix<f64>) -> (Vec<f64>, Vec<(f64, f64)>) {
    let p = fit.theta.len();
    let t = stats::t_quantile_two_sided(0.95, (fit.n as f64 - p as f64).max(1.0));
    let std_errors: Vec<f64> = (0..p).map(|k| cov[(k, k)].max(0.0).sqrt()).collect();
    let intervals = fit
        .theta
        .iter()
        .zip(&std_errors)
        .map(|(v, se)| (v - t * se, v + t * se))
        .collect();
    (std_errors, intervals)
}

/// Fits effect sets on one stage's data on top of `base` (the frozen mass effects).
pub(super) struct Fitter<'a> {
    pub(super) data: &'a dyn StageData,
    pub(super) base: EffectModel,
    /// Fold of each actuator, per repeat.
    pub(super) folds: Vec<Vec<usize>>,
    /// Upper bound of the dead length: 80% of the shortest piezo length in the data.
    pub(super) dead_length_max_mm: f64,
    /// What all actuators share (identifiability reasons), if anything.
    pub(super) shared: Option<String>,
}

impl Fitter<'_> {
    fn bounds(&self, ids: &[EffectId]) -> Vec<Bounds> {
        ids.iter()
            .map(|id| {
                let p = id.param();
                let hi = if *id == EffectId::DeadLength {
                    p.hi.min(self.dead_length_max_mm)
                } else {
                    p.hi
                };
                Bounds { lo: p.lo, hi }
            })
            .collect()
    }

    fn effects_at(&self, ids: &[EffectId], theta: &[f64]) -> EffectModel {
        let mut e = self.base.clone();
        for (id, v) in ids.iter().zip(theta) {
            id.apply(&mut e, *v);
        }
        e
    }

    fn fit_on(
        &self,
        ids: &[EffectId],
        keep: Option<&[bool]>,
        starts_list: &[Vec<f64>],
    ) -> FitResult {
        let bounds = self.bounds(ids);
        let f = |theta: &[f64], out: &mut Vec<f64>| {
            self.data.residuals(&self.effects_at(ids, theta), keep, out)
        };
        least_squares(&f, &bounds, starts_list)
    }

    pub(super) fn fit(&self, ids: &[EffectId], stage: Stage, role: Role) -> Candidate {
        let bounds = self.bounds(ids);
        let specs: Vec<(f64, f64, &'static [f64])> = ids
            .iter()
            .zip(&bounds)
            .map(|(id, b)| (b.lo, b.hi, id.param().starts))
            .collect();
        let fit = self.fit_on(ids, None, &starts(&specs));
        let p = ids.len();
        let n = fit.n;
        let aicc = stats::aicc(n, p, fit.rss);
        let bic = n as f64 * (fit.rss.max(1e-300) / n as f64).ln() + p as f64 * (n as f64).ln();
        let cov = fit.covariance();
        let (std_errors, intervals) = intervals(&fit, &cov);
        let correlation = (0..p)
            .map(|a| {
                (0..p)
                    .map(|b| {
                        let d = (cov[(a, a)] * cov[(b, b)]).sqrt();
                        if d > 0.0 {
                            cov[(a, b)] / d
                        } else {
                            0.0
                        }
                    })
                    .collect()
            })
            .collect();
        // Each fold starts from the full-data fit; the original model has nothing to refit.
        let cv_rmse = cross_validation::rmse(self.data, &self.folds, |train| {
            if ids.is_empty() {
                self.base.clone()
            } else {
                let refit = self.fit_on(ids, Some(train), std::slice::from_ref(&fit.theta));
                self.effects_at(ids, &refit.theta)
            }
        });
        let not_identifiable = identifiability::not_identifiable(ids, &fit, self.shared.as_deref());
        Candidate {
            not_identifiable,
            stage,
            role,
            effects: ids.to_vec(),
            values: fit.theta.clone(),
            std_errors,
            intervals,
            correlation,
            rss: fit.rss,
            n,
            aicc,
            bic,
            cv_rmse,
            accepted: false,
            note: String::new(),
            model: self.effects_at(ids, &fit.theta),
            fit,
        }
    }
}
