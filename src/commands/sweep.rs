//! `actuator-cam sweep factors.toml`: a full factorial over listed levels, main effects and a comparison
//! of two models, with every design as CSV on request.

use super::flags::{parse_model, ForceFlag, ModelFlag};
use actuator_cam::output::Output;
use actuator_cam::sweep::analysis::{self, Comparison, MainEffects};
use actuator_cam::sweep::spec::SweepSpec;
use actuator_cam::sweep::{check_models, evaluate};
use actuator_model::{ModelChoice, ModelKind};
use anyhow::{bail, Context};
use clap::Args;
use std::path::PathBuf;

/// Arguments of `sweep`.
#[derive(Debug, Clone, Args)]
pub struct SweepArgs {
    /// Factors file: materials, drive and the levels of each factor (see examples/sweep-*.toml).
    pub factors: PathBuf,
    /// `--model` for the outputs (a built-in one).
    #[command(flatten)]
    pub model: ModelFlag,
    /// Also predict with this model and report the mean and spread of the percent differences
    /// (X_model - X_compare) / X_model (thesis eq. 3.1).
    #[arg(long, value_name = "MODEL", value_parser = parse_model)]
    pub compare: Option<ModelChoice>,
    /// In the comparison, scale the lamination-theory blocked force (and so the energy) by 8/9 as the
    /// thesis' eq. 2.36 prints it; this reproduces its Table 4.1 blocked-force gap.
    #[arg(long, requires = "compare")]
    pub thesis_eq_2_36: bool,
    /// Write every design's levels and outputs as CSV.
    #[arg(long, value_name = "CSV")]
    pub csv: Option<PathBuf>,
    /// `--force`.
    #[command(flatten)]
    pub force: ForceFlag,
}

/// A built-in model: the sweep solves each laminate once and predicts from it, which a calibrated
/// model (it changes the stack) cannot share.
fn built_in(flag: &str, choice: &ModelChoice) -> anyhow::Result<ModelKind> {
    match choice {
        ModelChoice::Kind(kind) => Ok(*kind),
        ModelChoice::Calibrated(_) => bail!(
            "{flag}: unknown model for a sweep (a calibrated model is not swept); use original, thesis-adjusted or euler-bernoulli"
        ),
    }
}

/// Run `sweep`.
pub fn run(args: &SweepArgs) -> anyhow::Result<()> {
    let kind = built_in("--model", &args.model.model)?;
    let compare = args
        .compare
        .as_ref()
        .map(|c| built_in("--compare", c))
        .transpose()?;
    if args.thesis_eq_2_36 && kind == ModelKind::EulerBernoulli {
        bail!("--thesis-eq-2-36 scales the lamination-theory blocked force; --model euler-bernoulli has none (compare the other way round)");
    }
    let spec = SweepSpec::from_file(&args.factors)?;
    let file = args.factors.display().to_string();
    check_models(&spec, kind, compare).with_context(|| file.clone())?;
    let designs = evaluate(&spec, kind, compare)
        .with_context(|| format!("{file}: a design cannot be predicted"))?;
    let effects = MainEffects::new(&spec, &designs);
    print!(
        "{}",
        analysis::report(&spec, &file, kind, &designs, &effects)
    );
    if let Some(other) = compare {
        let c = Comparison::new(&designs, args.thesis_eq_2_36);
        print!("\n{}", c.report(kind, other, args.thesis_eq_2_36));
    }
    if let Some(path) = &args.csv {
        let text = analysis::to_csv(&spec, &designs, compare, args.thesis_eq_2_36)?;
        Output::new("sweep")
            .force(args.force.force)
            .inputs([&args.factors])
            .file("--csv", path, text)
            .write()?;
        println!("\nwrote {} ({} designs)", path.display(), designs.len());
    }
    Ok(())
}
