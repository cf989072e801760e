//! What may end a nesting search before its iteration budget, and how far a search got.
//!
//! The iteration budget ([`crate::NestSettings::iterations`]) is what makes a layout
//! reproducible: the same items, settings and seed give the same layout on any machine. A
//! [`SearchLimit`] adds the two things a person at a machine wants as well: a wall-clock
//! deadline (`nest --time 30s`) and an interrupt (the first Ctrl-C). Either one only decides
//! *where* the search stops, never what it does before: time is read between units of counted
//! work, and a unit that a limit cuts short is thrown away whole. A search that a
//! limit ended after its base search ([`Reached::replayable`]) therefore gives the same layout
//! as the iteration budget it reached ([`Reached::iterations`]); how many iterations a second of
//! wall time buys depends on the machine and its load, which is why a time budget is not
//! reproducible by itself.

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// Wall-clock deadline and interrupt of one search; the default has neither (the iteration
/// budget alone ends it).
#[derive(Debug, Clone, Copy, Default)]
pub struct SearchLimit<'a> {
    /// The search ends at the first check after this instant.
    pub deadline: Option<Instant>,
    /// The search ends at the first check after this is set (the command line's first Ctrl-C).
    pub interrupt: Option<&'a AtomicBool>,
}

impl SearchLimit<'_> {
    /// True once the deadline has passed or the interrupt is set.
    pub fn reached(&self) -> bool {
        self.interrupted() || self.deadline.is_some_and(|d| Instant::now() >= d)
    }

    /// True once the interrupt is set.
    pub fn interrupted(&self) -> bool {
        self.interrupt.is_some_and(|i| i.load(Ordering::Relaxed))
    }

    /// This limit with its deadline brought forward to `share` of the time from `started` to
    /// it (for a stage that must leave time to the stages after it).
    #[must_use]
    pub(crate) fn share_of(&self, started: Instant, share: f64) -> Self {
        SearchLimit {
            deadline: self
                .deadline
                .map(|d| started + d.saturating_duration_since(started).mul_f64(share)),
            interrupt: self.interrupt,
        }
    }
}

/// What ended a search.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SearchEnd {
    /// The iteration budget, or the search's own stop rules (counted, so the same anywhere).
    Budget,
    /// The deadline of [`SearchLimit`].
    Time,
    /// The interrupt of [`SearchLimit`].
    Interrupt,
}

/// How far a search got.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Reached {
    /// Iterations whose work the layout is the result of: the base search's budget plus the
    /// anytime rounds completed ([`crate::irregular`], "Anytime rounds").
    pub iterations: usize,
    /// True when [`nest`](crate::nest) with `iterations` as the budget gives the same layout
    /// (a limit that struck inside the base search leaves a layout no budget reproduces).
    pub replayable: bool,
    /// What ended the search.
    pub ended: SearchEnd,
    /// The search's wall time, set when the deadline of [`SearchLimit`] passed before the first
    /// feasible layout was complete. Every part must be placed once, so the greedy fill that
    /// places them ends (at its least effort once the limit is reached) whatever the limit:
    /// where that fill alone takes longer than the budget, the search took this long instead.
    /// `None` when the first layout was complete within the budget (the search then ends at
    /// the first check after the deadline) or there was no deadline.
    pub over_budget: Option<Duration>,
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    #[test]
    fn a_limit_is_reached_by_its_deadline_or_its_interrupt_and_never_without_one() {
        assert!(!SearchLimit::default().reached());
        let past = SearchLimit {
            deadline: Some(Instant::now() - Duration::from_millis(1)),
            interrupt: None,
        };
        assert!(past.reached() && !past.interrupted());
        let future = SearchLimit {
            deadline: Some(Instant::now() + Duration::from_secs(3600)),
            interrupt: None,
        };
        assert!(!future.reached());
        let flag = AtomicBool::new(false);
        let stop = SearchLimit {
            deadline: None,
            interrupt: Some(&flag),
        };
        assert!(!stop.reached());
        flag.store(true, Ordering::Relaxed);
        assert!(stop.reached() && stop.interrupted());
    }

    #[test]
    fn a_share_of_a_limit_ends_that_share_of_the_way_to_its_deadline() {
        let started = Instant::now();
        let limit = SearchLimit {
            deadline: Some(started + Duration::from_secs(30)),
            interrupt: None,
        };
        let third = limit.share_of(started, 1.0 / 3.0);
        assert_eq!(third.deadline, Some(started + Duration::from_secs(10)));
        assert!(SearchLimit::default()
            .share_of(started, 0.5)
            .deadline
            .is_none());
    }
}
