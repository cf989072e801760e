//! `actuator-cam calibrate` run as a child into a fresh folder (`child.rs` accounts for it): the
//! calibrate benches that measure the binary as a lab runs it.

use crate::child;
use std::path::Path;
use std::process::Command;

/// Calibrate `csv` with `binary` and the further arguments `args` into a fresh folder: the run's usage
/// and the verdict it wrote (`?` when it wrote none).
pub fn calibrate(binary: &str, csv: &Path, args: &[&str]) -> (child::Usage, String) {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = dir.path().join("out");
    let mut command = Command::new(binary);
    command
        .arg("calibrate")
        .arg(csv)
        .args(args)
        .arg("-o")
        .arg(&out);
    let usage = child::measure(command);
    let model = std::fs::read_to_string(out.join("calibrated-model.toml")).unwrap_or_default();
    let verdict = model
        .lines()
        .find_map(|l| l.strip_prefix("verdict = "))
        .unwrap_or("?")
        .trim_matches('"')
        .to_string();
    (usage, verdict)
}
