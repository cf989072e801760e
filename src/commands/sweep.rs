//! `actuator-cam sweep factors.toml`: a full factorial over listed levels, main effects and a comparison
//! of two models, with every design as CSV on request.

use super::flags::{parse_built_in_model, BuiltInModelFlag, ForceFlag};
use actuator_cam::{
    check_models, for_each_design, in_words, sweep_report, ComparisonSums, CsvRows, EffectSums,
    Output, SweepSpec,
};
use actuator_model::{ModelError, ModelKind};
use anyhow::{bail, Context};
use clap::Args;
use std::path::{Path, PathBuf};

/// Arguments of `sweep`.
#[derive(Debug, Clone, Args)]
pub struct SweepArgs {
    /// Factors file: materials, drive and the levels of each factor (see examples/sweep-*.toml).
    pub factors: PathBuf,
    /// `--model` for the outputs (a built-in one).
    #[command(flatten)]
    pub model: BuiltInModelFlag,
    /// Also predict with this built-in model and report the mean and spread of the percent differences
    /// (X_model - X_compare) / X_model (thesis eq. 3.1).
    #[arg(long, value_name = "MODEL", value_parser = parse_built_in_model)]
    pub compare: Option<ModelKind>,
    /// In the comparison, scale the lamination-theory blocked force (and so the energy) by 8/9 as the
    /// thesis' eq. 2.36 prints it; this reproduces its Table 4.1 blocked-force gap.
    #[arg(long, requires = "compare")]
    pub thesis_eq_2_36: bool,
    /// Write every design's levels and outputs as CSV to this file.
    #[arg(long, value_name = "FILE")]
    pub csv: Option<PathBuf>,
    /// `--force`.
    #[command(flatten)]
    pub force: ForceFlag,
}

/// Why a sweep stopped: a design the model refuses, or the CSV could not be written.
enum SweepFailure {
    Model(ModelError),
    Csv(anyhow::Error),
}

impl From<ModelError> for SweepFailure {
    fn from(e: ModelError) -> Self {
        SweepFailure::Model(e)
    }
}

/// A CSV write error (a full disk), in words, naming the file.
fn csv_error(path: &Path, e: csv::Error) -> SweepFailure {
    let why = match e.kind() {
        csv::ErrorKind::Io(io) => in_words(io),
        _ => e.to_string(),
    };
    SweepFailure::Csv(anyhow::anyhow!("--csv {}: {why}", path.display()))
}

/// Run `sweep`.
pub fn run(args: &SweepArgs) -> anyhow::Result<()> {
    let kind = args.model.model;
    let compare = args.compare;
    if args.thesis_eq_2_36 && kind == ModelKind::EulerBernoulli {
        bail!("--thesis-eq-2-36 scales the lamination-theory blocked force; --model euler-bernoulli has none (compare the other way round)");
    }
    let spec = SweepSpec::from_file(&args.factors)?;
    let file = args.factors.display().to_string();
    check_models(&spec, kind, compare).with_context(|| file.clone())?;
    // The CSV is held and checked against the output policy before any design is evaluated, then
    // written row by row: memory stays the same whatever the number of designs.
    let mut csv = match &args.csv {
        Some(path) => {
            let stream = Output::new("sweep")
                .force(args.force.force)
                .inputs([&args.factors])
                .stream_file("--csv", path)?;
            Some(CsvRows::new(stream, &spec, compare, args.thesis_eq_2_36)?)
        }
        None => None,
    };
    let csv_path = args.csv.as_deref().unwrap_or(Path::new(""));
    let mut effects = EffectSums::new(&spec);
    let mut comparison = ComparisonSums::default();
    for_each_design(&spec, kind, compare, |index, design| {
        effects.add(design);
        comparison.add(design, args.thesis_eq_2_36);
        if let Some(rows) = &mut csv {
            rows.row(index, design)
                .map_err(|e| csv_error(csv_path, e))?;
        }
        Ok::<(), SweepFailure>(())
    })
    .map_err(|e| match e {
        SweepFailure::Model(e) => {
            anyhow::Error::new(e).context(format!("{file}: a design cannot be predicted"))
        }
        SweepFailure::Csv(e) => e,
    })?;
    let effects = effects.finish(&spec);
    print!("{}", sweep_report(&spec, &file, kind, &effects));
    if let Some(other) = compare {
        let c = comparison.finish();
        print!("\n{}", c.report(kind, other, args.thesis_eq_2_36));
    }
    if let (Some(rows), Some(path)) = (csv, &args.csv) {
        let stream = rows
            .finish()
            .map_err(|e| csv_error(path, e))
            .map_err(|e| match e {
                SweepFailure::Csv(e) => e,
                SweepFailure::Model(e) => e.into(),
            })?;
        stream.finish()?;
        println!("\nwrote {} ({} designs)", path.display(), spec.count());
    }
    Ok(())
}
