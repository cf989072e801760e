//! Numbers in report.json are rounded to 6 significant digits, so the file is short and the same on
//! every run; a non-finite number is written as `null`. Fields opt in with
//! `#[serde(serialize_with = "six_digits")]`; the in-memory values (and report.md) keep full precision.
//! The text files write a non-finite number as a word ([`finite_or_word`]): no `inf` or `NaN` reaches
//! a file a lab reads.

use serde::Serializer;

/// `x` rounded to 6 significant digits, or `None` if it is not finite.
pub fn round6(x: f64) -> Option<f64> {
    if !x.is_finite() {
        return None;
    }
    Some(format!("{x:.5e}").parse().unwrap_or(x))
}

/// Serialize an `f64` rounded to 6 significant digits (`null` if not finite).
pub fn six_digits<S: Serializer>(x: &f64, s: S) -> Result<S::Ok, S::Error> {
    match round6(*x) {
        Some(v) => s.serialize_f64(v),
        None => s.serialize_none(),
    }
}

/// [`six_digits`] for an optional value (`null` if absent).
pub fn six_digits_opt<S: Serializer>(x: &Option<f64>, s: S) -> Result<S::Ok, S::Error> {
    match x.and_then(round6) {
        Some(v) => s.serialize_f64(v),
        None => s.serialize_none(),
    }
}

/// [`six_digits`] for an interval, as a two-element array.
pub fn six_digits_pair<S: Serializer>(x: &(f64, f64), s: S) -> Result<S::Ok, S::Error> {
    use serde::ser::SerializeTuple;
    let mut t = s.serialize_tuple(2)?;
    t.serialize_element(&round6(x.0))?;
    t.serialize_element(&round6(x.1))?;
    t.end()
}

/// `text(x)` for a finite `x`; else `unbounded` for an infinite one (an interval whose covariance the
/// fit could not bound) and `none` for NaN (a value the model could not evaluate).
pub fn finite_or_word(x: f64, text: impl FnOnce(f64) -> String) -> String {
    if x.is_finite() {
        text(x)
    } else if x.is_infinite() {
        "unbounded".to_string()
    } else {
        "none".to_string()
    }
}

/// An interval `[lo, hi]` with each end written by `text` ([`finite_or_word`]).
pub fn interval_text(interval: (f64, f64), text: impl Fn(f64) -> String) -> String {
    format!(
        "[{}, {}]",
        finite_or_word(interval.0, &text),
        finite_or_word(interval.1, &text)
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(serde::Serialize)]
    struct Sample {
        #[serde(serialize_with = "six_digits")]
        a: f64,
        #[serde(serialize_with = "six_digits")]
        b: f64,
        #[serde(serialize_with = "six_digits_opt")]
        c: Option<f64>,
        #[serde(serialize_with = "six_digits_pair")]
        d: (f64, f64),
    }

    #[test]
    fn rounds_to_six_significant_digits_and_nulls_non_finite() {
        let s = Sample {
            a: 0.123_456_789,
            b: f64::NAN,
            c: None,
            d: (1_234_567.0, f64::INFINITY),
        };
        assert_eq!(
            serde_json::to_string(&s).unwrap(),
            r#"{"a":0.123457,"b":null,"c":null,"d":[1234570.0,null]}"#
        );
    }

    #[test]
    fn text_writes_a_non_finite_number_as_a_word() {
        let sci = |v: f64| format!("{v:.2e}");
        assert_eq!(interval_text((1.5, 2.0), sci), "[1.50e0, 2.00e0]");
        assert_eq!(
            interval_text((f64::NEG_INFINITY, f64::INFINITY), sci),
            "[unbounded, unbounded]"
        );
        assert_eq!(finite_or_word(f64::NAN, sci), "none");
    }
}
