//! Property tests over every input parser: design, process template, batch, optimize spec, sweep factors,
//! measured-data CSV and failure CSV. Each case mutates a shipped example (a number swapped for an extreme
//! one, a value of the wrong type, a key renamed, dropped or repeated, a line of garbage) and checks that
//! the parser never panics, and that every refusal is one line naming the file and a field (or a line and a
//! column). Accepted designs must predict finite numbers: the ranges of `input::limits` and the
//! derived-geometry checks exist so that no `NaN` reaches an output.
//!
//! The library parsers are called directly (fast); `tests/predict.rs` and `tests/sweep.rs` drive the binary
//! on the absurd values and repeated levels. Case counts per parser are fixed here and stated in the README.

use actuator_cam::{
    parse_measured_file, parse_toml, read_failure_column as read_column, Batch, Design, InputError,
    OptimizeSpec as Spec, Prediction, SweepSpec, Template,
};
use actuator_model::model::ModelKind;
use proptest::prelude::*;
use std::path::{Path, PathBuf};

fn root(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(rel)
}

fn read(rel: &str) -> String {
    std::fs::read_to_string(root(rel)).unwrap()
}

/// The only refusals that may name no field: problems of the file as a whole.
const WHOLE_FILE: [&str; 3] = [
    "the file has no data rows",
    "cannot read the file",
    "not valid CSV",
];

/// A refusal names the file and a field (or a line and a column), and prints on one line.
fn names_file_and_field(e: &InputError, file: &Path) -> Result<(), TestCaseError> {
    let text = e.to_string();
    prop_assert_eq!(&e.file, &file.display().to_string(), "{}", text);
    prop_assert!(
        !e.field.is_empty() || WHOLE_FILE.iter().any(|w| e.expected.starts_with(w)),
        "no field named: {}",
        text
    );
    prop_assert!(!e.expected.is_empty(), "{}", text);
    prop_assert_eq!(text.lines().count(), 1, "{}", text);
    // Numbers are printed short (1e300 is not 300 digits).
    prop_assert!(text.len() < 1200, "{}", text);
    Ok(())
}

/// A value as TOML writes it, from a mix of ordinary, extreme and non-finite numbers.
fn toml_number() -> impl Strategy<Value = String> {
    prop_oneof![
        (-1000.0f64..1000.0).prop_map(|x| format!("{x:?}")),
        (0.0f64..3.0).prop_map(|x| format!("{x:?}")),
        any::<f64>().prop_map(|x| if x.is_finite() {
            format!("{x:?}")
        } else {
            "nan".into()
        }),
        prop::sample::select(vec![
            "1e-300",
            "-1e-300",
            "1e300",
            "-1e300",
            "0",
            "0.0",
            "-0.0",
            "nan",
            "inf",
            "-inf",
            "1",
            "2",
            "-1",
            "9223372036854775807",
            "-9223372036854775808",
            "0.01",
            "1.99",
            "1.9999",
        ])
        .prop_map(str::to_string),
    ]
}

/// Any TOML value, mostly numbers.
fn toml_value() -> impl Strategy<Value = String> {
    prop_oneof![
        6 => toml_number(),
        1 => "\"[a-zA-Z0-9 ./-]{0,12}\"".prop_map(|s| s),
        1 => prop::collection::vec(toml_number(), 0..4).prop_map(|v| format!("[{}]", v.join(", "))),
        1 => Just("{ }".to_string()),
        1 => Just("true".to_string()),
        1 => Just("[[0, 90], []]".to_string()),
    ]
}

/// One edit of a TOML text, on the line picked by the index (modulo the line count).
#[derive(Debug, Clone)]
enum Edit {
    /// Replace the value of a `key = value` line.
    Value(usize, String),
    /// Drop the line.
    Drop(usize),
    /// Write the line twice (a repeated key).
    Repeat(usize),
    /// Rename the key (a typo).
    Rename(usize),
    /// Insert a line of printable noise.
    Noise(usize, String),
}

fn edit() -> impl Strategy<Value = Edit> {
    prop_oneof![
        8 => (any::<usize>(), toml_value()).prop_map(|(i, v)| Edit::Value(i, v)),
        1 => any::<usize>().prop_map(Edit::Drop),
        1 => any::<usize>().prop_map(Edit::Repeat),
        1 => any::<usize>().prop_map(Edit::Rename),
        1 => (any::<usize>(), "[ -~]{0,20}").prop_map(|(i, s)| Edit::Noise(i, s)),
    ]
}

/// Apply edits to the text (comments stripped first, so that edits land on content).
fn mutate(text: &str, edits: &[Edit]) -> String {
    let mut lines: Vec<String> = text
        .lines()
        .map(|l| l.split(" #").next().unwrap_or("").to_string())
        .filter(|l| !l.trim().is_empty() && !l.starts_with('#'))
        .collect();
    for e in edits {
        let n = lines.len().max(1);
        match e {
            Edit::Value(i, v) => {
                // Pick the i-th `key = value` line.
                let keyed: Vec<usize> = (0..lines.len())
                    .filter(|&k| lines[k].contains(" = "))
                    .collect();
                if let Some(&k) = keyed.get(i % keyed.len().max(1)) {
                    let key = lines[k].split(" = ").next().unwrap().to_string();
                    lines[k] = format!("{key} = {v}");
                }
            }
            Edit::Drop(i) if !lines.is_empty() => {
                lines.remove(i % n);
            }
            Edit::Repeat(i) if !lines.is_empty() => {
                let l = lines[i % n].clone();
                lines.insert(i % n, l);
            }
            Edit::Rename(i) if !lines.is_empty() => {
                let l = &mut lines[i % n];
                if let Some(pos) = l.find(" = ") {
                    l.insert(pos, 'x');
                }
            }
            Edit::Noise(i, s) => lines.insert(i % n, s.clone()),
            _ => {}
        }
    }
    lines.join("\n") + "\n"
}

/// Parse a TOML text with `parse`, checking the refusal (if any); returns the accepted value.
fn check_toml<T>(
    file: &Path,
    text: &str,
    parse: impl Fn(&Path, &toml::Table) -> Result<T, InputError>,
) -> Result<Option<T>, TestCaseError> {
    let result = parse_toml(file, text).and_then(|t| parse(file, &t));
    match result {
        Ok(v) => Ok(Some(v)),
        Err(e) => {
            names_file_and_field(&e, file)?;
            Ok(None)
        }
    }
}

/// Every number a prediction prints is finite (no `NaN`, no `null` in `--json`).
fn predicts_finite(design: &Design) -> Result<(), TestCaseError> {
    for kind in [ModelKind::Original, ModelKind::ThesisAdjusted] {
        match Prediction::of(design, kind) {
            Ok(p) => {
                let r = p.ensure_finite(design);
                prop_assert!(r.is_ok(), "{:?}: {}", design.planform, r.unwrap_err());
            }
            Err(e) => prop_assert!(false, "accepted design not predicted: {e}: {design:?}"),
        }
    }
    Ok(())
}

/// A fixed number of cases, nothing persisted (CI runs from a clean tree).
fn config(cases: u32) -> ProptestConfig {
    ProptestConfig {
        cases,
        failure_persistence: None,
        ..ProptestConfig::default()
    }
}

const DESIGN_CASES: u32 = 512;
/// Process templates, optimize specs and sweep factors, each.
const SPEC_CASES: u32 = 256;
const CSV_CASES: u32 = 512;
const BATCH_CASES: u32 = 64;
const WEIBULL_CASES: u32 = 64;
const RANGE_CASES: u32 = 1024;

proptest! {
    #![proptest_config(config(DESIGN_CASES))]
    #[test]
    fn design_files(example in prop::sample::select(vec![
        "examples/thesis-C.toml", "examples/thesis-A.toml", "examples/thesis-C-method-1.toml",
    ]), edits in prop::collection::vec(edit(), 1..4)) {
        let file = Path::new("d.toml");
        let text = mutate(&read(example), &edits);
        if let Some(design) = check_toml(file, &text, Design::from_table)? {
            predicts_finite(&design)?;
        }
    }
}

proptest! {
    #![proptest_config(config(SPEC_CASES))]
    #[test]
    fn process_templates(example in prop::sample::select(vec![
        "templates/method-1.toml", "templates/method-2.toml",
    ]), edits in prop::collection::vec(edit(), 1..4)) {
        let text = mutate(&read(example), &edits);
        check_toml(Path::new("t.toml"), &text, Template::from_table)?;
    }

    #[test]
    fn optimize_specs(example in prop::sample::select(vec![
        "examples/optimize-thesis.toml", "examples/optimize-rectangular.toml",
    ]), edits in prop::collection::vec(edit(), 1..4)) {
        let text = mutate(&read(example), &edits);
        check_toml(Path::new("o.toml"), &text, Spec::from_table)?;
    }

    #[test]
    fn sweep_factors(example in prop::sample::select(vec![
        "examples/sweep-table-3-1.toml", "examples/sweep-table-3-2.toml", "examples/sweep-table-4-11.toml",
    ]), edits in prop::collection::vec(edit(), 1..4)) {
        let text = mutate(&read(example), &edits);
        if let Some(spec) = check_toml(Path::new("s.toml"), &text, SweepSpec::from_table)? {
            // Accepted levels are distinct (a repeated level is refused).
            for f in actuator_cam::Factor::ALL {
                let labels: Vec<String> = (0..spec.level_count(f)).map(|i| spec.level_label(f, i)).collect();
                let mut unique = labels.clone();
                unique.sort();
                unique.dedup();
                prop_assert_eq!(unique.len(), labels.len(), "{:?}", labels);
            }
        }
    }
}

/// One edit of a CSV text.
#[derive(Debug, Clone)]
enum CsvEdit {
    /// Replace the cell at (row, column), header included (row 0).
    Cell(usize, usize, String),
    /// Drop a cell of a row (a short row).
    DropCell(usize, usize),
    /// Repeat a header column (and its cells).
    RepeatColumn(usize),
    /// Drop a data row.
    DropRow(usize),
}

fn csv_cell() -> impl Strategy<Value = String> {
    prop_oneof![
        4 => toml_number(),
        1 => Just(String::new()),
        1 => "[a-z0-9_/\" ]{0,10}",
        1 => prop::sample::select(vec!["0/90/0", "0/x/0", "/", "parallel", "series", "PZT-5A", "kevlar", "mass_mg", "note"]).prop_map(str::to_string),
    ]
}

fn csv_edit() -> impl Strategy<Value = CsvEdit> {
    prop_oneof![
        8 => (any::<usize>(), any::<usize>(), csv_cell()).prop_map(|(r, c, v)| CsvEdit::Cell(r, c, v)),
        1 => (any::<usize>(), any::<usize>()).prop_map(|(r, c)| CsvEdit::DropCell(r, c)),
        1 => any::<usize>().prop_map(CsvEdit::RepeatColumn),
        1 => any::<usize>().prop_map(CsvEdit::DropRow),
    ]
}

fn mutate_csv(text: &str, edits: &[CsvEdit]) -> String {
    let mut rows: Vec<Vec<String>> = text
        .lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect();
    for e in edits {
        let n = rows.len();
        match e {
            CsvEdit::Cell(r, c, v) => {
                // Mostly data rows; the header one time in eight.
                let r = if r % 8 == 0 {
                    0
                } else {
                    1 + r % (n - 1).max(1)
                };
                if let Some(row) = rows.get_mut(r) {
                    let k = c % row.len().max(1);
                    if k < row.len() {
                        row[k] = v.replace(',', ";");
                    }
                }
            }
            CsvEdit::DropCell(r, c) => {
                let row = &mut rows[r % n];
                if !row.is_empty() {
                    let k = c % row.len();
                    row.remove(k);
                }
            }
            // A header emptied by DropCell has no column to repeat.
            CsvEdit::RepeatColumn(c) if !rows[0].is_empty() => {
                let k = c % rows[0].len();
                for row in rows.iter_mut() {
                    if k < row.len() {
                        let v = row[k].clone();
                        row.push(v);
                    }
                }
            }
            CsvEdit::DropRow(r) if n > 1 => {
                rows.remove(1 + r % (n - 1));
            }
            _ => {}
        }
    }
    rows.iter()
        .map(|r| r.join(","))
        .collect::<Vec<_>>()
        .join("\n")
        + "\n"
}

proptest! {
    #![proptest_config(config(CSV_CASES))]
    #[test]
    fn measured_csv(edits in prop::collection::vec(csv_edit(), 1..4), dynamics in any::<bool>()) {
        let file = Path::new("m.csv");
        // The first 12 rows keep each case fast; half the cases carry the dynamic columns (a first
        // resonance and a quality factor, the same for every row, so one per actuator).
        let mut header_seen = false;
        let base: String = read("examples/measured-thesis-like.csv")
            .lines()
            .take(14)
            .map(|l| {
                if !dynamics || l.starts_with('#') || l.trim().is_empty() {
                    l.to_string()
                } else if !header_seen {
                    header_seen = true;
                    format!("{l},resonance_Hz,quality_factor")
                } else {
                    format!("{l},900,60")
                }
            })
            .collect::<Vec<_>>()
            .join("\n");
        let text = mutate_csv(&base, &edits);
        match parse_measured_file(file, &text) {
            Ok(data) => {
                // Every header name is either a known column or named in the warning.
                if let Some(w) = data.unknown_columns_warning(file) {
                    prop_assert!(w.starts_with("m.csv: ignoring unknown column") && !w.contains('\n'), "{}", w);
                }
            }
            Err(e) => {
                names_file_and_field(&e, file)?;
                // A bad cell names its line and column; a repeated column names the column.
                let text = e.to_string();
                prop_assert!(e.field.starts_with("line ") || e.field.starts_with("header") || e.field.is_empty(), "{}", text);
            }
        }
    }
}

proptest! {
    #![proptest_config(config(WEIBULL_CASES))]
    #[test]
    fn failure_csv(edits in prop::collection::vec(csv_edit(), 1..4), named in any::<bool>()) {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("f.csv");
        std::fs::write(&path, mutate_csv(&read("tests/fixtures/failures.csv"), &edits)).unwrap();
        let column = named.then_some("field_V_per_mm");
        if let Err(e) = read_column(&path, column) {
            names_file_and_field(&e, &path)?;
        }
    }
}

proptest! {
    #![proptest_config(config(SPEC_CASES))]
    #[test]
    fn drive_files(example in prop::sample::select(vec![
        "examples/drive-hawkmoth.toml", "examples/drive-robobee-jafferis2016-linkage.toml",
    ]), edits in prop::collection::vec(edit(), 1..4)) {
        // A drive file names its design relative to itself: read it from the examples folder.
        let file = root(example);
        let text = mutate(&read(example), &edits);
        check_toml(&file, &text, actuator_cam::DriveSpec::from_table)?;
    }
}

proptest! {
    #![proptest_config(config(BATCH_CASES))]
    #[test]
    fn batch_files(edits in prop::collection::vec(edit(), 1..4)) {
        // The batch names designs relative to itself: copy them next to it.
        let dir = tempfile::tempdir().unwrap();
        for d in ["thesis-C.toml", "thesis-B.toml", "thesis-A.toml", "thesis-1.toml"] {
            std::fs::copy(root(&format!("examples/{d}")), dir.path().join(d)).unwrap();
        }
        let path = dir.path().join("batch.toml");
        std::fs::write(&path, mutate(&read("examples/batch.toml"), &edits)).unwrap();
        if let Err(e) = Batch::load(&path) {
            names_file_and_field(&e, &path)?;
        }
    }
}

/// A value anywhere in a field's range, its bounds included, with extra weight near the ends (where a
/// bound set too wide, such as `1e-300`, would give NaN).
fn in_range(lo: f64, hi: f64) -> impl Strategy<Value = f64> {
    prop_oneof![
        lo..=hi,
        Just(lo),
        Just(hi),
        (0.0f64..1.0).prop_map(move |u| lo + (hi - lo) * u.powi(8)),
    ]
}

proptest! {
    #![proptest_config(config(RANGE_CASES))]
    /// Every design the ranges and the geometry checks accept predicts finite numbers: the values that
    /// give NaN (length, width ratio, PZT thickness near zero) cannot be reached through any corner of
    /// the allowed ranges.
    #[test]
    fn every_accepted_design_predicts_finite_numbers(
        length in in_range(1.0, 1000.0),
        l_r in in_range(0.0, 20.0),
        w0 in in_range(0.5, 1000.0),
        w_r in in_range(0.25, 1.9999),
        tab in in_range(0.0, 1000.0),
        t_p in in_range(0.05, 2.0),
        t_ply in in_range(0.005, 5.0),
        field in in_range(1e-6, 3000.0),
        mode in prop::sample::select(vec!["parallel", "series", "simultaneous", "alternating"]),
    ) {
        let text = format!(
            "name = \"r\"\n[geometry]\nlength_mm = {length:?}\nextension_ratio = {l_r:?}\nbase_width_mm = {w0:?}\n\
             width_ratio = {w_r:?}\nbase_tab_mm = {tab:?}\n[laminate]\npzt = \"PZT-5H\"\npzt_thickness_mm = {t_p:?}\n\
             ply = \"CF-thesis\"\nply_thickness_mm = {t_ply:?}\nlayup_deg = [0, 90, 0]\n[drive]\nmode = \"{mode}\"\n\
             field_V_per_mm = {field:?}\n"
        );
        if let Some(design) = check_toml(Path::new("r.toml"), &text, Design::from_table)? {
            predicts_finite(&design)?;
        }
    }
}

/// Run the built binary from the crate root.
fn run(args: &[&str]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_actuator-cam"))
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .args(args)
        .output()
        .unwrap()
}

/// A repeated column (`mass_mg` twice, the first one used) is an error naming the file and the column;
/// unknown columns are named in one warning line and the run goes on.
#[test]
fn calibrate_refuses_a_repeated_column_and_names_unknown_ones() {
    let text = read("examples/measured-thesis-like.csv");
    let dir = tempfile::tempdir().unwrap();
    let header = text
        .lines()
        .find(|l| l.starts_with("id,"))
        .unwrap()
        .to_string();
    // mass_mg twice: the second copy's cells are the first's.
    let doubled: String = text
        .lines()
        .map(|l| {
            if l.starts_with('#') || l.trim().is_empty() {
                l.to_string()
            } else {
                let mass = l.split(',').nth(8).unwrap_or("");
                format!("{l},{mass}")
            }
        })
        .collect::<Vec<_>>()
        .join("\n");
    let path = dir.path().join("twice.csv");
    assert!(doubled.contains(&format!("{header},mass_mg")));
    std::fs::write(&path, doubled).unwrap();
    let out_dir = dir.path().join("cal");
    let o = run(&[
        "calibrate",
        path.to_str().unwrap(),
        "-o",
        out_dir.to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "accepted a repeated column");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(
        err.contains("twice.csv: header, column \"mass_mg\" = id,")
            && err
                .trim_end()
                .ends_with("the column appears twice; keep one"),
        "{err}"
    );
    assert!(!out_dir.exists());

    // Two unknown columns: one warning line naming both, then the usual run.
    let extra: String = text
        .lines()
        .map(|l| {
            if l.starts_with('#') || l.trim().is_empty() {
                l.to_string()
            } else if l.starts_with("id,") {
                format!("{l},operator,base_tab")
            } else {
                format!("{l},kb,0")
            }
        })
        .collect::<Vec<_>>()
        .join("\n");
    let path = dir.path().join("extra.csv");
    std::fs::write(&path, extra).unwrap();
    let o = run(&[
        "calibrate",
        path.to_str().unwrap(),
        "-o",
        out_dir.to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    let warnings: Vec<&str> = err.lines().filter(|l| l.starts_with("warning: ")).collect();
    assert_eq!(warnings.len(), 1, "{err}");
    assert!(
        warnings[0]
            .contains("extra.csv: ignoring unknown columns operator, base_tab; known columns: id,"),
        "{err}"
    );
    // The same data without the extra columns calibrates to the same model.
    let plain_dir = dir.path().join("plain");
    let o = run(&[
        "calibrate",
        "examples/measured-thesis-like.csv",
        "-o",
        plain_dir.to_str().unwrap(),
    ]);
    assert!(o.status.success());
    assert!(!String::from_utf8_lossy(&o.stderr).contains("warning"));
    assert_eq!(
        std::fs::read(out_dir.join("calibrated-model.toml")).unwrap(),
        std::fs::read(plain_dir.join("calibrated-model.toml")).unwrap()
    );
}

#[test]
fn the_dynamic_columns_of_the_property_cases_are_known_columns() {
    // The base of `measured_csv`'s dynamic half parses as it is, with no column ignored, so its
    // mutations exercise the resonance and quality-factor readers rather than the unknown-column path.
    let text: Vec<String> = read("examples/measured-thesis-like.csv")
        .lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
        .enumerate()
        .map(|(i, l)| {
            if i == 0 {
                format!("{l},resonance_Hz,quality_factor")
            } else {
                format!("{l},900,60")
            }
        })
        .collect();
    let file = Path::new("m.csv");
    let data = parse_measured_file(file, &(text.join("\n") + "\n")).unwrap();
    assert!(data.unknown_columns_warning(file).is_none());
    // And a resonance out of its range is refused naming the column.
    let bad = text.join("\n").replacen(",900,60", ",0,60", 1) + "\n";
    let e = parse_measured_file(file, &bad).unwrap_err().to_string();
    assert!(e.contains("resonance_Hz"), "{e}");
}
