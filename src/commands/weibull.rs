//! `actuator-cam weibull failures.csv`: maximum-likelihood Weibull fit and survival thresholds.

use super::flags;
use actuator_cam::{read_failure_column, short_number};
use actuator_model::Weibull;
use anyhow::{anyhow, bail};
use clap::Args;
use std::path::PathBuf;

/// Arguments of `weibull`.
#[derive(Debug, Args)]
pub struct WeibullArgs {
    /// CSV with a header row and a column of failure values (field, strain or stress, any unit).
    pub failures: PathBuf,
    /// Column to read (default: the first). Given twice, the run is refused rather than one winning.
    #[arg(long, value_name = "NAME", action = clap::ArgAction::Append)]
    pub column: Vec<String>,
    /// Survival rates to give thresholds for, each strictly between 0 and 1.
    #[arg(long, value_name = "RATES", value_delimiter = ',', default_value = "0.9,0.75,0.5", value_parser = flags::survival)]
    pub survival: Vec<f64>,
}

/// Run `weibull`.
pub fn run(args: &WeibullArgs) -> anyhow::Result<()> {
    let column = match args.column.as_slice() {
        [] => None,
        [one] => Some(one.as_str()),
        many => bail!(
            "--column given {} times ({}): name one column",
            many.len(),
            many.join(", ")
        ),
    };
    let (name, values) = read_failure_column(&args.failures, column)?;
    let fit = Weibull::fit_mle(&values)
        .map_err(|e| anyhow!("{}: column {name}: {e}", args.failures.display()))?;
    println!(
        "Weibull fit (maximum likelihood) of {} failure values in column {name}",
        values.len()
    );
    // Six significant digits whatever the unit: failure values run from 1e-12 (a strain in some
    // unit) to 1e12 (a stress in Pa), where a fixed count of decimals prints 0.000000 or 19 digits.
    println!("  scale lambda  {}", short_number(fit.scale));
    println!("  shape k       {}", short_number(fit.shape));
    for s in &args.survival {
        println!(
            "  {:>5.1}% survive up to {}",
            s * 100.0,
            short_number(fit.threshold(*s)?)
        );
    }
    Ok(())
}
