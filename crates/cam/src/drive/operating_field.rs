//! The operating field of a field-dependent model (the nonlinear ceramic, docs/physics.md §18.5): the
//! field at which the design is predicted must be the field its operating point then asks for. The
//! search is a fixed-point iteration on that field, and it says when it does not settle rather than
//! report a point predicted at a field it does not drive.

/// Rounds of the search before it gives up.
pub const FIELD_ROUNDS: usize = 16;

/// Relative change of the field between rounds taken as settled.
const SETTLED: f64 = 1e-4;

/// How the search ended.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FieldSearch {
    /// The field asked for is the field predicted at, or no field is asked for (no operating point).
    Settled,
    /// After [`FIELD_ROUNDS`] rounds the field asked for still moves: the last two fields asked for
    /// (V/m).
    Unsettled { previous: f64, last: f64 },
}

impl super::Analysis {
    /// Report no operating point, and why: the last round's point is at a field the drive does not
    /// settle on.
    pub fn refuse_operating_point(&mut self, why: String) {
        self.report.unsettled_field = Some(why);
        self.report.reached = false;
        (self.report.operating, self.state, self.operating_field) = (None, None, None);
    }
}

impl FieldSearch {
    /// Why no operating point is reported, for a search that did not settle.
    pub fn why(&self) -> Option<String> {
        match *self {
            FieldSearch::Settled => None,
            FieldSearch::Unsettled { previous, last } => Some(format!(
                "the operating field does not settle: after {FIELD_ROUNDS} rounds the predictions at {} and {} V/mm each ask for the other's field (docs/physics.md §18.5)",
                crate::input::fixed(previous * 1e-3, 1),
                crate::input::fixed(last * 1e-3, 1)
            )),
        }
    }
}

/// Iterate `predict_at(field)` from the result `first`, predicted at `start`, until the field each
/// result asks for (`asks`, V/m; `None` or non-positive for no operating point) is the one it was
/// predicted at. Returns the last result and how the search ended.
pub fn settle<T, E>(
    start: f64,
    first: T,
    asks: impl Fn(&T) -> Option<f64>,
    mut predict_at: impl FnMut(f64) -> Result<T, E>,
) -> Result<(T, FieldSearch), E> {
    let mut at = start;
    let mut result = first;
    for _ in 0..FIELD_ROUNDS {
        let field = match asks(&result) {
            Some(f) if f > 0.0 => f,
            _ => return Ok((result, FieldSearch::Settled)),
        };
        if (field - at).abs() <= SETTLED * field {
            return Ok((result, FieldSearch::Settled));
        }
        at = field;
        result = predict_at(field)?;
    }
    match asks(&result) {
        Some(last) if last > 0.0 && (last - at).abs() > SETTLED * last => {
            Ok((result, FieldSearch::Unsettled { previous: at, last }))
        }
        _ => Ok((result, FieldSearch::Settled)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A map whose fixed point is known: the field asked for is sqrt(c·E), which settles at E = c
    /// from any positive start (a contraction near c).
    #[test]
    fn a_contracting_field_settles_at_its_fixed_point() {
        let c = 4.0e5;
        let ask = |e: f64| (c * e).sqrt();
        let (result, search) =
            settle(1.0e5, ask(1.0e5), |&r| Some(r), |e| Ok::<_, ()>(ask(e))).unwrap();
        assert_eq!(search, FieldSearch::Settled);
        assert!((result - c).abs() < 1e-3 * c, "{result}");
    }

    /// The field asked for is 2c − E: it swaps between two fields forever and must be flagged with
    /// both, not returned as if settled.
    #[test]
    fn a_field_that_swings_between_two_values_is_flagged_unsettled() {
        let c = 4.0e5;
        let ask = |e: f64| 2.0 * c - e;
        let (_, search) = settle(3.0e5, ask(3.0e5), |&r| Some(r), |e| Ok::<_, ()>(ask(e))).unwrap();
        let FieldSearch::Unsettled { previous, last } = search else {
            panic!("{search:?}");
        };
        let mut pair = [previous, last];
        pair.sort_by(f64::total_cmp);
        assert_eq!(pair, [3.0e5, 5.0e5]);
        let why = search.why().unwrap();
        assert!(
            why.contains("300.0 and 500.0 V/mm") || why.contains("500.0 and 300.0 V/mm"),
            "{why}"
        );
    }

    #[test]
    fn no_operating_point_ends_the_search_at_once() {
        let mut calls = 0;
        let (_, search) = settle(
            1.0e5,
            0.0,
            |_| None,
            |_| {
                calls += 1;
                Ok::<f64, ()>(0.0)
            },
        )
        .unwrap();
        assert_eq!(search, FieldSearch::Settled);
        assert_eq!(calls, 0);
    }
}
