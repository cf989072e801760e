//! The command line: every subcommand's clap arguments and its `run`, one file each, over the library's
//! domain modules (which know nothing of clap, indicatif or anyhow). Flags that several subcommands share
//! are defined once in [`flags`].

pub mod calibrate;
pub mod cut_sheet;
pub mod drive;
pub mod flags;
pub mod interrupt;
pub mod laminate;
pub mod nest;
pub mod optimize;
pub mod predict;
pub mod sweep;
pub mod weibull;

use clap::{Parser, Subcommand};

/// CAD/CAM for piezoelectric bimorph bending actuators.
#[derive(Parser)]
#[command(name = "actuator-cam", version, about)]
pub struct Cli {
    /// The subcommand.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(Subcommand)]
pub enum Command {
    /// Find the physical effect behind measured-vs-model errors and write a calibrated model.
    Calibrate(calibrate::CalibrateArgs),
    /// Mass and performance of a design.
    Predict(predict::PredictArgs),
    /// Laser-cut layer files, report and build checklist for a design.
    CutSheet(cut_sheet::CutSheetArgs),
    /// Will a design flap a wing to a stroke at a frequency: voltage, field margin, linkage, mass.
    Drive(drive::DriveArgs),
    /// Nest a batch of designs on shared PZT, prepreg and Pyralux sheets and clamp panels.
    Nest(nest::NestArgs),
    /// ABD matrices, thickness and areal mass of a layup.
    Laminate(laminate::LaminateArgs),
    /// Weibull fit and survival thresholds from failure data.
    Weibull(weibull::WeibullArgs),
    /// Lightest actuator (or highest energy density) for a required mechanical energy.
    Optimize(optimize::OptimizeArgs),
    /// Full-factorial design sweep: every design's outputs, main effects, model comparison.
    Sweep(sweep::SweepArgs),
}

impl Command {
    /// Run the subcommand.
    pub fn run(&self) -> anyhow::Result<()> {
        match self {
            Command::Calibrate(a) => calibrate::run(a),
            Command::Predict(a) => predict::run(a),
            Command::CutSheet(a) => cut_sheet::run(a),
            Command::Drive(a) => drive::run(a),
            Command::Nest(a) => nest::run(a),
            Command::Laminate(a) => laminate::run(a),
            Command::Weibull(a) => weibull::run(a),
            Command::Optimize(a) => optimize::run(a),
            Command::Sweep(a) => sweep::run(a),
        }
    }
}
