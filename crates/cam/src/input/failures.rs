//! The failure-data CSV of `weibull`: one numeric column of failure values (field, strain or stress, any
//! unit) under a header row.

use super::limits::{FAILURE_SPREAD, FAILURE_VALUE};
use super::short_number;
use super::{refuse_repeated_columns, InputError};
use std::path::Path;

/// Read one numeric column of failure values; errors name the file, the line and the column.
pub fn read_column(path: &Path, column: Option<&str>) -> Result<(String, Vec<f64>), InputError> {
    let text = super::read_text(path)?;
    let mut reader = csv::ReaderBuilder::new()
        .comment(Some(b'#'))
        .trim(csv::Trim::All)
        .from_reader(text.as_bytes());
    let headers = reader
        .headers()
        .map_err(|e| InputError::whole_file(path, format!("not valid CSV in the header: {e}")))?
        .clone();
    refuse_repeated_columns(path, &headers)?;
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
                    format!("a failure value must be in the {FAILURE_VALUE}"),
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
    let lo = values.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = values.iter().copied().fold(0.0, f64::max);
    if hi / lo > FAILURE_SPREAD {
        return Err(InputError::invalid(
            path,
            &format!("column {name}"),
            format!("{} to {}", short_number(lo), short_number(hi)),
            format!(
                "the values span a factor of {}; a Weibull fit needs them within a factor of {} of \
                 each other (one unit, one kind of failure)",
                short_number(hi / lo),
                FAILURE_SPREAD
            ),
        ));
    }
    Ok((name, values))
}
