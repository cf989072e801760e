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

/// Squeeze any line breaks out of a message part, so that the error stays on one line; a number written
/// out at length (`1e300` printed by `{}` has 301 digits) is put in its [`short_number`] form.
fn one_line(text: &str) -> String {
    text.split(['\n', '\r'])
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .collect::<Vec<_>>()
        .join(" ")
        .split(' ')
        .map(shorten_word)
        .collect::<Vec<_>>()
        .join(" ")
}

/// Characters of a value an error prints: a header that swallowed the whole file (an unclosed quote)
/// is cut, so the message stays a line a terminal shows.
const MAX_VALUE_CHARS: usize = 300;

/// `text` cut to `max` characters, with `…` where it was cut.
fn at_most(text: String, max: usize) -> String {
    match text.char_indices().nth(max) {
        Some((end, _)) => format!("{}…", &text[..end]),
        None => text,
    }
}

/// A word that is a long number becomes its short form; anything else is kept as written.
fn shorten_word(word: &str) -> String {
    // Trailing punctuation (`1e300,` or `1e300:`) stays outside the number.
    let body = word.trim_end_matches([',', ':', ';', ')', ']']);
    if body.len() <= 12 {
        return word.to_string();
    }
    match body.parse::<f64>() {
        Ok(x) => format!("{}{}", short_number(x), &word[body.len()..]),
        Err(_) => word.to_string(),
    }
}

/// `x` with `decimals` decimals, or its short form when that would be long.
pub fn fixed(x: f64, decimals: usize) -> String {
    if x.is_finite() && x.abs() < 1e9 {
        format!("{x:.decimals$}")
    } else {
        short_number(x)
    }
}

/// A number as error messages print it: plain when it reads well (`42.2`, `0.0003`), otherwise in
/// scientific form with at most 6 significant digits (`1e300`, `1.23457e-300`), so that an absurd value
/// never fills the terminal. Every [`InputError`] passes its value and message through this.
pub fn short_number(x: f64) -> String {
    if !x.is_finite() {
        return x.to_string();
    }
    let plain = x.to_string();
    if plain.len() <= 12 && (x == 0.0 || x.abs() >= 1e-4) {
        return plain;
    }
    if (1e-4..1e6).contains(&x.abs()) {
        // Six significant digits in plain form: 0.30000000000000004 -> 0.3.
        let decimals = (5 - x.abs().log10().floor() as i32).max(0) as usize;
        let fixed = format!("{x:.decimals$}");
        let fixed = if fixed.contains('.') {
            fixed.trim_end_matches('0').trim_end_matches('.')
        } else {
            &fixed
        };
        return fixed.to_string();
    }
    let sci = format!("{x:.5e}");
    // Drop the trailing zeros of the mantissa: 1.00000e300 -> 1e300.
    match sci.split_once('e') {
        Some((mantissa, exp)) if mantissa.contains('.') => {
            let m = mantissa.trim_end_matches('0').trim_end_matches('.');
            format!("{m}e{exp}")
        }
        _ => sci,
    }
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
            value: at_most(one_line(&value.to_string()), MAX_VALUE_CHARS),
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

/// `text` with every control character written as an escape (`\u{1b}`): a file name, a key or a
/// value the user wrote reaches the terminal as text, never as a line break or an escape sequence.
fn escaped(text: &str) -> std::borrow::Cow<'_, str> {
    if !text.chars().any(char::is_control) {
        return text.into();
    }
    text.chars()
        .map(|c| {
            if c.is_control() {
                format!("\\u{{{:x}}}", c as u32)
            } else {
                c.to_string()
            }
        })
        .collect::<String>()
        .into()
}

impl fmt::Display for InputError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (file, field) = (escaped(&self.file), escaped(&self.field));
        let (value, expected) = (escaped(&self.value), escaped(&self.expected));
        match (field.is_empty(), value.is_empty()) {
            (true, _) => write!(f, "{file}: {expected}"),
            (false, true) => write!(f, "{file}: {field}: {expected}"),
            (false, false) => write!(f, "{file}: {field} = {value}: {expected}"),
        }
    }
}

impl std::error::Error for InputError {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn control_characters_a_user_wrote_are_printed_as_escapes() {
        let e = InputError::invalid(
            Path::new("a\u{1b}[2J.toml"),
            "effect[1].\u{7}key",
            "\"x\u{1b}y\"",
            "expected \t text",
        )
        .to_string();
        assert!(!e.chars().any(char::is_control), "{e:?}");
        assert_eq!(
            e,
            "a\\u{1b}[2J.toml: effect[1].\\u{7}key = \"x\\u{1b}y\": expected \\u{9} text"
        );
    }

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

    #[test]
    fn long_numbers_print_short() {
        assert_eq!(short_number(1e300), "1e300");
        assert_eq!(short_number(-1e-300), "-1e-300");
        assert_eq!(short_number(1.234567891e-7), "1.23457e-7");
        assert_eq!(short_number(42.2), "42.2");
        assert_eq!(short_number(0.0003), "0.0003");
        assert_eq!(short_number(1e-9), "1e-9");
        assert_eq!(short_number(0.1 + 0.2), "0.3");
        assert_eq!(short_number(123456.789012), "123457");
        assert_eq!(short_number(f64::NAN), "NaN");
        let e = InputError::invalid(Path::new("d.toml"), "geometry.length_mm", 1e300, "too long");
        assert_eq!(
            e.to_string(),
            "d.toml: geometry.length_mm = 1e300: too long"
        );
        let e = InputError::invalid(
            Path::new("d.toml"),
            "drive.voltage_V",
            1,
            format!("gives a plate field of {} V/mm, outside", 1e303),
        );
        assert_eq!(
            e.to_string(),
            "d.toml: drive.voltage_V = 1: gives a plate field of 1e303 V/mm, outside"
        );
        // Text that is not a number is kept, however long.
        let e = InputError::invalid(Path::new("d.toml"), "name", "\"abcdefghijklmnopq\"", "x");
        assert!(e.to_string().contains("abcdefghijklmnopq"));
    }

    #[test]
    fn a_value_that_swallowed_the_file_is_cut() {
        // An unclosed quote in a CSV header makes every later line part of it.
        let header = format!("\"id,{}", "A0,29.7,0.07,6.1\n".repeat(400));
        let e = InputError::invalid(Path::new("m.csv"), "header", &header, "missing column `id`");
        let text = e.to_string();
        assert_eq!(text.lines().count(), 1);
        assert!(
            text.len() < 400 && text.contains("…: missing column `id`"),
            "{text}"
        );
    }
}
