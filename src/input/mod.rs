//! Reading user files, one layer for every file kind (design, process template, batch, optimize spec,
//! sweep factors, measured-data CSV, failure CSV, declared effects).
//!
//! Each kind is read in two steps. The raw representation is the parsed file itself (a TOML table, or a
//! CSV record with its header); one validating conversion per kind (`Design::from_table`,
//! `Spec::from_table`, `calibrate::csv::parse`, …) walks it with a checked reader and produces the typed,
//! SI values that the rest of the code trusts. TOML files are walked with [`TableReader`] rather than
//! deserialized into serde structs: at the point where a value is refused the reader knows the field's
//! dotted path, the value as written and the allowed range from [`limits`], so every message is built
//! from those facts instead of being translated back from a deserializer's text, and no serde message
//! can reach the user. Every problem is one [`InputError`], printed on one line.

mod columns;
pub mod effects;
mod error;
pub mod finite;
pub mod library;
pub mod limits;
mod range;
mod table;

pub use columns::refuse_repeated_columns;
pub use error::{short_number, InputError};
pub use finite::ensure_finite;
pub use library::FieldSource;
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
