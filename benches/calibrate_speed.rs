//! Speed of `calibrate`: 500 rows (50 actuators x 10 voltages) with the full library — every subset of at
//! most two effects fitted and cross-validated — once with a hidden library pair (explained) and once with
//! the passive plies' E1 off its value (not explained, so discovery also fits every primitive outside the
//! library); and 10,000 rows (1000 actuators x 10 voltages, the pair).
//! Targets: 500 rows under 3 s, 10,000 rows under 10 s.
//!
//! `cargo bench --bench calibrate_speed` (release); prints the load average it ran at. The test suite checks
//! that the 500-row case finds its effects. `CALIBRATE_ONE_ROW_ACTUATORS=10000` also calibrates that many
//! actuators measured once each (target under 20 s at 10,000); a list (`1000,2000,4000`) calibrates each,
//! and `CALIBRATE_ONE_ROW_ONLY=1` skips the other cases.

#[path = "../tests/synthetic/mod.rs"]
mod synthetic;

use actuator_cam::{calibrate, parse_measured as parse, Settings};
use actuator_model::primitives::{Primitive, Property, Target};
use actuator_model::Effects;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use synthetic::*;

fn case(actuators: usize, truth: Truth, runs: usize, want: &str) -> Timing {
    case_at(actuators, 10, truth, runs, Some(want))
}

/// Median, fastest and slowest wall clock of the runs, s, and the median CPU time of one run (all
/// threads), s.
struct Timing {
    median: f64,
    min: f64,
    max: f64,
    cpu: f64,
}

/// `actuators` random designs, each measured at `voltages` fields (80 V/mm apart, the highest at
/// 80 x `voltages`).
fn case_at(
    actuators: usize,
    voltages: usize,
    truth: Truth,
    runs: usize,
    want: Option<&str>,
) -> Timing {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let designs: Vec<Design> = (0..actuators).map(|_| random_design(&mut rng)).collect();
    let fields: Vec<f64> = (1..=voltages)
        .map(|k| 80.0 * (k + 10 - voltages) as f64)
        .collect();
    let data = parse(&synthetic_csv_at(truth, &designs, &fields, &mut rng)).expect("valid data");
    let (mut times, mut cpu) = (Vec::new(), Vec::new());
    for _ in 0..runs {
        let (start, cpu_start) = (std::time::Instant::now(), cpu_seconds());
        let cal = calibrate(&data, &Settings::default()).expect("calibrates");
        times.push(start.elapsed().as_secs_f64());
        cpu.push(cpu_seconds() - cpu_start);
        let Some(want) = want else {
            println!("  verdict {}", cal.model.verdict);
            continue;
        };
        assert_eq!(cal.model.verdict, want);
        if want == "not-explained" {
            assert!(cal.discovery.is_some());
        }
    }
    times.sort_by(f64::total_cmp);
    cpu.sort_by(f64::total_cmp);
    Timing {
        median: times[runs / 2],
        min: times[0],
        max: times[runs - 1],
        cpu: cpu[runs / 2],
    }
}

fn main() {
    let load = std::fs::read_to_string("/proc/loadavg").unwrap_or_default();
    println!(
        "load average at start: {}",
        load.split_whitespace()
            .take(3)
            .collect::<Vec<_>>()
            .join(" ")
    );
    let pair = Truth::Library(Effects {
        dead_length: 3e-3,
        clamp_compliance: 0.5,
        ..Effects::default()
    });
    let soft = Truth::Primitive(
        Primitive::Scale {
            target: Target::Passive,
            property: Property::E1,
        },
        0.6,
    );
    // `CALIBRATE_ONE_ROW_ONLY=1`: only the one-row cases below (a scaling study of many actuators).
    let standard = std::env::var_os("CALIBRATE_ONE_ROW_ONLY").is_none();
    for (label, actuators, truth, runs, want) in [
        (
            "500 rows, library pair (explained)",
            50,
            pair,
            5,
            "explained",
        ),
        (
            "500 rows, passive E1 x 0.6 (not explained, discovery)",
            50,
            soft,
            5,
            "not-explained",
        ),
        (
            "10,000 rows, library pair (explained)",
            1000,
            pair,
            3,
            "explained",
        ),
    ]
    .into_iter()
    .filter(|_| standard)
    {
        let t = case(actuators, truth, runs, want);
        println!(
            "calibrate {label}: median {:.3} s of {runs} (min {:.3}, max {:.3}), CPU {:.3} s per run (median)",
            t.median, t.min, t.max, t.cpu
        );
    }
    // Many actuators measured once each (at 800 V/mm): the data grow with the actuators alone.
    // A comma-separated list (`1000,2000,4000`) shows how the time grows with the actuators.
    let one_row = std::env::var("CALIBRATE_ONE_ROW_ACTUATORS").unwrap_or_default();
    for n in one_row
        .split(',')
        .filter_map(|n| n.trim().parse::<usize>().ok())
    {
        let cpu = cpu_seconds();
        let t = case_at(n, 1, pair, 1, None);
        println!(
            "calibrate {n} actuators, one row each, library pair: {:.3} s, CPU {:.3} s (all threads, data included)",
            t.median,
            cpu_seconds() - cpu
        );
    }
    let load = std::fs::read_to_string("/proc/loadavg").unwrap_or_default();
    println!(
        "load average at end: {}",
        load.split_whitespace()
            .take(3)
            .collect::<Vec<_>>()
            .join(" ")
    );
}

/// User and system CPU time of this process so far, all threads: on a busy machine the wall clock
/// measures the other builds too.
fn cpu_seconds() -> f64 {
    // SAFETY: `rusage` is plain data the kernel fills for this process.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    unsafe { libc::getrusage(libc::RUSAGE_SELF, &mut usage) };
    let t = |v: libc::timeval| v.tv_sec as f64 + v.tv_usec as f64 * 1e-6;
    t(usage.ru_utime) + t(usage.ru_stime)
}
