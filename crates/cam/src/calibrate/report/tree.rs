//! The report of a calibration as one tree of serde structs: serialized to report.json (keys as in
//! docs/calibration.md §4) and read by the Markdown renderer, so the two files say the same thing.
//!
//! The structs keep full precision; JSON numbers are rounded to 6 significant digits on the way out
//! ([`crate::calibrate::rounded`]). report.json's keys are written in sorted order.

use crate::calibrate::baseline::{ErrorTable, ResidualCorrelation};
use crate::calibrate::broken::BrokenActuator;
use crate::calibrate::csv::Dataset;
use crate::calibrate::discover::Discovery;
use crate::calibrate::model_file;
use crate::calibrate::select::{Adequacy, Outlier, SeparatingDesign, Verdict};
use crate::calibrate::Calibration;
use serde::{Serialize, Serializer};

use super::fitted::parameter_correlations;
pub use super::fitted::{selected_effects, CandidateRow, ParameterCorrelation, SelectedEffect};

/// report.json.
#[derive(Debug, Clone, Serialize)]
pub struct Report<'a> {
    /// `no-effect`, `explained`, `ambiguous` or `not-explained`.
    pub verdict: &'static str,
    /// The contenders or the variable the residual follows.
    pub verdict_detail: VerdictDetail<'a>,
    /// Selected effects with their fitted parameter (mass stage first).
    pub selected_effects: Vec<SelectedEffect<'a>>,
    /// Correlations between the final actuation model's parameters.
    pub parameter_correlations: Vec<ParameterCorrelation<'a>>,
    /// Every fitted model, mass stage first.
    pub candidates: Vec<CandidateRow<'a>>,
    /// Errors of the original model.
    pub before: Errors<'a>,
    /// Errors of the calibrated model.
    pub after: Errors<'a>,
    /// Errors of the thesis' empirical corrections (eqs. 4.3-4.5).
    pub thesis_adjusted: Errors<'a>,
    /// With declared effects: the library-only calibration on the same actuators (absent otherwise).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub library_only: Option<LibraryOnlyErrors<'a>>,
    /// Adequacy of the final model.
    pub adequacy: &'a Adequacy,
    /// Flagged rows.
    pub outliers: &'a [Outlier],
    /// Actuators flagged as broken (absent when none).
    #[serde(skip_serializing_if = "<[_]>::is_empty")]
    pub broken_actuators: &'a [BrokenActuator],
    /// Designs that would separate ambiguous contenders.
    pub separating_designs: &'a [SeparatingDesign],
    /// Remarks of the selection.
    pub notes: &'a [String],
    /// Discovery, when not explained: the residual's power laws, the primitives that would produce it,
    /// designs that separate the leading ones (absent otherwise).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub discovery: Option<&'a Discovery>,
    /// The data set.
    pub data: DataSummary<'a>,
    /// Name of the model file written beside the report.
    pub model_file: &'static str,
}

/// What the verdict rests on (empty for `no-effect` and `explained`).
#[derive(Debug, Clone, Default, Serialize)]
pub struct VerdictDetail<'a> {
    /// Effect sets the data cannot tell apart (`ambiguous`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub contenders: Option<&'a [Vec<String>]>,
    /// The variable the remaining residual follows (`not-explained`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub follows: Option<&'a str>,
    /// Why no verdict could be given (`insufficient-data`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reason: Option<&'a str>,
}

/// Error table of one model, with its cross-validated error and residual correlations where known.
#[derive(Debug, Clone, Serialize)]
pub struct Errors<'a> {
    /// Errors per output.
    #[serde(flatten)]
    pub table: &'a ErrorTable,
    /// Cross-validated RMSE of the log residuals (δ, F_b).
    #[serde(
        rename = "cv_rmse_log_actuation",
        skip_serializing_if = "Option::is_none",
        serialize_with = "rounded_opt"
    )]
    pub cv_rmse: Option<f64>,
    /// Correlations of the residual with the design variables.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub residual_correlations: Option<&'a [ResidualCorrelation]>,
}

fn rounded_opt<S: Serializer>(x: &Option<f64>, s: S) -> Result<S::Ok, S::Error> {
    crate::calibrate::rounded::six_digits_opt(x, s)
}

/// The library-only calibration beside one with declared effects: its verdict and errors.
#[derive(Debug, Clone, Serialize)]
pub struct LibraryOnlyErrors<'a> {
    /// Its verdict.
    pub verdict: &'static str,
    /// What the verdict rests on.
    pub verdict_detail: VerdictDetail<'a>,
    /// Its errors and cross-validated RMSE.
    #[serde(flatten)]
    pub errors: Errors<'a>,
}

impl<'a> LibraryOnlyErrors<'a> {
    /// The library-only part of a calibration, when it has one.
    pub fn new(cal: &'a Calibration) -> Option<Self> {
        cal.library_only.as_ref().map(|l| LibraryOnlyErrors {
            verdict: l.verdict.name(),
            verdict_detail: VerdictDetail::new(&l.verdict),
            errors: Errors {
                table: &l.table,
                cv_rmse: Some(l.cv_rmse),
                residual_correlations: None,
            },
        })
    }
}

/// The measured data set.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DataSummary<'a> {
    /// File name.
    pub source: &'a str,
    /// Number of actuators.
    pub actuators: usize,
    /// Number of rows.
    pub rows: usize,
}

impl<'a> Report<'a> {
    /// The report of a calibration of `data` read from `source`.
    pub fn new(cal: &'a Calibration, data: &Dataset, source: &'a str) -> Self {
        let s = &cal.selection;
        Report {
            verdict: s.verdict.name(),
            verdict_detail: VerdictDetail::new(&s.verdict),
            selected_effects: selected_effects(cal),
            parameter_correlations: parameter_correlations(&s.candidates[s.final_index]),
            candidates: s
                .mass_candidates
                .iter()
                .chain(&s.candidates)
                .map(CandidateRow::new)
                .collect(),
            before: Errors {
                table: &cal.before,
                cv_rmse: Some(cal.cv_rmse_before),
                residual_correlations: Some(&cal.correlations_before),
            },
            after: Errors {
                table: &cal.after,
                cv_rmse: Some(cal.cv_rmse_after),
                residual_correlations: Some(&cal.correlations_after),
            },
            thesis_adjusted: Errors {
                table: &cal.thesis_adjusted,
                cv_rmse: None,
                residual_correlations: None,
            },
            library_only: LibraryOnlyErrors::new(cal),
            adequacy: &s.adequacy,
            outliers: &s.outliers,
            broken_actuators: &cal.broken,
            separating_designs: &s.separating_designs,
            notes: &s.notes,
            discovery: cal.discovery.as_ref(),
            data: DataSummary {
                source,
                actuators: data.actuators(),
                rows: data.rows.len(),
            },
            model_file: model_file::FILE_NAME,
        }
    }

    /// report.json's text: pretty-printed, keys sorted.
    pub fn to_json(&self) -> Result<String, serde_json::Error> {
        // Through a Value so every object's keys come out sorted, whatever the field order above.
        serde_json::to_string_pretty(&serde_json::to_value(self)?)
    }
}

impl<'a> VerdictDetail<'a> {
    /// The detail of a verdict.
    pub fn new(verdict: &'a Verdict) -> Self {
        match verdict {
            Verdict::Ambiguous { contenders } => VerdictDetail {
                contenders: Some(contenders),
                ..VerdictDetail::default()
            },
            Verdict::NotExplained { variable } => VerdictDetail {
                follows: Some(variable),
                ..VerdictDetail::default()
            },
            Verdict::InsufficientData { reason } => VerdictDetail {
                reason: Some(reason),
                ..VerdictDetail::default()
            },
            Verdict::NoEffect | Verdict::Explained => VerdictDetail::default(),
        }
    }
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use crate::calibrate::baseline::OutputErrors;
    use crate::calibrate::select::adequacy::{CorrelationTest, LackOfFit};
    use std::collections::BTreeMap;
    use std::sync::LazyLock;

    fn errors(k_mean: f64) -> OutputErrors {
        OutputErrors {
            n: 12,
            k_mean,
            k_std: 0.123_456_789,
            rmse_log: 0.05,
            mape: 4.0,
            max_error: 7.9,
            within_10: 1.0,
            within_20: 1.0,
        }
    }

    static TABLE: LazyLock<ErrorTable> = LazyLock::new(|| ErrorTable {
        mass: None,
        free_deflection: Some(errors(1.799)),
        blocked_force: Some(errors(f64::NAN)),
        stiffness: None,
        rmse_log_actuation: 0.589,
    });
    static CORRELATIONS: LazyLock<Vec<ResidualCorrelation>> = LazyLock::new(|| {
        vec![ResidualCorrelation {
            variable: "l_r".into(),
            deflection: Some(0.5),
            stiffness: None,
            mass: Some(-0.25),
        }]
    });
    static CONTENDERS: LazyLock<Vec<Vec<String>>> =
        LazyLock::new(|| vec![vec!["dead-length".into()], vec!["clamp-compliance".into()]]);
    static ADEQUACY: LazyLock<Adequacy> = LazyLock::new(|| Adequacy {
        lack_of_fit: Some(LackOfFit {
            f: 1.5,
            df1: 3.0,
            df2: 20.0,
            p: 0.25,
            sigma_pure: 0.04,
        }),
        correlations: vec![
            CorrelationTest {
                residual: "deflection",
                variable: "l_r",
                r: 0.3,
                n: 10,
                p: 0.4,
                p_holm: 1.0,
            },
            CorrelationTest {
                residual: "stiffness",
                variable: "w_r",
                r: -0.6,
                n: 10,
                p: 0.06,
                p_holm: 0.5,
            },
        ],
        passed: true,
        worst_variable: Some("w_r (stiffness residual, r = -0.60)".into()),
        resonance: None,
    });
    static OUTLIERS: LazyLock<Vec<Outlier>> = LazyLock::new(|| {
        vec![Outlier {
            id: "A7".into(),
            line: 9,
            output: "blocked_force",
            studentised: 3.75,
            cooks_distance: 0.5,
        }]
    });
    static NOTES: LazyLock<Vec<String>> = LazyLock::new(|| vec!["a remark".into()]);

    /// A hand-made report: an ambiguous verdict, one selected effect, an original and a candidate model.
    pub(in crate::calibrate::report) fn sample() -> Report<'static> {
        let with = |cv| Errors {
            table: &TABLE,
            cv_rmse: cv,
            residual_correlations: cv.map(|_| CORRELATIONS.as_slice()),
        };
        Report {
            verdict: "ambiguous",
            verdict_detail: VerdictDetail {
                contenders: Some(&CONTENDERS),
                ..VerdictDetail::default()
            },
            selected_effects: vec![SelectedEffect {
                name: "dead-length",
                parameter: "dead_length_mm",
                estimate: 2.293_123_456,
                interval: (1.908, f64::INFINITY),
                std_error: 0.19,
            }],
            parameter_correlations: vec![ParameterCorrelation {
                a: "eta",
                b: "dead_length_mm",
                rho: -0.912_345_678,
            }],
            candidates: vec![
                CandidateRow {
                    stage: "actuation",
                    role: "original",
                    effects: vec![],
                    parameters: BTreeMap::new(),
                    aicc: -10.0,
                    bic: -8.0,
                    cv_rmse: 0.6,
                    rss: 3.0,
                    n: 40,
                    accepted: false,
                    note: "",
                },
                CandidateRow {
                    stage: "actuation",
                    role: "candidate",
                    effects: vec!["d31-scale", "dead-length"],
                    parameters: BTreeMap::from([("eta", 0.8), ("dead_length_mm", 2.3)]),
                    aicc: -120.5,
                    bic: -118.0,
                    cv_rmse: 0.05,
                    rss: 0.1,
                    n: 40,
                    accepted: true,
                    note: "",
                },
            ],
            before: with(Some(0.61)),
            after: with(Some(0.052)),
            thesis_adjusted: with(None),
            library_only: None,
            adequacy: &ADEQUACY,
            outliers: &OUTLIERS,
            broken_actuators: &[],
            separating_designs: &[],
            notes: &NOTES,
            discovery: None,
            data: DataSummary {
                source: "measured.csv",
                actuators: 12,
                rows: 40,
            },
            model_file: model_file::FILE_NAME,
        }
    }

    fn json() -> serde_json::Value {
        serde_json::from_str(&sample().to_json().unwrap()).unwrap()
    }

    #[test]
    fn json_has_the_documented_top_level_keys_in_sorted_order() {
        let text = sample().to_json().unwrap();
        let v: serde_json::Value = serde_json::from_str(&text).unwrap();
        let keys: Vec<&String> = v.as_object().unwrap().keys().collect();
        let mut sorted = keys.clone();
        sorted.sort();
        assert_eq!(keys, sorted);
        for key in [
            "verdict",
            "verdict_detail",
            "selected_effects",
            "parameter_correlations",
            "candidates",
            "before",
            "after",
            "thesis_adjusted",
            "adequacy",
            "outliers",
            "separating_designs",
            "notes",
            "data",
            "model_file",
        ] {
            assert!(v.get(key).is_some(), "{key} missing");
        }
        // Written sorted in the text too (the struct's field order does not leak through).
        assert!(text.find("\"adequacy\"").unwrap() < text.find("\"verdict\"").unwrap());
    }

    #[test]
    fn selected_effects_group_values_by_parameter_and_round() {
        let v = json();
        let e = &v["selected_effects"][0];
        assert_eq!(e["name"], "dead-length");
        assert_eq!(e["parameters"]["dead_length_mm"], 2.29312);
        assert_eq!(e["intervals"]["dead_length_mm"][0], 1.908);
        assert!(e["intervals"]["dead_length_mm"][1].is_null());
        assert_eq!(e["std_errors"]["dead_length_mm"], 0.19);
        assert_eq!(v["parameter_correlations"][0]["rho"], -0.912346);
    }

    #[test]
    fn verdict_detail_and_error_tables() {
        let v = json();
        assert_eq!(v["verdict"], "ambiguous");
        assert_eq!(v["verdict_detail"]["contenders"][1][0], "clamp-compliance");
        assert!(v["verdict_detail"].get("follows").is_none());
        let before = &v["before"];
        assert_eq!(before["cv_rmse_log_actuation"], 0.61);
        assert_eq!(before["free_deflection"]["k_std"], 0.123457);
        assert!(before["blocked_force"]["k_mean"].is_null());
        assert!(before["mass"].is_null());
        assert_eq!(before["residual_correlations"][0]["mass"], -0.25);
        assert!(before["residual_correlations"][0]["stiffness"].is_null());
        let thesis = v["thesis_adjusted"].as_object().unwrap();
        assert!(!thesis.contains_key("cv_rmse_log_actuation"));
        assert!(!thesis.contains_key("residual_correlations"));
    }

    #[test]
    fn candidates_adequacy_outliers_and_data() {
        let v = json();
        let c = &v["candidates"][1];
        assert_eq!(c["role"], "candidate");
        assert_eq!(c["parameters"]["eta"], 0.8);
        assert_eq!(c["effects"][1], "dead-length");
        assert_eq!(v["candidates"][0]["parameters"], serde_json::json!({}));
        let a = &v["adequacy"];
        assert_eq!(a["lack_of_fit"]["sigma_pure_log"], 0.04);
        assert_eq!(a["lack_of_fit"]["df1"], 3.0);
        assert_eq!(a["correlations"][1]["p_holm"], 0.5);
        assert_eq!(v["outliers"][0]["line"], 9);
        assert_eq!(v["data"]["rows"], 40);
        assert_eq!(v["model_file"], "calibrated-model.toml");
        assert_eq!(sample().candidates[1].label(), "{d31-scale, dead-length}");
        assert_eq!(sample().candidates[0].label(), "original");
    }
}
