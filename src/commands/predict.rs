//! `actuator-cam predict design.toml`: mass and performance of one design.

use crate::design::Design;
use crate::prediction::Prediction;
use actuator_model::ModelKind;
use clap::{Args, ValueEnum};
use std::path::PathBuf;

/// Built-in model choice on the command line.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ModelArg {
    /// Lamination theory with the tapered-beam compliance.
    Original,
    /// Original with the thesis' empirical corrections (eqs. 4.3-4.5).
    ThesisAdjusted,
    /// Euler-Bernoulli beam (rectangles only).
    EulerBernoulli,
}

impl From<ModelArg> for ModelKind {
    fn from(m: ModelArg) -> Self {
        match m {
            ModelArg::Original => ModelKind::Original,
            ModelArg::ThesisAdjusted => ModelKind::ThesisAdjusted,
            ModelArg::EulerBernoulli => ModelKind::EulerBernoulli,
        }
    }
}

/// Arguments of `predict`.
#[derive(Debug, Args)]
pub struct PredictArgs {
    /// Design file (design.toml).
    pub design: PathBuf,
    /// Which model predicts.
    #[arg(long, value_enum, default_value = "original")]
    pub model: ModelArg,
    /// Print one JSON object instead of a table.
    #[arg(long)]
    pub json: bool,
}

/// Run `predict`.
pub fn run(args: &PredictArgs) -> anyhow::Result<()> {
    let design = Design::load(&args.design)?;
    let prediction = Prediction::of(&design, args.model.into())
        .map_err(|e| anyhow::anyhow!("{}: {e}", args.design.display()))?;
    if args.json {
        println!("{}", serde_json::to_string_pretty(&prediction)?);
    } else {
        print!("{}", prediction.table());
    }
    Ok(())
}
