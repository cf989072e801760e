//! The integration tests, one binary (as ripgrep's tests/tests.rs): each module drives the built binary or
//! the library on the shipped examples. Long calibration studies are `#[ignore = "study"]`: the README's
//! test command skips them and CI runs them in a step of their own (`cargo test --release -- --ignored`).

mod common;
mod synthetic;

mod architecture;
mod build_book;
mod calibrate;
mod calibrate_broken;
mod calibrate_declared;
mod calibrate_discovery;
mod calibrate_false_alarm;
mod calibrate_identifiable;
mod calibrate_loop;
mod calibrate_power;
mod calibrate_resonance;
mod calibrate_selection;
mod calibrate_synthetic;
mod calibrate_thickness;
mod cam_writers;
mod cut_sheet;
mod drive;
mod golden;
mod linkage;
mod nest;
mod nest_linkage;
mod nest_parts;
mod optimize;
mod optimize_wing;
mod output_safety;
mod parsers;
mod predict;
mod press_fit;
mod readme_help;
mod refusals;
mod scoring;
mod stock;
mod sweep;
mod weibull;
