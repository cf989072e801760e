//! `cargo bench --bench calibrate_rows`: `actuator-cam calibrate` through the binary on 10,000 and 50,000
//! rows generated from `examples/measured-thesis-like.csv`, as a lab would run it, into a fresh folder.
//! For each run: wall time, CPU time (user and system apart) and peak resident memory, the kernel's own
//! account of the child (`common/child.rs`), and the verdict. Target: 50,000 rows under 20 s of wall time
//! on the project's 2 cores.
//!
//! The rows: actuators taking the 24 geometries of the example in turn, each with a new id, measured at
//! `CALIBRATE_VOLTAGES` (default 20) voltages evenly up to its example actuator's highest; deflection and
//! force that example actuator's highest-voltage readings scaled in proportion to the voltage, each times
//! `1 + 0.05 z` (z standard normal, seeded ChaCha8: the same rows on every machine); the example mass on
//! each actuator's first row. The example carries effects the library holds and one it lacks, so the
//! verdict is `not-explained` and discovery runs too: the whole of calibrate.
//!
//! `CALIBRATE_ROWS=2000,4000` picks other sizes, `CALIBRATE_VOLTAGES=1` one row per actuator. With
//! `ACTUATOR_CAM_PEER=/path/to/other/actuator-cam` set, that binary calibrates the same file just before
//! ours, so both are measured side by side at the same load.

#[path = "common/calibrate_child.rs"]
mod calibrate_child;
#[path = "common/child.rs"]
mod child;
#[path = "../tests/common/fixtures.rs"]
mod fixtures;
#[path = "../tests/synthetic/mod.rs"]
mod synthetic;

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use std::fmt::Write as _;
use synthetic::normal;

/// An example actuator: its geometry columns as written, its highest voltage with the deflection and
/// force there, and its mass.
struct Base {
    geometry: String,
    voltage: f64,
    deflection_mm: f64,
    force_n: f64,
    mass: String,
}

/// The example's actuators, in the order they first appear.
fn bases() -> Vec<Base> {
    let text = std::fs::read_to_string(fixtures::example_path("measured-thesis-like.csv"))
        .expect("the example reads");
    let mut bases: Vec<(String, Base)> = Vec::new();
    for line in text.lines().filter(|l| !l.starts_with('#')).skip(1) {
        let f: Vec<&str> = line.split(',').collect();
        let number = |i: usize| f[i].parse::<f64>().expect("a number");
        let voltage = number(7);
        let at = match bases.iter().position(|(id, _)| id == f[0]) {
            Some(at) => at,
            None => {
                bases.push((
                    f[0].to_string(),
                    Base {
                        geometry: f[1..7].join(","),
                        voltage: 0.0,
                        deflection_mm: 0.0,
                        force_n: 0.0,
                        mass: f[8].to_string(),
                    },
                ));
                bases.len() - 1
            }
        };
        let b = &mut bases[at].1;
        if voltage > b.voltage {
            (b.voltage, b.deflection_mm, b.force_n) = (voltage, number(9), number(10));
        }
    }
    bases.into_iter().map(|(_, b)| b).collect()
}

/// `rows` rows (rounded down to whole actuators) at `voltages` voltages per actuator.
fn generated(rows: usize, voltages: usize) -> String {
    let bases = bases();
    let mut rng = ChaCha8Rng::seed_from_u64(62);
    let mut csv = String::from(
        "id,l_tot_mm,l_r,w0_mm,w_r,t_p_mm,layup,voltage_V,mass_mg,free_deflection_mm,blocked_force_N\n",
    );
    for k in 0..rows / voltages {
        let b = &bases[k % bases.len()];
        for j in 1..=voltages {
            let share = j as f64 / voltages as f64;
            let mass = if j == 1 { b.mass.as_str() } else { "" };
            let deflection = b.deflection_mm * share * (1.0 + 0.05 * normal(&mut rng));
            let force = b.force_n * share * (1.0 + 0.05 * normal(&mut rng));
            let _ = writeln!(
                csv,
                "G{k},{},{:.4},{mass},{deflection:.8},{force:.8}",
                b.geometry,
                b.voltage * share
            );
        }
    }
    csv
}

fn main() {
    let list = |name: &str, default: &str| -> Vec<usize> {
        std::env::var(name)
            .unwrap_or_else(|_| default.into())
            .split(',')
            .map(|n| n.trim().parse().expect("a whole number"))
            .collect()
    };
    let sizes = list("CALIBRATE_ROWS", "10000,50000");
    let voltages = list("CALIBRATE_VOLTAGES", "20")[0].max(1);
    let ours = env!("CARGO_BIN_EXE_actuator-cam").to_string();
    let peer = std::env::var("ACTUATOR_CAM_PEER").ok();
    let dir = tempfile::tempdir().expect("temp dir");
    println!(
        "calibrate <generated rows, {voltages} voltages per actuator> -o <new folder>, the binary as a child (load {})",
        child::load()
    );
    println!(
        "      rows  actuators  binary     wall s     user s      sys s   peak RSS MB  verdict"
    );
    for rows in sizes {
        let csv = dir.path().join(format!("rows-{rows}.csv"));
        std::fs::write(&csv, generated(rows, voltages)).expect("the rows write");
        for (label, binary) in peer
            .iter()
            .map(|p| ("peer", p.as_str()))
            .chain([("ours", ours.as_str())])
        {
            let (u, verdict) = calibrate_child::calibrate(binary, &csv, &[]);
            println!(
                "  {rows:>8} {:>10}  {label:<6} {:>10.2} {:>10.2} {:>10.2} {:>13.1}  {verdict}",
                rows / voltages,
                u.wall_s,
                u.user_s,
                u.sys_s,
                u.peak_mb
            );
        }
    }
    println!("  (load after: {})", child::load());
}
