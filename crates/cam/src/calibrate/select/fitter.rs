//! Fit one effect set on one stage: multi-start bounded least squares, then the information criteria,
//! covariance intervals and the cross-validated error that the selection compares.

use super::candidate::{Candidate, CarriedValue, Role};
use super::cross_validation;
use super::identifiability;
use super::joint::CarriedParameter;
use super::observations::{ActuationData, StageData};
use crate::calibrate::fit::{least_squares_grouped, FitResult, ParameterRange};
use crate::calibrate::library::{EffectId, Stage};
use crate::calibrate::stats;
use actuator_model::EffectModel;
use nalgebra::DMatrix;

/// Every combination of the parameters' start values, clamped to their bounds.
fn starts(specs: &[(f64, f64, &[f64])]) -> Vec<Vec<f64>> {
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
    /// Mass parameters fitted again with every effect set (the joint data's; empty: the mass model in
    /// `base` stays frozen).
    pub(super) carried: Vec<CarriedParameter>,
}

impl Fitter<'_> {
    fn bounds(&self, ids: &[EffectId]) -> Vec<ParameterRange> {
        ids.iter()
            .map(|id| {
                let p = id.param();
                let hi = if *id == EffectId::DeadLength {
                    p.hi.min(self.dead_length_max_mm)
                } else {
                    p.hi
                };
                ParameterRange { lo: p.lo, hi }
            })
            .collect()
    }

    /// The model with the carried mass parameters at `held` and `ids` at `theta`.
    fn model_at(&self, held: &[f64], ids: &[EffectId], theta: &[f64]) -> EffectModel {
        let mut e = self.base.clone();
        for (c, v) in self.carried.iter().zip(held) {
            c.id.apply(&mut e, *v);
        }
        for (id, v) in ids.iter().zip(theta) {
            id.apply(&mut e, *v);
        }
        e
    }

    /// The stage's deflections and forces with the carried mass parameters held at `held`: their stacks
    /// once, and the masses, which only they move, left out (None: nothing is carried; fit the stage's
    /// data).
    fn held_data(&self, held: &[f64]) -> Option<ActuationData<'_>> {
        self.data.held_at(&self.model_at(held, &[], &[]))
    }

    /// Fit `ids` after the carried mass parameters, which are fitted too when `held` is empty (then
    /// `theta` starts with them) and else held there, with `held_data` the stage's data at them
    /// ([`Fitter::held_data`]).
    fn fit_on(
        &self,
        ids: &[EffectId],
        (held, held_data): (&[f64], Option<&ActuationData>),
        keep: Option<&[bool]>,
        starts_list: &[Vec<f64>],
    ) -> FitResult {
        let c = if held.is_empty() {
            self.carried.len()
        } else {
            0
        };
        let mut bounds: Vec<ParameterRange> = self.carried[..c].iter().map(|p| p.bounds).collect();
        bounds.extend(self.bounds(ids));
        let f = |theta: &[f64], out: &mut Vec<f64>| {
            if c > 0 {
                let model = self.model_at(&theta[..c], ids, &theta[c..]);
                self.data.residuals(&model, keep, out)
            } else {
                let model = self.model_at(held, ids, theta);
                match &held_data {
                    Some(d) => d.residuals(&model, keep, out),
                    None => self.data.held_out(&model, keep, out),
                }
            }
        };
        // A model linear in the field at every value of its parameters (the carried mass effects are)
        // is searched on the grouped residuals, where the stage has them.
        let linear = self.base.linear_in_field() && ids.iter().all(EffectId::linear_in_field);
        let grouped = |theta: &[f64], out: &mut Vec<f64>| {
            let left_out = if !linear {
                None
            } else if c > 0 {
                let model = self.model_at(&theta[..c], ids, &theta[c..]);
                self.data.grouped(&model, keep, out)
            } else {
                let model = self.model_at(held, ids, theta);
                match &held_data {
                    Some(d) => d.grouped(&model, keep, out),
                    None => self.data.grouped_held_out(&model, keep, out),
                }
            };
            if left_out.is_none() {
                f(theta, out);
            }
            left_out
        };
        least_squares_grouped(&grouped, &f, &bounds, starts_list)
    }

    pub(super) fn fit(&self, ids: &[EffectId], stage: Stage, role: Role) -> Candidate {
        self.fit_scored(ids, stage, role, true)
    }

    /// [`Fitter::fit`] without the cross-validation (its error left infinite): a screen for a model
    /// that is fitted in full only if its AICc qualifies.
    pub(super) fn fit_without_cv(&self, ids: &[EffectId], stage: Stage, role: Role) -> Candidate {
        self.fit_scored(ids, stage, role, false)
    }

    fn fit_scored(&self, ids: &[EffectId], stage: Stage, role: Role, cv: bool) -> Candidate {
        let bounds = self.bounds(ids);
        let specs: Vec<(f64, f64, &[f64])> = ids
            .iter()
            .zip(&bounds)
            .map(|(id, b)| (b.lo, b.hi, id.param().starts))
            .collect();
        // The search from every start with the mass parameters at their masses-only values (as cheap
        // as a frozen mass model), then one joint fit of all of them from the best.
        let masses_only: Vec<f64> = self.carried.iter().map(|c| c.start).collect();
        let masses_only_data = self.held_data(&masses_only);
        let at_masses_only = (&masses_only[..], masses_only_data.as_ref());
        let frozen = self.fit_on(ids, at_masses_only, None, &starts(&specs));
        let joint = if self.carried.is_empty() {
            frozen
        } else {
            let start: Vec<f64> = masses_only.iter().chain(&frozen.theta).copied().collect();
            self.fit_on(ids, (&[], None), None, &[start])
        };
        let c = self.carried.len();
        let carried = carried_values(&self.carried, &joint);
        // The scores, intervals and identifiability are those of this stage's own effects on its own
        // outputs, at the carried mass values (as they were when those were frozen).
        let fit = own_part(&joint, c, self.data.scored_rows());
        let held: Vec<f64> = joint.theta[..c].to_vec();
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
        // The carried mass parameters stay at their full-data values: the folds compare the effects this
        // stage adds.
        let cv_rmse = if !cv {
            f64::INFINITY
        } else {
            let held_data = (!ids.is_empty()).then(|| self.held_data(&held)).flatten();
            cross_validation::rmse(self.data, &self.folds, |train| {
                if ids.is_empty() {
                    self.model_at(&held, ids, &[])
                } else {
                    let at_held = (&held[..], held_data.as_ref());
                    let refit =
                        self.fit_on(ids, at_held, Some(train), std::slice::from_ref(&fit.theta));
                    self.model_at(&held, ids, &refit.theta)
                }
            })
        };
        let not_identifiable = identifiability::not_identifiable(ids, &fit, self.shared.as_deref());
        Candidate {
            carried,
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
            model: self.model_at(&held, ids, &fit.theta),
            fit,
        }
    }
}

/// The carried mass parameters of a joint fit with their intervals, from its covariance on all its data
/// (the masses weighted by their noise).
fn carried_values(carried: &[CarriedParameter], joint: &FitResult) -> Vec<CarriedValue> {
    if carried.is_empty() {
        return Vec::new();
    }
    let (std_errors, intervals) = intervals(joint, &joint.covariance());
    carried
        .iter()
        .enumerate()
        .map(|(k, c)| CarriedValue {
            id: c.id.clone(),
            value: joint.theta[k],
            std_error: std_errors[k],
            interval: intervals[k],
        })
        .collect()
}

/// A joint fit restricted to the parameters after the first `carried` and to the first `scored`
/// residuals (None: all).
fn own_part(joint: &FitResult, carried: usize, scored: Option<usize>) -> FitResult {
    let n = scored.unwrap_or(joint.n).min(joint.n);
    if carried == 0 && n == joint.n {
        return joint.clone();
    }
    let p = joint.theta.len() - carried;
    let residuals = joint.residuals[..n].to_vec();
    FitResult {
        theta: joint.theta[carried..].to_vec(),
        rss: residuals.iter().map(|r| r * r).sum(),
        n,
        residuals,
        jacobian: joint.jacobian.view((0, carried), (n, p)).into_owned(),
    }
}
