//! `suggested-effects.toml`: the loop's next step as an effects file (docs/calibration.md §3,
//! "Discovery"), written beside the report when the verdict is not-explained or ambiguous. The leading
//! candidates ([`suggest::suggestions`]) are declared; the runners-up follow as comments, each with its
//! rank, estimate, interval and AICc gain, to put in the leader's place.

use crate::calibrate::discover::suggest::Suggestion;
use crate::calibrate::effects_file::primitive_fields;
use crate::calibrate::rounded::{finite_or_word, interval_text};
use crate::calibrate::Calibration;
use std::fmt::Write;

/// The file's name.
pub const FILE_NAME: &str = "suggested-effects.toml";

/// The file, or None when there is nothing to suggest (a verdict that needs no next step, or no
/// candidate outside the library).
pub fn render(cal: &Calibration, source: &str) -> Option<String> {
    let s = &cal.selection;
    let verdict = s.verdict.name();
    if !matches!(verdict, "not-explained" | "ambiguous") {
        return None;
    }
    let list = &cal.suggestions;
    if !list.iter().any(|x| x.declared) {
        return None;
    }
    let mut t = String::new();
    let _ = writeln!(
        t,
        "# The next step of the calibration loop, from the discovery in report.md: verdict {verdict}{}.",
        s.adequacy
            .worst_variable
            .as_deref()
            .filter(|_| !s.adequacy.passed)
            .map(|v| format!(", the residual follows {v}"))
            .unwrap_or_default()
    );
    let _ = writeln!(
        t,
        "# Run: actuator-cam calibrate {source} --effects {} -o NEXT",
        FILE_NAME
    );
    t.push_str("# The leading candidates are declared; the others are listed as comments, to declare in\n# their place. Values are SI; bounds are the physical range discovery searched.\n");
    for x in list {
        t.push('\n');
        t.push_str(&entry(x));
    }
    Some(t)
}

fn entry(x: &Suggestion) -> String {
    let mut t = String::new();
    let beside = x
        .partner
        .as_ref()
        .map(|a| format!(", fitted beside the library's {a}"))
        .unwrap_or_default();
    let _ = writeln!(
        t,
        "# rank {} of the {} candidates{beside}: {} = {} {}, {}AICc gain {} over {}",
        x.rank,
        x.residual,
        x.parameter,
        finite_or_word(x.estimate, |v| format!("{v:.4e}")),
        interval_text(x.interval, |v| format!("{v:.4e}")),
        // The deflection and force ranking's is the joint criterion (docs/calibration.md §3, "Joint
        // ranking").
        if x.residual == "deflection and force" {
            "joint "
        } else {
            ""
        },
        finite_or_word(x.gain, |v| format!("{v:.1}")),
        match x.residual {
            "mass" => "the chosen mass model",
            "resonance" => "the chosen model on the resonances",
            _ => "{eta}",
        }
    );
    let body = format!(
        "[[effect]]\nname = \"{}\"\nparameter = \"{}\"\nnull = {:?}\nbounds = [{:?}, {:?}]\nprimitives = [{{ {} }}]\n",
        x.name,
        x.parameter,
        x.null,
        x.bounds.0,
        x.bounds.1,
        primitive_fields(x.primitive)
    );
    if x.declared {
        t.push_str(&body);
    } else {
        for line in body.lines() {
            let _ = writeln!(t, "# {line}");
        }
    }
    t
}

#[cfg(test)]
mod tests {
    use super::*;
    use actuator_model::primitives::Primitive;

    #[test]
    fn a_runner_up_without_an_interval_says_so_in_words() {
        // A resonance candidate whose model could not be evaluated beside its optimum has no
        // covariance: its interval is infinite, and the file says "unbounded", never "inf".
        let x = Suggestion {
            rank: 2,
            residual: "resonance",
            name: "tip-mass".into(),
            partner: None,
            primitive: Primitive::TipMass,
            parameter: "tip_mass_kg",
            null: 0.0,
            bounds: (0.0, 1e-4),
            estimate: 4.1e-19,
            interval: (f64::NEG_INFINITY, f64::INFINITY),
            gain: -2.2,
            declared: false,
        };
        let text = entry(&x);
        assert!(
            text.starts_with("# rank 2 of the resonance candidates: tip_mass_kg = 4.1000e-19 [unbounded, unbounded], AICc gain -2.2 over the chosen model on the resonances\n"),
            "{text}"
        );
        assert!(!text.contains("inf"), "{text}");
    }
}
