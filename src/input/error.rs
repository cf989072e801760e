//! The one error type for bad user input.

use std::fmt;
use std::path::Path;

/// A problem with a user file, printed as one line:
/// `FILE: FIELD = VALUE: what is allowed`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct InputError {
    /// The file the input came from.
    pub file: String,
    /// Dotted field path (`geometry.width_ratio`), or a location such as `line 4`.
    pub field: String,
    /// The offending value as written (empty when missing).
    pub value: String,
    /// What is allowed.
    pub expected: String,
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
            value: value.to_string(),
            expected: expected.into(),
        }
    }

    /// A required field that is absent.
    pub fn missing(file: &Path, field: &str, expected: &str) -> Self {
        InputError {
            file: file.display().to_string(),
            field: field.to_string(),
            value: String::new(),
            expected: format!("missing; required: {expected}"),
        }
    }

    /// The file could not be read.
    pub fn io(file: &Path, err: &std::io::Error) -> Self {
        InputError {
            file: file.display().to_string(),
            field: String::new(),
            value: String::new(),
            expected: format!("cannot read the file: {err}"),
        }
    }

    /// A syntax error at a line.
    pub fn syntax(file: &Path, line: usize, message: &str) -> Self {
        InputError {
            file: file.display().to_string(),
            field: format!("line {line}"),
            value: String::new(),
            expected: format!("not valid TOML: {}", message.replace('\n', " ")),
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
