//! The integration tests, one binary (as ripgrep's tests/tests.rs): each module drives the built binary or
//! the library on the shipped examples. The calibration studies (`studies`, minutes of fits on synthetic
//! data) are `#[ignore = "study"]`: the README's test command skips them and CI runs them in a step of
//! their own (see `studies`).

mod common;
mod studies;
mod synthetic;

mod architecture;
mod book_process;
mod build_book;
mod calibrate;
mod calibrated_base;
mod cam_writers;
mod cut_sheet;
mod drive;
mod drive_field;
mod file_pairs;
mod golden;
mod linkage;
mod misspelt_keys;
mod nest;
mod nest_linkage;
mod nest_parts;
mod optimize;
mod optimize_wing;
mod output_safety;
mod parsers;
mod parts_import;
mod predict;
mod press_fit;
mod readme_help;
mod refusals;
mod scoring;
mod stock;
mod sweep;
mod two_stage;
mod validation;
mod validation_vehicle;
mod weibull;
