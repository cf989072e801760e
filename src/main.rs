//! The `actuator-cam` command line: parses arguments and hands them to the library.

use actuator_cam::commands::{cut_sheet, laminate, predict, weibull};
use actuator_cam::{optimize, sweep};
use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// CAD/CAM for piezoelectric bimorph bending actuators.
#[derive(Parser)]
#[command(name = "actuator-cam", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Find the physical effect behind measured-vs-model errors and write a calibrated model.
    Calibrate(actuator_cam::calibrate::CalibrateArgs),
    /// Mass and performance of a design.
    Predict(predict::PredictArgs),
    /// Laser-cut layer files, report and build checklist for a design.
    CutSheet(cut_sheet::CutSheetArgs),
    /// Nest a batch of designs on shared PZT, prepreg and Pyralux sheets and clamp panels.
    Nest(actuator_cam::commands::nest::NestArgs),
    /// ABD matrices, thickness and areal mass of a layup.
    Laminate(laminate::LaminateArgs),
    /// Weibull fit and survival thresholds from failure data.
    Weibull(weibull::WeibullArgs),
    /// Lightest actuator (or highest energy density) for a required mechanical energy.
    Optimize(optimize::OptimizeArgs),
    /// Full-factorial design sweep: every design's outputs, main effects, model comparison.
    Sweep(sweep::SweepArgs),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match &cli.command {
        Command::Calibrate(a) => actuator_cam::calibrate::run(a),
        Command::Predict(a) => predict::run(a),
        Command::CutSheet(a) => cut_sheet::run(a),
        Command::Nest(a) => actuator_cam::commands::nest::run(a),
        Command::Laminate(a) => laminate::run(a),
        Command::Weibull(a) => weibull::run(a),
        Command::Optimize(a) => optimize::run(a),
        Command::Sweep(a) => sweep::run(a),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {}", format!("{e:#}").replace('\n', " "));
            ExitCode::FAILURE
        }
    }
}
