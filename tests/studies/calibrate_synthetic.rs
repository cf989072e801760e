//! The 20-seed simulation study: random designs (30 actuators x 4 voltages, 5% noise on deflection and
//! force, 1% on mass) with one effect hidden in the data, generated with the model crate's effect physics
//! and not declared to the calibrator.
//!
//! CI runs the first 4 seeds of each case, with the thresholds scaled to them (rounded up: every one of
//! the 4 must pass, and an out-of-library case must never be explained); `ACTUATOR_CAM_FULL_STUDY=1`
//! runs all 20 (`-- --nocapture` prints the table).
//! `CALIBRATE_CASE=dead-length CALIBRATE_SEEDS=5 cargo test --test tests calibrate_synthetic -- --ignored --nocapture`
//! runs one case with a given number of seeds while tuning.

use crate::synthetic;

use actuator_cam::{calibrate, parse_measured as parse, Settings};
use actuator_model::Effects;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use synthetic::*;

struct Outcome {
    verdict: String,
    selected: Vec<String>,
    before: f64,
    after: f64,
}

fn run_case(case: &Case, seed: u64) -> Outcome {
    let mut rng = ChaCha8Rng::seed_from_u64(seed * 7919 + 17);
    let designs: Vec<Design> = (0..30).map(|_| random_design(&mut rng)).collect();
    let held_out: Vec<Design> = (0..10).map(|_| random_design(&mut rng)).collect();
    let data = parse(&synthetic_csv(case.truth, &designs, &mut rng)).unwrap();
    let cal = calibrate(&data, &Settings::default()).unwrap();
    Outcome {
        verdict: cal.model.verdict.clone(),
        selected: cal.model.selected_effects.clone(),
        before: held_out_error(case.truth, &held_out, &Effects::default()),
        after: held_out_error(case.truth, &held_out, &cal.model.effects),
    }
}

/// Null case: `no-effect`; out-of-library case: anything but `explained`. Otherwise the right effect(s)
/// named: `explained`, every hidden effect selected and no other library effect
/// (d31-scale aside, which is part of both null models, unless it is the hidden one).
fn is_hit(case: &Case, o: &Outcome) -> bool {
    if case.name == "null" {
        return o.verdict == "no-effect";
    }
    if case.name.starts_with("out-of-library") {
        return o.verdict != "explained";
    }
    names_exactly(case.hidden, &o.verdict, &o.selected)
}

/// The study saturates the cores; the timed test must not overlap it.
static CORES: std::sync::Mutex<()> = std::sync::Mutex::new(());

#[test]
#[ignore = "study"]
fn seed_study_names_the_hidden_effect() {
    let _cores = CORES.lock().unwrap_or_else(|e| e.into_inner());
    let only = std::env::var("CALIBRATE_CASE").ok();
    let seeds: u64 = std::env::var("CALIBRATE_SEEDS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(if full_study() { 20 } else { CI_SAMPLE as u64 });
    let mut failures = Vec::new();
    println!(
        "{:<38} {:>6} {:>9} {:>9} {:>10} {:>12}",
        "case", "hits", "explained", "ambiguous", "no-effect", "not-explained"
    );
    for case in cases() {
        if only.as_deref().is_some_and(|o| o != case.name) {
            continue;
        }
        let outcomes: Vec<Outcome> = (0..seeds)
            .into_par_iter()
            .map(|s| run_case(&case, s))
            .collect();
        let count = |v: &str| outcomes.iter().filter(|o| o.verdict == v).count();
        let hits = outcomes.iter().filter(|o| is_hit(&case, o)).count();
        println!(
            "{:<38} {:>3}/{:<2} {:>9} {:>9} {:>10} {:>12}",
            case.name,
            hits,
            seeds,
            count("explained"),
            count("ambiguous"),
            count("no-effect"),
            count("not-explained")
        );
        for (s, o) in outcomes.iter().enumerate() {
            if std::env::var("CALIBRATE_VERBOSE").is_ok() || (!is_hit(&case, o) && only.is_some()) {
                println!(
                    "    seed {s}: {} {:?} held-out rmse_log before {:.4} after {:.4}",
                    o.verdict, o.selected, o.before, o.after
                );
            }
            // The null case has no error to lower (before = 0): an `explained` there is already a miss.
            let has_effect = o.before > 1e-9;
            if has_effect && o.verdict == "explained" && o.after * 3.0 > o.before {
                failures.push(format!(
                    "{} seed {s}: explained but held-out error {:.4} -> {:.4} (< 3x lower)",
                    case.name, o.before, o.after
                ));
            }
        }
        let scaled = |k: u64| (k * seeds).div_ceil(20) as usize;
        match case.name {
            "null" => {
                if count("no-effect") < scaled(18) {
                    failures.push(format!("null: no-effect {}/{seeds}", count("no-effect")));
                }
            }
            name if name.starts_with("out-of-library") => {
                if count("explained") > 4 * seeds as usize / 20 {
                    failures.push(format!(
                        "{}: explained {} times",
                        case.name,
                        count("explained")
                    ));
                }
            }
            _ => {
                if hits < scaled(16) {
                    failures.push(format!("{}: named {hits}/{seeds}", case.name));
                }
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The speed case (50 actuators x 10 voltages, full library) must still find what is hidden in it.
/// Its time is a benchmark figure, not a test: `cargo bench --bench calibrate_speed`.
#[test]
#[ignore = "study"]
fn fifty_actuators_by_ten_voltages_name_the_hidden_pair() {
    let _cores = CORES.lock().unwrap_or_else(|e| e.into_inner());
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let designs: Vec<Design> = (0..50).map(|_| random_design(&mut rng)).collect();
    let fields: Vec<f64> = (1..=10).map(|k| 80.0 * k as f64).collect();
    let case = cases()
        .into_iter()
        .find(|c| c.name.starts_with("pair"))
        .unwrap();
    let data = parse(&synthetic_csv_at(case.truth, &designs, &fields, &mut rng)).unwrap();
    assert_eq!(data.rows.len(), 500);
    let cal = calibrate(&data, &Settings::default()).unwrap();
    assert_eq!(cal.model.verdict, "explained");
    for hidden in case.hidden {
        assert!(
            cal.model.selected_effects.iter().any(|e| e == hidden),
            "{hidden} not in {:?}",
            cal.model.selected_effects
        );
    }
}

/// Writes `examples/measured-thesis-like.csv`: 24 actuators of thesis-like designs with resin-rich plies,
/// a lower d31, an undriven root length and a compliant clamp, none declared.
/// `cargo test --test tests calibrate_synthetic::write_example -- --ignored`
#[test]
#[ignore = "regenerates examples/measured-thesis-like.csv"]
fn write_example() {
    let mut rng = ChaCha8Rng::seed_from_u64(2013);
    let designs: Vec<Design> = (0..24).map(|_| random_design(&mut rng)).collect();
    let truth = Truth::Library(Effects {
        d31_scale: 0.8,
        dead_length: 2.5e-3,
        clamp_compliance: 0.4,
        ply_thickness_scale: 1.25,
        ..Effects::default()
    });
    let csv = synthetic_csv(truth, &designs, &mut rng);
    let text = format!(
        "# Synthetic thesis-like measurements (24 actuators x 4 voltages, 5% noise on deflection and force,\n\
         # 1% on mass). Generated by tests/studies/calibrate_synthetic.rs::write_example with effects that are NOT\n\
         # declared here; `actuator-cam calibrate` should find them.\n{csv}"
    );
    std::fs::write(
        concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/examples/measured-thesis-like.csv"
        ),
        text,
    )
    .unwrap();
}

/// Identifiability: when every actuator is driven at one field that grows with its length, an undriven
/// root length (worst for short actuators) and a d31 that rises with the field look alike. The
/// calibrator must then say `ambiguous` (seen 4 times in 6) and never name the field-dependent d31 as the
/// explanation.
#[test]
#[ignore = "study"]
fn confounded_designs_do_not_name_the_wrong_effect() {
    let _cores = CORES.lock().unwrap_or_else(|e| e.into_inner());
    let truth = Truth::Library(Effects {
        dead_length: 3e-3,
        ..Effects::default()
    });
    let mut verdicts = Vec::new();
    for seed in 0..6u64 {
        let mut rng = ChaCha8Rng::seed_from_u64(100 + seed);
        let designs: Vec<Design> = (0..30)
            .map(|_| Design {
                l_r: 0.0,
                w_r: 1.0,
                ..random_design(&mut rng)
            })
            .collect();
        let field_of = |d: &Design| vec![200.0 + 600.0 * (d.l_tot_mm - 20.0) / 30.0];
        let data = parse(&synthetic_csv_each(truth, &designs, &field_of, &mut rng)).unwrap();
        let cal = calibrate(&data, &Settings::default()).unwrap();
        println!(
            "seed {seed}: {} {:?} {:?}",
            cal.model.verdict, cal.model.selected_effects, cal.selection.verdict
        );
        if cal.model.verdict == "ambiguous" {
            // It says which designs would tell the contenders apart.
            assert!(!cal.selection.separating_designs.is_empty());
        }
        verdicts.push((
            cal.model.verdict.clone(),
            cal.model.selected_effects.clone(),
        ));
    }
    for (verdict, selected) in &verdicts {
        assert!(
            !(verdict == "explained" && selected.iter().any(|e| e == "field-dependent-d31")),
            "{verdict} {selected:?}"
        );
    }
    let ambiguous = verdicts.iter().filter(|(v, _)| v == "ambiguous").count();
    assert!(ambiguous >= 3, "ambiguous only {ambiguous}/6");
}
