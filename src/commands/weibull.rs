//! `actuator-cam weibull failures.csv`: maximum-likelihood Weibull fit and survival thresholds.

use actuator_model::Weibull;
use anyhow::{anyhow, bail, Context};
use clap::Args;
use std::path::PathBuf;

/// Arguments of `weibull`.
#[derive(Debug, Args)]
pub struct WeibullArgs {
    /// CSV with a header row and a column of failure values (field, strain or stress, any unit).
    pub failures: PathBuf,
    /// Column to read (default: the first).
    #[arg(long)]
    pub column: Option<String>,
    /// Survival rates to give thresholds for.
    #[arg(long, value_delimiter = ',', default_value = "0.9,0.75,0.5")]
    pub survival: Vec<f64>,
}

/// Read one numeric column; errors name the file, the row and the column.
pub fn read_column(path: &PathBuf, column: Option<&str>) -> anyhow::Result<(String, Vec<f64>)> {
    let file = path.display();
    let mut reader = csv::ReaderBuilder::new()
        .comment(Some(b'#'))
        .trim(csv::Trim::All)
        .from_path(path)
        .with_context(|| format!("{file}: cannot read"))?;
    let headers = reader
        .headers()
        .with_context(|| format!("{file}: no header row"))?
        .clone();
    let index = match column {
        Some(name) => headers.iter().position(|h| h == name).ok_or_else(|| {
            anyhow!(
                "{file}: no column {name:?}; columns: {}",
                headers.iter().collect::<Vec<_>>().join(", ")
            )
        })?,
        None => 0,
    };
    let name = headers.get(index).unwrap_or("value").to_string();
    let mut values = Vec::new();
    for (i, record) in reader.records().enumerate() {
        let row = i + 2; // 1-based, after the header
        let record = record.with_context(|| format!("{file}: row {row}: malformed CSV"))?;
        let cell = record.get(index).unwrap_or("");
        if cell.is_empty() {
            continue;
        }
        let x: f64 = cell
            .parse()
            .map_err(|_| anyhow!("{file}: row {row}, column {name}: {cell:?} is not a number"))?;
        if !(x.is_finite() && x > 0.0) {
            bail!("{file}: row {row}, column {name} = {cell}: a failure value must be a positive finite number");
        }
        values.push(x);
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
    let (name, values) = read_column(&args.failures, args.column.as_deref())?;
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
