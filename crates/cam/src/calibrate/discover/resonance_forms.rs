//! The forms only the resonance separates (docs/calibration.md §3, "Discovery"), offered when the
//! resonance residuals fail their own tests (`select/resonance_tests.rs`): a mass at the tip fitted after
//! weighing (`tip-mass`: `f1` alone falls, most on the light actuators) and a compliant root
//! (`clamp-compliance`: `f1` falls with the tip stiffness, most on the stiff actuators, and the blocked
//! forces fall with it). Each is added to the final model and fitted to the resonance residuals alone;
//! its evidence is its AICc gain on them, its value with a 95 % interval, and what it does to the
//! deflections and forces, which a root compliance moves and a tip mass does not.

use crate::calibrate::rounded::{six_digits, six_digits_pair};
use crate::calibrate::select::observations::ActuationData;
use crate::calibrate::stats;
use actuator_model::primitives::{Applied, Primitive};
use actuator_model::EffectModel;
use serde::Serialize;

/// One form fitted to the resonance residuals.
#[derive(Debug, Clone, Serialize)]
pub struct ResonanceForm {
    /// The primitive's report name.
    pub name: &'static str,
    /// The primitive.
    #[serde(skip)]
    pub primitive: Primitive,
    /// Its parameter, SI.
    pub parameter: &'static str,
    /// Physical bounds searched, SI.
    #[serde(skip)]
    pub bounds: (f64, f64),
    /// Estimate.
    #[serde(serialize_with = "six_digits")]
    pub estimate: f64,
    /// 95 % interval (Student t on the resonances, the scale from their residuals).
    #[serde(serialize_with = "six_digits_pair")]
    pub interval: (f64, f64),
    /// AICc of the resonance residuals below the final model's.
    #[serde(serialize_with = "six_digits")]
    pub gain: f64,
    /// Root mean square of the log resonance residuals with it.
    #[serde(rename = "resonance_rms_log", serialize_with = "six_digits")]
    pub rms: f64,
    /// How much its fit raises the sum of squares of the deflections and forces, in units of their
    /// variance (0 for a tip mass, which moves neither).
    #[serde(serialize_with = "six_digits")]
    pub actuation_cost: f64,
    /// Whether the deflections and forces allow it: its cost is below the 1 % point of χ² on one
    /// degree of freedom (6.63).
    pub allowed: bool,
}

/// The forms tried and their ranges, SI: a tip mass up to 20 mg (a wing hinge and its glue), the
/// clamp compliance over discovery's range (`catalogue.rs`).
const FORMS: [(Primitive, &str, &str, f64); 2] = [
    (Primitive::TipMass, "tip-mass", "tip_mass_kg", 2e-5),
    (
        Primitive::ClampCompliance,
        "clamp-compliance",
        "rad_per_N_m",
        200.0,
    ),
];

/// The level at which a form's cost to the deflections and forces (χ² on one degree of freedom)
/// rules it out.
const COST_LEVEL: f64 = 0.01;

/// Each form fitted to the resonance residuals of `model` on `act`, best gain first; empty with fewer
/// than 4 resonances.
pub(crate) fn rank(act: &ActuationData, model: &EffectModel) -> Vec<ResonanceForm> {
    let split = |m: &EffectModel| super::joint::split(act, m);
    let (act0, f0) = split(model);
    let n = f0.len();
    if n < 4 || act0.is_empty() {
        return Vec::new();
    }
    let ss = |r: &[f64]| r.iter().map(|x| x * x).sum::<f64>();
    let (ss_act0, ss_f0) = (ss(&act0), ss(&f0));
    let var_act = ss_act0 / act0.len() as f64;
    let mut forms: Vec<ResonanceForm> = FORMS
        .iter()
        .filter_map(|&(primitive, name, parameter, hi)| {
            let with = |v: f64| {
                let mut m = model.clone();
                m.primitives.push(Applied {
                    primitive,
                    value: v,
                });
                split(&m)
            };
            let cost = |v: f64| {
                let f = with(v).1;
                let s = ss(&f);
                if s.is_finite() {
                    s
                } else {
                    f64::INFINITY
                }
            };
            let v = minimise(&cost, hi);
            let (act1, f1) = with(v);
            let ss_f1 = ss(&f1);
            if !(ss_f1.is_finite() && v > 0.0) {
                return None;
            }
            // The slope of the residuals at the estimate, for its interval.
            let h = 1e-3 * v;
            let (up, down) = (with(v + h).1, with((v - h).max(0.0)).1);
            let step = v + h - (v - h).max(0.0);
            let jj: f64 = up
                .iter()
                .zip(&down)
                .map(|(a, b)| ((a - b) / step).powi(2))
                .sum();
            let se = (ss_f1 / (n - 1) as f64 / jj).sqrt();
            let t = stats::t_quantile_two_sided(0.95, (n - 1) as f64);
            let actuation_cost = ((ss(&act1) - ss_act0) / var_act).max(0.0);
            Some(ResonanceForm {
                name,
                primitive,
                parameter,
                bounds: (0.0, hi),
                estimate: v,
                interval: (v - t * se, v + t * se),
                gain: stats::aicc(n, 0, ss_f0) - stats::aicc(n, 1, ss_f1),
                rms: (ss_f1 / n as f64).sqrt(),
                actuation_cost,
                allowed: stats::chi_square_upper_p(actuation_cost, 1.0) > COST_LEVEL,
            })
        })
        .collect();
    forms.sort_by(|a, b| b.gain.total_cmp(&a.gain));
    forms
}

/// The value in `[0, hi]` of least `cost`: the best of a geometric grid from `hi` 1e-6, then a golden
/// section between its neighbours.
fn minimise(cost: &dyn Fn(f64) -> f64, hi: f64) -> f64 {
    let grid: Vec<f64> = std::iter::once(0.0)
        .chain((0..=36).map(|i| hi * 10f64.powf(-6.0 + i as f64 / 6.0)))
        .collect();
    let costs: Vec<f64> = grid.iter().map(|&v| cost(v)).collect();
    let best = (0..grid.len())
        .min_by(|&a, &b| costs[a].total_cmp(&costs[b]))
        .unwrap_or(0);
    let (mut a, mut b) = (
        grid[best.saturating_sub(1)],
        grid[(best + 1).min(grid.len() - 1)],
    );
    let g = 0.5 * (5f64.sqrt() - 1.0);
    let (mut c, mut d) = (b - g * (b - a), a + g * (b - a));
    let (mut fc, mut fd) = (cost(c), cost(d));
    for _ in 0..40 {
        if fc < fd {
            b = d;
            d = c;
            fd = fc;
            c = b - g * (b - a);
            fc = cost(c);
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + g * (b - a);
            fd = cost(d);
        }
    }
    0.5 * (a + b)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_minimum_of_a_parabola_is_found_within_the_grid_and_at_zero() {
        let at = |x0: f64| minimise(&|v: f64| (v - x0).powi(2), 2e-5);
        assert!((at(3e-6) / 3e-6 - 1.0).abs() < 1e-6, "{}", at(3e-6));
        assert!(at(-1e-6) < 1e-10, "{}", at(-1e-6));
    }
}
