//! Allowed ranges of numeric fields, stated once with their unit.

use std::fmt;

/// A closed or open interval with a unit, for validation and for the error message.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Range {
    /// Lower bound.
    pub lo: f64,
    /// Whether `lo` itself is allowed.
    pub lo_inclusive: bool,
    /// Upper bound.
    pub hi: f64,
    /// Whether `hi` itself is allowed.
    pub hi_inclusive: bool,
    /// Unit shown in messages ("mm", "V/mm", "" for none).
    pub unit: &'static str,
}

impl Range {
    /// `lo < x <= hi`.
    pub const fn positive_up_to(hi: f64, unit: &'static str) -> Self {
        Range {
            lo: 0.0,
            lo_inclusive: false,
            hi,
            hi_inclusive: true,
            unit,
        }
    }

    /// `lo <= x <= hi`.
    pub const fn closed(lo: f64, hi: f64, unit: &'static str) -> Self {
        Range {
            lo,
            lo_inclusive: true,
            hi,
            hi_inclusive: true,
            unit,
        }
    }

    /// `lo < x < hi`.
    pub const fn open(lo: f64, hi: f64, unit: &'static str) -> Self {
        Range {
            lo,
            lo_inclusive: false,
            hi,
            hi_inclusive: false,
            unit,
        }
    }

    /// `lo <= x < hi`.
    pub const fn half_open(lo: f64, hi: f64, unit: &'static str) -> Self {
        Range {
            lo,
            lo_inclusive: true,
            hi,
            hi_inclusive: false,
            unit,
        }
    }

    /// `0 < x`, no upper bound (a measured quantity that only has to be physical).
    pub const fn positive(unit: &'static str) -> Self {
        Self::open(0.0, f64::INFINITY, unit)
    }

    /// `lo <= x`, no upper bound.
    pub const fn at_least(lo: f64, unit: &'static str) -> Self {
        Range {
            lo,
            lo_inclusive: true,
            hi: f64::INFINITY,
            hi_inclusive: false,
            unit,
        }
    }

    /// True if `x` is finite and inside.
    pub fn contains(&self, x: f64) -> bool {
        x.is_finite()
            && (if self.lo_inclusive {
                x >= self.lo
            } else {
                x > self.lo
            })
            && (if self.hi_inclusive {
                x <= self.hi
            } else {
                x < self.hi
            })
    }
}

impl Range {
    /// The interval alone: in brackets when finite (`[1, 1000] mm`), an unbounded side in words
    /// (`greater than 0 mg`), since `inf` reads as a value a user could write.
    pub fn bounds(&self) -> String {
        let lo = super::short_number(self.lo);
        let hi = super::short_number(self.hi);
        let text = match (self.lo.is_finite(), self.hi.is_finite()) {
            (true, true) => {
                let open = if self.lo_inclusive { '[' } else { '(' };
                let close = if self.hi_inclusive { ']' } else { ')' };
                format!("{open}{lo}, {hi}{close}")
            }
            (true, false) if self.lo_inclusive => format!("at least {lo}"),
            (true, false) => format!("greater than {lo}"),
            (false, true) if self.hi_inclusive => format!("at most {hi}"),
            (false, true) => format!("less than {hi}"),
            (false, false) => return "any finite number".to_string(),
        };
        if self.unit.is_empty() {
            text
        } else {
            format!("{text} {}", self.unit)
        }
    }
}

impl fmt::Display for Range {
    /// `allowed range [1, 1000] mm`, `allowed range: greater than 0 mg`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let sep = if self.lo.is_finite() && self.hi.is_finite() {
            " "
        } else {
            ": "
        };
        write!(f, "allowed range{sep}{}", self.bounds())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bounds_and_nan() {
        let r = Range::open(0.0, 2.0, "");
        assert!(r.contains(1.0) && !r.contains(2.0) && !r.contains(0.0) && !r.contains(f64::NAN));
        assert_eq!(r.to_string(), "allowed range (0, 2)");
        assert_eq!(
            Range::positive_up_to(1000.0, "mm").to_string(),
            "allowed range (0, 1000] mm"
        );
        let p = Range::positive("mg");
        assert!(p.contains(1e30) && !p.contains(f64::INFINITY) && !p.contains(0.0));
        assert_eq!(p.to_string(), "allowed range: greater than 0 mg");
        assert_eq!(
            Range::at_least(0.0, "").to_string(),
            "allowed range: at least 0"
        );
        assert_eq!(
            Range::open(f64::NEG_INFINITY, f64::INFINITY, "m").to_string(),
            "allowed range: any finite number"
        );
        assert_eq!(
            Range::open(f64::NEG_INFINITY, 1e300, "").to_string(),
            "allowed range: less than 1e300"
        );
    }
}
