//! Which fitted models are accepted, and which accepted models the data cannot tell apart.

use super::candidate::{Candidate, Role};
use super::settings::Settings;
use crate::calibrate::library::{effect_names, EffectId};
use crate::calibrate::stats;

/// The stages whose candidates share the selection's level (the mass stage and the actuation stage):
/// each is held to `alpha / STAGES`, so together they make one false selection in `1 / alpha`.
const STAGES: f64 = 2.0;

/// The p-value of `c`'s gain over the nested null `base`: the F test of nested least squares
/// (Seber & Wild, Nonlinear Regression, 1989, ch. 5: `F = ((RSS₀ - RSS)/(p - p₀)) / (RSS/(n - p))` on
/// `(p - p₀, n - p)` degrees of freedom, asymptotically valid for any noise of finite variance).
fn gain_p(c: &Candidate, base: &Candidate) -> f64 {
    let (p, p0) = (c.effects.len() as f64, base.effects.len() as f64);
    let dof = c.n as f64 - p;
    if p <= p0 || dof < 1.0 || c.rss <= 0.0 {
        return 0.0;
    }
    let f = ((base.rss - c.rss).max(0.0) / (p - p0)) / (c.rss / dof);
    stats::f_upper_p(f, p - p0, dof)
}

/// Why `c` is not accepted for its gain over the first null `base` among `m` candidates: the selection
/// tries every candidate against the same null, so under no effect one of `m` passes ΔAICc > 4 (a
/// likelihood ratio above 6, p ≈ 0.014 for one parameter) about `m` times as often as one does. The gain
/// must be significant at the selection's share of the level, Bonferroni-divided over the `m`
/// (docs/calibration.md §3, step 4).
fn multiplicity(c: &Candidate, base: &Candidate, m: usize, settings: &Settings) -> Option<String> {
    let level = settings.alpha / STAGES / m.max(1) as f64;
    let p = gain_p(c, base);
    (p >= level).then(|| {
        format!(
            "gain over {} not significant among {m} candidates (p = {p:.2e}, needs < {level:.1e})",
            base.label()
        )
    })
}

/// Whether candidate `i` of `candidates` gains significantly over the null `candidates[null]` among
/// all their candidates (the multiplicity test of [`judge`]).
pub(super) fn gains_among(
    candidates: &[Candidate],
    i: usize,
    null: usize,
    settings: &Settings,
) -> bool {
    let m = candidates
        .iter()
        .filter(|c| c.role == Role::Candidate)
        .count();
    multiplicity(&candidates[i], &candidates[null], m, settings).is_none()
}

/// Mark which candidates pass: ΔAICc over every parent (the nulls for singles, both singles for a pair),
/// better cross-validation than every parent, and intervals that exclude the null value.
pub(super) fn judge(candidates: &mut [Candidate], nulls: &[usize], settings: &Settings) {
    // Parents by effect, not by parameter: a declared effect with two parameters is one effect.
    let effects: Vec<Vec<EffectId>> = candidates.iter().map(Candidate::library_effects).collect();
    let snapshot: Vec<(Vec<&str>, f64, f64)> = candidates
        .iter()
        .zip(&effects)
        .map(|(c, e)| (effect_names(e), c.aicc, c.cv_rmse))
        .collect();
    let labels: Vec<String> = candidates.iter().map(Candidate::label).collect();
    let m = candidates
        .iter()
        .filter(|c| c.role == Role::Candidate)
        .count();
    let base = nulls.first().map(|&i| candidates[i].clone());
    for (c, own) in candidates.iter_mut().zip(&effects) {
        if c.role != Role::Candidate {
            continue;
        }
        let mine = effect_names(own);
        let mut parents: Vec<usize> = nulls.to_vec();
        if mine.len() >= 2 {
            parents = snapshot
                .iter()
                .enumerate()
                .filter(|(_, (e, _, _))| {
                    e.len() + 1 == mine.len() && e.iter().all(|x| mine.contains(x))
                })
                .map(|(i, _)| i)
                .collect();
            parents.extend_from_slice(nulls);
        }
        let mut why = Vec::new();
        for &p in &parents {
            let (_, aicc, cv) = snapshot[p];
            let label = &labels[p];
            // The stiffness null has as many parameters as a single: it must only be beaten, not by 4.
            let margin = if mine.len() == 1 && nulls.len() > 1 && p == nulls[nulls.len() - 1] {
                0.0
            } else {
                settings.min_delta_aicc
            };
            if c.aicc > aicc - margin {
                why.push(format!("dAICc vs {label} {:.1}", aicc - c.aicc));
            }
            if c.cv_rmse >= cv {
                why.push(format!("CV no better than {label}"));
            }
        }
        why.extend(base.as_ref().and_then(|b| multiplicity(c, b, m, settings)));
        for (id, reason) in &c.not_identifiable {
            why.push(format!("{} not identifiable: {reason}", id.name()));
        }
        for (k, id) in c.effects.iter().enumerate() {
            if c.not_identifiable.iter().any(|(e, _)| e == id) {
                continue;
            }
            if id.stage() == c.stage && *id != EffectId::D31Scale && !c.excludes_null(k) {
                why.push(format!("{} interval includes the null value", id.name()));
            }
        }
        c.accepted = why.is_empty();
        c.note = why.join("; ");
    }
}

/// Each selected effect's parameter with the 95 % interval the report gives it: a mass effect refitted
/// beside the actuation model its joint interval, else that of the final mass or actuation fit.
pub(super) fn reported_intervals(
    selected: &[EffectId],
    mass: Option<&Candidate>,
    chosen: &Candidate,
) -> Vec<(EffectId, (f64, f64))> {
    selected
        .iter()
        .filter_map(|id| {
            let interval = chosen
                .carried
                .iter()
                .find(|c| c.id == *id)
                .map(|c| c.interval)
                .or_else(|| {
                    [mass, Some(chosen)].into_iter().flatten().find_map(|c| {
                        let k = c.effects.iter().position(|e| e == id)?;
                        Some(c.intervals[k])
                    })
                })?;
            Some((id.clone(), interval))
        })
        .collect()
}

/// The selected parameters whose interval holds their null value, named with the interval
/// (docs/calibration.md §3, step 4: an effect is accepted only when its interval excludes the null; the
/// final fit, refitted with the resonances or the masses beside it, must still show it).
pub(super) fn holding_null(reported: &[(EffectId, (f64, f64))]) -> Vec<String> {
    reported
        .iter()
        .filter_map(|(id, (lo, hi))| {
            let p = id.param();
            let excludes = lo.is_finite() && hi.is_finite() && (*lo > p.null || *hi < p.null);
            (!excludes).then(|| {
                format!(
                    "{} ({} [{lo:.4}, {hi:.4}]) holds its null {}",
                    id.name(),
                    p.name,
                    p.null
                )
            })
        })
        .collect()
}

/// Indices of the best accepted model and its rivals (within ΔAICc 2, not nested in it).
pub(super) fn best_and_rivals_indices(candidates: &[Candidate], settings: &Settings) -> Vec<usize> {
    let _ = settings;
    let Some(best) = candidates
        .iter()
        .enumerate()
        .filter(|(_, c)| c.accepted)
        .min_by(|a, b| a.1.aicc.total_cmp(&b.1.aicc))
        .map(|(i, _)| i)
    else {
        return Vec::new();
    };
    let best_effects = candidates[best].library_effects();
    let mut out = vec![best];
    for (i, c) in candidates.iter().enumerate() {
        if i == best || c.role != Role::Candidate {
            continue;
        }
        let mine = c.library_effects();
        let nested = mine.iter().all(|e| best_effects.contains(e))
            || best_effects.iter().all(|e| mine.contains(e));
        let own_effects_significant = c
            .effects
            .iter()
            .enumerate()
            .filter(|(_, e)| e.stage() == c.stage && **e != EffectId::D31Scale)
            .all(|(k, _)| c.excludes_null(k));
        if !nested && own_effects_significant && c.aicc < candidates[best].aicc + 2.0 {
            out.push(i);
        }
    }
    out
}

/// The best accepted model and the effect sets of its rivals (within ΔAICc 2, not nested in it).
pub(super) fn best_and_rivals(
    candidates: &[Candidate],
    settings: &Settings,
) -> (Option<usize>, Vec<Vec<String>>) {
    let idx = best_and_rivals_indices(candidates, settings);
    let rivals = idx
        .iter()
        .skip(1)
        .map(|&i| {
            candidates[i]
                .library_effects()
                .iter()
                .map(|e| e.name().to_string())
                .collect()
        })
        .collect();
    (idx.first().copied(), rivals)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_selected_interval_that_holds_its_null_is_named() {
        // docs/calibration.md §3, step 4: each selected parameter's 95 % interval must exclude its null.
        let reported = [
            (EffectId::D31Scale, (0.70, 0.80)),
            (EffectId::DeadLength, (-0.2, 1.4)),
            (EffectId::ClampCompliance, (0.0, 0.9)),
            (EffectId::PlyThickness, (1.02, 1.1)),
        ];
        let named = holding_null(&reported);
        assert_eq!(named.len(), 2, "{named:?}");
        assert!(named[0].starts_with("dead-length (") && named[0].contains("holds its null 0"));
        assert!(named[1].starts_with("clamp-compliance ("));
        assert!(holding_null(&[(EffectId::D31Scale, (0.9, 1.01))])[0].contains("holds its null 1"));
        assert!(holding_null(&[(EffectId::DeadLength, (f64::NAN, 2.0))]).len() == 1);
        assert!(holding_null(&reported[3..]).is_empty());
    }
}
