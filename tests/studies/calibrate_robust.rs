//! Robust statistics (docs/calibration.md §3, "Heavy tails" and "False alarms on null data").
//!
//! Null data with heavy-tailed noise: 30 random actuators, a quarter of them measured at two voltages
//! and the rest at four, Student-t noise of 3 degrees of freedom scaled to 5 % on δ and F_b, 1 % normal
//! noise on the mass, and one cracked actuator (δ and F_b 45 % low at every voltage). Beside it the
//! studies' Gaussian null data (`random_csv`). Any verdict but `no-effect` is a false alarm, allowed at
//! the rate chance allows at 3 % (`allowed_null_alarms`); the cracked actuator must be named.
//!
//! A load cell that gives under the tip: the loop (calibrate; declare `suggested-effects.toml`;
//! calibrate again) must end not-explained naming a force-only residual, since no effect of the
//! actuator lowers the force alone.
//!
//! The multiplicity test and the Huber pseudo-observations were chosen on seeds 62 000-62 019 and
//! 70 000-70 199 of both kinds of null data, and the correlations' weights on the alarms of seeds
//! 80 000-81 199 and 84 000-85 199; the figures are measured on seeds no choice was made on.

use super::calibrate_loop::{declaring, suggested};
use super::calibrate_touches::through_compliant_load_cell;
use crate::synthetic;

use actuator_cam::{calibrate, parse_measured as parse, Calibration, Settings};
use actuator_model::Effects;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use synthetic::*;

/// The fields of an actuator measured at two voltages only (V/mm).
const TWO_LEVELS: [f64; 2] = [400.0, 800.0];

/// Measuring seeds of the Gaussian and the heavy-tailed null data, and of the load cell.
const GAUSSIAN_SEEDS: u64 = 86_000;
const HEAVY_SEEDS: u64 = 87_000;
const LOAD_CELL_SEEDS: u64 = 82_000;

/// Data sets per kind in the full study (fast: a null data set calibrates in a tenth of a second).
const NULL_SETS: u64 = 400;

/// A null data set of 30 random actuators (`random_design`), a quarter of them (drawn from the seed)
/// measured at two voltages and the rest at four, with `noise` on δ and F_b and 1 % on the mass, and
/// one actuator drawn from the seed cracked (δ and F_b × 0.55 at every voltage). Returns the CSV and the
/// cracked actuator's id.
pub fn heavy_null_csv(seed: u64, noise: Noise) -> (String, String) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let designs: Vec<Design> = (0..30).map(|_| random_design(&mut rng)).collect();
    let two: Vec<bool> = (0..30).map(|_| rng.gen_bool(0.25)).collect();
    let fields_of = |d: &Design| {
        let i = designs
            .iter()
            .position(|e| std::ptr::eq(e, d))
            .expect("one of the designs");
        if two[i] {
            TWO_LEVELS.to_vec()
        } else {
            FIELDS_V_PER_MM.to_vec()
        }
    };
    let which = rng.gen_range(0..30);
    let csv = synthetic_csv_noise(
        Truth::Library(Effects::default()),
        &designs,
        &fields_of,
        noise,
        &mut rng,
    );
    (break_actuators(&csv, &[which], 0.55), format!("A{which}"))
}

fn describe(cal: &Calibration) -> String {
    format!(
        "{:?} {:?}",
        cal.selection.verdict, cal.model.selected_effects
    )
}

/// The false alarms among the verdicts on `seeds`, each with its description.
fn alarms(seeds: &[u64], csv_of: &(dyn Fn(u64) -> String + Sync)) -> Vec<(u64, String)> {
    seeds
        .par_iter()
        .filter_map(|&seed| {
            let cal = calibrate(&parse(&csv_of(seed)).unwrap(), &Settings::default()).unwrap();
            (cal.model.verdict != "no-effect").then(|| (seed, describe(&cal)))
        })
        .collect()
}

fn seeds_from(first: u64, count: u64) -> Vec<u64> {
    sample((first..first + count).collect())
}

#[test]
#[ignore = "study"]
fn null_data_with_heavy_tails_and_a_broken_actuator_give_no_effect_but_by_chance() {
    let gaussian = seeds_from(GAUSSIAN_SEEDS, NULL_SETS);
    let heavy = seeds_from(HEAVY_SEEDS, NULL_SETS);
    // The cracked actuator is named on every heavy-tailed data set.
    let missed: Vec<u64> = heavy
        .par_iter()
        .copied()
        .filter(|&seed| {
            let (csv, id) = heavy_null_csv(seed, Noise::StudentT3);
            let cal = calibrate(&parse(&csv).unwrap(), &Settings::default()).unwrap();
            !cal.broken.iter().any(|b| b.id == id && b.excluded)
        })
        .collect();
    let from_gaussian = alarms(&gaussian, &|s| {
        random_csv(Truth::Library(Effects::default()), s)
    });
    let from_heavy = alarms(&heavy, &|s| heavy_null_csv(s, Noise::StudentT3).0);
    let from_gaussian_broken = alarms(&heavy, &|s| heavy_null_csv(s, Noise::Gaussian).0);
    for (name, n, found) in [
        ("Gaussian", gaussian.len(), &from_gaussian),
        ("Student-t(3), broken, two-level", heavy.len(), &from_heavy),
        (
            "Gaussian, broken, two-level",
            heavy.len(),
            &from_gaussian_broken,
        ),
    ] {
        eprintln!("{name}: {} false alarms in {n}: {found:?}", found.len());
        assert!(found.len() <= allowed_null_alarms(n), "{name}: {found:?}");
    }
    eprintln!("cracked actuator not named: {missed:?}");
    assert!(missed.is_empty(), "{missed:?}");
}

/// The loop on null data measured through a load cell of 1 N/mm: the final verdict and whether it
/// ends right (not-explained, naming a force-only residual).
fn load_cell_loop(seed: u64) -> (String, bool) {
    let csv =
        through_compliant_load_cell(&random_csv(Truth::Library(Effects::default()), seed), 1.0);
    let data = parse(&csv).unwrap();
    let first = calibrate(&data, &Settings::default()).unwrap();
    let last = match suggested(&first, &data) {
        None => first,
        Some(text) => calibrate(&data, &declaring(&text)).unwrap(),
    };
    let verdict = format!("{:?}", last.selection.verdict);
    let right = last.model.verdict == "not-explained" && verdict.contains("a force-only residual");
    (
        format!("{verdict} {:?}", last.model.selected_effects),
        right,
    )
}

#[test]
#[ignore = "study"]
fn a_compliant_load_cell_loop_ends_naming_a_force_only_residual() {
    let seeds = seeds_from(LOAD_CELL_SEEDS, 20);
    let ends: Vec<(u64, (String, bool))> =
        seeds.par_iter().map(|&s| (s, load_cell_loop(s))).collect();
    let wrong: Vec<&(u64, (String, bool))> = ends.iter().filter(|e| !e.1 .1).collect();
    eprintln!(
        "load cell: {} of {} loops end naming a force-only residual; the others: {wrong:?}",
        ends.len() - wrong.len(),
        ends.len()
    );
    assert!(
        ends.len() - wrong.len() >= of_20(18, ends.len()),
        "{wrong:?}"
    );
}
