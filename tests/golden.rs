//! Golden snapshot: every example through every command, every byte it prints and writes.
//!
//! The snapshot pins the tool's observable output, so a restructuring that should change nothing is
//! shown to change nothing. What a person can read is kept as it is, so a change shows as a diff: the
//! standard output and error of each case and every text file it writes (reports, JSON, TOML, CSV, the
//! manifest) live under `tests/golden/text/<case>/`. The layer files (SVG and DXF drawings, thousands of
//! lines of coordinates each) are pinned by their SHA-256 in `tests/golden/layers.sha256`. When a change
//! alters an output on purpose, regenerate the snapshot in the same commit and say why in the message:
//!
//! ```sh
//! GOLDEN_UPDATE=1 cargo test --release --test tests golden
//! ```
//!
//! Every case runs from the crate root with inputs given as `examples/…` paths; the scratch output
//! directory's path is replaced by `<out>` before comparing, so the snapshot does not depend on where the
//! temporary directory is.

use crate::common;

use sha2::{Digest, Sha256};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The layer files' hashes, one `case/file sha256` line each.
const LAYERS: &str = "tests/golden/layers.sha256";
/// The text outputs, one folder per case.
const TEXT: &str = "tests/golden/text";

/// One command run: a name for the snapshot and its arguments; `{out}` stands for the scratch folder.
struct Case {
    name: String,
    args: Vec<String>,
}

fn case(name: impl Into<String>, args: &[&str]) -> Case {
    Case {
        name: name.into(),
        args: args.iter().map(|a| a.to_string()).collect(),
    }
}

fn cases() -> Vec<Case> {
    let mut cases = design_cases();
    cases.extend(command_cases());
    cases
}

/// predict, cut-sheet and nest on the shipped designs and batches.
fn design_cases() -> Vec<Case> {
    let mut cases = Vec::new();
    // Every shipped design: the six thesis designs and design C by method 1.
    for d in common::THESIS_DESIGNS.iter().chain(&["thesis-C-method-1"]) {
        let file = format!("examples/{d}.toml");
        cases.push(case(format!("predict-{d}"), &["predict", &file]));
        cases.push(case(
            format!("predict-json-{d}"),
            &["predict", &file, "--json"],
        ));
        cases.push(case(
            format!("cut-sheet-{d}"),
            &["cut-sheet", &file, "-o", "{out}"],
        ));
    }
    // Euler-Bernoulli covers rectangles only: design B is one.
    for model in ["thesis-adjusted", "euler-bernoulli"] {
        cases.push(case(
            format!("predict-json-thesis-B-{model}"),
            &[
                "predict",
                "examples/thesis-B.toml",
                "--json",
                "--model",
                model,
            ],
        ));
    }
    cases.push(case(
        "cut-sheet-thesis-C-options",
        &[
            "cut-sheet",
            "examples/thesis-C.toml",
            "-o",
            "{out}",
            "--format",
            "svg",
            "--kerf-mm",
            "0.05",
            "--quantity",
            "3",
            "--stroke-mm",
            "0.1",
        ],
    ));
    cases.push(case(
        "nest-batch",
        &[
            "nest",
            "examples/batch.toml",
            "-o",
            "{out}",
            "--seed",
            "1",
            "--iterations",
            "100",
        ],
    ));
    cases.push(case(
        "nest-batch-json",
        &[
            "nest",
            "examples/batch.toml",
            "-o",
            "{out}",
            "--seed",
            "1",
            "--iterations",
            "100",
            "--json",
        ],
    ));
    cases
}

/// optimize, sweep, laminate, weibull and drive on their examples.
fn command_cases() -> Vec<Case> {
    let mut cases = Vec::new();
    for spec in ["optimize-thesis", "optimize-rectangular"] {
        let file = format!("examples/{spec}.toml");
        cases.push(case(spec, &["optimize", &file, "-o", "{out}", "--pareto"]));
    }
    cases.push(case(
        "optimize-thesis-adjusted-max-density",
        &[
            "optimize",
            "examples/optimize-thesis.toml",
            "--model",
            "thesis-adjusted",
            "--objective",
            "max-energy-density",
            "-o",
            "{out}",
        ],
    ));
    cases.push(case(
        "sweep-table-3-1",
        &[
            "sweep",
            "examples/sweep-table-3-1.toml",
            "--compare",
            "euler-bernoulli",
            "--csv",
            "{out}/designs.csv",
        ],
    ));
    cases.push(case(
        "sweep-table-3-1-eq-2-36",
        &[
            "sweep",
            "examples/sweep-table-3-1.toml",
            "--compare",
            "euler-bernoulli",
            "--thesis-eq-2-36",
        ],
    ));
    cases.push(case(
        "sweep-table-3-2",
        &[
            "sweep",
            "examples/sweep-table-3-2.toml",
            "--csv",
            "{out}/designs.csv",
        ],
    ));
    cases.push(case(
        "sweep-table-4-11",
        &[
            "sweep",
            "examples/sweep-table-4-11.toml",
            "--model",
            "thesis-adjusted",
            "--csv",
            "{out}/designs.csv",
        ],
    ));
    cases.push(case(
        "calibrate",
        &[
            "calibrate",
            "examples/measured-thesis-like.csv",
            "-o",
            "{out}",
        ],
    ));
    cases.push(case(
        "calibrate-json",
        &[
            "calibrate",
            "examples/measured-thesis-like.csv",
            "-o",
            "{out}",
            "--json",
        ],
    ));
    cases.push(case("laminate", &["laminate", "--layup", "0/90/0"]));
    cases.push(case(
        "laminate-json",
        &[
            "laminate",
            "--layup",
            "0/90/0/90",
            "--ply",
            "M60J-epoxy",
            "--pzt-thickness-mm",
            "0.127",
            "--json",
        ],
    ));
    cases.push(case("weibull", &["weibull", "tests/fixtures/failures.csv"]));
    cases.extend(drive_cases());
    cases.push(case(
        "weibull-survival",
        &[
            "weibull",
            "tests/fixtures/failures.csv",
            "--column",
            "field_V_per_mm",
            "--survival",
            "0.99,0.5",
        ],
    ));
    cases
}

/// drive on its examples, and the published vehicle under the nonlinear ceramic.
fn drive_cases() -> Vec<Case> {
    let mut cases = Vec::new();
    for wing in [
        "drive-hawkmoth",
        "drive-robobee-jafferis2016-linkage",
        "drive-robobee-jafferis2016-two-stage",
        "drive-robobee-jafferis2016",
    ] {
        let file = format!("examples/{wing}.toml");
        cases.push(case(wing, &["drive", &file, "-o", "{out}"]));
        cases.push(case(format!("{wing}-json"), &["drive", &file, "--json"]));
    }
    // The published vehicle under the ceramic the flying labs use: docs/drive.md §4 and
    // docs/validation.md §3 quote its stiffness, resonance and signal.
    cases.push(case(
        "drive-robobee-jafferis2016-nonlinear",
        &[
            "drive",
            "examples/drive-robobee-jafferis2016.toml",
            "--model",
            "nonlinear",
        ],
    ));
    cases
}

/// The calibrated model feeds back into predict, optimize and cut-sheet: run those on the model
/// file that `calibrate` wrote (its own case), so the loop's far end is pinned too.
fn calibrated_cases(model: &str) -> Vec<Case> {
    vec![
        case(
            "predict-json-thesis-C-calibrated",
            &[
                "predict",
                "examples/thesis-C.toml",
                "--json",
                "--model",
                model,
            ],
        ),
        case(
            "cut-sheet-thesis-C-calibrated",
            &[
                "cut-sheet",
                "examples/thesis-C.toml",
                "-o",
                "{out}",
                "--model",
                model,
            ],
        ),
    ]
}

fn sha256(bytes: &[u8]) -> String {
    Sha256::digest(bytes)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

/// Every file below `dir`, by path relative to it with `/` separators.
fn files_below(dir: &Path, prefix: &str, into: &mut BTreeMap<String, Vec<u8>>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries {
        let e = e.unwrap();
        let name = format!("{prefix}{}", e.file_name().to_string_lossy());
        if e.file_type().unwrap().is_dir() {
            files_below(&e.path(), &format!("{name}/"), into);
        } else {
            into.insert(name, std::fs::read(e.path()).unwrap());
        }
    }
}

/// Replace the scratch path (and its canonical form) by `<out>` so outputs do not depend on it.
fn scrub(bytes: &[u8], scratch: &[String]) -> Vec<u8> {
    match std::str::from_utf8(bytes) {
        Ok(text) => {
            let mut t = text.to_string();
            for s in scratch {
                t = t.replace(s.as_str(), "<out>");
            }
            t.into_bytes()
        }
        Err(_) => bytes.to_vec(),
    }
}

/// A layer file: a drawing the laser reads, pinned by its hash.
fn is_layer_file(name: &str) -> bool {
    name.ends_with(".svg") || name.ends_with(".dxf")
}

/// What one case gave: text outputs by `case/name` (`stdout`, `stderr` and the files written) and
/// layer-file hashes by `case/name`.
#[derive(Default)]
struct Outputs {
    text: BTreeMap<String, Vec<u8>>,
    layers: BTreeMap<String, String>,
}

/// Run one case into `into`; returns the scratch folder (kept alive for dependent cases).
fn run_case(c: &Case, also_scrub: &[String], into: &mut Outputs) -> tempfile::TempDir {
    let scratch = tempfile::tempdir().unwrap();
    let out = scratch.path().join("out");
    let out_text = out.to_string_lossy().into_owned();
    let args: Vec<String> = c
        .args
        .iter()
        .map(|a| a.replace("{out}", &out_text))
        .collect();
    if args.iter().any(|a| a.starts_with(&format!("{out_text}/"))) {
        // A command that writes a single file (sweep --csv) expects its folder to exist.
        std::fs::create_dir_all(&out).unwrap();
    }
    let o = common::bin()
        .args(&args)
        .env("RAYON_NUM_THREADS", "2")
        .output()
        .expect("the binary runs");
    let mut names = vec![out_text.clone()];
    names.extend(also_scrub.iter().cloned());
    if let Ok(canon) = out.canonicalize() {
        names.push(canon.to_string_lossy().into_owned());
    }
    // A run that refuses (a drive whose linkage cannot be built) is pinned by its exit status and its
    // one-line message, beside what it wrote before refusing.
    if !o.status.success() {
        into.text
            .insert(format!("{}/stderr", c.name), scrub(&o.stderr, &names));
        into.text.insert(
            format!("{}/exit", c.name),
            format!("{:?}\n", o.status.code()).into_bytes(),
        );
    }
    into.text
        .insert(format!("{}/stdout", c.name), scrub(&o.stdout, &names));
    into.text
        .insert(format!("{}/stderr", c.name), scrub(&o.stderr, &names));
    let mut written = BTreeMap::new();
    files_below(&out, "", &mut written);
    for (name, bytes) in &written {
        let key = format!("{}/{name}", c.name);
        let bytes = scrub(bytes, &names);
        if is_layer_file(name) {
            into.layers.insert(key, sha256(&bytes));
        } else {
            into.text.insert(key, bytes);
        }
    }
    scratch
}

/// The pinned text outputs: every file below `dir`.
fn pinned_text(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    let mut files = BTreeMap::new();
    files_below(dir, "", &mut files);
    files
}

/// The first lines where `want` and `got` differ, with a line of context, as a reader wants them.
fn text_diff(want: &[u8], got: &[u8]) -> String {
    let want = String::from_utf8_lossy(want);
    let got = String::from_utf8_lossy(got);
    let w: Vec<&str> = want.lines().collect();
    let g: Vec<&str> = got.lines().collect();
    let Some(first) = (0..w.len().max(g.len())).find(|&i| w.get(i) != g.get(i)) else {
        return "    (the same lines; the line endings differ)".to_string();
    };
    let mut out = Vec::new();
    let from = first.saturating_sub(1);
    for i in from..(first + 4).min(w.len().max(g.len())) {
        match (w.get(i), g.get(i)) {
            (Some(a), Some(b)) if a == b => out.push(format!("    {:>5}   {a}", i + 1)),
            (a, b) => {
                if let Some(a) = a {
                    out.push(format!("    {:>5} - {a}", i + 1));
                }
                if let Some(b) = b {
                    out.push(format!("    {:>5} + {b}", i + 1));
                }
            }
        }
    }
    out.join("\n")
}

/// Every difference between the snapshot and what the run gave, one entry each, text with its lines.
fn differences(
    want_text: &BTreeMap<String, Vec<u8>>,
    want_layers: &BTreeMap<String, String>,
    got: &Outputs,
) -> Vec<String> {
    let mut diff = Vec::new();
    for (k, v) in want_text {
        match got.text.get(k) {
            None => diff.push(format!("  missing now: {k}")),
            Some(g) if g != v => diff.push(format!("  changed:     {k}\n{}", text_diff(v, g))),
            _ => {}
        }
    }
    for k in got.text.keys().filter(|k| !want_text.contains_key(*k)) {
        diff.push(format!("  new:         {k}"));
    }
    for (k, v) in want_layers {
        match got.layers.get(k) {
            None => diff.push(format!("  missing now: {k}")),
            Some(g) if g != v => diff.push(format!("  changed:     {k} (layer file)")),
            _ => {}
        }
    }
    for k in got.layers.keys().filter(|k| !want_layers.contains_key(*k)) {
        diff.push(format!("  new:         {k}"));
    }
    diff
}

/// Write the snapshot anew: the text folder replaced whole (so an output no longer written goes), the
/// layer hashes rewritten.
fn update(root: &Path, got: &Outputs) {
    let text = root.join(TEXT);
    if text.exists() {
        std::fs::remove_dir_all(&text).unwrap();
    }
    for (k, v) in &got.text {
        let path = text.join(k);
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(path, v).unwrap();
    }
    let layers: String = got
        .layers
        .iter()
        .map(|(k, v)| format!("{k} {v}\n"))
        .collect();
    std::fs::write(root.join(LAYERS), layers).unwrap();
}

#[test]
fn every_command_on_every_example_gives_the_pinned_bytes() {
    let mut got = Outputs::default();
    for c in cases() {
        run_case(&c, &[], &mut got);
    }
    // The calibrated model, written once more into a folder that lives for the dependent cases.
    let calibration = run_case(
        &case(
            "calibrate-for-model",
            &[
                "calibrate",
                "examples/measured-thesis-like.csv",
                "-o",
                "{out}",
            ],
        ),
        &[],
        &mut Outputs::default(),
    );
    let model: PathBuf = calibration.path().join("out/calibrated-model.toml");
    let model_text = model.to_string_lossy().into_owned();
    for c in calibrated_cases(&model_text) {
        run_case(&c, std::slice::from_ref(&model_text), &mut got);
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    if std::env::var_os("GOLDEN_UPDATE").is_some() {
        update(root, &got);
        return;
    }
    let layers = std::fs::read_to_string(root.join(LAYERS))
        .unwrap_or_else(|e| panic!("{LAYERS}: {e}; create it with GOLDEN_UPDATE=1"));
    let want_layers: BTreeMap<String, String> = layers
        .lines()
        .filter_map(|l| l.split_once(' '))
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect();
    let want_text = pinned_text(&root.join(TEXT));
    let diff = differences(&want_text, &want_layers, &got);
    assert!(
        diff.is_empty(),
        "{} output(s) differ from the snapshot in tests/golden (if on purpose: GOLDEN_UPDATE=1 and say why in the commit):\n{}",
        diff.len(),
        diff.join("\n")
    );
}

#[test]
fn a_changed_report_line_is_shown_with_its_neighbours() {
    let want = b"mass 310.35 mg\nenergy 0.0582 mJ\nfield 800 V/mm\n";
    let got = b"mass 310.35 mg\nenergy 0.0583 mJ\nfield 800 V/mm\n";
    let d = text_diff(want, got);
    assert!(d.contains("2 - energy 0.0582 mJ"), "{d}");
    assert!(d.contains("2 + energy 0.0583 mJ"), "{d}");
    assert!(d.contains("1   mass 310.35 mg"), "{d}");
}
