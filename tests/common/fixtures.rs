//! Inputs the integration tests and the benches both use: the shipped example and template files.
//!
//! The benches include this file on its own (`#[path = "../tests/common/fixtures.rs"] mod fixtures;`),
//! so it depends on nothing but the standard library and names the same inputs for both, which keeps a
//! bench figure about the same designs the tests check.
#![allow(dead_code)]

use std::path::PathBuf;

/// The six thesis designs shipped in `examples/` (file stems), in the order of the thesis tables.
pub const THESIS_DESIGNS: [&str; 6] = [
    "thesis-A",
    "thesis-B",
    "thesis-C",
    "thesis-1",
    "thesis-7",
    "thesis-21",
];

/// Path of a file in `examples/`, as text for a command line.
pub fn example(name: &str) -> String {
    format!("{}/examples/{name}", env!("CARGO_MANIFEST_DIR"))
}

/// Path of a file in `examples/`.
pub fn example_path(name: &str) -> PathBuf {
    PathBuf::from(example(name))
}

/// Text of a process template shipped in `templates/` (`name` with its `.toml`).
pub fn shipped_template(name: &str) -> String {
    let path = format!("{}/templates/{name}", env!("CARGO_MANIFEST_DIR"));
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"))
}
