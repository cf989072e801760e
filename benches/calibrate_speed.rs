//! Speed figure of issue 6: calibrate 50 actuators x 10 voltages with the full effect library.
//! `cargo bench --bench calibrate_speed` (release); the test suite checks the same case finds its effects.

#[path = "../tests/synthetic/mod.rs"]
mod synthetic;

use actuator_cam::calibrate::{self, csv::parse, Settings};
use actuator_model::Effects;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use synthetic::*;

fn main() {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let designs: Vec<Design> = (0..50).map(|_| random_design(&mut rng)).collect();
    let fields: Vec<f64> = (1..=10).map(|k| 80.0 * k as f64).collect();
    let truth = Truth::Library(Effects {
        dead_length: 3e-3,
        clamp_compliance: 0.5,
        ..Effects::default()
    });
    let data = parse(&synthetic_csv_at(truth, &designs, &fields, &mut rng)).expect("valid data");
    let mut times = Vec::new();
    for _ in 0..3 {
        let start = std::time::Instant::now();
        let cal = calibrate::calibrate(&data, &Settings::default()).expect("calibrates");
        times.push(start.elapsed().as_secs_f64());
        assert_eq!(cal.model.verdict, "explained");
    }
    times.sort_by(f64::total_cmp);
    println!(
        "calibrate 50 actuators x 10 voltages, full library: median {:.3} s (min {:.3}, max {:.3})",
        times[1], times[0], times[2]
    );
}
