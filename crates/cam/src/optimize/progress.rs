//! How far the optimiser's long exhaustive stage has come. The optimiser reports through this trait and
//! prints nothing itself: the command line draws a bar on a terminal, tests and benches stay silent.

/// A receiver of progress reports. Calls come from worker threads, hence `Sync`.
pub trait Progress: Sync {
    /// The stage begins and has `total` steps.
    fn start(&self, total: u64);
    /// `steps` more steps are done.
    fn advance(&self, steps: u64);
    /// The stage is over.
    fn finish(&self);
}

/// Progress reported nowhere.
#[derive(Debug, Clone, Copy, Default)]
pub struct Silent;

impl Progress for Silent {
    fn start(&self, _total: u64) {}
    fn advance(&self, _steps: u64) {}
    fn finish(&self) {}
}
