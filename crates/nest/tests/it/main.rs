//! The nester's integration tests, one binary (as ripgrep keeps its own): each module drives
//! the public API on one concern, and every layout is checked with `cam_nest::verify`.
//! `cargo test -p cam-nest --release` runs them in a few tens of seconds; the studies that
//! take longer are `#[ignore = "study: ..."]`d (run them with `-- --ignored`).

/// The parts of the engine tests and benches, one definition for both.
#[path = "../fixtures/mod.rs"]
mod fixtures;

mod anytime;
mod many_parts;
mod nest_engine;
mod strip_and_progress;
