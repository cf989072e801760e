//! The fitted models as report.json lists them: the selected effects with their parameters, the
//! correlations of the final model's parameters, and every model the selection fitted.

use crate::calibrate::library::Stage;
use crate::calibrate::rounded::{six_digits, six_digits_pair};
use crate::calibrate::select::{Candidate, Role};
use crate::calibrate::Calibration;
use serde::ser::SerializeMap;
use serde::{Serialize, Serializer};
use std::collections::BTreeMap;

/// A selected effect and its one parameter, written as
/// `{"name", "parameters": {p: v}, "intervals": {p: [lo, hi]}, "std_errors": {p: se}}`.
#[derive(Debug, Clone, PartialEq)]
pub struct SelectedEffect<'a> {
    /// Effect name.
    pub name: &'a str,
    /// Parameter name (report units in the name).
    pub parameter: &'a str,
    /// Estimate.
    pub estimate: f64,
    /// 95% interval.
    pub interval: (f64, f64),
    /// Standard error.
    pub std_error: f64,
}

/// A number rounded for report.json.
struct Rounded(f64);

impl Serialize for Rounded {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        six_digits(&self.0, s)
    }
}

/// An interval rounded for report.json.
struct RoundedPair((f64, f64));

impl Serialize for RoundedPair {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        six_digits_pair(&self.0, s)
    }
}

impl Serialize for SelectedEffect<'_> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let one = |v| BTreeMap::from([(self.parameter, v)]);
        let mut m = s.serialize_map(Some(4))?;
        m.serialize_entry("name", self.name)?;
        m.serialize_entry("parameters", &one(Rounded(self.estimate)))?;
        m.serialize_entry(
            "intervals",
            &BTreeMap::from([(self.parameter, RoundedPair(self.interval))]),
        )?;
        m.serialize_entry("std_errors", &one(Rounded(self.std_error)))?;
        m.end()
    }
}

/// Correlation of two fitted parameters.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ParameterCorrelation<'a> {
    /// First parameter.
    pub a: &'a str,
    /// Second parameter.
    pub b: &'a str,
    /// Correlation coefficient.
    #[serde(serialize_with = "six_digits")]
    pub rho: f64,
}

/// One fitted model.
#[derive(Debug, Clone, Serialize)]
pub struct CandidateRow<'a> {
    /// `mass` or `actuation`.
    pub stage: &'static str,
    /// `original`, `null` or `candidate`.
    pub role: &'static str,
    /// Effect names in parameter order.
    pub effects: Vec<&'a str>,
    /// Estimate per parameter name.
    #[serde(serialize_with = "rounded_map")]
    pub parameters: BTreeMap<&'a str, f64>,
    /// AICc.
    #[serde(serialize_with = "six_digits")]
    pub aicc: f64,
    /// BIC.
    #[serde(serialize_with = "six_digits")]
    pub bic: f64,
    /// Grouped cross-validated RMSE of the log residuals.
    #[serde(serialize_with = "six_digits")]
    pub cv_rmse: f64,
    /// Residual sum of squares.
    #[serde(serialize_with = "six_digits")]
    pub rss: f64,
    /// Number of residuals.
    pub n: usize,
    /// Passed every acceptance test.
    pub accepted: bool,
    /// Why it was not accepted.
    pub note: &'a str,
}

fn rounded_map<S: Serializer>(m: &BTreeMap<&str, f64>, s: S) -> Result<S::Ok, S::Error> {
    s.collect_map(m.iter().map(|(k, v)| (k, Rounded(*v))))
}

impl CandidateRow<'_> {
    /// Display label like `{eta, dead-length}` (`original` for no effects).
    pub fn label(&self) -> String {
        if self.effects.is_empty() {
            return "original".into();
        }
        format!("{{{}}}", self.effects.join(", "))
    }
}

/// Each selected effect with the parameter fitted for it, from the final mass or actuation model.
pub fn selected_effects(cal: &Calibration) -> Vec<SelectedEffect<'_>> {
    let s = &cal.selection;
    let mass = s.final_mass_index.map(|i| &s.mass_candidates[i]);
    let act = &s.candidates[s.final_index];
    s.selected
        .iter()
        .filter_map(|id| {
            // A mass effect refitted on all the data beside the actuation model reports that fit.
            if let Some(c) = act.carried.iter().find(|c| c.id == *id) {
                return Some(SelectedEffect {
                    name: id.name(),
                    parameter: id.param().name,
                    estimate: c.value,
                    interval: c.interval,
                    std_error: c.std_error,
                });
            }
            [mass, Some(act)]
                .into_iter()
                .flatten()
                .find_map(|c| c.effects.iter().position(|e| e == id).map(|k| (c, k)))
                .map(|(c, k): (&Candidate, usize)| SelectedEffect {
                    name: id.name(),
                    parameter: id.param().name,
                    estimate: c.values[k],
                    interval: c.intervals[k],
                    std_error: c.std_errors[k],
                })
        })
        .collect()
}

/// The correlation of each pair of a model's parameters.
pub(super) fn parameter_correlations(c: &Candidate) -> Vec<ParameterCorrelation<'_>> {
    let mut out = Vec::new();
    for (a, ea) in c.effects.iter().enumerate() {
        for (b, eb) in c.effects.iter().enumerate().skip(a + 1) {
            out.push(ParameterCorrelation {
                a: ea.param().name,
                b: eb.param().name,
                rho: c.correlation[a][b],
            });
        }
    }
    out
}

impl<'a> CandidateRow<'a> {
    /// The row of a fitted model.
    pub(super) fn new(c: &'a Candidate) -> Self {
        CandidateRow {
            stage: match c.stage {
                Stage::Mass => "mass",
                Stage::Actuation => "actuation",
            },
            role: match c.role {
                Role::Original => "original",
                Role::Null => "null",
                Role::Candidate => "candidate",
            },
            effects: c.effects.iter().map(|e| e.name()).collect(),
            parameters: c
                .effects
                .iter()
                .zip(&c.values)
                .map(|(id, v)| (id.param().name, *v))
                .collect(),
            aicc: c.aicc,
            bic: c.bic,
            cv_rmse: c.cv_rmse,
            rss: c.rss,
            n: c.n,
            accepted: c.accepted,
            note: &c.note,
        }
    }
}
