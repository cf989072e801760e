//! actuator-cam: command line over the library; each subcommand hands a typed configuration to its module.
use actuator_cam::{optimize, sweep};
use clap::{Parser, Subcommand};
use std::process::ExitCode;

#[derive(Debug, Parser)]
#[command(
    name = "actuator-cam",
    version,
    about = "CAD/CAM for piezoelectric bimorph bending actuators"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Lightest actuator (or highest energy density) for a required mechanical energy.
    Optimize(optimize::OptimizeArgs),
    /// Full-factorial design sweep: every design's outputs, main effects, model comparison.
    Sweep(sweep::SweepArgs),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match &cli.command {
        Command::Optimize(args) => optimize::run(args),
        Command::Sweep(args) => sweep::run(args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}
