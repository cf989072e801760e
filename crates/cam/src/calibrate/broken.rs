//! Broken actuators (docs/calibration.md §3, "Broken actuators"): an actuator whose deflection or force is
//! off by the same factor at every voltage, far outside the spread of the other actuators around a shared
//! model, is a device fault (a cracked plate, a failed bond, a slipping clamp), not an effect of the
//! design. It is named with its residual and likely cause and left out of the fit.

use super::csv::Dataset;
use super::rounded::{six_digits, six_digits_opt};
use actuator_model::Performance;
use serde::Serialize;

/// Robust z (offset over the larger of the between-actuator MAD spread and the actuator's own noise)
/// above which an actuator is an outlier among its peers.
const Z_LIMIT: f64 = 5.0;

/// Smallest offset (log) that makes an outlier a broken device: ln(1/0.85), a 15 % gain change. A smaller
/// one is within what a shared effect the model lacks leaves on single actuators.
const MIN_OFFSET: f64 = 0.1625;

/// Largest share of the actuators treated as broken: more than this is a shared effect, not device faults.
pub const MAX_SHARE: f64 = 0.2;

/// An actuator flagged as broken.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BrokenActuator {
    /// Actuator id.
    pub id: String,
    /// Mean change of the free deflection against its peers, % (negative: low).
    #[serde(serialize_with = "six_digits_opt")]
    pub deflection_percent: Option<f64>,
    /// Mean change of the blocked force against its peers, %.
    #[serde(serialize_with = "six_digits_opt")]
    pub force_percent: Option<f64>,
    /// Largest robust z of the two offsets.
    #[serde(serialize_with = "six_digits")]
    pub robust_z: f64,
    /// Whether every voltage level is off in the same direction.
    pub every_voltage: bool,
    /// Likely cause, one line.
    pub likely_cause: String,
    /// Left out of the fit (false when the exclusion was undone; see the report's notes).
    pub excluded: bool,
}

/// The median of `v` (sorted in place).
pub(crate) fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

/// Per-output statistics of one actuator: its mean log residual and its rows' residuals.
struct Offsets {
    mean: Option<f64>,
    rows: Vec<f64>,
}

fn offsets(values: Vec<f64>) -> Offsets {
    let mean = (!values.is_empty()).then(|| values.iter().sum::<f64>() / values.len() as f64);
    Offsets { mean, rows: values }
}

/// One output's verdict on an actuator: (offset from the peers' median, robust z, every row off the
/// same way).
type Flag = Option<(f64, f64, bool)>;

/// Screen the actuators of `data` against a shared model's `predictions` (one per row). Returns the group
/// index and description of each broken actuator, in group order.
pub fn screen(data: &Dataset, predictions: &[Performance]) -> Vec<(usize, BrokenActuator)> {
    let per_group: Vec<[Offsets; 2]> = data
        .groups
        .iter()
        .map(|g| {
            let (mut d, mut f) = (Vec::new(), Vec::new());
            for &i in g {
                let (m, p) = (&data.rows[i], &predictions[i]);
                if m.voltage <= 0.0 {
                    continue;
                }
                if let Some(v) = m.free_deflection {
                    d.push((v / p.free_deflection).ln());
                }
                if let Some(v) = m.blocked_force {
                    f.push((v / p.blocked_force).ln());
                }
            }
            [offsets(d), offsets(f)]
        })
        .collect();
    let flags: Vec<[Flag; 2]> = {
        let mut out = vec![[None, None]; per_group.len()];
        for slot in 0..2 {
            let means: Vec<(usize, f64)> = per_group
                .iter()
                .enumerate()
                .filter_map(|(g, o)| o[slot].mean.map(|m| (g, m)))
                .collect();
            if means.len() < 5 {
                continue;
            }
            let center = median(&mut means.iter().map(|m| m.1).collect::<Vec<_>>());
            let spread = 1.4826
                * median(
                    &mut means
                        .iter()
                        .map(|m| (m.1 - center).abs())
                        .collect::<Vec<_>>(),
                );
            // Pooled within-actuator noise, so a data set with a perfect shared fit still has a scale.
            let (mut ss, mut dof) = (0.0, 0usize);
            for o in &per_group {
                if let Some(m) = o[slot].mean {
                    ss += o[slot].rows.iter().map(|r| (r - m).powi(2)).sum::<f64>();
                    dof += o[slot].rows.len().saturating_sub(1);
                }
            }
            let within = if dof > 0 {
                (ss / dof as f64).sqrt()
            } else {
                0.0
            };
            for &(g, m) in &means {
                let own = within / (per_group[g][slot].rows.len() as f64).sqrt();
                let scale = spread.max(own).max(1e-12);
                let off = m - center;
                let z = off / scale;
                if z.abs() > Z_LIMIT && off.abs() >= MIN_OFFSET {
                    let every = per_group[g][slot]
                        .rows
                        .iter()
                        .all(|r| (r - center) * off.signum() > 0.0);
                    out[g][slot] = Some((off, z, every));
                } else {
                    // Kept for the description when the other output is flagged.
                    out[g][slot] = None;
                }
            }
        }
        out
    };
    let mut found = Vec::new();
    for (g, [d, f]) in flags.into_iter().enumerate() {
        if d.is_none() && f.is_none() {
            continue;
        }
        let pct = |o: Flag| o.map(|(off, _, _)| 100.0 * (off.exp() - 1.0));
        let z = [d, f]
            .iter()
            .flatten()
            .map(|x| x.1.abs())
            .fold(0.0, f64::max);
        let every = [d, f].iter().flatten().all(|x| x.2);
        found.push((
            g,
            BrokenActuator {
                id: data.rows[data.groups[g][0]].id.clone(),
                deflection_percent: pct(d),
                force_percent: pct(f),
                robust_z: z,
                every_voltage: every,
                likely_cause: likely_cause(pct(d), pct(f), every),
                excluded: true,
            },
        ));
    }
    found
}

/// The device fault a pattern of offsets points to.
fn likely_cause(deflection: Option<f64>, force: Option<f64>, every: bool) -> String {
    let when = if every {
        "at every voltage"
    } else {
        "on average"
    };
    let dir = |p: f64| if p < 0.0 { "low" } else { "high" };
    match (deflection, force) {
        (Some(d), Some(f)) if d.signum() == f.signum() => {
            let p = 0.5 * (d.abs() + f.abs());
            if d < 0.0 {
                format!("cracked plate or failed bond: deflection and force {p:.0} % low {when}")
            } else {
                format!(
                    "design or drive not as recorded (thinner plate, higher voltage): deflection and \
                     force {p:.0} % high {when}"
                )
            }
        }
        (Some(d), Some(f)) => format!(
            "measurement fault: deflection {:.0} % {} and force {:.0} % {} {when}",
            d.abs(),
            dir(d),
            f.abs(),
            dir(f)
        ),
        (None, Some(f)) if f < 0.0 => format!(
            "slipping clamp or force-sensor fault: blocked force {:.0} % low {when}, deflection as \
             predicted",
            f.abs()
        ),
        (None, Some(f)) => format!(
            "force-sensor calibration: blocked force {f:.0} % high {when}, deflection as predicted"
        ),
        (Some(d), None) => format!(
            "deflection-measurement fault (tip not tracked, wrong reference): free deflection {:.0} % \
             {} {when}, force as predicted",
            d.abs(),
            dir(d)
        ),
        (None, None) => String::new(),
    }
}

/// The data set without the actuators marked `false` in `keep` (indexed by group).
pub fn subset(data: &Dataset, keep: &[bool]) -> Dataset {
    let mut rows = Vec::new();
    let mut groups = Vec::new();
    let mut group_of = Vec::new();
    for (g, members) in data.groups.iter().enumerate() {
        if !keep[g] {
            continue;
        }
        let mut idx = Vec::new();
        for &i in members {
            idx.push(rows.len());
            group_of.push(groups.len());
            rows.push(data.rows[i].clone());
        }
        groups.push(idx);
    }
    // Rows stay grouped by actuator rather than in file order; every consumer goes through the groups.
    Dataset {
        rows,
        groups,
        group_of,
        unknown_columns: data.unknown_columns.clone(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn causes_follow_the_pattern_of_the_offsets() {
        assert_eq!(
            likely_cause(Some(-44.0), Some(-46.0), true),
            "cracked plate or failed bond: deflection and force 45 % low at every voltage"
        );
        assert!(likely_cause(None, Some(-30.0), false).starts_with("slipping clamp"));
        assert!(likely_cause(Some(-30.0), None, true).contains("force as predicted"));
        assert!(likely_cause(Some(25.0), Some(25.0), true).contains("25 % high"));
    }

    #[test]
    fn median_of_even_and_odd_counts() {
        assert_eq!(median(&mut [3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median(&mut [4.0, 1.0, 2.0, 3.0]), 2.5);
    }
}
