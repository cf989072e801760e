//! Effects a lab declares (issue 17 item 4): `calibrate --effects FILE` fits compositions of the model's
//! primitives beside the library, the calibrated model records them, and `predict`, `optimize` and
//! `cut-sheet --model FILE` apply them.
//!
//! The data are generated (tests/synthetic) with an effect outside the library built from the model
//! crate's own primitives, and never declared to the calibrator unless the test says so.

mod common;
mod synthetic;

use actuator_cam::calibrate::library::{Declared, DeclaredSpec};
use actuator_cam::calibrate::{self, csv::parse, Calibration, Settings};
use actuator_cam::input;
use actuator_model::primitives::{Applied, Primitive, Property, Target};
use actuator_model::Effects;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use synthetic::*;

/// Clamp compliance per unit clamped width, `c_θ = c_w / w_0` (rad·m/(N·m)).
const C_W: f64 = 4e-3;

fn clamp_per_width() -> Applied {
    Applied {
        primitive: Primitive::ClampCompliancePerWidth,
        value: C_W,
    }
}

fn soft_fibre() -> Applied {
    Applied {
        primitive: Primitive::Scale {
            target: Target::Passive,
            property: Property::E1,
        },
        value: 0.7,
    }
}

const DECLARATIONS: &str = r#"
[[effect]]
name = "wide-clamp"
parameter = "c_w_rad_m_per_N_m"
null = 0.0
bounds = [0.0, 0.05]
primitives = [{ kind = "clamp-compliance-per-width" }]

[[effect]]
name = "soft-fibre"
parameter = "passive_e1_scale"
null = 1.0
bounds = [0.3, 1.2]
primitives = [{ kind = "scale", target = "passive", property = "E1" }]
"#;

fn declarations() -> Vec<DeclaredSpec> {
    let file = std::path::Path::new("effects.toml");
    input::effects::parse(file, &input::parse_toml(file, DECLARATIONS).unwrap()).unwrap()
}

/// 30 actuators x 4 voltages, 5 % noise, with `truth`.
fn data(truth: Truth, seed: u64) -> actuator_cam::calibrate::Dataset {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let designs: Vec<Design> = (0..30).map(|_| random_design(&mut rng)).collect();
    parse(&synthetic_csv(truth, &designs, &mut rng)).unwrap()
}

fn calibrate_with(data: &actuator_cam::calibrate::Dataset, declared: bool) -> Calibration {
    let settings = Settings {
        declared: if declared {
            declarations().into_iter().map(Declared::new).collect()
        } else {
            Vec::new()
        },
        ..Settings::default()
    };
    calibrate::calibrate(data, &settings).unwrap()
}

/// The fitted value and 95 % interval of a selected declared effect.
fn fitted(cal: &Calibration, name: &str) -> (f64, (f64, f64)) {
    let c = &cal.selection.candidates[cal.selection.final_index];
    let k = c
        .effects
        .iter()
        .position(|e| e.name() == name)
        .unwrap_or_else(|| panic!("{name} not in the final model {}", c.label()));
    (c.values[k], c.intervals[k])
}

/// An out-of-library effect is "not-explained" by the library alone, and explained once declared, with
/// the declared effect selected, its fitted value's interval holding the truth, and the error down.
fn library_misses_and_declaration_explains(truth: Applied, name: &str, seed: u64) {
    let d31 = Effects {
        d31_scale: 0.85,
        ..Effects::default()
    };
    let data = data(Truth::Composed(d31, truth), seed);
    let library = calibrate_with(&data, false);
    assert_eq!(
        library.model.verdict, "not-explained",
        "library alone: {:?} {:?}",
        library.selection.verdict, library.model.selected_effects
    );
    let declared = calibrate_with(&data, true);
    assert_eq!(
        declared.model.verdict, "explained",
        "{:?} {:?}",
        declared.selection.verdict, declared.model.selected_effects
    );
    assert!(
        declared.model.selected_effects.iter().any(|e| e == name),
        "{:?}",
        declared.model.selected_effects
    );
    let (value, (lo, hi)) = fitted(&declared, name);
    assert!(
        lo <= truth.value && truth.value <= hi,
        "{name}: {value} [{lo}, {hi}] vs truth {}",
        truth.value
    );
    // The model file records it, at the fitted value.
    let record = declared
        .model
        .declared
        .iter()
        .find(|d| d.name == name)
        .unwrap();
    assert_eq!(record.value, value);
    assert!(declared.cv_rmse_after < library.cv_rmse_after);
}

#[test]
fn clamp_compliance_per_width_is_explained_once_declared() {
    library_misses_and_declaration_explains(clamp_per_width(), "wide-clamp", 1701);
}

#[test]
fn soft_passive_fibre_is_explained_once_declared() {
    library_misses_and_declaration_explains(soft_fibre(), "soft-fibre", 1702);
}
