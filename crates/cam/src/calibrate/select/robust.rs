//! Heavy-tailed noise in the adequacy tests (docs/calibration.md §3, "Heavy tails"): the deflection and
//! force residuals are replaced by Huber pseudo-observations, and the lack-of-fit test counts only the
//! sweeps that have a pure error of their own.

use super::observations::ActuationData;
use crate::calibrate::broken::median;

/// Huber's tuning constant in robust standard deviations: a normal residual is clipped with probability
/// 4.6 %, and the pseudo-observations' variance is then within 1 % of the residuals' own
/// (`E ψ² / (E ψ')² = 1.010` at c = 2), so on normal noise the tests keep their level.
const HUBER_C: f64 = 2.0;

/// Fewest rows a sweep needs to have a pure error of its own (a line in the field has two parameters).
const MIN_SWEEP: usize = 3;

/// The rows (indices into [`ActuationData::labels`]) of each sweep: one actuator, one output.
fn sweeps(act: &ActuationData) -> Vec<Vec<usize>> {
    let mut by = vec![[Vec::new(), Vec::new()]; act.groups];
    for (k, &(i, output)) in act.labels().iter().enumerate() {
        by[act.obs[i].group][(output == "blocked_force") as usize].push(k);
    }
    by.into_iter().flatten().filter(|s| !s.is_empty()).collect()
}

/// The least-squares line of `ys` against `xs` at each `xs` (their mean when `xs` does not vary), and
/// the parameters it takes.
fn line(xs: &[f64], ys: &[f64]) -> (Vec<f64>, usize) {
    let m = xs.len() as f64;
    let mx = xs.iter().sum::<f64>() / m;
    let my = ys.iter().sum::<f64>() / m;
    let sxx: f64 = xs.iter().map(|x| (x - mx).powi(2)).sum();
    if sxx <= 1e-12 * mx * mx * m {
        return (vec![my; xs.len()], 1);
    }
    let slope = xs
        .iter()
        .zip(ys)
        .map(|(x, y)| (x - mx) * (y - my))
        .sum::<f64>()
        / sxx;
    (xs.iter().map(|x| my + slope * (x - mx)).collect(), 2)
}

/// The residuals `r` (in [`ActuationData::labels`] order) as Huber pseudo-observations of the fitted
/// model (Huber & Ronchetti, Robust Statistics, 2nd ed. 2009, ch. 7): `r* = ψ_c(r)`, each residual clipped
/// at `c σ̂`, with `σ̂` the pure error's robust scale, 1.4826 times the median absolute residual of the
/// least-squares lines in the field through the sweeps of 3 rows or more (corrected for the lines'
/// parameters), pooled over every sweep. A reading far in a tail then counts as one at `c σ̂` would, in
/// the lack of fit and in each actuator's mean alike; the tests take ratios and correlations of the
/// pseudo-observations, to which a common factor (`1 / E ψ'`) makes no difference. Unchanged without
/// the pure error to scale them (fewer than 5 degrees of freedom).
pub(super) fn pseudo_observations(act: &ActuationData, r: &[f64]) -> Vec<f64> {
    let mut s = SweepSums::of(act, r);
    if s.df() < 5.0 {
        return r.to_vec();
    }
    let rows = s.rows as f64;
    let clip = HUBER_C * 1.4826 * median(&mut s.deviations) * (rows / s.df()).sqrt();
    if clip <= 0.0 {
        return r.to_vec();
    }
    r.iter().map(|x| x.clamp(-clip, clip)).collect()
}

/// The residuals `r` against the lines in the field through each sweep of 3 rows or more.
struct SweepSums {
    /// The residuals' sum of squares on those rows.
    rss: f64,
    /// The lines' (the pure error).
    rss_full: f64,
    /// The parameters the lines take.
    lines_params: usize,
    /// The rows.
    rows: usize,
    /// The sweeps.
    sweeps: usize,
    /// Each row's distance from its sweep's line.
    deviations: Vec<f64>,
}

impl SweepSums {
    fn of(act: &ActuationData, r: &[f64]) -> SweepSums {
        let fields: Vec<f64> = act
            .labels()
            .iter()
            .map(|&(i, _)| act.obs[i].basis.field)
            .collect();
        let mut sums = SweepSums {
            rss: 0.0,
            rss_full: 0.0,
            lines_params: 0,
            rows: 0,
            sweeps: 0,
            deviations: Vec::new(),
        };
        for s in sweeps(act).iter().filter(|s| s.len() >= MIN_SWEEP) {
            let xs: Vec<f64> = s.iter().map(|&k| fields[k]).collect();
            let ys: Vec<f64> = s.iter().map(|&k| r[k]).collect();
            let (fit, k) = line(&xs, &ys);
            sums.rss += ys.iter().map(|y| y * y).sum::<f64>();
            let first = sums.deviations.len();
            sums.deviations
                .extend(ys.iter().zip(&fit).map(|(y, f)| (y - f).abs()));
            sums.rss_full += sums.deviations[first..]
                .iter()
                .map(|d| d.powi(2))
                .sum::<f64>();
            sums.lines_params += k;
            sums.rows += s.len();
            sums.sweeps += 1;
        }
        sums
    }

    /// The pure error's degrees of freedom.
    fn df(&self) -> f64 {
        self.rows as f64 - self.lines_params as f64
    }

    /// Enough to estimate the noise: 3 sweeps, 5 degrees of freedom and some scatter.
    fn estimates_noise(&self) -> bool {
        self.sweeps >= 3 && self.df() >= 5.0 && self.rss_full > 0.0
    }
}

/// The variance of one log deflection or force reading from the pure error of the residuals `r` (in
/// [`ActuationData::labels`] order) about the lines in the field through the sweeps of 3 rows or
/// more: a line per actuator and output absorbs every library effect, so what is left is the noise.
/// None without 3 such sweeps and 5 degrees of freedom.
pub(super) fn pure_error_variance(act: &ActuationData, r: &[f64]) -> Option<f64> {
    let s = SweepSums::of(act, r);
    s.estimates_noise().then(|| s.rss_full / s.df())
}

/// The sums of squares of the lack-of-fit F test of the residuals `r` (pseudo-observations) of a model
/// with `params` fitted parameters against the pure error of the sweeps of 3 rows or more: the model's
/// RSS on those rows, the RSS of their lines in the field, and the two degrees of freedom. A sweep of two
/// voltages has no pure error of its own, and a tail on it would count in full as misfit, so it is left
/// out of both sides; the model's parameters are charged to the rows tested by their share
/// (`params · n_S / n` rounded, the mean leverage of those rows: all of them when every sweep is
/// tested). None without 3 such sweeps and the degrees of freedom to test.
pub(super) fn lack_of_fit_sums(
    act: &ActuationData,
    r: &[f64],
    params: usize,
) -> Option<LackOfFitSums> {
    let s = SweepSums::of(act, r);
    let df1 =
        s.lines_params as f64 - (params as f64 * s.rows as f64 / r.len().max(1) as f64).round();
    (s.estimates_noise() && df1 >= 1.0).then_some(LackOfFitSums {
        rss: s.rss,
        rss_full: s.rss_full,
        df1,
        df2: s.df(),
    })
}

/// What the lack-of-fit F test is computed from.
pub(super) struct LackOfFitSums {
    /// The model's RSS on the rows tested.
    pub(super) rss: f64,
    /// The RSS of the sweeps' lines on them (the pure error).
    pub(super) rss_full: f64,
    /// Lack-of-fit degrees of freedom.
    pub(super) df1: f64,
    /// Pure-error degrees of freedom.
    pub(super) df2: f64,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::calibrate::csv::{parse, Dataset};
    use crate::calibrate::select::actuation_data;
    use actuator_model::EffectModel;

    /// Four actuators swept over four voltages and two measured at two.
    fn data() -> Dataset {
        let mut csv = String::from(
            "id,l_tot_mm,l_r,w0_mm,w_r,t_p_mm,layup,voltage_V,mass_mg,free_deflection_mm,blocked_force_N\n",
        );
        for a in 0..6 {
            let volts: &[f64] = if a < 4 {
                &[40.0, 80.0, 120.0, 160.0]
            } else {
                &[80.0, 160.0]
            };
            for v in volts {
                csv.push_str(&format!(
                    "a{a},{},0.5,8,1,0.191,0/90/0,{v},,{},{}\n",
                    25 + 4 * a,
                    v / 500.0,
                    v / 3000.0
                ));
            }
        }
        parse(&csv).expect("valid rows")
    }

    /// Normal-sized scatter, the same on every run.
    fn scatter(n: usize) -> Vec<f64> {
        (0..n).map(|k| 0.05 * (2.1 * k as f64).sin()).collect()
    }

    /// The F statistic and the pure-error standard deviation of the sweeps' sums.
    fn f_and_sigma(act: &ActuationData, r: &[f64]) -> (f64, f64) {
        let s = lack_of_fit_sums(act, r, 1).expect("sweeps to test");
        let f = ((s.rss - s.rss_full).max(0.0) / s.df1) / (s.rss_full / s.df2);
        (f, (s.rss_full / s.df2).sqrt())
    }

    #[test]
    fn a_tail_on_a_two_voltage_actuator_is_not_misfit_and_a_tail_is_clipped() {
        let data = data();
        let act = actuation_data(&data, &EffectModel::default()).expect("physical stacks");
        let labels = act.labels();
        let r = scatter(labels.len());
        let sums = lack_of_fit_sums(&act, &r, 1).expect("sweeps to test");
        // 8 sweeps of four rows: 16 pure-error degrees of freedom, 16 - 1 of lack of fit.
        assert_eq!((sums.df1, sums.df2), (15.0, 16.0));
        let clean = f_and_sigma(&act, &pseudo_observations(&act, &r));
        // A reading 20 standard deviations off on a two-voltage actuator (the last rows).
        let mut tail = r.clone();
        *tail.last_mut().unwrap() += 1.0;
        assert_eq!(f_and_sigma(&act, &pseudo_observations(&act, &tail)), clean);
        // The same reading on a swept actuator counts as a clipped reading.
        let mut swept = r.clone();
        swept[2] += 1.0;
        let pseudo = pseudo_observations(&act, &swept);
        let clip = pseudo.iter().fold(0.0, |m: f64, x| m.max(x.abs()));
        assert_eq!(pseudo[2], clip);
        assert!(clip < 0.2, "{clip}");
        // Its pure error is that of the clean data within half, not several times over.
        let (raw, robust) = (f_and_sigma(&act, &swept).1, f_and_sigma(&act, &pseudo).1);
        assert!(
            raw > 2.0 * clean.1 && robust < 1.5 * clean.1,
            "{raw} {robust} vs {}",
            clean.1
        );
        // Readings inside the clip are left alone.
        let inside = r.iter().zip(&pseudo).filter(|(a, b)| a == b).count();
        assert!(inside >= labels.len() - 3, "{inside}");
    }
}
