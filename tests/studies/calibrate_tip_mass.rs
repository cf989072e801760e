//! A mass at the tip seen only in the resonance (docs/calibration.md §3, "The resonance"): a glue blob or a
//! wing hinge of 1-5 mg fitted after the actuators were weighed (the model crate's `tip-mass`
//! primitive) leaves δ, F_b and the mass as they were and lowers every `f1`, most on the light
//! actuators, so no design variable follows the resonance residual. Its mean offset does not escape the
//! resonance tests: the loop (calibrate; declare `suggested-effects.toml` when there is one; calibrate
//! again) must end `not-explained` naming a resonance-only residual, or `explained` with the tip mass
//! discovery offers. A lab that declares a tip mass of 4 mg or more itself must get it explained, the
//! hidden mass inside its interval.
//!
//! Data: 30 random actuators x 4 voltages, 5 % noise on δ and F_b, 1 % on the mass and on `f1`, whose
//! precision the file states (`resonance_sd_Hz`, 1 % of each `f1`). The null rows hide nothing, with the
//! column stated and without it (the tests then take the sweeps' pure error as the precision).
//!
//! Seeds: written and tuned against seeds 59 000-59 004; measured on 59 101-59 120 (tip mass) and
//! 59 201-59 220 (null), the first `synthetic::CI_SAMPLE` of each in CI and 20 with
//! `ACTUATOR_CAM_FULL_STUDY=1`.

use super::calibrate_loop::{declaring, suggested};
use crate::synthetic;

use actuator_cam::{calibrate, parse_measured as parse, Calibration, Settings};
use actuator_model::primitives::{Applied, Primitive};
use actuator_model::{EffectModel, Effects};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use synthetic::*;

/// The tip mass of measuring seed `k` (0-based), kg: 1, 2, 3, 4 and 5 mg in turn.
fn tip_mass(k: usize) -> f64 {
    (1 + k % 5) as f64 * 1e-6
}

/// A data set of 30 random actuators hiding a tip mass `m` (kg; 0 for none), with `resonance_Hz` (1 %
/// noise) and, if `stated`, `resonance_sd_Hz` (1 % of it) on each actuator's first row.
fn data_set(m: f64, seed: u64, stated: bool) -> String {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let designs: Vec<Design> = (0..30).map(|_| random_design(&mut rng)).collect();
    let truth = Truth::Primitive(Primitive::TipMass, m);
    let csv = synthetic_csv(truth, &designs, &mut rng);
    let physics = EffectModel {
        effects: Effects::default(),
        primitives: vec![Applied {
            primitive: Primitive::TipMass,
            value: m,
        }],
    };
    let header = if stated {
        ",resonance_Hz,resonance_sd_Hz"
    } else {
        ",resonance_Hz"
    };
    with_first_row_columns(&csv, header, |id| {
        let f = resonance_of(&physics, &designs[id]) * (0.01 * normal(&mut rng)).exp();
        if stated {
            format!(",{f:.4},{:.4}", 0.01 * f)
        } else {
            format!(",{f:.4}")
        }
    })
}

/// The verdict with what it names: `not-explained: <words>` or the verdict's name with the selected
/// effects.
fn said(cal: &Calibration) -> String {
    let v = &cal.selection.verdict;
    match v.name() {
        // The verdict's words, as Debug prints them: `NotExplained { variable: "…" }`.
        "not-explained" => format!(
            "not-explained: {}",
            format!("{v:?}").split('"').nth(1).unwrap_or("")
        ),
        name => format!("{name} {:?}", cal.model.selected_effects),
    }
}

/// Whether a loop's last word is right: the tip mass explained, or a resonance-only residual named.
fn right(last: &str) -> bool {
    (last.starts_with("not-explained: ") && last.contains("a resonance-only residual"))
        || (last.starts_with("explained") && last.contains("tip"))
}

/// One turn of the loop on a data set: the first verdict, whether a suggestion was declared, the last
/// verdict.
fn turn(csv: &str) -> (String, bool, String) {
    let data = parse(csv).unwrap();
    let first = calibrate(&data, &Settings::default()).unwrap();
    let Some(text) = suggested(&first, &data) else {
        return (said(&first), false, said(&first));
    };
    let second = calibrate(&data, &declaring(&text)).unwrap();
    (said(&first), true, said(&second))
}

/// The tip mass a lab declares by hand, up to 20 mg.
const DECLARED: &str = r#"
[[effect]]
name = "tip"
primitives = [{ kind = "tip-mass", parameter = "m_kg", null = 0.0, bounds = [0.0, 2e-5] }]
"#;

/// The declared tip mass's value and 95 % interval in the final model, kg.
fn declared_fit(cal: &Calibration) -> Option<(f64, (f64, f64))> {
    let c = &cal.selection.candidates[cal.selection.final_index];
    c.effects
        .iter()
        .zip(c.values.iter().zip(&c.intervals))
        .find(|(id, _)| id.name() == "tip")
        .map(|(_, (v, ci))| (*v, *ci))
}

#[test]
#[ignore = "study"]
fn a_tip_mass_seen_only_in_the_resonance_ends_the_loop_right() {
    let seeds: Vec<(usize, u64)> = sample((59_101..59_121).collect())
        .into_iter()
        .enumerate()
        .collect();
    let rows: Vec<_> = seeds
        .par_iter()
        .map(|&(k, s)| {
            let csv = data_set(tip_mass(k), s, true);
            let by_hand = calibrate(&parse(&csv).unwrap(), &declaring(DECLARED)).unwrap();
            (turn(&csv), said(&by_hand), declared_fit(&by_hand))
        })
        .collect();
    let (mut wrong, mut explained, mut covered, mut fitted, mut heavy) = (Vec::new(), 0, 0, 0, 0);
    for ((k, seed), ((first, declared, last), by_hand, fit)) in seeds.iter().zip(&rows) {
        let m = tip_mass(*k);
        println!(
            "seed {seed}, tip mass {:.0} mg: first {first}; suggestion declared {declared}; last {last}; \
             declared by hand {by_hand} {fit:?}",
            m * 1e6
        );
        if !right(last) {
            wrong.push(*seed);
        }
        explained += usize::from(last.starts_with("explained"));
        // Declared by hand, from 4 mg: a mass of 1-3 mg moves f1 by 1-3 %, which the comparison of
        // models, counting a resonance as one deflection reading, does not always select (the verdict
        // then names the resonance-only residual, which the loop's check above counts as right).
        if m < 3.5e-6 {
            continue;
        }
        heavy += 1;
        if let Some((_, (lo, hi))) = fit.filter(|_| by_hand.starts_with("explained")) {
            fitted += 1;
            covered += usize::from(lo <= m && m <= hi);
        }
    }
    let n = seeds.len();
    println!(
        "right {} of {n} (explained with the tip mass {explained}); tip mass of 4-5 mg declared by hand \
         explained {fitted} of {heavy}, interval holds it {covered}",
        n - wrong.len()
    );
    assert!(wrong.len() <= n - of_20(18, n), "wrong on {wrong:?} of {n}");
    assert!(
        fitted >= of_20(18, heavy),
        "declared tip mass explained on {fitted} of {heavy}"
    );
    assert!(
        fitted - covered <= allowed_misses(fitted),
        "{covered} of {fitted} intervals hold the hidden mass"
    );
}

#[test]
#[ignore = "study"]
fn the_resonance_tests_raise_no_more_alarms_than_their_level_on_null_data() {
    let seeds = sample((59_201..59_221).collect());
    let rows: Vec<_> = seeds
        .par_iter()
        .map(|&s| {
            [true, false].map(|stated| {
                let cal = calibrate(
                    &parse(&data_set(0.0, s, stated)).unwrap(),
                    &Settings::default(),
                )
                .unwrap();
                let tests = cal.selection.adequacy.resonance;
                (said(&cal), tests)
            })
        })
        .collect();
    let (mut alarms, mut any) = ([0usize; 2], [0usize; 2]);
    for (seed, row) in seeds.iter().zip(&rows) {
        for (i, (verdict, tests)) in row.iter().enumerate() {
            let t = tests.expect("30 resonances are tested");
            println!(
                "seed {seed} ({}): {verdict}; mean t {:.2} p {:.3}, chi-square {:.1} p {:.3}",
                t.precision, t.t, t.p_mean, t.chi_square, t.p_size
            );
            alarms[i] += usize::from(!t.passed);
            any[i] += usize::from(verdict != "no-effect []");
        }
    }
    let n = seeds.len();
    println!(
        "resonance tests failed: stated {} of {n}, sweeps {} of {n}; any verdict but no-effect: {} and {}",
        alarms[0], alarms[1], any[0], any[1]
    );
    // The two tests together at the adequacy level (1 %, 0.5 % each).
    for a in alarms {
        assert!(a <= chance_allows(n, 0.01), "{alarms:?} of {n}");
    }
    for a in any {
        assert!(
            a <= allowed_false_alarms(n) + chance_allows(n, 0.01),
            "{any:?} of {n}"
        );
    }
}

/// The seeds the study was written against, with what each gives (`--nocapture`); nothing asserted.
#[test]
#[ignore = "study"]
fn full_tip_mass_tuning_seeds() {
    for s in 59_000..59_005 {
        let csv = data_set(tip_mass(s as usize), s, true);
        let data = parse(&csv).unwrap();
        let first = calibrate(&data, &Settings::default()).unwrap();
        println!(
            "seed {s}: {} {:?} {:?}\n  suggested {:?}",
            said(&first),
            first.model.selected_effects,
            first.selection.adequacy.resonance,
            suggested(&first, &data).map(|t| t
                .lines()
                .filter(|l| l.contains("kind"))
                .collect::<Vec<_>>()
                .join(" | "))
        );
        println!("  loop {:?}", turn(&csv));
    }
}

/// Each pool thread keeps its own resonances' modes (`crates/cam/src/calibrate/select/resonances.rs`),
/// and their values are functions of the beam alone: the same data calibrated on one thread and on
/// three give the same calibration, to the bit.
#[test]
fn a_calibration_with_resonances_is_the_same_at_any_thread_count() {
    let data = parse(&data_set(3e-6, 59_990, true)).unwrap();
    let on = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let cal = pool.install(|| calibrate(&data, &Settings::default()).unwrap());
        format!("{cal:?}")
    };
    let one = on(1);
    assert!(one.contains("resonance"), "the data hold resonances");
    assert!(one == on(3), "one thread and three differ");
}
