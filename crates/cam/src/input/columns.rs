//! The header row of a CSV file: every column named once, so no column can silently win over another of
//! the same name.

use super::InputError;
use std::path::Path;

/// Refuse a header that names a column twice, naming the file, the column and the header as written.
pub fn refuse_repeated_columns(file: &Path, headers: &csv::StringRecord) -> Result<(), InputError> {
    for (i, name) in headers.iter().enumerate() {
        if headers.iter().take(i).any(|h| h == name) {
            return Err(InputError::invalid(
                file,
                &format!("header, column {name:?}"),
                headers.iter().collect::<Vec<_>>().join(","),
                "the column appears twice; keep one",
            ));
        }
    }
    Ok(())
}
