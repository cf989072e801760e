//! Golden snapshot: every example through every command, a SHA-256 of every byte it prints and writes.
//!
//! The snapshot (`tests/golden/outputs.sha256`) pins the tool's observable output, so a restructuring
//! that should change nothing is shown to change nothing. When a change alters an output on purpose,
//! regenerate the snapshot in the same commit and say why in the message:
//!
//! ```sh
//! GOLDEN_UPDATE=1 cargo test --release --test golden
//! ```
//!
//! Every case runs from the crate root with inputs given as `examples/…` paths; the scratch output
//! directory's path is replaced by `<out>` before hashing, so the snapshot does not depend on where the
//! temporary directory is.

mod common;

use sha2::{Digest, Sha256};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

const SNAPSHOT: &str = "tests/golden/outputs.sha256";

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
    for spec in ["optimize-thesis", "optimize-rectangular"] {
        let file = format!("examples/{spec}.toml");
        cases.push(case(
            spec,
            &[
                "optimize",
                &file,
                "-o",
                "{out}/best.toml",
                "--pareto",
                "{out}/front.csv",
            ],
        ));
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
            "{out}/best.toml",
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
    for wing in ["drive-hawkmoth", "drive-robobee"] {
        let file = format!("examples/{wing}.toml");
        cases.push(case(wing, &["drive", &file, "-o", "{out}"]));
        cases.push(case(format!("{wing}-json"), &["drive", &file, "--json"]));
    }
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

/// Replace the scratch path (and its canonical form) by `<out>` so hashes do not depend on it.
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

/// Run one case; returns `case/stream-or-file sha256` lines and the scratch folder (kept alive).
fn run_case(c: &Case, also_scrub: &[String]) -> (Vec<String>, tempfile::TempDir) {
    let scratch = tempfile::tempdir().unwrap();
    let out = scratch.path().join("out");
    let out_text = out.to_string_lossy().into_owned();
    let args: Vec<String> = c
        .args
        .iter()
        .map(|a| a.replace("{out}", &out_text))
        .collect();
    if args.iter().any(|a| a.starts_with(&format!("{out_text}/"))) {
        // Commands that write single files (optimize -o, sweep --csv) expect the folder to exist.
        std::fs::create_dir_all(&out).unwrap();
    }
    let o = common::bin()
        .args(&args)
        .env("RAYON_NUM_THREADS", "2")
        .output()
        .expect("the binary runs");
    assert!(
        o.status.success(),
        "{}: {:?} failed: {}",
        c.name,
        args,
        String::from_utf8_lossy(&o.stderr)
    );
    let mut names = vec![out_text.clone()];
    names.extend(also_scrub.iter().cloned());
    if let Ok(canon) = out.canonicalize() {
        names.push(canon.to_string_lossy().into_owned());
    }
    let mut lines = vec![
        format!("{}/<stdout> {}", c.name, sha256(&scrub(&o.stdout, &names))),
        format!("{}/<stderr> {}", c.name, sha256(&scrub(&o.stderr, &names))),
    ];
    let mut written = BTreeMap::new();
    files_below(&out, "", &mut written);
    for (name, bytes) in &written {
        lines.push(format!(
            "{}/{name} {}",
            c.name,
            sha256(&scrub(bytes, &names))
        ));
    }
    (lines, scratch)
}

#[test]
fn every_command_on_every_example_gives_the_pinned_bytes() {
    let mut lines = Vec::new();
    for c in cases() {
        let (l, _scratch) = run_case(&c, &[]);
        lines.extend(l);
    }
    // The calibrated model, written once more into a folder that lives for the dependent cases.
    let (_, calibration) = run_case(
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
    );
    let model: PathBuf = calibration.path().join("out/calibrated-model.toml");
    let model_text = model.to_string_lossy().into_owned();
    for c in calibrated_cases(&model_text) {
        let (l, _scratch) = run_case(&c, std::slice::from_ref(&model_text));
        lines.extend(l);
    }
    let actual = lines.join("\n") + "\n";
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(SNAPSHOT);
    if std::env::var_os("GOLDEN_UPDATE").is_some() {
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(&path, &actual).unwrap();
        return;
    }
    let expected = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("{SNAPSHOT}: {e}; create it with GOLDEN_UPDATE=1"));
    if expected != actual {
        let want: BTreeMap<&str, &str> =
            expected.lines().filter_map(|l| l.split_once(' ')).collect();
        let got: BTreeMap<&str, &str> = actual.lines().filter_map(|l| l.split_once(' ')).collect();
        let mut diff = Vec::new();
        for (k, v) in &want {
            match got.get(k) {
                None => diff.push(format!("  missing now: {k}")),
                Some(g) if g != v => diff.push(format!("  changed:     {k}")),
                _ => {}
            }
        }
        for k in got.keys().filter(|k| !want.contains_key(*k)) {
            diff.push(format!("  new:         {k}"));
        }
        panic!(
            "{} output(s) differ from {SNAPSHOT} (if on purpose: GOLDEN_UPDATE=1 and say why in the commit):\n{}",
            diff.len(),
            diff.join("\n")
        );
    }
}
