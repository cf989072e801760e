//! `cargo bench --bench sweep`: a sweep of 10⁷ designs with `--csv`, through the release binary as a
//! child (`common/child.rs`): wall time, CPU time and peak resident memory. The factors are ten levels of
//! each of seven factors (PZT modulus, PZT thickness, layup, length, extension ratio, base width, width
//! ratio); the CSV goes to a temporary folder and is removed. `SWEEP_LEVELS=5` runs 5⁷ designs instead.
//! Target: peak RSS under 200 MB at 10⁷ designs.

#[path = "common/child.rs"]
mod child;

use std::process::Command;

fn levels(n: usize, from: f64, step: f64) -> String {
    let v: Vec<String> = (0..n)
        .map(|i| format!("{}", ((from + step * i as f64) * 1e6).round() / 1e6))
        .collect();
    format!("[{}]", v.join(", "))
}

fn main() {
    let n: usize = std::env::var("SWEEP_LEVELS")
        .ok()
        .map(|s| s.trim().parse().expect("a level count"))
        .unwrap_or(10);
    assert!((2..=10).contains(&n), "SWEEP_LEVELS in 2..=10");
    let layups = [
        "[0, 90, 0]",
        "[90, 0, 90]",
        "[0, 0, 90, 0, 0]",
        "[0, 90, 90, 90, 0]",
        "[0, 0, 0, 90, 0, 0, 0]",
        "[0, 45, 0]",
        "[0, -45, 45, -45, 0]",
        "[0, 0, 0]",
        "[90, 90, 90]",
        "[0, 30, 0]",
    ];
    let factors = format!(
        "[laminate]\npzt = \"PZT-5H\"\nply = \"CF-thesis\"\n\n[drive]\nmode = \"parallel\"\nfield_V_per_mm = 800\n\n\
         [factors]\npzt_modulus_GPa = {}\npzt_thickness_mm = {}\nlayups_deg = [{}]\nlength_mm = {}\n\
         extension_ratio = {}\nbase_width_mm = {}\nwidth_ratio = {}\n",
        levels(n, 50.0, 2.0),
        levels(n, 0.127, 0.014),
        layups[..n].join(", "),
        levels(n, 20.0, 5.0),
        levels(n, 0.0, 0.1),
        levels(n, 5.0, 1.0),
        levels(n, 1.0, 0.1),
    );
    let dir = tempfile::tempdir().expect("temp dir");
    let spec = dir.path().join("factors.toml");
    std::fs::write(&spec, factors).expect("factors written");
    let csv = dir.path().join("designs.csv");
    let designs = n.pow(7);
    println!(
        "sweep of {designs} designs with --csv, the binary as a child (load {})",
        child::load()
    );
    let mut command = Command::new(env!("CARGO_BIN_EXE_actuator-cam"));
    command.arg("sweep").arg(&spec).arg("--csv").arg(&csv);
    let u = child::measure(command);
    let csv_mb = std::fs::metadata(&csv).map_or(0, |m| m.len()) as f64 / 1e6;
    println!("  designs     wall s     user s      sys s   peak RSS MB   CSV MB");
    println!(
        "  {designs:>8} {:>10.2} {:>10.2} {:>10.2} {:>13.1} {:>8.0}",
        u.wall_s, u.user_s, u.sys_s, u.peak_mb, csv_mb
    );
    println!("  (load after: {})", child::load());
}
