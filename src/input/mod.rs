//! Reading user files: a checked walk over a parsed TOML table, so that every error names the file, the
//! field, the value and the allowed range, and unknown keys are refused.

mod error;
mod range;
mod table;

pub use error::InputError;
pub use range::Range;
pub use table::TableReader;

use std::path::Path;

/// Read and parse a TOML file into a table.
pub fn read_toml(path: &Path) -> Result<toml::Table, InputError> {
    let text = std::fs::read_to_string(path).map_err(|e| InputError::io(path, &e))?;
    parse_toml(path, &text)
}

/// Parse TOML text (named `path` in errors).
pub fn parse_toml(path: &Path, text: &str) -> Result<toml::Table, InputError> {
    text.parse::<toml::Table>().map_err(|e| {
        let line = e
            .span()
            .map(|s| text[..s.start.min(text.len())].lines().count().max(1))
            .unwrap_or(0);
        InputError::syntax(path, line, e.message())
    })
}
