//! A checked reader over one TOML table: typed getters that validate and record which keys were read, and
//! a final check that refuses any key nobody asked for.

use super::{InputError, Range};
use std::cell::RefCell;
use std::collections::BTreeSet;
use std::path::Path;
use toml::{Table, Value};

/// Reads fields of one table; `finish` reports the first unknown key.
pub struct TableReader<'a> {
    file: &'a Path,
    prefix: String,
    table: &'a Table,
    used: RefCell<BTreeSet<String>>,
}

impl<'a> TableReader<'a> {
    /// A reader over `table`, whose fields are named `prefix.key` in errors (prefix "" for the root).
    pub fn new(file: &'a Path, prefix: &str, table: &'a Table) -> Self {
        TableReader {
            file,
            prefix: prefix.to_string(),
            table,
            used: RefCell::new(BTreeSet::new()),
        }
    }

    /// The file being read.
    pub fn file(&self) -> &'a Path {
        self.file
    }

    /// Dotted path of a key.
    pub fn path(&self, key: &str) -> String {
        if self.prefix.is_empty() {
            key.to_string()
        } else {
            format!("{}.{key}", self.prefix)
        }
    }

    /// This table's own dotted path, or `root` for the root table.
    pub fn prefix_or(&self, root: &str) -> String {
        if self.prefix.is_empty() {
            root.to_string()
        } else {
            self.prefix.clone()
        }
    }

    fn get(&self, key: &str) -> Option<&'a Value> {
        self.used.borrow_mut().insert(key.to_string());
        self.table.get(key)
    }

    /// True if the key is present (and marks it as known).
    pub fn has(&self, key: &str) -> bool {
        self.get(key).is_some()
    }

    fn number(&self, key: &str, value: &Value, range: &Range) -> Result<f64, InputError> {
        let x = match value {
            Value::Float(x) => *x,
            Value::Integer(i) => *i as f64,
            other => {
                return Err(InputError::invalid(
                    self.file,
                    &self.path(key),
                    other,
                    format!("expected a number, {range}"),
                ))
            }
        };
        if range.contains(x) {
            Ok(x)
        } else {
            Err(InputError::invalid(
                self.file,
                &self.path(key),
                x,
                format!("outside the {range}"),
            ))
        }
    }

    /// A required number in a range.
    pub fn number_in(&self, key: &str, range: Range) -> Result<f64, InputError> {
        match self.get(key) {
            Some(v) => self.number(key, v, &range),
            None => Err(self.missing(key, &format!("a number, {range}"))),
        }
    }

    /// An optional number in a range.
    pub fn optional_number_in(&self, key: &str, range: Range) -> Result<Option<f64>, InputError> {
        self.get(key)
            .map(|v| self.number(key, v, &range))
            .transpose()
    }

    /// An optional whole number in `[lo, hi]`.
    pub fn optional_count(&self, key: &str, lo: i64, hi: i64) -> Result<Option<usize>, InputError> {
        match self.get(key) {
            None => Ok(None),
            Some(Value::Integer(i)) if (lo..=hi).contains(i) => Ok(Some(*i as usize)),
            Some(v) => Err(InputError::invalid(
                self.file,
                &self.path(key),
                v,
                format!("expected a whole number in [{lo}, {hi}]"),
            )),
        }
    }

    /// A required whole number in `[lo, hi]`.
    pub fn count(&self, key: &str, lo: i64, hi: i64) -> Result<usize, InputError> {
        self.optional_count(key, lo, hi)?
            .ok_or_else(|| self.missing(key, &format!("a whole number in [{lo}, {hi}]")))
    }

    /// A required span `[min, max]` of numbers in `range`, or one number for a fixed value (`min == max`).
    pub fn span_in(&self, key: &str, range: Range) -> Result<(f64, f64), InputError> {
        let expected = format!("expected a number or [min, max], each in the {range}");
        let field = self.path(key);
        let value = self
            .get(key)
            .ok_or_else(|| self.missing(key, &expected["expected ".len()..]))?;
        let bad =
            |why: &str| InputError::invalid(self.file, &field, value, format!("{why}{expected}"));
        let (lo, hi) = match value {
            Value::Float(_) | Value::Integer(_) => {
                let x = self.number(key, value, &range)?;
                (x, x)
            }
            Value::Array(items) if items.is_empty() => return Err(bad("the range is empty; ")),
            Value::Array(items) if items.len() == 2 => {
                let lo = self.number(&format!("{key}[0]"), &items[0], &range)?;
                let hi = self.number(&format!("{key}[1]"), &items[1], &range)?;
                (lo, hi)
            }
            _ => return Err(bad("")),
        };
        if lo > hi {
            return Err(bad("inverted range: min > max; "));
        }
        Ok((lo, hi))
    }

    /// A required array of `min_len..=max_len` arrays, each of `1..=inner_max` numbers in `range`
    /// (layups: a list of ply-angle lists).
    pub fn number_lists_in(
        &self,
        key: &str,
        range: Range,
        (min_len, max_len): (usize, usize),
        inner_max: usize,
    ) -> Result<Vec<Vec<f64>>, InputError> {
        let expected = format!(
            "an array of {min_len} to {max_len} arrays of 1 to {inner_max} numbers, each in the {range}"
        );
        match self.get(key) {
            Some(Value::Array(lists)) if (min_len..=max_len).contains(&lists.len()) => lists
                .iter()
                .enumerate()
                .map(|(i, list)| match list {
                    Value::Array(items) if (1..=inner_max).contains(&items.len()) => items
                        .iter()
                        .enumerate()
                        .map(|(j, v)| self.number(&format!("{key}[{i}][{j}]"), v, &range))
                        .collect(),
                    other => Err(InputError::invalid(
                        self.file,
                        &self.path(&format!("{key}[{i}]")),
                        other,
                        format!(
                            "expected an array of 1 to {inner_max} numbers, each in the {range}"
                        ),
                    )),
                })
                .collect(),
            Some(v) => Err(InputError::invalid(
                self.file,
                &self.path(key),
                v,
                format!("expected {expected}"),
            )),
            None => Err(self.missing(key, &expected)),
        }
    }

    /// An optional array of numbers (see [`TableReader::numbers_in`]).
    pub fn optional_numbers_in(
        &self,
        key: &str,
        range: Range,
        min_len: usize,
        max_len: usize,
    ) -> Result<Option<Vec<f64>>, InputError> {
        if self.table.contains_key(key) {
            self.numbers_in(key, range, min_len, max_len).map(Some)
        } else {
            self.used.borrow_mut().insert(key.to_string());
            Ok(None)
        }
    }

    /// Refuse at once any key outside `known`: used where a misspelt table would otherwise be reported
    /// as a missing one.
    pub fn only_keys(&self, known: &[&str]) -> Result<(), InputError> {
        if let Some(key) = self.table.keys().find(|k| !known.contains(&k.as_str())) {
            return Err(self.unknown_key(key, known));
        }
        Ok(())
    }

    fn unknown_key(&self, key: &str, known: &[&str]) -> InputError {
        let value = match &self.table[key] {
            Value::Table(_) => "(table)".to_string(),
            v => v.to_string(),
        };
        let hint = match nearest(key, known.iter().copied()) {
            Some(near) => format!("unknown key; did you mean `{near}`? known keys here: "),
            None => "unknown key; known keys here: ".to_string(),
        };
        InputError::invalid(
            self.file,
            &self.path(key),
            value,
            format!("{hint}{}", known.join(", ")),
        )
    }

    /// A required `key` is absent. If the table holds a key nobody asked for that is a near miss of it
    /// (`length_m`, `Width_ratio`), that key is what the user wrote: it is named, with `key` as the
    /// "did you mean".
    fn missing(&self, key: &str, expected: &str) -> InputError {
        self.missing_one_of(&[key], expected)
    }

    /// None of `keys`, a group of which one is required, is present. The unasked key nearest to any of
    /// them is what the user wrote (`sapn_mm` for `span_mm`): it is named as written, with the key it
    /// misses. The nearest wins, so a valid key that has not been read yet (`window_height_mm`) is not
    /// blamed for a typo of its neighbour (`windoww_idth_mm`).
    pub fn missing_one_of(&self, keys: &[&str], expected: &str) -> InputError {
        let used = self.used.borrow();
        let typo = self
            .table
            .keys()
            .map(String::as_str)
            .filter(|k| !used.contains(*k))
            .filter_map(|k| nearest_with_distance(k, keys.iter().copied()).map(|(d, m)| (d, k, m)))
            .min_by_key(|(d, _, _)| *d);
        if let Some((_, typo, meant)) = typo {
            let value = match &self.table[typo] {
                Value::Table(_) => "(table)".to_string(),
                v => v.to_string(),
            };
            return InputError::invalid(
                self.file,
                &self.path(typo),
                value,
                format!("unknown key; did you mean `{meant}`? ({expected})"),
            );
        }
        InputError::missing(self.file, &self.path(keys[0]), expected)
    }

    /// An optional `true` / `false`.
    pub fn optional_bool(&self, key: &str) -> Result<Option<bool>, InputError> {
        match self.get(key) {
            None => Ok(None),
            Some(Value::Boolean(b)) => Ok(Some(*b)),
            Some(v) => Err(InputError::invalid(
                self.file,
                &self.path(key),
                v,
                "expected true or false",
            )),
        }
    }

    /// Text a user wrote, which reaches a terminal, a report or a drawing: a control character (a line
    /// break, a tab, an escape sequence) would break the line it is printed on, or drive the terminal.
    fn printable(&self, key: &str, text: &'a str) -> Result<&'a str, InputError> {
        if text.chars().any(char::is_control) {
            return Err(InputError::invalid(
                self.file,
                &self.path(key),
                format!("{text:?}"),
                "expected printable text: no control characters (tabs, line breaks, \\u0001, …)",
            ));
        }
        Ok(text)
    }

    /// A required string, printable ([`TableReader::printable`]).
    pub fn string(&self, key: &str, expected: &str) -> Result<&'a str, InputError> {
        match self.get(key) {
            Some(Value::String(s)) => self.printable(key, s),
            Some(v) => Err(InputError::invalid(
                self.file,
                &self.path(key),
                v,
                format!("expected {expected}"),
            )),
            None => Err(self.missing(key, expected)),
        }
    }

    /// An optional string, printable.
    pub fn optional_string(
        &self,
        key: &str,
        expected: &str,
    ) -> Result<Option<&'a str>, InputError> {
        match self.get(key) {
            None => Ok(None),
            Some(Value::String(s)) => self.printable(key, s).map(Some),
            Some(v) => Err(InputError::invalid(
                self.file,
                &self.path(key),
                v,
                format!("expected {expected}"),
            )),
        }
    }

    /// A required array of numbers, each in `range`, with `min_len..=max_len` entries.
    pub fn numbers_in(
        &self,
        key: &str,
        range: Range,
        min_len: usize,
        max_len: usize,
    ) -> Result<Vec<f64>, InputError> {
        let expected = format!("an array of {min_len} to {max_len} numbers, each in the {range}");
        match self.get(key) {
            Some(Value::Array(items)) if (min_len..=max_len).contains(&items.len()) => items
                .iter()
                .enumerate()
                .map(|(i, v)| self.number(&format!("{key}[{i}]"), v, &range))
                .collect(),
            Some(v) => Err(InputError::invalid(self.file, &self.path(key), v, expected)),
            None => Err(self.missing(key, &expected)),
        }
    }

    /// An optional number, or an array of exactly `len` numbers, each in `range` (one value standing for
    /// all `len`, as the caller reads it).
    pub fn optional_number_or_numbers_in(
        &self,
        key: &str,
        range: Range,
        len: usize,
    ) -> Result<Option<Vec<f64>>, InputError> {
        match self.get(key) {
            None => Ok(None),
            Some(Value::Array(_)) => self.numbers_in(key, range, len, len).map(Some),
            Some(_) => self.number_in(key, range).map(|x| Some(vec![x])),
        }
    }

    /// A required array of printable strings.
    pub fn strings(&self, key: &str, expected: &str) -> Result<Vec<String>, InputError> {
        match self.get(key) {
            Some(Value::Array(items)) => items
                .iter()
                .enumerate()
                .map(|(i, v)| {
                    let item = format!("{key}[{i}]");
                    match v.as_str() {
                        Some(s) => self.printable(&item, s).map(str::to_string),
                        None => Err(InputError::invalid(
                            self.file,
                            &self.path(&item),
                            v,
                            format!("expected {expected}"),
                        )),
                    }
                })
                .collect(),
            Some(v) => Err(InputError::invalid(
                self.file,
                &self.path(key),
                v,
                format!("expected {expected}"),
            )),
            None => Err(self.missing(key, expected)),
        }
    }

    /// A required sub-table.
    pub fn table(&self, key: &str) -> Result<TableReader<'a>, InputError> {
        match self.get(key) {
            Some(Value::Table(t)) => Ok(TableReader::new(self.file, &self.path(key), t)),
            Some(v) => Err(InputError::invalid(
                self.file,
                &self.path(key),
                v,
                "expected a table",
            )),
            None => Err(self.missing(key, &format!("a [{}] table", self.path(key)))),
        }
    }

    /// An optional sub-table.
    pub fn optional_table(&self, key: &str) -> Result<Option<TableReader<'a>>, InputError> {
        match self.get(key) {
            None => Ok(None),
            Some(Value::Table(t)) => Ok(Some(TableReader::new(self.file, &self.path(key), t))),
            Some(v) => Err(InputError::invalid(
                self.file,
                &self.path(key),
                v,
                "expected a table",
            )),
        }
    }

    /// A required name: text of 1 to 64 characters, not only blanks, and no control characters (labels,
    /// titles, SVG text and DXF entries show it; a control character is not well-formed XML and ends a
    /// DXF value).
    pub fn name(&self, key: &str, expected: &str) -> Result<String, InputError> {
        let name = self.string(key, expected)?;
        if name.trim().is_empty() || name.len() > 64 {
            return Err(InputError::invalid(
                self.file,
                &self.path(key),
                format!("{name:?}"),
                "expected 1 to 64 characters",
            ));
        }
        Ok(name.to_string())
    }

    /// A required, non-empty array of tables (`[[key]]`), each named `key[i]` in errors.
    pub fn tables(&self, key: &str) -> Result<Vec<TableReader<'a>>, InputError> {
        match self.get(key) {
            Some(Value::Array(items)) if !items.is_empty() => items
                .iter()
                .enumerate()
                .map(|(i, v)| match v {
                    Value::Table(t) => Ok(TableReader::new(
                        self.file,
                        &format!("{}[{}]", self.path(key), i + 1),
                        t,
                    )),
                    other => Err(InputError::invalid(
                        self.file,
                        &format!("{}[{}]", self.path(key), i + 1),
                        other,
                        "expected a table",
                    )),
                })
                .collect(),
            Some(v) => Err(InputError::invalid(
                self.file,
                &self.path(key),
                v,
                format!("expected one or more [[{}]] tables", self.path(key)),
            )),
            None => Err(self.missing(key, &format!("one or more [[{}]] tables", self.path(key)))),
        }
    }

    /// Keys of this table, sorted.
    pub fn keys(&self) -> Vec<&'a str> {
        self.table.keys().map(String::as_str).collect()
    }

    /// Refuse any key that no getter asked for: a typo must not be silently ignored.
    pub fn finish(&self) -> Result<(), InputError> {
        let used = self.used.borrow();
        if let Some(key) = self.table.keys().find(|k| !used.contains(*k)) {
            let known: Vec<&str> = used.iter().map(String::as_str).collect();
            return Err(self.unknown_key(key, &known));
        }
        Ok(())
    }
}

/// The known key closest to `key` by edit distance (letter case ignored), if it is close enough to be a
/// typo of it: at most a third of its letters changed.
pub fn nearest<'k>(key: &str, known: impl Iterator<Item = &'k str>) -> Option<&'k str> {
    nearest_with_distance(key, known).map(|(_, k)| k)
}

/// [`nearest`] with its edit distance.
fn nearest_with_distance<'k>(
    key: &str,
    known: impl Iterator<Item = &'k str>,
) -> Option<(usize, &'k str)> {
    let key = key.to_lowercase();
    known
        .map(|k| (edit_distance(&key, &k.to_lowercase()), k))
        .filter(|(d, k)| *d <= (k.chars().count() / 3).max(1))
        .min_by_key(|(d, _)| *d)
}

/// Optimal-string-alignment distance: insertions, deletions and substitutions of one character, and
/// swaps of two neighbours, each one edit. The swap matters for short keys: `omde` is one edit from
/// `mode`, where plain Levenshtein counts two, more than a four-letter key's typo allowance.
fn edit_distance(a: &str, b: &str) -> usize {
    let a: Vec<char> = a.chars().collect();
    let b: Vec<char> = b.chars().collect();
    // Three rows: the one before last is needed for the swap.
    let mut before: Vec<usize> = vec![0; b.len() + 1];
    let mut last: Vec<usize> = (0..=b.len()).collect();
    for i in 1..=a.len() {
        let mut row = vec![i; b.len() + 1];
        for j in 1..=b.len() {
            let cost = usize::from(a[i - 1] != b[j - 1]);
            let mut d = (last[j] + 1).min(row[j - 1] + 1).min(last[j - 1] + cost);
            if i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] {
                d = d.min(before[j - 2] + 1);
            }
            row[j] = d;
        }
        before = std::mem::replace(&mut last, row);
    }
    last[b.len()]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table(text: &str) -> Table {
        text.parse().unwrap()
    }

    #[test]
    fn a_misspelt_key_is_named_with_the_key_it_misses() {
        let f = Path::new("d.toml");
        for (text, typo, meant) in [
            ("length_m = 40\nwidth_ratio = 1", "length_m", "length_mm"),
            (
                "length_mm = 40\nWidth_ratio = 1",
                "Width_ratio",
                "width_ratio",
            ),
        ] {
            let t = table(text);
            let r = TableReader::new(f, "geometry", &t);
            let e = r
                .number_in("length_mm", Range::closed(1.0, 1000.0, "mm"))
                .and_then(|_| r.number_in("width_ratio", Range::closed(0.25, 2.0, "")))
                .unwrap_err()
                .to_string();
            assert!(
                e.starts_with(&format!("d.toml: geometry.{typo} = "))
                    && e.contains(&format!("did you mean `{meant}`")),
                "{e}"
            );
        }
        // An optional key misspelt is caught by finish, with the nearest known key.
        let t = table("survivl = 0.9\nvoltage_V = 100");
        let r = TableReader::new(f, "drive", &t);
        r.optional_number_in("survival", Range::open(0.0, 1.0, ""))
            .unwrap();
        r.optional_number_in("voltage_V", Range::closed(0.0, 1e5, "V"))
            .unwrap();
        let e = r.finish().unwrap_err().to_string();
        assert!(
            e.contains("drive.survivl = 0.9: unknown key; did you mean `survival`?"),
            "{e}"
        );
        // Nothing near: no guess.
        assert_eq!(
            nearest("colour", ["length_mm", "width_ratio"].into_iter()),
            None
        );
        assert_eq!(edit_distance("kitten", "sitting"), 3);
        assert_eq!(edit_distance("omde", "mode"), 1);
        assert_eq!(edit_distance("ca", "abc"), 3);
    }

    #[test]
    fn short_keys_with_two_letters_swapped_are_named() {
        let f = Path::new("d.toml");
        for (typo, meant) in [
            ("omde", "mode"),
            ("ifle", "file"),
            ("chrod", "chord"),
            ("nmae", "name"),
            ("kidn", "kind"),
            ("stakc", "stack"),
        ] {
            let t = table(&format!("{typo} = \"x\""));
            let r = TableReader::new(f, "t", &t);
            let e = r.string(meant, "text").unwrap_err().to_string();
            assert!(
                e.starts_with(&format!("d.toml: t.{typo} = ")) && e.contains(&format!("`{meant}`")),
                "{e}"
            );
        }
    }

    #[test]
    fn a_group_of_which_one_is_required_names_the_misspelt_member() {
        let f = Path::new("d.toml");
        let t = table("field_V_pe_rmm = 100");
        let r = TableReader::new(f, "drive", &t);
        assert!(!r.has("field_V_per_mm") && !r.has("voltage_V"));
        let e = r
            .missing_one_of(&["field_V_per_mm", "voltage_V"], "exactly one of …")
            .to_string();
        assert!(
            e.starts_with(
                "d.toml: drive.field_V_pe_rmm = 100: unknown key; did you mean `field_V_per_mm`?"
            ),
            "{e}"
        );
    }

    #[test]
    fn the_nearest_unasked_key_is_blamed_not_a_valid_neighbour() {
        let f = Path::new("t.toml");
        let t = table("window_height_mm = 1\nwindoww_idth_mm = 2");
        let r = TableReader::new(f, "sheet", &t);
        let e = r
            .number_in("window_width_mm", Range::closed(0.0, 10.0, "mm"))
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with(
                "t.toml: sheet.windoww_idth_mm = 2: unknown key; did you mean `window_width_mm`?"
            ),
            "{e}"
        );
    }
}
