//! `suggested-effects.toml`: the loop's next step as an effects file (docs/calibration.md §3,
//! "Discovery"), written beside the report when the verdict is not-explained or ambiguous. The leading
//! candidates ([`suggest::suggestions`]) are declared; the runners-up follow as comments, each with its
//! rank, estimate, interval and AICc gain, to put in the leader's place.

use crate::calibrate::discover::suggest::Suggestion;
use crate::calibrate::effects_file::primitive_fields;
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
        "# rank {} of the {} candidates{beside}: {} = {:.4e} [{:.4e}, {:.4e}], {}AICc gain {:.1} over {}",
        x.rank,
        x.residual,
        x.parameter,
        x.estimate,
        x.interval.0,
        x.interval.1,
        // The deflection and force ranking's is the joint criterion (docs/calibration.md §3, "Joint
        // ranking").
        if x.residual == "deflection and force" {
            "joint "
        } else {
            ""
        },
        x.gain,
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
