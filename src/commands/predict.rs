//! `actuator-cam predict design.toml`: mass and performance of one design.

use super::flags::{JsonFlag, ModelFlag};
use actuator_cam::{design_for_process, Design, Prediction, Template};
use clap::Args;
use std::path::PathBuf;

/// Arguments of `predict`.
#[derive(Debug, Args)]
pub struct PredictArgs {
    /// Design file (design.toml).
    pub design: PathBuf,
    /// `--model`: which model predicts.
    #[command(flatten)]
    pub model: ModelFlag,
    /// `--json` instead of a table.
    #[command(flatten)]
    pub json: JsonFlag,
}

/// Run `predict`.
pub fn run(args: &PredictArgs) -> anyhow::Result<()> {
    let model = &args.model.model;
    // The design as its process builds it, so `predict` and `cut-sheet` print the same mass: method 1
    // adds its Pyralux bond layers (method 2 adds nothing).
    let design = Design::load(&args.design)?;
    let template = Template::resolve(&design.process, &design.source)?;
    let design = design_for_process(&design, &template)?;
    let prediction = Prediction::with_dynamics(&design, model)
        .map_err(|e| anyhow::anyhow!("{}: {e}", args.design.display()))?;
    prediction.ensure_finite(&design)?;
    if args.json.json {
        println!("{}", serde_json::to_string_pretty(&prediction)?);
    } else {
        print!("{}", prediction.table());
    }
    Ok(())
}
