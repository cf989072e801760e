//! Ctrl-C while a nest searches: the first ends the search, and the run writes the best layout so
//! far through the one writer; a second aborts the run as any interrupt does (its staging folder
//! removed, nothing written). Outside a search every interrupt aborts at once.

use std::sync::atomic::{AtomicBool, Ordering};

/// Set by the first interrupt of a search; the nester reads it between units of its work.
pub static SEARCH_STOP: AtomicBool = AtomicBool::new(false);
/// True while a command is running a search that the first interrupt may end.
static SEARCH_RUNNING: AtomicBool = AtomicBool::new(false);

/// From now on the first interrupt ends the search instead of the run.
pub fn search_started() {
    SEARCH_RUNNING.store(true, Ordering::SeqCst);
}

/// The search is over: from now on every interrupt aborts the run (while it writes, that removes
/// what it staged).
pub fn search_finished() {
    SEARCH_RUNNING.store(false, Ordering::SeqCst);
}

/// Called by the interrupt handler: true if this interrupt was the first of a search and has
/// ended it (the run goes on to write); false if the run must abort.
pub fn end_search() -> bool {
    SEARCH_RUNNING.load(Ordering::SeqCst) && !SEARCH_STOP.swap(true, Ordering::SeqCst)
}

/// After a search an interrupt ended, the library's test hook may hold the run a moment before it
/// writes (only in a build with its `test-hooks` feature: tests/nest/budget.rs sends its second interrupt
/// there).
pub fn pause_after_interrupted_search() {
    if search_ended() {
        actuator_cam::pause_after_interrupted_search();
    }
}

/// True if an interrupt ended the search.
pub fn search_ended() -> bool {
    SEARCH_STOP.load(Ordering::SeqCst)
}
