//! The subcommands: each file holds its clap arguments and a `run` that does the job.

pub mod cut_sheet;
pub mod formats;
pub mod laminate;
pub mod model_arg;
pub mod nest;
pub mod predict;
pub mod weibull;
