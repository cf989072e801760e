//! The one error type for bad user input, shared by every file kind (design, template, batch, optimize
//! spec, sweep factors, measured-data CSV, failure CSV).

use std::fmt;
use std::path::Path;

/// A problem with a user file, printed as one line: `FILE: FIELD = VALUE: what is allowed`.
///
/// `field` is a dotted TOML path (`geometry.width_ratio`) or a CSV location (`line 26, column mass_mg`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct InputError {
    /// The file the input came from.
    pub file: String,
    /// Dotted field path (`geometry.width_ratio`), or a location such as `line 4, column w0_mm`.
    pub field: String,
    /// The offending value as written (empty when missing).
    pub value: String,
    /// What is allowed.
    pub expected: String,
}

/// Squeeze any line breaks out of a message part, so that the error stays on one line.
fn one_line(text: &str) -> String {
    text.split(['\n', '\r'])
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .collect::<Vec<_>>()
        .join(" ")
}

impl InputError {
    /// A field with a bad value.
    pub fn invalid(
        file: &Path,
        field: &str,
        value: impl fmt::Display,
        expected: impl Into<String>,
    ) -> Self {
        InputError {
            file: file.display().to_string(),
            field: field.to_string(),
            value: one_line(&value.to_string()),
            expected: one_line(&expected.into()),
        }
    }

    /// A required field that is absent.
    pub fn missing(file: &Path, field: &str, expected: &str) -> Self {
        InputError {
            file: file.display().to_string(),
            field: field.to_string(),
            value: String::new(),
            expected: format!("missing; required: {}", one_line(expected)),
        }
    }

    /// A bad CSV cell: `line` is the line of the file, `column` the header name.
    pub fn cell(
        file: &Path,
        line: u64,
        column: &str,
        value: impl fmt::Display,
        expected: impl Into<String>,
    ) -> Self {
        Self::invalid(
            file,
            &format!("line {line}, column {column}"),
            value,
            expected,
        )
    }

    /// A problem with the file as a whole (no data rows, a missing CSV column).
    pub fn whole_file(file: &Path, expected: impl Into<String>) -> Self {
        InputError {
            file: file.display().to_string(),
            field: String::new(),
            value: String::new(),
            expected: one_line(&expected.into()),
        }
    }

    /// The file could not be read.
    pub fn io(file: &Path, err: &std::io::Error) -> Self {
        Self::whole_file(file, format!("cannot read the file: {err}"))
    }

    /// A syntax error at a line.
    pub fn syntax(file: &Path, line: usize, message: &str) -> Self {
        InputError {
            file: file.display().to_string(),
            field: format!("line {line}"),
            value: String::new(),
            expected: format!("not valid TOML: {}", one_line(message)),
        }
    }
}

impl fmt::Display for InputError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match (self.field.is_empty(), self.value.is_empty()) {
            (true, _) => write!(f, "{}: {}", self.file, self.expected),
            (false, true) => write!(f, "{}: {}: {}", self.file, self.field, self.expected),
            (false, false) => write!(
                f,
                "{}: {} = {}: {}",
                self.file, self.field, self.value, self.expected
            ),
        }
    }
}

impl std::error::Error for InputError {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_form_is_one_line() {
        let f = Path::new("m.csv");
        let e = InputError::cell(
            f,
            26,
            "mass_mg",
            -400,
            "outside the allowed range (0, inf) mg",
        );
        assert_eq!(
            e.to_string(),
            "m.csv: line 26, column mass_mg = -400: outside the allowed range (0, inf) mg"
        );
        let e = InputError::syntax(f, 3, "expected `]`\nat the end");
        assert_eq!(
            e.to_string(),
            "m.csv: line 3: not valid TOML: expected `]` at the end"
        );
        assert_eq!(
            InputError::whole_file(f, "no data rows").to_string(),
            "m.csv: no data rows"
        );
    }
}
