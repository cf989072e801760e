//! What a residual the final model leaves touches (docs/calibration.md §3, "Verdicts"): each measured
//! quantity's per-actuator residual tested against the design variables, Holm-corrected over them all,
//! so a not-explained verdict can say "force-only" when the deflections, masses and resonances fit and
//! only the blocked forces follow a variable (a compliant load cell, not an effect of the actuator).

use super::adequacy::{push_variable_tests, Adequacy, CorrelationTest, Point};
use super::observations::{ActuationData, MassData, StageData};
use crate::calibrate::csv::Dataset;
use crate::calibrate::stats;
use actuator_model::EffectModel;

/// Per-actuator residuals of one measured quantity.
pub(super) type Points = Vec<Point>;

/// Each actuator's mean deflection and mean force residual from the rows' residuals `row_res`
/// (deflection, force; None where not measured), in [`ActuationData::obs`] order.
pub(super) fn actuation_points(act: &ActuationData, row_res: &[[Option<f64>; 2]]) -> [Points; 2] {
    let mut sums = vec![[(0.0, 0usize); 2]; act.groups];
    for (o, r) in act.obs.iter().zip(row_res) {
        for slot in 0..2 {
            if let Some(v) = r[slot] {
                sums[o.group][slot].0 += v;
                sums[o.group][slot].1 += 1;
            }
        }
    }
    [0, 1].map(|slot| {
        sums.iter()
            .enumerate()
            .filter(|(_, s)| s[slot].1 > 0)
            .map(|(g, s)| Point {
                actuator: g,
                value: s[slot].0 / s[slot].1 as f64,
                readings: s[slot].1,
            })
            .collect()
    })
}

/// The per-actuator residuals of every measured quantity under `model` (deflection, force, mass under
/// `mass`'s model, resonance).
pub(super) fn quantities(
    act: &ActuationData,
    model: &EffectModel,
    mass: Option<(&EffectModel, &MassData)>,
) -> [(&'static str, Points); 4] {
    let mut r = Vec::new();
    act.residuals(model, None, &mut r);
    let labels = act.labels();
    let frequency: Points = act
        .resonances
        .obs
        .iter()
        .zip(r.get(labels.len()..).unwrap_or(&[]))
        .map(|(o, &v)| Point::one(o.group, v))
        .collect();
    // The residuals as measured, not the adequacy tests' Huber pseudo-observations: what a residual
    // touches is an offset of whole actuators (a load cell's share of every force), which clipping at
    // the noise's scale would shrink until no quantity follows a variable.
    let mut row_res = vec![[None, None]; act.obs.len()];
    for (&(i, output), &res) in labels.iter().zip(&r) {
        row_res[i][(output == "blocked_force") as usize] = Some(res);
    }
    let mut mass_pts = Points::new();
    if let Some((mm, data)) = mass {
        let mut out = Vec::new();
        data.residuals(mm, None, &mut out);
        mass_pts = data
            .obs
            .iter()
            .zip(out)
            .map(|(o, v)| Point::one(o.0, v))
            .collect();
    }
    let [deflection, force] = actuation_points(act, &row_res);
    [
        ("deflection", deflection),
        ("force", force),
        ("mass", mass_pts),
        ("resonance", frequency),
    ]
}

/// The quantities that fit under the model `before` (none of their correlations with a design variable
/// significant) and follow a design variable under `after`: the measurements the fitted effects
/// contradict (docs/calibration.md §3, "Verdicts").
pub(super) fn contradicted(
    data: &Dataset,
    before: &[(&'static str, Points)],
    after: &[(&'static str, Points)],
    alpha: f64,
) -> Vec<&'static str> {
    let [failed_before, _] = failing(data, before, alpha);
    let [failed_after, _] = failing(data, after, alpha);
    failed_after
        .into_iter()
        .filter(|q| !failed_before.contains(q))
        .collect()
}

/// Why a fitted model is not accepted when it contradicts a measured quantity: what the residual of
/// the original model touches (when one quantity), then the fitted `effects` and the quantities they
/// make follow a design variable though they fit the original model. None when it contradicts none.
pub(super) fn refusal(
    data: &Dataset,
    before: &[(&'static str, Points)],
    after: &[(&'static str, Points)],
    effects: &[&str],
    alpha: f64,
) -> Option<String> {
    let worse = contradicted(data, before, after, alpha);
    if worse.is_empty() || effects.is_empty() {
        return None;
    }
    let plural: Vec<String> = worse.iter().map(|q| plural(q)).collect();
    let why = format!(
        "the fit of {} is not accepted: it makes the {}, which fit the original model, follow a design variable",
        effects.join(" + "),
        plural.join(" and ")
    );
    Some(match only_one(data, before, alpha) {
        Some(t) => format!("{t}; {why}"),
        None => why,
    })
}

/// A quantity's name in the plural.
fn plural(q: &str) -> String {
    match q {
        "mass" => "masses".to_string(),
        other => format!("{other}s"),
    }
}

/// The quantities in `(name, points)` whose residual follows a design variable at the family level
/// `alpha`, and those measured on enough actuators to test (4 or more).
fn failing(
    data: &Dataset,
    quantities: &[(&'static str, Points)],
    alpha: f64,
) -> [Vec<&'static str>; 2] {
    let first_row = |g: usize| &data.rows[data.groups[g][0]];
    let mut tests: Vec<CorrelationTest> = Vec::new();
    let mut measured = Vec::new();
    for (name, pts) in quantities {
        if pts.len() >= 4 {
            measured.push(*name);
            push_variable_tests(&mut tests, name, pts, &first_row);
        }
    }
    let raw: Vec<f64> = tests.iter().map(|t| t.p).collect();
    let mut failed: Vec<&'static str> = Vec::new();
    for (t, p) in tests.iter().zip(stats::holm(&raw)) {
        if p < alpha && !failed.contains(&t.residual) {
            failed.push(t.residual);
        }
    }
    [failed, measured]
}

/// Add to a failed `adequacy`'s named residual what it touches, when its correlations failed and one
/// quantity of `quantities` (the final model's) alone follows a design variable.
pub(super) fn name_in(
    adequacy: &mut Adequacy,
    data: &Dataset,
    quantities: &[(&'static str, Points)],
    alpha: f64,
) {
    let correlations_failed = adequacy.correlations.iter().any(|t| t.p_holm < alpha);
    if adequacy.passed || !correlations_failed {
        return;
    }
    if let (Some(w), Some(t)) = (
        adequacy.worst_variable.as_mut(),
        only_one(data, quantities, alpha),
    ) {
        w.push_str("; ");
        w.push_str(&t);
    }
}

/// "a force-only residual: the deflections and masses fit" when exactly one of the measured quantities
/// (deflection, force, mass, resonance) follows a design variable and the others do not; None otherwise.
pub(super) fn only_one(
    data: &Dataset,
    quantities: &[(&'static str, Points)],
    alpha: f64,
) -> Option<String> {
    let [failed, measured] = failing(data, quantities, alpha);
    describe(&failed, &measured)
}

/// The words for one quantity touched among those measured.
fn describe(failed: &[&str], measured: &[&str]) -> Option<String> {
    let [only] = failed else { return None };
    let others: Vec<String> = measured
        .iter()
        .filter(|q| *q != only)
        .map(|q| plural(q))
        .collect();
    let (last, rest) = others.split_last()?;
    let list = if rest.is_empty() {
        last.clone()
    } else {
        format!("{} and {last}", rest.join(", "))
    };
    Some(format!("a {only}-only residual: the {list} fit"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_quantity_touched_is_named_with_the_others_that_fit() {
        assert_eq!(
            describe(&["force"], &["deflection", "force", "mass", "resonance"]).unwrap(),
            "a force-only residual: the deflections, masses and resonances fit"
        );
        assert_eq!(
            describe(&["mass"], &["deflection", "force", "mass"]).unwrap(),
            "a mass-only residual: the deflections and forces fit"
        );
        assert_eq!(
            describe(&["deflection", "force"], &["deflection", "force"]),
            None
        );
        assert_eq!(describe(&["force"], &["force"]), None);
        assert_eq!(describe(&[], &["force", "mass"]), None);
    }
}
