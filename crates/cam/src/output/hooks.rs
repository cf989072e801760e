//! Test hooks of the writer, compiled only with the `test-hooks` feature (which the integration tests
//! turn on, and a release build leaves off), so that no variable in a user's environment can stop,
//! pause or change a real run.
//!
//! - `ACTUATOR_CAM_STOP_AFTER_MOVE=k` aborts the process right after its k-th move (the intent log
//!   going into place is move 1; a recovery's moves count too), as a SIGKILL would, so tests can stop a
//!   run at every stage.
//! - `ACTUATOR_CAM_PAUSE_AFTER_MOVE=k` says `paused after move k` on stderr and sleeps two seconds after
//!   its k-th move, so a test can send a signal while the files move.
//! - `ACTUATOR_CAM_LIST_INPUTS` prints each input of the run on stderr (`input: PATH`), so a test can
//!   aim the outputs at every one of them.

use std::path::PathBuf;

/// Count one move; stop or pause after the k-th if a test asks.
#[cfg(feature = "test-hooks")]
pub(super) fn moved() {
    use std::sync::atomic::{AtomicUsize, Ordering};
    use std::sync::OnceLock;
    static STOP_AFTER: OnceLock<Option<usize>> = OnceLock::new();
    static PAUSE_AFTER: OnceLock<Option<usize>> = OnceLock::new();
    static MOVES: AtomicUsize = AtomicUsize::new(0);
    let number = |var: &str| std::env::var(var).ok().and_then(|k| k.parse().ok());
    let stop = STOP_AFTER.get_or_init(|| number("ACTUATOR_CAM_STOP_AFTER_MOVE"));
    let pause = PAUSE_AFTER.get_or_init(|| number("ACTUATOR_CAM_PAUSE_AFTER_MOVE"));
    let n = MOVES.fetch_add(1, Ordering::SeqCst) + 1;
    if *stop == Some(n) {
        std::process::abort();
    }
    if *pause == Some(n) {
        eprintln!("paused after move {n}");
        std::thread::sleep(std::time::Duration::from_secs(2));
    }
}

/// Without the test hooks a move is just a move.
#[cfg(not(feature = "test-hooks"))]
pub(super) fn moved() {}

/// Print the run's inputs if a test asks.
#[cfg(feature = "test-hooks")]
pub(super) fn list_inputs(inputs: &[PathBuf]) {
    if std::env::var_os("ACTUATOR_CAM_LIST_INPUTS").is_some() {
        for p in inputs {
            eprintln!("input: {}", p.display());
        }
    }
}

/// Without the test hooks the inputs are not printed.
#[cfg(not(feature = "test-hooks"))]
pub(super) fn list_inputs(_inputs: &[PathBuf]) {}

/// `ACTUATOR_CAM_PAUSE_AFTER_SEARCH`: a run whose search an interrupt ended waits two seconds before it
/// writes, so that a test's second interrupt lands between the search and the writing whatever the
/// machine's load; without it the gap is milliseconds. The command line calls it when the first
/// interrupt ended a nest's search.
#[cfg(feature = "test-hooks")]
pub fn pause_after_interrupted_search() {
    if std::env::var_os("ACTUATOR_CAM_PAUSE_AFTER_SEARCH").is_some() {
        std::thread::sleep(std::time::Duration::from_secs(2));
    }
}

/// Without the test hooks the run writes at once.
#[cfg(not(feature = "test-hooks"))]
pub fn pause_after_interrupted_search() {}
