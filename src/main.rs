//! actuator-cam: command line over the library (subcommands wire straight to library calls).

use clap::{Parser, Subcommand};

#[derive(Parser)]
#[command(
    name = "actuator-cam",
    version,
    about = "CAD/CAM for piezoelectric bimorph bending actuators"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Find the physical effect behind measured-vs-model errors and write a calibrated model.
    Calibrate(actuator_cam::calibrate::CalibrateArgs),
}

fn main() -> anyhow::Result<()> {
    match Cli::parse().command {
        Command::Calibrate(args) => actuator_cam::calibrate::run(&args),
    }
}
