//! `actuator-cam weibull failures.csv`: maximum-likelihood Weibull fit and survival thresholds.

use crate::input::limits::FAILURE_VALUE;
use crate::input::InputError;
use actuator_model::Weibull;
use anyhow::{anyhow, bail};
use clap::Args;
use std::path::{Path, PathBuf};

/// Arguments of `weibull`.
#[derive(Debug, Args)]
pub struct WeibullArgs {
    /// CSV with a header row and a column of failure values (field, strain or stress, any unit).
    pub failures: PathBuf,
    /// Column to read (default: the first). Given twice, the run is refused rather than one winning.
    #[arg(long, action = clap::ArgAction::Append)]
    pub column: Vec<String>,
    /// Survival rates to give thresholds for.
    #[arg(long, value_delimiter = ',', default_value = "0.9,0.75,0.5")]
    pub survival: Vec<f64>,
}

/// Read one numeric column of failure values; errors name the file, the line and the column.
pub fn read_column(path: &Path, column: Option<&str>) -> Result<(String, Vec<f64>), InputError> {
    let text = std::fs::read_to_string(path).map_err(|e| InputError::io(path, &e))?;
    let mut reader = csv::ReaderBuilder::new()
        .comment(Some(b'#'))
        .trim(csv::Trim::All)
        .from_reader(text.as_bytes());
    let headers = reader
        .headers()
        .map_err(|e| InputError::whole_file(path, format!("not valid CSV in the header: {e}")))?
        .clone();
    crate::input::refuse_repeated_columns(path, &headers)?;
    let index = match column {
        Some(name) => headers.iter().position(|h| h == name).ok_or_else(|| {
            InputError::invalid(
                path,
                "header",
                headers.iter().collect::<Vec<_>>().join(","),
                format!("no column {name:?} (from --column)"),
            )
        })?,
        None => 0,
    };
    let name = headers.get(index).unwrap_or("value").to_string();
    let mut values = Vec::new();
    for record in reader.records() {
        let record =
            record.map_err(|e| InputError::whole_file(path, format!("not valid CSV: {e}")))?;
        let line = record.position().map(|p| p.line()).unwrap_or(0);
        let cell = record.get(index).unwrap_or("");
        if cell.is_empty() {
            continue;
        }
        match cell.parse::<f64>() {
            Ok(x) if FAILURE_VALUE.contains(x) => values.push(x),
            Ok(_) => {
                return Err(InputError::cell(
                    path,
                    line,
                    &name,
                    cell,
                    format!("a failure value must be positive: outside the {FAILURE_VALUE}"),
                ))
            }
            Err(_) => {
                return Err(InputError::cell(
                    path,
                    line,
                    &name,
                    format!("{cell:?}"),
                    format!("expected a number, {FAILURE_VALUE}"),
                ))
            }
        }
    }
    Ok((name, values))
}

/// Run `weibull`.
pub fn run(args: &WeibullArgs) -> anyhow::Result<()> {
    for s in &args.survival {
        if !(*s > 0.0 && *s < 1.0) {
            bail!("--survival {s}: outside the allowed range (0, 1)");
        }
    }
    let column = match args.column.as_slice() {
        [] => None,
        [one] => Some(one.as_str()),
        many => bail!(
            "--column given {} times ({}): name one column",
            many.len(),
            many.join(", ")
        ),
    };
    let (name, values) = read_column(&args.failures, column)?;
    let fit = Weibull::fit_mle(&values)
        .map_err(|e| anyhow!("{}: column {name}: {e}", args.failures.display()))?;
    println!(
        "Weibull fit (maximum likelihood) of {} failure values in column {name}",
        values.len()
    );
    println!("  scale lambda  {:.6}", fit.scale);
    println!("  shape k       {:.6}", fit.shape);
    for s in &args.survival {
        println!(
            "  {:>5.1}% survive up to {:.6}",
            s * 100.0,
            fit.threshold(*s)?
        );
    }
    Ok(())
}
