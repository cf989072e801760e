//! The subcommands: each file holds its clap arguments and a `run` that does the job.

pub mod cut_sheet;
pub mod laminate;
pub mod model_arg;
pub mod predict;
pub mod weibull;
