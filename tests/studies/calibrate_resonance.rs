//! The measured first resonance in the calibration (docs/calibration.md §3, "The resonance"): a stiffness
//! effect moves `F_b / δ` and `f1` together, a mass effect moves `f1` alone, and a d31 effect moves neither.
//! Each is hidden in synthetic data (30 actuators x 4 voltages, 5 % noise on δ and F_b, 1 % on the mass and
//! on `f1`, `tests/synthetic`), whose `f1` comes from the model crate's beam under the same physics as δ,
//! F_b and the mass, and `calibrate` must select it and estimate it.
//!
//! The mass case is the one the resonance decides: every actuator has the same PZT plates, so a mass per
//! actuator at the clamp (leads, solder) and a mass per bonded area under the plates add the same to each
//! measured mass; only the plates' mass lowers `f1`. Without the resonance column the masses cannot tell
//! the two apart.
//!
//! Seeds: the cases were written against seed 7 (tuning); they are measured on seeds 1001 onwards, the
//! first `synthetic::CI_SAMPLE` of them in CI and 20 with `ACTUATOR_CAM_FULL_STUDY=1`.

use crate::synthetic;

use actuator_cam::{calibrate, parse_measured as parse, Calibration, Settings};
use actuator_model::primitives::{Applied, Primitive};
use actuator_model::{EffectModel, Effects, ModelChoice, ModelKind};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use std::path::Path;
use std::sync::Arc;
use synthetic::*;

/// Seeds the studies measure on (seed 7, which the cases were written against, is not among them).
fn measuring_seeds() -> Vec<u64> {
    sample((1001..1021).collect())
}

/// Hidden clamp compliance, rad/(N·m): the value of the selection study's clamp case (`tests/synthetic`).
const CLAMP: f64 = 0.5;
/// Hidden d31 scale.
const D31: f64 = 0.75;
/// Hidden adhesive under the plates, kg/m² per bonded face (about 80 µm of epoxy).
const GLUE: f64 = 0.1;
/// Hidden structural loss factor (Q = 25).
const ETA: f64 = 0.04;

/// The physics of a hidden truth as the model crate evaluates it.
fn physics(truth: Truth) -> EffectModel {
    match truth {
        Truth::Library(effects) => EffectModel {
            effects,
            primitives: Vec::new(),
        },
        Truth::Primitive(primitive, value) => EffectModel {
            effects: Effects::default(),
            primitives: vec![Applied { primitive, value }],
        },
        _ => unreachable!("the resonance cases hide a library effect or one primitive"),
    }
}

/// The first resonance of design `d` under a hidden truth, Hz.
fn resonance(truth: Truth, d: &Design) -> f64 {
    resonance_of(&physics(truth), d)
}

/// Designs with the same PZT plates (l_p 20 mm, w0 6 mm, w_r 1.2): extension, thickness and layup vary.
fn same_plates(rng: &mut ChaCha8Rng) -> Vec<Design> {
    (0..30)
        .map(|_| {
            let l_r: f64 = rng.gen_range(0.0..1.0);
            Design {
                l_tot_mm: 20.0 * (1.0 + l_r),
                l_r,
                w0_mm: 6.0,
                w_r: 1.2,
                t_p_mm: T_P_MM[rng.gen_range(0..3)],
                layup: rng.gen_range(0..3),
            }
        })
        .collect()
}

/// The synthetic CSV with `resonance_Hz` (1 % noise) and `quality_factor` (Q = 1/η, 10 % noise) on each
/// actuator's first row.
fn with_resonance(truth: Truth, designs: &[Design], rng: &mut ChaCha8Rng) -> String {
    let csv = synthetic_csv(truth, designs, rng);
    with_first_row_columns(&csv, ",resonance_Hz,quality_factor", |id| {
        let f = resonance(truth, &designs[id]) * (0.01 * normal(rng)).exp();
        let q = (1.0 / ETA) * (0.1 * normal(rng)).exp();
        format!(",{f:.4},{q:.3}")
    })
}

/// The same CSV without the resonance and quality factor columns.
fn without_resonance(csv: &str) -> String {
    csv.lines()
        .map(|l| {
            let cells: Vec<&str> = l.split(',').collect();
            cells[..cells.len() - 2].join(",") + "\n"
        })
        .collect()
}

/// The added mass at the clamp and the adhesive under the plates, declared together.
fn mass_effects() -> Settings {
    let text = r#"
[[effect]]
name = "leads"
primitives = [{ kind = "added-mass", parameter = "m_a_kg", null = 0.0, bounds = [0.0, 1e-3] }]

[[effect]]
name = "glue"
primitives = [{ kind = "added-mass-per-area", parameter = "mu_kg_per_m2", null = 0.0, bounds = [0.0, 1.0] }]
"#;
    super::calibrate_loop::declaring(text)
}

/// Value and 95 % interval of effect `name` in the final model (mass stage, then actuation).
fn fitted(cal: &Calibration, name: &str) -> Option<(f64, (f64, f64))> {
    let s = &cal.selection;
    let mass = s.final_mass_index.map(|i| &s.mass_candidates[i]);
    mass.into_iter()
        .chain([&s.candidates[s.final_index]])
        .flat_map(|c| c.effects.iter().zip(c.values.iter().zip(&c.intervals)))
        .find(|(id, _)| id.name() == name)
        .map(|(_, (v, ci))| (*v, *ci))
}

/// RMS of the log error of a calibrated model's `f1` against the noise-free truth, over the designs.
fn resonance_error(cal: &Calibration, truth: Truth, designs: &[Design]) -> f64 {
    model_resonance_error(&cal.model.effect_model().unwrap(), truth, designs)
}

/// The same for any model.
fn model_resonance_error(model: &EffectModel, truth: Truth, designs: &[Design]) -> f64 {
    let sum: f64 = designs
        .iter()
        .map(|d| (resonance_of(model, d) / resonance(truth, d)).ln().powi(2))
        .sum();
    (sum / designs.len() as f64).sqrt()
}

/// One data set: the designs, the CSV with resonances and its calibration.
fn calibrated(
    truth: Truth,
    seed: u64,
    designs: fn(&mut ChaCha8Rng) -> Vec<Design>,
    settings: &Settings,
) -> (Vec<Design>, String, Calibration) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let d = designs(&mut rng);
    let csv = with_resonance(truth, &d, &mut rng);
    let cal = calibrate(&parse(&csv).unwrap(), settings).unwrap();
    (d, csv, cal)
}

fn random_designs(rng: &mut ChaCha8Rng) -> Vec<Design> {
    (0..30).map(|_| random_design(rng)).collect()
}

#[test]
#[ignore = "study"]
fn a_stiffness_effect_moves_the_force_and_the_resonance_together() {
    let truth = Truth::Library(Effects {
        clamp_compliance: CLAMP,
        ..Effects::default()
    });
    let seeds = measuring_seeds();
    let rows: Vec<_> = seeds
        .par_iter()
        .map(|&s| calibrated(truth, s, random_designs, &Settings::default()))
        .collect();
    let (mut misses, mut named_other) = (0, 0);
    // Seeds whose calibrated f1 is off the truth's (checked after every seed is printed).
    let mut off_f1 = Vec::new();
    for (seed, (designs, _, cal)) in seeds.iter().zip(&rows) {
        let selected = &cal.model.selected_effects;
        let fit = fitted(cal, "clamp-compliance");
        println!(
            "seed {seed}: {} {selected:?} c_theta {fit:?}, f1 error {:.4} (original {:.4})",
            cal.selection.verdict.name(),
            resonance_error(cal, truth, designs),
            model_resonance_error(&EffectModel::default(), truth, designs)
        );
        if !names_exactly(
            &["clamp-compliance"],
            cal.selection.verdict.name(),
            selected,
        ) {
            named_other += 1;
            continue;
        }
        let (v, (lo, hi)) = fit.expect("clamp-compliance fitted");
        assert!((v / CLAMP - 1.0).abs() < 0.2, "seed {seed}: c_theta {v}");
        misses += usize::from(!(lo <= CLAMP && CLAMP <= hi));
        // The calibrated f1 is that of the truth, well inside the 1 % noise of one reading.
        if resonance_error(cal, truth, designs) >= 0.005 {
            off_f1.push(*seed);
        }
    }
    hold_the_study(seeds.len(), named_other, misses);
    assert!(
        off_f1.is_empty(),
        "seeds {off_f1:?}: the calibrated f1 is 0.5 % or more off the truth's"
    );
}

/// Prints how many of `seeds` data sets named exactly the hidden effect and holds a study to at least
/// 15 of 20 of them (where the masses alone choose a bond layer by chance, no mass effect is kept, but
/// the adequacy test leaves that data set not explained: docs/calibration.md §3, "No mass effect"), and
/// its intervals to the misses their confidence allows.
fn hold_the_study(seeds: usize, named_other: usize, misses: usize) {
    println!(
        "{} of {seeds} data sets name exactly the hidden effect",
        seeds - named_other
    );
    assert!(
        seeds - named_other >= of_20(15, seeds),
        "{named_other} of {seeds} data sets named another effect"
    );
    assert!(misses <= allowed_misses(seeds), "{misses} intervals missed");
}

#[test]
#[ignore = "study"]
fn a_d31_effect_leaves_the_resonance_alone() {
    let truth = Truth::Library(Effects {
        d31_scale: D31,
        ..Effects::default()
    });
    let original = Truth::Library(Effects::default());
    let seeds = measuring_seeds();
    let rows: Vec<_> = seeds
        .par_iter()
        .map(|&s| calibrated(truth, s, random_designs, &Settings::default()))
        .collect();
    let (mut misses, mut named_other) = (0, 0);
    for (seed, (designs, _, cal)) in seeds.iter().zip(&rows) {
        // The hidden d31 scale leaves every f1 where the original model puts it.
        for d in designs {
            assert!((resonance(truth, d) / resonance(original, d) - 1.0).abs() < 1e-12);
        }
        let selected = &cal.model.selected_effects;
        if !names_exactly(&["d31-scale"], cal.selection.verdict.name(), selected) {
            println!("seed {seed}: {} {selected:?}", cal.selection.verdict.name());
            named_other += 1;
            continue;
        }
        let (v, (lo, hi)) = fitted(cal, "d31-scale").unwrap();
        assert!((v / D31 - 1.0).abs() < 0.02, "seed {seed}: eta {v}");
        misses += usize::from(!(lo <= D31 && D31 <= hi));
        assert!(resonance_error(cal, truth, designs) < 0.005);
    }
    hold_the_study(seeds.len(), named_other, misses);
}

/// A mass effect the masses would choose by chance is refused. Seed 1003 of the d31 case is a data set
/// whose masses alone gain from a bond layer by more than the ΔAICc margin (the truth has no mass
/// effect); the selection's multiplicity test refuses it on the masses, so with and without the `f1`
/// column the d31 scale alone is selected, at its value. (The verdict is the adequacy test's:
/// docs/calibration.md §3 gives it for this data set.)
#[test]
#[ignore = "study"]
fn a_chance_mass_pick_the_resonances_do_not_support_is_dropped() {
    let truth = Truth::Library(Effects {
        d31_scale: D31,
        ..Effects::default()
    });
    let (designs, csv, with) = calibrated(truth, 1003, random_designs, &Settings::default());
    let without = calibrate(
        &parse(&without_resonance(&csv)).unwrap(),
        &Settings::default(),
    )
    .unwrap();
    let masses_chose = |cal: &Calibration| {
        cal.selection
            .mass_candidates
            .iter()
            .filter(|c| c.accepted)
            .min_by(|a, b| a.aicc.total_cmp(&b.aicc))
            .map(|c| c.label())
    };
    // The masses alone gain from a bond layer here by chance; the selection's multiplicity test
    // (docs/calibration.md §3, step 4) refuses that pick before the resonances are asked, with or
    // without the `f1` column.
    for cal in [&with, &without] {
        assert_eq!(masses_chose(cal), None);
        let bond = cal
            .selection
            .mass_candidates
            .iter()
            .find(|c| c.label() == "{bond-layer}")
            .unwrap();
        assert!(bond.note.contains("not significant among"), "{}", bond.note);
        assert_eq!(cal.model.selected_effects, ["d31-scale"]);
    }
    let (v, _) = fitted(&with, "d31-scale").unwrap();
    assert!((v / D31 - 1.0).abs() < 0.02, "eta {v}");
    // Its f1 is the truth's to the beam's mesh: the resonance residual's trend in w_r that leaves this
    // data set not explained is the draw of its 1 % noise, not a model error.
    assert!(resonance_error(&with, truth, &designs) < 1e-4);
}

#[test]
#[ignore = "study"]
fn a_mass_on_the_plates_is_told_from_a_mass_at_the_clamp_by_the_resonance_alone() {
    let truth = Truth::Primitive(Primitive::AddedMassPerArea, GLUE);
    let settings = mass_effects();
    let seeds = measuring_seeds();
    let rows: Vec<_> = seeds
        .par_iter()
        .map(|&s| {
            let (designs, csv, with) = calibrated(truth, s, same_plates, &settings);
            let without = calibrate(&parse(&without_resonance(&csv)).unwrap(), &settings).unwrap();
            (designs, with, without)
        })
        .collect();
    let (mut misses, mut false_alarms) = (0, 0);
    for (seed, (designs, with, without)) in seeds.iter().zip(&rows) {
        println!(
            "seed {seed}: with f1 {:?} {:?} glue {:?}; without f1 {} {:?}",
            with.selection.verdict,
            with.model.selected_effects,
            fitted(with, "glue"),
            without.selection.verdict.name(),
            without.model.selected_effects,
        );
        // The hidden mass lowers f1 on every design, the deflections and forces not at all.
        let fall: Vec<f64> = designs
            .iter()
            .map(|d| -(resonance(truth, d) / resonance(Truth::Library(Effects::default()), d)).ln())
            .collect();
        assert!(fall.iter().all(|&x| x > 0.0), "{fall:?}");
        // The resonance picks the glue on every data set; the verdict is the adequacy test's, whose
        // false alarms on a true model are counted below.
        assert_eq!(with.model.selected_effects, ["glue"], "seed {seed}");
        false_alarms += usize::from(with.selection.verdict.name() != "explained");
        let (v, (lo, hi)) = fitted(with, "glue").unwrap();
        assert!((v / GLUE - 1.0).abs() < 0.2, "seed {seed}: glue {v}");
        misses += usize::from(!(lo <= GLUE && GLUE <= hi));
        assert!(resonance_error(with, truth, designs) < 0.005);
        // Without the resonance the two masses fit the masses alike: no verdict names the glue alone.
        assert!(
            !names_exactly(
                &["glue"],
                without.selection.verdict.name(),
                &without.model.selected_effects
            ),
            "seed {seed}: without f1 {} {:?}",
            without.selection.verdict.name(),
            without.model.selected_effects
        );
    }
    assert!(
        misses <= allowed_misses(seeds.len()),
        "{misses} intervals missed"
    );
    assert!(
        false_alarms <= allowed_false_alarms(seeds.len()),
        "{false_alarms} of {} verdicts not explained",
        seeds.len()
    );
}

/// The two data sets of the full study on which resonances counted as 5 % readings failed
/// (docs/calibration.md §3, "The resonance"): weighted by their noise, the clamp case's calibrated f1
/// (seed 1009) is within 0.5 % of the truth's, and the glue case (seed 1008) picks the glue, which
/// only the resonances tell from a mass at the clamp.
#[test]
#[ignore = "study"]
fn resonances_weighted_by_their_noise_hold_the_data_sets_that_counted_them_as_deflections() {
    let clamp = Truth::Library(Effects {
        clamp_compliance: CLAMP,
        ..Effects::default()
    });
    let (designs, _, cal) = calibrated(clamp, 1009, random_designs, &Settings::default());
    let error = resonance_error(&cal, clamp, &designs);
    assert!(error < 0.005, "clamp seed 1009: f1 off by {error}");
    let glue = Truth::Primitive(Primitive::AddedMassPerArea, GLUE);
    let (_, _, cal) = calibrated(glue, 1008, same_plates, &mass_effects());
    assert_eq!(cal.model.selected_effects, ["glue"]);
    assert!(
        cal.selection
            .notes
            .iter()
            .any(|n| n.contains("forces (and resonances) together better")),
        "{:?}",
        cal.selection.notes
    );
}

#[test]
#[ignore = "study"]
fn the_quality_factors_give_the_models_loss_factor_and_drive_uses_it() {
    let truth = Truth::Library(Effects::default());
    let (_, _, cal) = calibrated(truth, 1001, random_designs, &Settings::default());
    let loss = cal
        .model
        .loss
        .expect("a loss factor from the quality factors");
    assert_eq!(loss.actuators, 30);
    let [lo, hi] = loss.interval;
    assert!(lo <= ETA && ETA <= hi, "{loss:?}");
    // 10 % noise on 30 actuators: the mean within a few per cent.
    assert!((loss.loss_factor / ETA - 1.0).abs() < 0.05, "{loss:?}");
    // The drive takes it when its file gives none, and the file's own value over it.
    let drive = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/drive-hawkmoth.toml");
    let mut spec = actuator_cam::DriveSpec::load(&drive).unwrap();
    spec.loss_factor_given = None;
    let model = ModelChoice::Calibrated(Arc::new(cal.model.clone()));
    assert_eq!(spec.loss_factor(&model), loss.loss_factor);
    assert_eq!(
        spec.loss_factor(&ModelChoice::Kind(ModelKind::Original)),
        actuator_model::dynamics::DEFAULT_LOSS_FACTOR
    );
    spec.loss_factor_given = Some(0.1);
    assert_eq!(spec.loss_factor(&model), 0.1);
}

/// The one data set of the adhesive study whose verdict is not `explained` (seed 1017, the resonances'
/// mean-offset test, docs/calibration.md §3) draws its offset from its own noise: the measured f1 sit
/// 0.6 % below the noise-free truth's on average, four standard errors, before any model is fitted. The
/// test's alarm there is the data's, not a bias of the calibrated model.
#[test]
fn the_adhesive_study_alarm_is_in_the_noise_of_its_data() {
    let truth = Truth::Primitive(Primitive::AddedMassPerArea, GLUE);
    let offset_t = |seed: u64| {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let designs = same_plates(&mut rng);
        let data = parse(&with_resonance(truth, &designs, &mut rng)).unwrap();
        let logs: Vec<f64> = data
            .groups
            .iter()
            .zip(&designs)
            .map(|(rows, d)| (data.rows[rows[0]].resonance.unwrap() / resonance(truth, d)).ln())
            .collect();
        let n = logs.len() as f64;
        let mean = logs.iter().sum::<f64>() / n;
        let var = logs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0);
        (mean, mean / (var / n).sqrt())
    };
    let (mean, t) = offset_t(1017);
    assert!(mean < -0.005 && t < -3.5, "seed 1017: mean {mean}, t {t}");
    // Its neighbours' draws are ordinary.
    for seed in [1016, 1018] {
        let (_, t) = offset_t(seed);
        assert!(t.abs() < 2.5, "seed {seed}: t {t}");
    }
}
