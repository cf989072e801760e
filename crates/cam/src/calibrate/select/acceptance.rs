//! Which fitted models are accepted, and which accepted models the data cannot tell apart.

use super::candidate::{Candidate, Role};
use super::settings::Settings;
use crate::calibrate::library::{effect_names, EffectId};
use crate::calibrate::stats;

/// The stages whose candidates share the selection's level (the mass stage and the actuation stage):
/// each is held to `alpha / STAGES`, so together they make one false selection in `1 / alpha`.
const STAGES: f64 = 2.0;

/// The p-value of a nested least-squares fit's gain: the F test (Seber & Wild, Nonlinear Regression,
/// 1989, ch. 5: `F = ((RSS₀ - RSS)/(p - p₀)) / (RSS/(n - p))` on `(p - p₀, n - p)` degrees of freedom,
/// asymptotically valid for any noise of finite variance) of a fit of `p` parameters and residual sum
/// of squares `rss` over its null of `p0` parameters and `rss0`, both on `n` residuals. None when
/// there is nothing to test: no parameter beyond the null's, no residual degree of freedom, or an
/// exact fit.
fn nested_gain_p(rss0: f64, rss: f64, p0: usize, p: usize, n: usize) -> Option<f64> {
    let dof = n as f64 - p as f64;
    if p <= p0 || dof < 1.0 || rss <= 0.0 {
        return None;
    }
    let extra = (p - p0) as f64;
    let f = ((rss0 - rss).max(0.0) / extra) / (rss / dof);
    Some(stats::f_upper_p(f, extra, dof))
}

/// Why `c` is not accepted for its gain over the first null `base` among `m` candidates: the selection
/// tries every candidate against the same null, so under no effect one of `m` passes ΔAICc > 4 (a
/// likelihood ratio above 6, p ≈ 0.014 for one parameter) about `m` times as often as one does. The gain
/// must be significant at the selection's share of the level, Bonferroni-divided over the `m`
/// (docs/calibration.md §3, step 4). A gain the F test cannot judge ([`nested_gain_p`] None: as many
/// parameters as the null, or an exact fit) is left to the comparison of AICc alone.
fn multiplicity(c: &Candidate, base: &Candidate, m: usize, settings: &Settings) -> Option<String> {
    let level = multiplicity_level(settings.alpha, m);
    let p = nested_gain_p(base.rss, c.rss, base.effects.len(), c.effects.len(), c.n)?;
    (p >= level).then(|| {
        format!(
            "gain over {} not significant among {m} candidates (p = {p:.2e}, needs < {level:.1e})",
            base.label()
        )
    })
}

/// The level each of `m` candidates' gains is tested at: the family level `alpha` shared by the two
/// stages and Bonferroni-divided over the stage's candidates.
fn multiplicity_level(alpha: f64, m: usize) -> f64 {
    alpha / STAGES / m.max(1) as f64
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
    use crate::calibrate::stats::standard_normal;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    #[test]
    fn the_gain_test_holds_its_level_on_nested_lines_under_no_effect() {
        // Pure noise fitted by its mean (the null, one parameter) and by a line in a design variable
        // (two): the F test of the gain must reject at its nominal level, here 5 % and the 1 % share of
        // the selection over one stage's five candidates (0.1 %), within the binomial scatter of the draws.
        let mut rng = ChaCha8Rng::seed_from_u64(59_300);
        let (draws, n) = (20_000, 30);
        let xs: Vec<f64> = (0..n)
            .map(|k| (k as f64 * 0.37).sin() + 0.1 * k as f64)
            .collect();
        let mx = xs.iter().sum::<f64>() / n as f64;
        let sxx: f64 = xs.iter().map(|x| (x - mx).powi(2)).sum();
        let level = multiplicity_level(0.01, 5);
        assert_eq!(level, 0.001);
        let (mut at5, mut at_level) = (0, 0);
        for _ in 0..draws {
            let ys: Vec<f64> = (0..n).map(|_| standard_normal(&mut rng)).collect();
            let my = ys.iter().sum::<f64>() / n as f64;
            let rss0: f64 = ys.iter().map(|y| (y - my).powi(2)).sum();
            let sxy: f64 = xs.iter().zip(&ys).map(|(x, y)| (x - mx) * (y - my)).sum();
            let rss = rss0 - sxy * sxy / sxx;
            let p = nested_gain_p(rss0, rss, 1, 2, n).expect("a gain to test");
            at5 += (p < 0.05) as usize;
            at_level += (p < level) as usize;
        }
        // Binomial 99.9 % bounds: 1,000 ± 101 of 20,000 at 5 %, 20 ± 15 at 0.1 %.
        assert!((899..=1101).contains(&at5), "{at5}");
        assert!((5..=35).contains(&at_level), "{at_level}");
    }

    #[test]
    fn a_gain_with_nothing_to_test_is_left_to_the_aicc() {
        assert_eq!(nested_gain_p(2.0, 1.0, 2, 2, 30), None);
        assert_eq!(nested_gain_p(2.0, 1.0, 1, 2, 2), None);
        assert_eq!(nested_gain_p(2.0, 0.0, 1, 2, 30), None);
        // A fit no better than its null gains nothing.
        assert_eq!(nested_gain_p(2.0, 2.0, 1, 2, 30), Some(1.0));
    }

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
