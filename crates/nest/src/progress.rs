//! What the nester tells its caller while it works: a [`NestProgress`] after the greedy fill,
//! after every epoch of the search and once at the end (see [`crate::nest_observed`]).
//!
//! The engine knows one job (one call); a caller that nests several jobs (materials of a batch)
//! counts them itself and draws the bar (the command layer uses indicatif). The reports come
//! from the thread that called the nester, between epochs, so an observer needs no locking and
//! never changes the layout: the same input gives the same layout with or without one.

/// A snapshot of one nesting job.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NestProgress {
    /// Search iterations done so far, over all workers.
    pub iterations_done: usize,
    /// Iterations the job may use at most ([`crate::NestSettings::iterations`] scaled to the
    /// job's size); a job that stops early (see [`crate::irregular`], "Stop rule") jumps to
    /// `finished`.
    pub iterations_budget: usize,
    /// Sheets of the best layout so far.
    pub sheets: usize,
    /// Fewest sheets the parts could need: total part area over sheet area, rounded up.
    pub sheets_lower_bound: usize,
    /// Used-length utilisation of the best layout so far
    /// ([`crate::NestSolution::used_length_utilization`]), in 0..=1.
    pub best_density: f64,
    /// True on the last report of the job (after the final compression).
    pub finished: bool,
}

/// The observer [`crate::nest`] uses: ignores every report.
pub(crate) fn ignore(_: &NestProgress) {}
