//! What the remaining residual looks like (docs/calibration.md §3, "Discovery"): per actuator, the mean
//! log residual of the deflection (the gain), of the stiffness `F_b/δ` (the inverse of the compliance)
//! and of the mass, as in the adequacy test; then a power law of each in the independent design
//! variables together, and one in each design variable or ratio alone, ranked by p-value. The field acts
//! within each voltage sweep, so its exponent is fitted on the residuals centred per actuator.

use super::power_law::{self, Exponent, PowerLaw};
use crate::calibrate::csv::Dataset;
use crate::calibrate::rounded::six_digits;
use crate::calibrate::select::observations::ActuationData;
use crate::calibrate::variables::design_variables;
use actuator_model::EffectModel;
use serde::Serialize;

/// The variables of the joint power law: independent ones (the ratios are products of their powers).
const JOINT: [&str; 8] = [
    "l_p_mm",
    "1+l_r",
    "w0_mm",
    "w_r",
    "t_p_mm",
    "plies",
    "field_V_per_um",
    "zero_ply_share",
];

/// A power law of one residual in one variable.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Trend {
    /// `deflection`, `stiffness` or `mass`.
    pub residual: &'static str,
    /// The exponent.
    #[serde(flatten)]
    pub exponent: Exponent,
    /// Share of the residual's variance it explains.
    #[serde(serialize_with = "six_digits")]
    pub r_squared: f64,
}

/// Per-actuator mean residuals and the within-sweep pairs.
struct Residuals {
    /// (group, deflection, stiffness) means.
    actuation: Vec<(usize, Option<f64>, Option<f64>)>,
    /// (group, mass residual).
    mass: Vec<(usize, f64)>,
    /// Centred (ln field, deflection residual, stiffness residual) within each sweep.
    sweep: Vec<(f64, f64, Option<f64>)>,
    /// Actuators with a sweep of two or more levels (each centring uses a degree of freedom).
    sweeps: usize,
}

fn residuals(act: &ActuationData, model: &EffectModel, mass: &[(usize, f64)]) -> Residuals {
    let rows = act.row_residuals(model);
    let mut actuation = Vec::new();
    let mut sweep = Vec::new();
    let mut sweeps = 0;
    for (g, obs) in act.obs_by_actuator().iter().enumerate() {
        let mine: Vec<(f64, Option<f64>, Option<f64>)> = obs
            .iter()
            .map(|&i| (&act.obs[i], &rows[i]))
            .map(|(o, r)| (o.basis.field.ln(), r[0], r[1].zip(r[0]).map(|(f, d)| f - d)))
            .collect();
        if mine.is_empty() {
            continue;
        }
        let mean = |v: Vec<f64>| (!v.is_empty()).then(|| v.iter().sum::<f64>() / v.len() as f64);
        let d = mean(mine.iter().filter_map(|m| m.1).collect());
        let k = mean(mine.iter().filter_map(|m| m.2).collect());
        actuation.push((g, d, k));
        let with_d: Vec<&(f64, Option<f64>, Option<f64>)> =
            mine.iter().filter(|m| m.1.is_some()).collect();
        if with_d.len() >= 2 {
            sweeps += 1;
            let n = with_d.len() as f64;
            let me = with_d.iter().map(|m| m.0).sum::<f64>() / n;
            let md = with_d.iter().filter_map(|m| m.1).sum::<f64>() / n;
            let ks: Vec<f64> = with_d.iter().filter_map(|m| m.2).collect();
            let mk = (ks.len() == with_d.len()).then(|| ks.iter().sum::<f64>() / n);
            for m in with_d {
                sweep.push((
                    m.0 - me,
                    m.1.unwrap_or(0.0) - md,
                    mk.zip(m.2).map(|(mk, k)| k - mk),
                ));
            }
        }
    }
    Residuals {
        actuation,
        mass: mass.to_vec(),
        sweep,
        sweeps,
    }
}

/// ln of each design variable of actuator `g` that is positive for every actuator, with its name, plus
/// `1+l_r` (`l_tot/l_p`; `l_r` itself may be 0).
fn log_variables(data: &Dataset, groups: &[usize]) -> (Vec<&'static str>, Vec<Vec<f64>>) {
    let all: Vec<Vec<(&'static str, f64)>> = groups
        .iter()
        .map(|&g| {
            let m = &data.rows[data.groups[g][0]];
            let mut v: Vec<(&'static str, f64)> = design_variables(m).to_vec();
            v.push(("1+l_r", 1.0 + m.planform.extension_ratio));
            v
        })
        .collect();
    let Some(first) = all.first() else {
        return (Vec::new(), Vec::new());
    };
    let keep: Vec<usize> = (0..first.len())
        .filter(|&k| all.iter().all(|v| v[k].1 > 0.0 && v[k].1.is_finite()))
        .collect();
    let names = keep.iter().map(|&k| first[k].0).collect();
    let values = all
        .iter()
        .map(|v| keep.iter().map(|&k| v[k].1.ln()).collect())
        .collect();
    (names, values)
}

/// The joint power laws (deflection, stiffness, mass; those with data) and every one-variable trend,
/// smallest p first.
pub(super) fn describe(
    data: &Dataset,
    act: &ActuationData,
    model: &EffectModel,
    mass: &[(usize, f64)],
) -> (Vec<PowerLaw>, Vec<Trend>) {
    let res = residuals(act, model, mass);
    let mut laws = Vec::new();
    let mut trends = Vec::new();
    let series: [(&'static str, Vec<(usize, f64)>); 3] = [
        (
            "deflection",
            res.actuation
                .iter()
                .filter_map(|(g, d, _)| d.map(|d| (*g, d)))
                .collect(),
        ),
        (
            "stiffness",
            res.actuation
                .iter()
                .filter_map(|(g, _, k)| k.map(|k| (*g, k)))
                .collect(),
        ),
        ("mass", res.mass.clone()),
    ];
    for (residual, pts) in series {
        let groups: Vec<usize> = pts.iter().map(|p| p.0).collect();
        let y: Vec<f64> = pts.iter().map(|p| p.1).collect();
        let (names, x) = log_variables(data, &groups);
        let joint: Vec<usize> = JOINT
            .iter()
            .filter_map(|j| names.iter().position(|n| n == j))
            .collect();
        let jx: Vec<Vec<f64>> = x
            .iter()
            .map(|row| joint.iter().map(|&k| row[k]).collect())
            .collect();
        let jnames: Vec<&'static str> = joint.iter().map(|&k| names[k]).collect();
        if let Some(law) = power_law::fit(residual, &jnames, &jx, &y, 0) {
            laws.push(law);
        }
        for (k, name) in names.iter().enumerate() {
            let col: Vec<Vec<f64>> = x.iter().map(|row| vec![row[k]]).collect();
            if let Some(law) = power_law::fit(residual, &[name], &col, &y, 0) {
                trends.extend(law.exponents.into_iter().map(|exponent| Trend {
                    residual,
                    exponent,
                    r_squared: law.r_squared,
                }));
            }
        }
    }
    // The field within each sweep.
    for (residual, slot) in [("deflection", 0usize), ("stiffness", 1)] {
        let pts: Vec<(f64, f64)> = res
            .sweep
            .iter()
            .filter_map(|s| match slot {
                0 => Some((s.0, s.1)),
                _ => s.2.map(|k| (s.0, k)),
            })
            .collect();
        let x: Vec<Vec<f64>> = pts.iter().map(|p| vec![p.0]).collect();
        let y: Vec<f64> = pts.iter().map(|p| p.1).collect();
        if let Some(law) = power_law::fit(
            residual,
            &["field_V_per_um (within sweep)"],
            &x,
            &y,
            res.sweeps.saturating_sub(1),
        ) {
            trends.extend(law.exponents.into_iter().map(|exponent| Trend {
                residual,
                exponent,
                r_squared: law.r_squared,
            }));
        }
    }
    trends.sort_by(|a, b| {
        a.exponent
            .p
            .total_cmp(&b.exponent.p)
            .then(b.r_squared.total_cmp(&a.r_squared))
    });
    (laws, trends)
}
