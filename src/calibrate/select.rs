//! Model selection (CALIBRATION-NOTES §3): mass effects first, then every subset of at most two effects
//! (+ η) against the null models {η} and {η, uniform stiffness}, by AICc and grouped cross-validation,
//! with covariance intervals, an adequacy test and a verdict that refuses to name an effect it cannot
//! tell apart or that leaves the residual following a design variable.

use super::csv::{Dataset, Measurement};
use super::fit::{least_squares, Bounds, FitResult};
use super::library::{EffectId, Stage};
use super::stats;
use actuator_model::effects::{Actuator, Effects, StackBasis};
use actuator_model::{Drive, ModelError, Planform};
use rayon::prelude::*;

/// Knobs of the selection; the defaults are the documented procedure.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Settings {
    /// Seed of the cross-validation folds.
    pub seed: u64,
    /// Folds of grouped cross-validation.
    pub folds: usize,
    /// Repeats of the K-fold split.
    pub repeats: usize,
    /// Largest number of effects (besides η) in one model.
    pub max_effects: usize,
    /// ΔAICc an added effect must gain over its parent.
    pub min_delta_aicc: f64,
    /// Family-wise level of the adequacy tests.
    pub alpha: f64,
    /// Smallest |η - 1| reported as a d31 scale: below it the change is immaterial to a design and a
    /// 5%-noise data set flags it by chance more often than the 1-in-10 the null case allows.
    pub min_relevant_d31_change: f64,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            seed: 1,
            folds: 5,
            repeats: 2,
            max_effects: 2,
            min_delta_aicc: 4.0,
            alpha: 0.01,
            min_relevant_d31_change: 0.02,
        }
    }
}

/// Role of a fitted model in the selection.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Role {
    /// The original model, nothing fitted.
    Original,
    /// A null model ({η} or {η, stiffness-scale}).
    Null,
    /// A model with library effects.
    Candidate,
}

/// One fitted model.
#[derive(Debug, Clone)]
pub struct Candidate {
    /// Which data it was fitted on.
    pub stage: Stage,
    /// Role in the selection.
    pub role: Role,
    /// Fitted effects, in parameter order.
    pub effects: Vec<EffectId>,
    /// Estimates in report units.
    pub values: Vec<f64>,
    /// Standard errors.
    pub std_errors: Vec<f64>,
    /// 95% intervals (t quantile times the covariance standard error).
    pub intervals: Vec<(f64, f64)>,
    /// Parameter correlation matrix.
    pub correlation: Vec<Vec<f64>>,
    /// Residual sum of squares (log residuals).
    pub rss: f64,
    /// Number of residuals.
    pub n: usize,
    /// AICc.
    pub aicc: f64,
    /// BIC.
    pub bic: f64,
    /// Grouped cross-validated RMSE of the log residuals.
    pub cv_rmse: f64,
    /// Passed every acceptance test.
    pub accepted: bool,
    /// Why it was not accepted (empty if accepted or a null model).
    pub note: String,
    /// The complete effects of this model (frozen mass effects included).
    pub model: Effects,
    /// The fit itself (residuals, Jacobian).
    pub fit: FitResult,
}

impl Candidate {
    /// Effects other than η and stiffness-scale.
    pub fn library_effects(&self) -> Vec<EffectId> {
        self.effects
            .iter()
            .copied()
            .filter(|e| !matches!(e, EffectId::D31Scale | EffectId::StiffnessScale))
            .collect()
    }

    /// Display label like `{eta, dead-length}`.
    pub fn label(&self) -> String {
        if self.effects.is_empty() {
            return "original".into();
        }
        let names: Vec<&str> = self.effects.iter().map(|e| e.name()).collect();
        format!("{{{}}}", names.join(", "))
    }

    fn excludes_null(&self, k: usize) -> bool {
        let null = self.effects[k].param().null;
        let (lo, hi) = self.intervals[k];
        lo.is_finite() && hi.is_finite() && (lo > null || hi < null)
    }
}

/// The verdict of issue 6.
#[derive(Debug, Clone, PartialEq)]
pub enum Verdict {
    /// The original model (no significant d31 scale) fits within the noise.
    NoEffect,
    /// The selected effects explain the residual.
    Explained,
    /// Several effect sets fit equally well.
    Ambiguous {
        /// The competing effect sets.
        contenders: Vec<Vec<String>>,
    },
    /// The residual still follows a variable no selected effect explains.
    NotExplained {
        /// The variable it follows most strongly.
        variable: String,
    },
}

impl Verdict {
    /// The name written to report.json.
    pub fn name(&self) -> &'static str {
        match self {
            Verdict::NoEffect => "no-effect",
            Verdict::Explained => "explained",
            Verdict::Ambiguous { .. } => "ambiguous",
            Verdict::NotExplained { .. } => "not-explained",
        }
    }
}

/// Lack-of-fit F test against per-actuator lines in the field (pure error from the voltage sweeps).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LackOfFit {
    /// F statistic.
    pub f: f64,
    /// Numerator degrees of freedom.
    pub df1: f64,
    /// Denominator (pure-error) degrees of freedom.
    pub df2: f64,
    /// Upper-tail p-value.
    pub p: f64,
    /// Pure-error standard deviation of the log residuals.
    pub sigma_pure: f64,
}

/// Correlation of a remaining residual with a design variable.
#[derive(Debug, Clone, PartialEq)]
pub struct CorrelationTest {
    /// `deflection`, `stiffness` or `mass`.
    pub residual: &'static str,
    /// Variable name.
    pub variable: &'static str,
    /// Pearson r.
    pub r: f64,
    /// Pairs used.
    pub n: usize,
    /// Raw p-value.
    pub p: f64,
    /// Holm-adjusted p-value.
    pub p_holm: f64,
}

/// Adequacy of the final model.
#[derive(Debug, Clone, PartialEq)]
pub struct Adequacy {
    /// Lack-of-fit test (None without sweeps of 3+ levels).
    pub lack_of_fit: Option<LackOfFit>,
    /// Holm-corrected correlations of the remaining residual.
    pub correlations: Vec<CorrelationTest>,
    /// Both tests pass at the family level.
    pub passed: bool,
    /// Variable the residual follows most (smallest p).
    pub worst_variable: Option<String>,
}

/// A flagged data row.
#[derive(Debug, Clone, PartialEq)]
pub struct Outlier {
    /// Actuator id.
    pub id: String,
    /// File line.
    pub line: u64,
    /// `free_deflection` or `blocked_force`.
    pub output: &'static str,
    /// Studentised residual.
    pub studentised: f64,
    /// Cook's distance.
    pub cooks_distance: f64,
}

/// A design that would tell two contenders apart.
#[derive(Debug, Clone, PartialEq)]
pub struct SeparatingDesign {
    /// l_tot, mm.
    pub l_tot_mm: f64,
    /// l_r.
    pub l_r: f64,
    /// w_0, mm.
    pub w0_mm: f64,
    /// w_r.
    pub w_r: f64,
    /// t_p, mm.
    pub t_p_mm: f64,
    /// Layup.
    pub layup: String,
    /// Voltage, V.
    pub voltage_v: f64,
    /// Predicted ratio of deflections (contender 1 / contender 2).
    pub deflection_ratio: f64,
    /// Predicted ratio of blocked forces.
    pub force_ratio: f64,
}

/// Everything the selection concluded.
#[derive(Debug, Clone)]
pub struct Selection {
    /// Verdict.
    pub verdict: Verdict,
    /// Mass-stage models (empty without mass data).
    pub mass_candidates: Vec<Candidate>,
    /// Actuation-stage models.
    pub candidates: Vec<Candidate>,
    /// Index of the final actuation model in `candidates`.
    pub final_index: usize,
    /// Index of the final mass model in `mass_candidates`.
    pub final_mass_index: Option<usize>,
    /// The calibrated effects.
    pub model: Effects,
    /// Selected effects (mass stage first).
    pub selected: Vec<EffectId>,
    /// Adequacy of the final model.
    pub adequacy: Adequacy,
    /// Flagged rows.
    pub outliers: Vec<Outlier>,
    /// Designs that separate ambiguous contenders.
    pub separating_designs: Vec<SeparatingDesign>,
    /// Remarks for the report.
    pub notes: Vec<String>,
}

/// Residuals of one stage under given effects, optionally on a subset of actuators.
trait StageData: Sync {
    fn residuals(&self, effects: &Effects, keep: Option<&[bool]>, out: &mut Vec<f64>);
    fn groups(&self) -> usize;
}

struct MassData<'a> {
    data: &'a Dataset,
    /// (group, row, ln measured mass)
    obs: Vec<(usize, usize, f64)>,
}

impl StageData for MassData<'_> {
    fn residuals(&self, effects: &Effects, keep: Option<&[bool]>, out: &mut Vec<f64>) {
        out.clear();
        for &(g, row, ln_m) in &self.obs {
            if keep.is_some_and(|k| !k[g]) {
                continue;
            }
            let m = effects.mass(&self.data.rows[row].actuator()).total();
            out.push(ln_m - m.ln());
        }
    }
    fn groups(&self) -> usize {
        self.data.actuators()
    }
}

/// One row of the actuation stage.
#[derive(Debug, Clone, Copy)]
struct ActuationObs {
    group: usize,
    row: usize,
    basis: StackBasis,
    ln_delta: Option<f64>,
    ln_force: Option<f64>,
}

struct ActuationData {
    obs: Vec<ActuationObs>,
    groups: usize,
}

impl StageData for ActuationData {
    fn residuals(&self, effects: &Effects, keep: Option<&[bool]>, out: &mut Vec<f64>) {
        out.clear();
        for o in &self.obs {
            if keep.is_some_and(|k| !k[o.group]) {
                continue;
            }
            let (delta, force) = effects.outputs(&o.basis);
            if let Some(d) = o.ln_delta {
                out.push(d - delta.ln());
            }
            if let Some(f) = o.ln_force {
                out.push(f - force.ln());
            }
        }
    }
    fn groups(&self) -> usize {
        self.groups
    }
}

impl ActuationData {
    /// (obs index, output name) of each residual in the unmasked order.
    fn labels(&self) -> Vec<(usize, &'static str)> {
        let mut labels = Vec::new();
        for (i, o) in self.obs.iter().enumerate() {
            if o.ln_delta.is_some() {
                labels.push((i, "free_deflection"));
            }
            if o.ln_force.is_some() {
                labels.push((i, "blocked_force"));
            }
        }
        labels
    }
}

/// splitmix64: a fixed, dependency-free generator for the fold assignment.
fn splitmix(state: &mut u64) -> u64 {
    *state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// Fold of each actuator for each repeat (deterministic from the seed).
fn folds(groups: usize, settings: &Settings) -> Vec<Vec<usize>> {
    let k = settings.folds.clamp(2, groups.max(2));
    (0..settings.repeats.max(1))
        .map(|rep| {
            let mut state = settings.seed ^ (0xA5A5_0000 + rep as u64);
            let mut order: Vec<usize> = (0..groups).collect();
            for i in (1..groups).rev() {
                let j = (splitmix(&mut state) % (i as u64 + 1)) as usize;
                order.swap(i, j);
            }
            let mut fold = vec![0; groups];
            for (pos, &g) in order.iter().enumerate() {
                fold[g] = pos % k;
            }
            fold
        })
        .collect()
}

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

struct Fitter<'a> {
    data: &'a dyn StageData,
    base: Effects,
    folds: Vec<Vec<usize>>,
    dead_length_max_mm: f64,
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

    fn effects_at(&self, ids: &[EffectId], theta: &[f64]) -> Effects {
        let mut e = self.base;
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

    fn fit(&self, ids: &[EffectId], stage: Stage, role: Role) -> Candidate {
        let bounds = self.bounds(ids);
        let specs: Vec<(f64, f64, &'static [f64])> = ids
            .iter()
            .zip(&bounds)
            .map(|(id, b)| (b.lo, b.hi, id.param().starts))
            .collect();
        let fit = self.fit_on(ids, None, &starts(&specs));
        let p = ids.len();
        let n = fit.n;
        let nf = n as f64;
        let kf = p as f64;
        let rss = fit.rss.max(1e-300);
        let aicc = if n > p + 1 {
            nf * (rss / nf).ln() + 2.0 * kf + 2.0 * kf * (kf + 1.0) / (nf - kf - 1.0)
        } else {
            f64::INFINITY
        };
        let bic = nf * (rss / nf).ln() + kf * nf.ln();
        let cov = fit.covariance();
        let t = stats::t_quantile_two_sided(0.95, (nf - kf).max(1.0));
        let std_errors: Vec<f64> = (0..p).map(|k| cov[(k, k)].max(0.0).sqrt()).collect();
        let intervals = fit
            .theta
            .iter()
            .zip(&std_errors)
            .map(|(v, se)| (v - t * se, v + t * se))
            .collect();
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
        let cv_rmse = self.cross_validate(ids, &fit.theta);
        Candidate {
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

    /// Repeated grouped K-fold: whole actuators are held out; each fold starts from the full-data fit.
    fn cross_validate(&self, ids: &[EffectId], theta: &[f64]) -> f64 {
        let groups = self.data.groups();
        let (mut sum, mut count) = (0.0, 0usize);
        let mut out = Vec::new();
        for fold_of in &self.folds {
            let k = fold_of.iter().copied().max().unwrap_or(0) + 1;
            for fold in 0..k {
                let test: Vec<bool> = (0..groups).map(|g| fold_of[g] == fold).collect();
                let train: Vec<bool> = test.iter().map(|t| !t).collect();
                let e = if ids.is_empty() {
                    self.base
                } else {
                    let fit = self.fit_on(ids, Some(&train), &[theta.to_vec()]);
                    self.effects_at(ids, &fit.theta)
                };
                self.data.residuals(&e, Some(&test), &mut out);
                sum += out.iter().map(|r| r * r).sum::<f64>();
                count += out.len();
            }
        }
        if count == 0 {
            f64::INFINITY
        } else {
            (sum / count as f64).sqrt()
        }
    }
}

/// Design variables per actuator: name and value (report units).
pub fn design_variables(m: &Measurement) -> [(&'static str, f64); 9] {
    let pl = &m.planform;
    let t = 2.0 * m.pzt_thickness + m.layup_deg.len() as f64 * m.ply_thickness;
    [
        ("l_tot_mm", pl.length * 1e3),
        ("l_p_mm", pl.piezo_length() * 1e3),
        ("l_r", pl.extension_ratio),
        ("w0_mm", pl.base_width * 1e3),
        ("w_r", pl.width_ratio),
        ("t_p_mm", m.pzt_thickness * 1e3),
        ("plies", m.layup_deg.len() as f64),
        ("w0*t_p_mm2", pl.base_width * m.pzt_thickness * 1e6),
        (
            "w*t^3/L_mm3",
            pl.nominal_width() * t.powi(3) / pl.length * 1e9,
        ),
    ]
}

/// Largest number of parameters a model can have: η + the allowed effects.
pub fn max_parameters(settings: &Settings) -> usize {
    1 + settings.max_effects
}

/// Run the whole selection.
pub fn select(data: &Dataset, settings: &Settings) -> Result<Selection, ModelError> {
    let mut notes = Vec::new();
    let groups = data.actuators();
    let folds_of = folds(groups, settings);
    let l_p_min_mm = data
        .rows
        .iter()
        .map(|r| r.planform.piezo_length() * 1e3)
        .fold(f64::INFINITY, f64::min);
    let dead_length_max_mm = 0.8 * l_p_min_mm;

    // --- Stage 1: mass effects on the measured masses, then frozen.
    let mut seen = vec![false; groups];
    let mut mass_obs = Vec::new();
    for (i, r) in data.rows.iter().enumerate() {
        let g = data.group_of[i];
        if let (false, Some(m)) = (seen[g], r.mass) {
            seen[g] = true;
            mass_obs.push((g, i, m.ln()));
        }
    }
    let mass_data = MassData {
        data,
        obs: mass_obs,
    };
    let mut mass_candidates = Vec::new();
    let mut base = Effects::default();
    let mut selected = Vec::new();
    let mut contenders: Vec<Vec<String>> = Vec::new();
    let mut final_mass_index = None;
    if mass_data.obs.len() >= 4 {
        let fitter = Fitter {
            data: &mass_data,
            base,
            folds: folds_of.clone(),
            dead_length_max_mm,
        };
        let mass_effects = [EffectId::PlyThickness, EffectId::BondLayer];
        let mut sets: Vec<(Vec<EffectId>, Role)> = vec![(vec![], Role::Original)];
        for e in mass_effects {
            sets.push((vec![e], Role::Candidate));
        }
        if settings.max_effects >= 2 && mass_data.obs.len() >= 8 {
            sets.push((mass_effects.to_vec(), Role::Candidate));
        }
        mass_candidates = sets
            .par_iter()
            .map(|(ids, role)| fitter.fit(ids, Stage::Mass, *role))
            .collect();
        judge(&mut mass_candidates, &[0], settings);
        let (best, rivals) = best_and_rivals(&mass_candidates, settings);
        let chosen = best.unwrap_or(0);
        final_mass_index = Some(chosen);
        base = mass_candidates[chosen].model;
        selected.extend(mass_candidates[chosen].library_effects());
        contenders.extend(rivals);
    } else {
        notes.push(
            "fewer than 4 actuators with a measured mass: mass effects (ply-thickness, bond-layer) \
             were not fitted"
                .into(),
        );
    }

    // --- Stage 2: actuation and compliance effects on deflection and force.
    let mut obs = Vec::new();
    for (i, r) in data.rows.iter().enumerate() {
        if r.free_deflection.is_none() && r.blocked_force.is_none() {
            continue;
        }
        if r.voltage <= 0.0 {
            continue;
        }
        obs.push(ActuationObs {
            group: data.group_of[i],
            row: i,
            basis: base.basis(&r.actuator())?,
            ln_delta: r.free_deflection.map(f64::ln),
            ln_force: r.blocked_force.map(f64::ln),
        });
    }
    let act_groups: std::collections::BTreeSet<usize> = obs.iter().map(|o| o.group).collect();
    if act_groups.len() < max_parameters(settings) + 2 {
        return Err(ModelError::Fit(format!(
            "{} actuators with deflection or force data: the largest model has {} parameters and \
             needs at least {} actuators",
            act_groups.len(),
            max_parameters(settings),
            max_parameters(settings) + 2
        )));
    }
    let act_data = ActuationData { obs, groups };
    let fitter = Fitter {
        data: &act_data,
        base,
        folds: folds_of,
        dead_length_max_mm,
    };
    let eta = EffectId::D31Scale;
    let library: Vec<EffectId> = EffectId::LIBRARY
        .into_iter()
        .filter(|e| *e != eta && e.stage() == Stage::Actuation)
        .collect();
    let mut sets: Vec<(Vec<EffectId>, Role)> = vec![
        (vec![], Role::Original),
        (vec![eta], Role::Null),
        (vec![eta, EffectId::StiffnessScale], Role::Null),
    ];
    let n_points: usize = act_data
        .obs
        .iter()
        .map(|o| o.ln_delta.is_some() as usize + o.ln_force.is_some() as usize)
        .sum();
    // Parameter count at most n/10 (CALIBRATION-NOTES §3).
    let max_effects = settings.max_effects.min((n_points / 10).saturating_sub(1));
    if max_effects < settings.max_effects {
        notes.push(format!(
            "{n_points} data points: models limited to {max_effects} effect(s) besides eta (parameters <= n/10)"
        ));
    }
    if max_effects >= 1 {
        for &a in &library {
            sets.push((vec![eta, a], Role::Candidate));
        }
    }
    if max_effects >= 2 {
        for (i, &a) in library.iter().enumerate() {
            for &b in &library[i + 1..] {
                sets.push((vec![eta, a, b], Role::Candidate));
            }
        }
    }
    let mut candidates: Vec<Candidate> = sets
        .par_iter()
        .map(|(ids, role)| fitter.fit(ids, Stage::Actuation, *role))
        .collect();
    judge(&mut candidates, &[1, 2], settings);
    let (best, rivals) = best_and_rivals(&candidates, settings);
    contenders.extend(rivals);
    let final_index = match best {
        Some(b) => b,
        None => {
            let (original, null_eta) = (&candidates[0], &candidates[1]);
            if null_eta.aicc < original.aicc - settings.min_delta_aicc
                && null_eta.excludes_null(0)
                && (null_eta.values[0] - 1.0).abs() >= settings.min_relevant_d31_change
            {
                1
            } else {
                0
            }
        }
    };
    let chosen = &candidates[final_index];
    if let Some(k) = chosen.effects.iter().position(|e| *e == eta) {
        if chosen.excludes_null(k)
            && (chosen.values[k] - 1.0).abs() >= settings.min_relevant_d31_change
        {
            selected.insert(0, eta);
        }
    }
    selected.extend(chosen.library_effects());
    let model = chosen.model;

    let adequacy = adequacy(
        data,
        &act_data,
        chosen,
        final_mass_index.map(|i| &mass_candidates[i]),
        &mass_data,
        settings,
    );
    let outliers = outliers(data, &act_data, chosen);
    let mut separating_designs = Vec::new();
    let verdict = if !adequacy.passed {
        Verdict::NotExplained {
            variable: adequacy
                .worst_variable
                .clone()
                .unwrap_or_else(|| "(lack of fit, no single variable)".into()),
        }
    } else if !contenders.is_empty() {
        let mut all = vec![selected.iter().map(|e| e.name().to_string()).collect()];
        all.extend(contenders);
        if let Some(&rival) = best_and_rivals_indices(&candidates, settings).get(1) {
            separating_designs = separate(
                data,
                &candidates[final_index].model,
                &candidates[rival].model,
            );
        }
        Verdict::Ambiguous { contenders: all }
    } else if selected.is_empty() {
        Verdict::NoEffect
    } else {
        Verdict::Explained
    };
    Ok(Selection {
        verdict,
        mass_candidates,
        candidates,
        final_index,
        final_mass_index,
        model,
        selected,
        adequacy,
        outliers,
        separating_designs,
        notes,
    })
}

/// Mark which candidates pass: ΔAICc over every parent (the nulls for singles, both singles for a pair),
/// better cross-validation than every parent, and intervals that exclude the null value.
fn judge(candidates: &mut [Candidate], nulls: &[usize], settings: &Settings) {
    let snapshot: Vec<(Vec<EffectId>, f64, f64)> = candidates
        .iter()
        .map(|c| (c.library_effects(), c.aicc, c.cv_rmse))
        .collect();
    let labels: Vec<String> = candidates.iter().map(Candidate::label).collect();
    for c in candidates.iter_mut() {
        if c.role != Role::Candidate {
            continue;
        }
        let mine = c.library_effects();
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
        for (k, id) in c.effects.iter().enumerate() {
            if id.stage() == c.stage && *id != EffectId::D31Scale && !c.excludes_null(k) {
                why.push(format!("{} interval includes the null value", id.name()));
            }
        }
        c.accepted = why.is_empty();
        c.note = why.join("; ");
    }
}

fn best_and_rivals_indices(candidates: &[Candidate], settings: &Settings) -> Vec<usize> {
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
fn best_and_rivals(
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

fn adequacy(
    data: &Dataset,
    act: &ActuationData,
    chosen: &Candidate,
    mass_model: Option<&Candidate>,
    mass_data: &MassData,
    settings: &Settings,
) -> Adequacy {
    let mut r = Vec::new();
    act.residuals(&chosen.model, None, &mut r);
    let labels = act.labels();
    // Per (group, output): (field, residual) pairs.
    let groups = data.actuators();
    let mut by: Vec<[Vec<(f64, f64)>; 2]> = vec![[Vec::new(), Vec::new()]; groups];
    let mut row_res: Vec<[Option<f64>; 2]> = vec![[None, None]; act.obs.len()];
    for (&(i, output), &res) in labels.iter().zip(&r) {
        let o = &act.obs[i];
        let slot = (output == "blocked_force") as usize;
        by[o.group][slot].push((o.basis.field, res));
        row_res[i][slot] = Some(res);
    }
    // Pure error: a line in the field per actuator and output.
    let (mut rss_full, mut q) = (0.0, 0usize);
    let mut sweeps = 0usize;
    for pair in &by {
        for pts in pair {
            if pts.is_empty() {
                continue;
            }
            let m = pts.len() as f64;
            let mx = pts.iter().map(|p| p.0).sum::<f64>() / m;
            let my = pts.iter().map(|p| p.1).sum::<f64>() / m;
            let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
            let slope = if sxx > 1e-12 * mx * mx * m {
                q += 2;
                pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum::<f64>() / sxx
            } else {
                q += 1;
                0.0
            };
            if pts.len() >= 3 {
                sweeps += 1;
            }
            rss_full += pts
                .iter()
                .map(|p| (p.1 - my - slope * (p.0 - mx)).powi(2))
                .sum::<f64>();
        }
    }
    let n = r.len();
    let p = chosen.values.len();
    let df2 = n as f64 - q as f64;
    let df1 = q as f64 - p as f64;
    let lack_of_fit = if sweeps >= 3 && df2 >= 5.0 && df1 >= 1.0 && rss_full > 0.0 {
        let f = ((chosen.fit.rss - rss_full).max(0.0) / df1) / (rss_full / df2);
        Some(LackOfFit {
            f,
            df1,
            df2,
            p: stats::f_upper_p(f, df1, df2),
            sigma_pure: (rss_full / df2).sqrt(),
        })
    } else {
        None
    };

    // Correlations of the per-actuator mean residuals with the design variables.
    let mut tests = Vec::new();
    let mut per_group: Vec<(usize, [Vec<f64>; 2])> = Vec::new();
    for (i, o) in act.obs.iter().enumerate() {
        let entry = match per_group.iter_mut().find(|(g, _)| *g == o.group) {
            Some(e) => e,
            None => {
                per_group.push((o.group, [Vec::new(), Vec::new()]));
                per_group.last_mut().expect("just pushed")
            }
        };
        if let Some(d) = row_res[i][0] {
            entry.1[0].push(d);
            if let Some(f) = row_res[i][1] {
                entry.1[1].push(f - d);
            }
        }
    }
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    let mut mass_res = vec![None; groups];
    if let Some(mm) = mass_model {
        let mut out = Vec::new();
        mass_data.residuals(&mm.model, None, &mut out);
        for (&(g, _, _), v) in mass_data.obs.iter().zip(out) {
            mass_res[g] = Some(v);
        }
    }
    let first_row = |g: usize| &data.rows[data.groups[g][0]];
    for (kind, slot) in [("deflection", 0usize), ("stiffness", 1)] {
        let pts: Vec<(usize, f64)> = per_group
            .iter()
            .filter(|(_, v)| !v[slot].is_empty())
            .map(|(g, v)| (*g, mean(&v[slot])))
            .collect();
        push_variable_tests(&mut tests, kind, &pts, &first_row);
    }
    let mass_pts: Vec<(usize, f64)> = (0..groups)
        .filter_map(|g| mass_res[g].map(|v| (g, v)))
        .collect();
    push_variable_tests(&mut tests, "mass", &mass_pts, &first_row);
    // Within-sweep trend with the field.
    for (kind, slot) in [("deflection", 0usize), ("stiffness", 1)] {
        let (mut xs, mut ys) = (Vec::new(), Vec::new());
        for (g, _) in &per_group {
            let pts: Vec<(f64, f64)> = act
                .obs
                .iter()
                .enumerate()
                .filter(|(_, o)| o.group == *g)
                .filter_map(|(i, o)| {
                    let d = row_res[i][0];
                    let v = if slot == 0 {
                        d
                    } else {
                        row_res[i][1].zip(d).map(|(f, d)| f - d)
                    };
                    v.map(|v| (o.basis.field * 1e-6, v))
                })
                .collect();
            if pts.len() < 2 {
                continue;
            }
            let mx = pts.iter().map(|p| p.0).sum::<f64>() / pts.len() as f64;
            let my = pts.iter().map(|p| p.1).sum::<f64>() / pts.len() as f64;
            for (x, y) in pts {
                xs.push(x - mx);
                ys.push(y - my);
            }
        }
        if let Some(r) = stats::pearson(&xs, &ys) {
            let groups_used = per_group.len();
            // Each actuator's centring removes one degree of freedom.
            let n_eff = xs.len().saturating_sub(groups_used) + 2;
            tests.push(CorrelationTest {
                residual: kind,
                variable: "field_V_per_um (within sweep)",
                r,
                n: n_eff,
                p: stats::correlation_p(r, n_eff),
                p_holm: 1.0,
            });
        }
    }
    let raw: Vec<f64> = tests.iter().map(|t| t.p).collect();
    for (t, adj) in tests.iter_mut().zip(stats::holm(&raw)) {
        t.p_holm = adj;
    }
    let worst = tests
        .iter()
        .min_by(|a, b| a.p.total_cmp(&b.p))
        .map(|t| format!("{} ({} residual, r = {:.2})", t.variable, t.residual, t.r));
    let correlations_pass = tests.iter().all(|t| t.p_holm >= settings.alpha);
    let lof_pass = lack_of_fit.is_none_or(|l| l.p >= settings.alpha);
    Adequacy {
        lack_of_fit,
        correlations: tests,
        passed: correlations_pass && lof_pass,
        worst_variable: worst,
    }
}

fn push_variable_tests<'a>(
    tests: &mut Vec<CorrelationTest>,
    kind: &'static str,
    pts: &[(usize, f64)],
    first_row: &dyn Fn(usize) -> &'a Measurement,
) {
    if pts.len() < 4 {
        return;
    }
    let ys: Vec<f64> = pts.iter().map(|p| p.1).collect();
    let vars: Vec<[(&'static str, f64); 9]> = pts
        .iter()
        .map(|p| design_variables(first_row(p.0)))
        .collect();
    for k in 0..9 {
        let xs: Vec<f64> = vars.iter().map(|v| v[k].1).collect();
        if let Some(r) = stats::pearson(&xs, &ys) {
            tests.push(CorrelationTest {
                residual: kind,
                variable: vars[0][k].0,
                r,
                n: xs.len(),
                p: stats::correlation_p(r, xs.len()),
                p_holm: 1.0,
            });
        }
    }
}

fn outliers(data: &Dataset, act: &ActuationData, chosen: &Candidate) -> Vec<Outlier> {
    let fit = &chosen.fit;
    let p = chosen.values.len();
    let dof = (fit.n as f64 - p as f64).max(1.0);
    let sigma = (fit.rss / dof).sqrt();
    if sigma <= 0.0 {
        return Vec::new();
    }
    let leverage = fit.leverage();
    let labels = act.labels();
    let mut out = Vec::new();
    for ((&(i, output), &r), &h) in labels.iter().zip(&fit.residuals).zip(&leverage) {
        let h = h.clamp(0.0, 0.99);
        let t = r / (sigma * (1.0 - h).sqrt());
        let cooks = if p > 0 {
            t * t * h / (p as f64 * (1.0 - h))
        } else {
            0.0
        };
        if t.abs() > 3.5 || cooks > 1.0 {
            let row = &data.rows[act.obs[i].row];
            out.push(Outlier {
                id: row.id.clone(),
                line: row.line,
                output,
                studentised: t,
                cooks_distance: cooks,
            });
        }
    }
    out
}

/// Designs in the span of the data where two fitted models disagree most.
fn separate(data: &Dataset, a: &Effects, b: &Effects) -> Vec<SeparatingDesign> {
    let range = |f: &dyn Fn(&Measurement) -> f64| {
        let v: Vec<f64> = data.rows.iter().map(f).collect();
        let lo = v.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        (lo, hi)
    };
    let (l_lo, l_hi) = range(&|m| m.planform.length);
    let (lr_lo, lr_hi) = range(&|m| m.planform.extension_ratio);
    let (w_lo, w_hi) = range(&|m| m.planform.base_width);
    let (wr_lo, wr_hi) = range(&|m| m.planform.width_ratio);
    let (e_lo, e_hi) = range(&|m| m.field);
    let mut layups: Vec<usize> = Vec::new();
    let mut thick: Vec<usize> = Vec::new();
    for (i, m) in data.rows.iter().enumerate() {
        if !layups.iter().any(|&j| data.rows[j].layup == m.layup) {
            layups.push(i);
        }
        if !thick
            .iter()
            .any(|&j| (data.rows[j].pzt_thickness - m.pzt_thickness).abs() < 1e-9)
        {
            thick.push(i);
        }
    }
    let mut scored = Vec::new();
    for l in [l_lo, l_hi] {
        for lr in [lr_lo, lr_hi] {
            for w in [w_lo, w_hi] {
                for wr in [wr_lo, 1.0f64.clamp(wr_lo, wr_hi), wr_hi] {
                    for &li in &layups {
                        for &ti in &thick {
                            for e in [e_lo.max(1.0), e_hi] {
                                let lay = &data.rows[li];
                                let t_p = data.rows[ti].pzt_thickness;
                                let Ok(pl) = Planform::new(l, lr, w, wr, 0.0) else {
                                    continue;
                                };
                                let act = Actuator {
                                    pzt: &lay.pzt,
                                    pzt_thickness: t_p,
                                    ply: &lay.ply,
                                    ply_thickness: lay.ply_thickness,
                                    layup_deg: &lay.layup_deg,
                                    planform: pl,
                                    drive: Drive {
                                        mode: lay.drive_mode,
                                        field: e,
                                    },
                                };
                                let (Ok(pa), Ok(pb)) = (a.predict(&act), b.predict(&act)) else {
                                    continue;
                                };
                                let rd = pa.free_deflection / pb.free_deflection;
                                let rf = pa.blocked_force / pb.blocked_force;
                                let score = rd.ln().abs().max(rf.ln().abs());
                                scored.push((
                                    score,
                                    SeparatingDesign {
                                        l_tot_mm: l * 1e3,
                                        l_r: lr,
                                        w0_mm: w * 1e3,
                                        w_r: wr,
                                        t_p_mm: t_p * 1e3,
                                        layup: lay.layup.clone(),
                                        voltage_v: lay.drive_mode.voltage_from_field(e, t_p),
                                        deflection_ratio: rd,
                                        force_ratio: rf,
                                    },
                                ));
                            }
                        }
                    }
                }
            }
        }
    }
    scored.sort_by(|a, b| b.0.total_cmp(&a.0));
    scored.into_iter().take(3).map(|(_, d)| d).collect()
}
