//! The calibration studies: each runs `calibrate` on synthetic data sets whose hidden truth it knows
//! (`tests/synthetic`) and checks that the verdict and the estimates find it, over several seeds. They
//! take minutes, so they are `#[ignore = "study"]` and run in a CI step of their own:
//!
//! ```sh
//! cargo test --release --test tests -- --ignored --skip ::write_ --skip ::full_
//! ```
//!
//! A study runs a 4-seed sample of its measuring seeds; `ACTUATOR_CAM_FULL_STUDY=1` runs them all and
//! prints the tables of docs/calibration.md. Run by hand only: the `full_` studies (minutes each, they
//! print the tables of docs/calibration.md), and the `write_` tests, which regenerate the example data
//! sets in `examples/`.

mod calibrate_broken;
mod calibrate_declared;
mod calibrate_discovery;
mod calibrate_false_alarm;
mod calibrate_identifiable;
mod calibrate_loop;
mod calibrate_null_alarm;
mod calibrate_plate_thickness;
mod calibrate_power;
mod calibrate_resonance;
mod calibrate_robust;
mod calibrate_selection;
mod calibrate_synthetic;
mod calibrate_thickness;
mod calibrate_tip_mass;
mod calibrate_touches;
