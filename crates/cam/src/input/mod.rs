//! Reading user files: the one checked reader, error type and range table that the parser of every file
//! kind uses (design, process template, batch, optimize spec, sweep factors, measured-data CSV, failure CSV,
//! declared effects). Each parser lives beside the domain type it produces, so this layer names no domain
//! module and every domain module may use it.
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
mod error;
pub mod failures;
pub mod finite;
pub mod library;
pub mod limits;
mod range;
mod read;
mod table;

pub use columns::refuse_repeated_columns;
pub use error::{fixed, short_number, InputError};
pub use finite::ensure_finite;
pub use library::FieldSource;
pub use range::Range;
pub use read::{files_read, read_text, record};
pub use table::{nearest, TableReader};

use std::path::Path;

/// Read and parse a TOML file into a table.
pub fn read_toml(path: &Path) -> Result<toml::Table, InputError> {
    let text = read_text(path)?;
    parse_toml(path, &text)
}

/// Parse TOML text (named `path` in errors).
pub fn parse_toml(path: &Path, text: &str) -> Result<toml::Table, InputError> {
    text.parse::<toml::Table>()
        .map_err(|e| InputError::syntax(path, toml_error_line(text, &e), e.message()))
}

/// The line a TOML error starts on (0 if it has no place): one more than the newlines before it. Counting
/// `lines()` of the text before it would be one short when the error starts a line.
pub fn toml_error_line(text: &str, error: &toml::de::Error) -> usize {
    error.span().map_or(0, |s| {
        let before = &text.as_bytes()[..s.start.min(text.len())];
        before.iter().filter(|&&b| b == b'\n').count() + 1
    })
}

#[cfg(test)]
mod tests {
    use super::parse_toml;
    use std::path::Path;

    #[test]
    fn a_syntax_error_names_the_line_it_is_on() {
        // The bad key starts line 3, at the first byte of the line.
        let e = parse_toml(Path::new("d.toml"), "a = 1\nb = 2\n= 3\n").unwrap_err();
        assert!(e.to_string().contains("line 3"), "{e}");
        // Mid-line error on line 2.
        let e = parse_toml(Path::new("d.toml"), "a = 1\nb = @\n").unwrap_err();
        assert!(e.to_string().contains("line 2"), "{e}");
        let e = parse_toml(Path::new("d.toml"), "x = [\n").unwrap_err();
        assert!(e.to_string().contains("line "), "{e}");
    }
}
