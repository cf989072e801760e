//! `actuator-cam sweep` (in progress).
use clap::Args;
use std::path::PathBuf;

/// `actuator-cam sweep`.
#[derive(Debug, Clone, Args)]
pub struct SweepArgs {
    /// Factors file.
    pub factors: PathBuf,
}

/// `actuator-cam sweep`.
pub fn run(_args: &SweepArgs) -> anyhow::Result<()> {
    anyhow::bail!("not yet")
}
