//! The output policy, driven through the binary as a lab would meet it: nothing a user owns is deleted
//! or overwritten unasked, a folder the tool wrote before is updated in place, and an interrupted run
//! leaves nothing behind once the next run has looked.

mod folders;
mod inputs;
mod interrupted;
mod journal;

use crate::common;
use common::*;
use std::fs;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

const MANIFEST: &str = ".actuator-cam-manifest";

/// Design C's cut sheet into `out`.
fn cut_sheet_into(out: &Path, extra: &[&str]) -> std::process::Output {
    cut_sheet("examples/thesis-C.toml", out, extra)
}

/// Staging folders beside `out` (what a killed run could leave).
fn staging_beside(out: &Path) -> Vec<String> {
    staging_left(out.parent().unwrap())
}

/// Every file of `out` except the tool's manifest, by name.
fn outputs(out: &Path) -> std::collections::BTreeMap<String, Vec<u8>> {
    let mut f = files(out);
    f.remove(MANIFEST);
    f
}

/// The names a folder's manifest lists.
fn listed(out: &Path) -> std::collections::BTreeSet<String> {
    fs::read_to_string(out.join(MANIFEST))
        .unwrap()
        .lines()
        .filter(|l| !l.starts_with('#'))
        .filter_map(|l| l.split_once('\t').map(|(_, n)| n.to_string()))
        .collect()
}

fn copy_folder(from: &Path, to: &Path) {
    fs::create_dir_all(to).unwrap();
    for (name, bytes) in files(from) {
        fs::write(to.join(name), bytes).unwrap();
    }
}

const LOCK: &str = ".actuator-cam-lock";

const INTENT: &str = ".actuator-cam-intent";

/// A design outside the output folder, and the folder `out` beside it (made, empty).
fn design_and_folder() -> (tempfile::TempDir, std::path::PathBuf, std::path::PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let design = dir.path().join("d.toml");
    fs::copy(example("thesis-C.toml"), &design).unwrap();
    let out = dir.path().join("out");
    fs::create_dir(&out).unwrap();
    (dir, design, out)
}

/// A folder written by cut-sheet (40 actuators, svg), with the user's notes and optimize's design.
fn written_before(dir: &Path) -> std::path::PathBuf {
    let before = dir.join("before");
    run_ok(&[
        "cut-sheet",
        "examples/thesis-C.toml",
        "-o",
        before.to_str().unwrap(),
        "--quantity",
        "40",
        "--format",
        "svg",
    ]);
    fs::write(before.join("notes.txt"), "mine").unwrap();
    run_ok(&[
        "optimize",
        "examples/optimize-thesis.toml",
        "-o",
        before.to_str().unwrap(),
    ]);
    before
}

/// cut-sheet of 2 actuators into `out`, stopped (or paused, `hook`) after move `k`.
fn cut_two(out: &Path, hook: &str, k: usize) -> Command {
    let mut c = bin();
    c.env(hook, k.to_string()).args([
        "cut-sheet",
        "examples/thesis-C.toml",
        "-o",
        out.to_str().unwrap(),
        "--quantity",
        "2",
        "--format",
        "svg",
    ]);
    c
}

/// optimize's design written into `out` (another command's run into the same folder).
fn optimize_into(out: &Path) -> std::process::Output {
    run(&[
        "optimize",
        "examples/optimize-thesis.toml",
        "-o",
        out.to_str().unwrap(),
    ])
}

/// Every file under `dir`, by its path inside it, with its bytes.
fn every_file(dir: &Path) -> std::collections::BTreeMap<std::path::PathBuf, Vec<u8>> {
    let mut found = std::collections::BTreeMap::new();
    let mut folders = vec![dir.to_path_buf()];
    while let Some(folder) = folders.pop() {
        for e in fs::read_dir(&folder).unwrap() {
            let path = e.unwrap().path();
            if path.is_dir() {
                folders.push(path);
            } else {
                let bytes = fs::read(&path).unwrap();
                found.insert(path.strip_prefix(dir).unwrap().to_path_buf(), bytes);
            }
        }
    }
    found
}
