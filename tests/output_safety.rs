//! The output policy, driven through the binary as a lab would meet it: nothing a user owns is deleted
//! or overwritten unasked, a folder the tool wrote before is updated in place, and an interrupted run
//! leaves nothing behind once the next run has looked.

use crate::common;
use common::*;
use std::fs;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

const MANIFEST: &str = ".actuator-cam-manifest";

/// Design C's cut sheet into `out`.
fn cut_sheet_into(out: &Path, extra: &[&str]) -> std::process::Output {
    cut_sheet("examples/thesis-C.toml", out, extra)
}

/// Staging folders beside `out` (what a killed run could leave).
fn staging_beside(out: &Path) -> Vec<String> {
    staging_left(out.parent().unwrap())
}

#[test]
fn a_folder_with_user_files_is_refused_and_left_as_it_was() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("sb");
    fs::create_dir(&out).unwrap();
    fs::copy(example("thesis-C.toml"), out.join("design.toml")).unwrap();
    fs::write(out.join("notes.txt"), "n\n").unwrap();
    fs::create_dir(out.join("sub")).unwrap();
    fs::write(out.join("sub/canary"), "c").unwrap();

    let o = run(&[
        "cut-sheet",
        out.join("design.toml").to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    let err = refused_in_one_line(&o);
    assert!(
        err.contains("sb") && err.contains("notes.txt") && err.contains("--force"),
        "{err}"
    );
    // Untouched: the same three entries, the same bytes, nothing written.
    let mut names: Vec<_> = fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(names, ["design.toml", "notes.txt", "sub"]);
    assert_eq!(fs::read_to_string(out.join("notes.txt")).unwrap(), "n\n");
    assert_eq!(fs::read_to_string(out.join("sub/canary")).unwrap(), "c");
    assert!(staging_beside(&out).is_empty());
}

#[test]
fn force_writes_beside_user_files_and_spares_inputs() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("proj");
    fs::create_dir(&out).unwrap();
    fs::copy(example("thesis-C.toml"), out.join("design.toml")).unwrap();
    fs::write(out.join("notes.txt"), "n\n").unwrap();
    // A user file that has the name of an output: --force is the user's word to replace it.
    fs::write(out.join("report.md"), "mine").unwrap();
    let design = out.join("design.toml");
    let design_bytes = fs::read(&design).unwrap();

    let o = run(&[
        "cut-sheet",
        design.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--force",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(fs::read(&design).unwrap(), design_bytes);
    assert_eq!(fs::read_to_string(out.join("notes.txt")).unwrap(), "n\n");
    assert!(layer_file(&out, "pzt-1.svg").exists() && out.join(MANIFEST).exists());
    assert_ne!(fs::read_to_string(out.join("report.md")).unwrap(), "mine");
}

#[test]
fn force_never_overwrites_an_input_of_the_run() {
    // The batch and its designs live in the output folder; an output named like an input is refused.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("p");
    fs::create_dir(&out).unwrap();
    fs::copy(example("thesis-C.toml"), out.join("report.md")).unwrap();
    let input = out.join("report.md");
    let before = fs::read(&input).unwrap();
    let o = run(&[
        "cut-sheet",
        input.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--force",
    ]);
    assert!(!o.status.success());
    let err = stderr(&o);
    assert!(err.contains("report.md") && err.contains("input"), "{err}");
    assert_eq!(fs::read(&input).unwrap(), before);
}

#[test]
fn a_folder_written_before_is_updated_and_only_our_stale_files_go() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o");
    // First run: 40 actuators need more sheets and panels than the second run's 2.
    let o = cut_sheet_into(&out, &["--quantity", "40"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let many = files(&out).len();
    fs::write(out.join("notes.txt"), "lab notes").unwrap();
    let o = cut_sheet_into(&out, &["--quantity", "2"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let now = files(&out);
    assert!(
        now.len() < many,
        "stale sheets of the first run remain: {} vs {many}",
        now.len()
    );
    assert_eq!(now["notes.txt"], b"lab notes");
    // Same bytes as a run into a fresh folder (apart from nothing: the manifest lists the same files).
    let fresh = dir.path().join("fresh");
    assert!(cut_sheet_into(&fresh, &["--quantity", "2"])
        .status
        .success());
    let mut want = files(&fresh);
    want.insert("notes.txt".into(), b"lab notes".to_vec());
    assert_eq!(now, want);
}

#[test]
fn commands_share_a_folder_without_removing_each_others_files() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o");
    fs::create_dir(&out).unwrap();
    let best = out.join("design.toml");
    let o = run(&[
        "optimize",
        "examples/optimize-thesis.toml",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let o = cut_sheet_into(&out, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(best.exists(), "cut-sheet removed optimize's design");
    // And optimize again, into the same folder: its files replaced, cut-sheet's files still there.
    let o = run(&[
        "optimize",
        "examples/optimize-rectangular.toml",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(layer_file(&out, "pzt-1.svg").exists());
}

#[test]
fn a_single_output_file_the_user_owns_is_not_overwritten_unasked() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("designs.csv");
    fs::write(&csv, "precious").unwrap();
    let o = run(&[
        "sweep",
        "examples/sweep-table-3-2.toml",
        "--csv",
        csv.to_str().unwrap(),
    ]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("designs.csv") && stderr(&o).contains("--force"));
    assert_eq!(fs::read_to_string(&csv).unwrap(), "precious");
    let o = run(&[
        "sweep",
        "examples/sweep-table-3-2.toml",
        "--csv",
        csv.to_str().unwrap(),
        "--force",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(fs::read_to_string(&csv).unwrap().starts_with("design,"));
}

#[test]
fn dot_and_dot_dot_get_a_message_that_says_what_is_wrong() {
    let dir = tempfile::tempdir().unwrap();
    let inner = dir.path().join("a/b");
    fs::create_dir_all(&inner).unwrap();
    fs::write(inner.join("keep.txt"), "k").unwrap();
    for target in [".", ".."] {
        let o = Command::new(env!("CARGO_BIN_EXE_actuator-cam"))
            .args(["cut-sheet", &example("thesis-C.toml"), "-o", target])
            .current_dir(&inner)
            .output()
            .unwrap();
        let err = stderr(&o);
        assert!(!o.status.success(), "{target}");
        assert!(!err.contains("os error"), "{target}: {err}");
        assert!(err.contains("--force"), "{target}: {err}");
    }
    assert_eq!(fs::read_to_string(inner.join("keep.txt")).unwrap(), "k");
}

/// Start a long cut-sheet, stop it mid-way, and look beside the output folder.
fn interrupted_run(signal: &str, after: Duration) -> (tempfile::TempDir, std::path::PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o");
    let mut child = Command::new(env!("CARGO_BIN_EXE_actuator-cam"))
        .args([
            "cut-sheet",
            &example("thesis-C.toml"),
            "-o",
            out.to_str().unwrap(),
            "--quantity",
            "3000",
        ])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    // Wait until the run has staged something (or give up after `after`).
    let start = Instant::now();
    while start.elapsed() < after && (!out.exists() || staging_left(&out).is_empty()) {
        std::thread::sleep(Duration::from_millis(20));
    }
    Command::new("kill")
        .args([signal, &child.id().to_string()])
        .status()
        .unwrap();
    child.wait().unwrap();
    (dir, out)
}

#[test]
fn sigint_and_sigterm_clean_up_the_staging_folder() {
    for signal in ["-INT", "-TERM"] {
        let (_dir, out) = interrupted_run(signal, Duration::from_secs(20));
        assert!(
            staging_beside(&out).is_empty() && (!out.exists() || staging_left(&out).is_empty()),
            "{signal}: {:?}",
            staging_beside(&out)
        );
        assert!(
            !out.exists() || files(&out).is_empty(),
            "{signal}: half-written output"
        );
    }
}

#[test]
fn a_staging_folder_left_by_sigkill_is_removed_by_the_next_run() {
    let (_dir, out) = interrupted_run("-KILL", Duration::from_secs(20));
    // SIGKILL cannot be caught: whatever it left, the next run into the same place clears it.
    let o = cut_sheet_into(&out, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        staging_beside(&out).is_empty(),
        "{:?}",
        staging_beside(&out)
    );
}

/// A project folder holding copies of the examples (parts, effects, measured data), a template file that
/// a design names, and a calibrated model: every kind of file a run reads.
fn project() -> (tempfile::TempDir, std::path::PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("p");
    fs::create_dir_all(p.join("parts")).unwrap();
    for e in fs::read_dir(example("")).unwrap() {
        let e = e.unwrap();
        if e.file_type().unwrap().is_file() {
            fs::copy(e.path(), p.join(e.file_name())).unwrap();
        }
    }
    for name in ["spar.dxf", "flexure.svg"] {
        fs::copy(
            example(&format!("parts/{name}")),
            p.join("parts").join(name),
        )
        .unwrap();
    }
    fs::copy(
        format!("{}/templates/method-2.toml", env!("CARGO_MANIFEST_DIR")),
        p.join("my-process.toml"),
    )
    .unwrap();
    fs::write(
        p.join("design.toml"),
        design_c_with(&[("process", "process = \"my-process.toml\"")]),
    )
    .unwrap();
    let cal = dir.path().join("cal");
    run_ok(&[
        "calibrate",
        &example("measured-thesis-like.csv"),
        "-o",
        cal.to_str().unwrap(),
    ]);
    fs::copy(cal.join("calibrated-model.toml"), p.join("model.toml")).unwrap();
    (dir, p)
}

/// Run with the writer's list of inputs on stderr; the list, and the run's output.
fn with_inputs(args: &[&str]) -> (Vec<std::path::PathBuf>, std::process::Output) {
    let o = bin()
        .env("ACTUATOR_CAM_LIST_INPUTS", "1")
        .args(args)
        .output()
        .unwrap();
    let list = stderr(&o)
        .lines()
        .filter_map(|l| l.strip_prefix("input: "))
        .map(std::path::PathBuf::from)
        .collect();
    (list, o)
}

fn snapshot(paths: &[std::path::PathBuf]) -> Vec<Vec<u8>> {
    paths.iter().map(|p| fs::read(p).unwrap()).collect()
}

#[test]
fn every_file_a_run_reads_is_an_input_no_output_replaces() {
    let (_dir, p) = project();
    let at = |n: &str| p.join(n).to_str().unwrap().to_string();
    let model = at("model.toml");
    let folder_runs: Vec<Vec<String>> = vec![
        vec![
            "cut-sheet".into(),
            at("design.toml"),
            "--model".into(),
            model.clone(),
        ],
        vec!["nest".into(), at("batch-with-parts.toml")],
        vec![
            "calibrate".into(),
            at("measured-thesis-like.csv"),
            "--effects".into(),
            at("effects-clamp-width.toml"),
        ],
    ];
    for args in &folder_runs {
        let mut args: Vec<&str> = args.iter().map(String::as_str).collect();
        let out = p.to_str().unwrap();
        args.extend(["-o", out, "--force"]);
        let named: Vec<std::path::PathBuf> = args
            .iter()
            .filter(|a| a.ends_with(".toml") || a.ends_with(".csv"))
            .map(std::path::PathBuf::from)
            .collect();
        let named_before = snapshot(&named);
        let (inputs, o) = with_inputs(&args);
        assert!(o.status.success(), "{args:?}: {}", stderr(&o));
        assert_eq!(snapshot(&named), named_before, "{args:?}");
        // The list holds what the command line names and what those files name.
        for named in args
            .iter()
            .filter(|a| a.ends_with(".toml") || a.ends_with(".csv"))
        {
            assert!(
                inputs.iter().any(|i| i.to_str() == Some(named)),
                "{named} not in {inputs:?}"
            );
        }
        if args[0] == "cut-sheet" {
            assert!(
                inputs.iter().any(|i| i.ends_with("my-process.toml")),
                "{inputs:?}"
            );
        }
        if args[0] == "nest" {
            for part in ["spar.dxf", "flexure.svg", "thesis-A.toml"] {
                assert!(
                    inputs.iter().any(|i| i.ends_with(part)),
                    "{part}: {inputs:?}"
                );
            }
        }
    }
    // optimize's files aimed at each input of the same run: an input in the output folder under the
    // name of one of its files is refused, even with --force; an input given as the folder is not one.
    let optimize = |extra: &[&str]| {
        let mut args = vec![
            "optimize".to_string(),
            at("optimize-thesis.toml"),
            "--model".into(),
            model.clone(),
        ];
        args.extend(extra.iter().map(|s| s.to_string()));
        args
    };
    let scratch = at("optimum");
    let (inputs, o) = with_inputs(
        &optimize(&["-o", &scratch])
            .iter()
            .map(String::as_str)
            .collect::<Vec<_>>(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(inputs.len(), 2, "{inputs:?}");
    let before = snapshot(&inputs);
    for input in &inputs {
        let input = input.to_str().unwrap();
        let args = optimize(&["-o", input, "--force"]);
        let o = run(&args.iter().map(String::as_str).collect::<Vec<_>>());
        refused_in_one_line(&o);
    }
    assert_eq!(snapshot(&inputs), before);
    let named = Path::new(&scratch).join("design.toml");
    fs::copy(&model, &named).unwrap();
    let o = run(&[
        "optimize",
        &at("optimize-thesis.toml"),
        "--model",
        named.to_str().unwrap(),
        "-o",
        &scratch,
        "--force",
    ]);
    let err = refused_in_one_line(&o);
    assert!(err.contains("design.toml is an input of this run"), "{err}");
    let factors = at("sweep-table-3-2.toml");
    let (inputs, _) = with_inputs(&["sweep", &factors, "--csv", &at("designs.csv")]);
    assert_eq!(inputs, [std::path::PathBuf::from(&factors)]);
    let o = run(&["sweep", &factors, "--csv", &factors, "--force"]);
    let err = refused_in_one_line(&o);
    assert!(err.contains("is an input of this run"), "{err}");
}

#[test]
fn a_model_file_is_an_input_under_any_output_name() {
    let dir = tempfile::tempdir().unwrap();
    let c = dir.path().join("C");
    run_ok(&[
        "calibrate",
        &example("measured-thesis-like.csv"),
        "-o",
        c.to_str().unwrap(),
    ]);
    let model = c.join("calibrated-model.toml");
    let before = fs::read(&model).unwrap();
    // The model named as one of optimize's files, in its output folder, with --force.
    let d = dir.path().join("D");
    fs::create_dir(&d).unwrap();
    fs::copy(&model, d.join("report.txt")).unwrap();
    let o = run(&[
        "optimize",
        "examples/optimize-thesis.toml",
        "--model",
        d.join("report.txt").to_str().unwrap(),
        "-o",
        d.to_str().unwrap(),
        "--force",
    ]);
    let err = refused_in_one_line(&o);
    assert!(err.contains("report.txt is an input of this run"), "{err}");
    assert_eq!(fs::read(d.join("report.txt")).unwrap(), before);
    // A model file named like an output of cut-sheet, in the output folder, with --force.
    let p = dir.path().join("P");
    fs::create_dir(&p).unwrap();
    fs::copy(&model, p.join("report.md")).unwrap();
    let o = cut_sheet(
        "examples/thesis-C.toml",
        &p,
        &["--model", p.join("report.md").to_str().unwrap(), "--force"],
    );
    let err = refused_in_one_line(&o);
    assert!(err.contains("report.md is an input of this run"), "{err}");
    assert_eq!(fs::read(p.join("report.md")).unwrap(), before);
}

#[test]
fn one_command_does_not_replace_anothers_files_unasked() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path().join("D");
    run_ok(&[
        "calibrate",
        &example("measured-thesis-like.csv"),
        "-o",
        d.to_str().unwrap(),
    ]);
    let report = fs::read(d.join("report.md")).unwrap();
    let o = cut_sheet_into(&d, &[]);
    let err = refused_in_one_line(&o);
    assert!(
        err.contains("was written by `actuator-cam calibrate`") && err.contains("--force"),
        "{err}"
    );
    assert_eq!(fs::read(d.join("report.md")).unwrap(), report);
    let o = cut_sheet_into(&d, &["--force"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_ne!(fs::read(d.join("report.md")).unwrap(), report);
}

/// Every file of `out` except the tool's manifest, by name.
fn outputs(out: &Path) -> std::collections::BTreeMap<String, Vec<u8>> {
    let mut f = files(out);
    f.remove(MANIFEST);
    f
}

/// The names a folder's manifest lists.
fn listed(out: &Path) -> std::collections::BTreeSet<String> {
    fs::read_to_string(out.join(MANIFEST))
        .unwrap()
        .lines()
        .filter(|l| !l.starts_with('#'))
        .filter_map(|l| l.split_once('\t').map(|(_, n)| n.to_string()))
        .collect()
}

fn copy_folder(from: &Path, to: &Path) {
    fs::create_dir_all(to).unwrap();
    for (name, bytes) in files(from) {
        fs::write(to.join(name), bytes).unwrap();
    }
}

#[test]
fn a_run_killed_after_any_move_is_finished_by_the_next_run() {
    let dir = tempfile::tempdir().unwrap();
    let before = written_before(dir.path());
    // What the killed run meant: 2 actuators' files (fewer sheets: stale ones go).
    let meant = dir.path().join("meant");
    copy_folder(&before, &meant);
    run_ok(&[
        "cut-sheet",
        "examples/thesis-C.toml",
        "-o",
        meant.to_str().unwrap(),
        "--quantity",
        "2",
        "--format",
        "svg",
    ]);
    let want = outputs(&meant);
    let mut k = 1;
    loop {
        let out = dir.path().join(format!("k{k}"));
        copy_folder(&before, &out);
        let o = bin()
            .env("ACTUATOR_CAM_STOP_AFTER_MOVE", k.to_string())
            .args([
                "cut-sheet",
                "examples/thesis-C.toml",
                "-o",
                out.to_str().unwrap(),
                "--quantity",
                "2",
                "--format",
                "svg",
            ])
            .output()
            .unwrap();
        if o.status.success() {
            // More stops than moves: the run went through.
            assert!(k > 10, "only {k} moves");
            assert_eq!(outputs(&out), want);
            break;
        }
        // Another command's run into the same folder finishes the dead run's moves first.
        run_ok(&[
            "optimize",
            "examples/optimize-thesis.toml",
            "-o",
            out.to_str().unwrap(),
        ]);
        assert_eq!(outputs(&out), want, "stopped after move {k}");
        let listed = listed(&out);
        for name in outputs(&out).keys().filter(|n| *n != "notes.txt") {
            assert!(
                listed.contains(name),
                "stopped after move {k}: {name} is not listed"
            );
        }
        fs::remove_dir_all(&out).unwrap();
        k += 1;
    }
}

#[test]
fn a_run_killed_while_staging_into_a_new_folder_leaves_nothing_after_the_next() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o");
    // Killed before the first move: its staging folder and lock stay behind.
    let o = bin()
        .env("ACTUATOR_CAM_STOP_AFTER_MOVE", "1")
        .args([
            "cut-sheet",
            "examples/thesis-C.toml",
            "-o",
            out.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert!(!o.status.success());
    run_ok(&[
        "cut-sheet",
        "examples/thesis-C.toml",
        "-o",
        out.to_str().unwrap(),
    ]);
    let names: Vec<String> = fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with(".actuator-cam-") && n != MANIFEST)
        .collect();
    assert!(names.is_empty(), "{names:?}");
    assert!(staging_beside(&out).is_empty());
}

#[test]
fn two_commands_into_one_folder_at_once_never_mix() {
    let dir = tempfile::tempdir().unwrap();
    let reference_cut = dir.path().join("rc");
    let reference_nest = dir.path().join("rn");
    let cut_args = ["cut-sheet", "examples/thesis-C.toml", "--quantity", "300"];
    let nest_args = ["nest", "examples/batch.toml", "--iterations", "100"];
    run_ok(&[&cut_args[..], &["-o", reference_cut.to_str().unwrap()]].concat());
    run_ok(&[&nest_args[..], &["-o", reference_nest.to_str().unwrap()]].concat());
    for pair in 0..4 {
        let dst = dir.path().join(format!("dst{pair}"));
        let d = dst.to_str().unwrap();
        let a = bin()
            .args([&cut_args[..], &["-o", d]].concat())
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let b = bin()
            .args([&nest_args[..], &["-o", d]].concat())
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let (a, b) = (a.wait_with_output().unwrap(), b.wait_with_output().unwrap());
        let listed = listed(&dst);
        let now = outputs(&dst);
        assert_eq!(
            now.keys()
                .cloned()
                .collect::<std::collections::BTreeSet<_>>(),
            listed,
            "pair {pair}"
        );
        // Each file is the bytes of the command the manifest names.
        let manifest = fs::read_to_string(dst.join(MANIFEST)).unwrap();
        for line in manifest.lines().filter(|l| !l.starts_with('#')) {
            let (command, name) = line.split_once('\t').unwrap();
            let reference = if command == "nest" {
                &reference_nest
            } else {
                &reference_cut
            };
            assert_eq!(
                now[name],
                fs::read(reference.join(name)).unwrap(),
                "pair {pair}: {name}"
            );
        }
        for (o, what) in [(&a, "cut-sheet"), (&b, "nest")] {
            if !o.status.success() {
                let err = stderr(o);
                assert_eq!(err.trim().lines().count(), 1, "{what}: {err}");
                assert!(
                    err.contains("another run") || err.contains("was written by"),
                    "{what}: {err}"
                );
            }
        }
    }
}

#[test]
fn a_signal_while_the_files_move_waits_for_them_and_the_run_exits_0() {
    // SIGINT or SIGTERM arriving during the moves (after the first, or after the last) waits until
    // every file is in place, then changes nothing: the run ends with exit 0 and its whole output,
    // as a run no signal reached.
    let dir = tempfile::tempdir().unwrap();
    let want_dir = dir.path().join("want");
    run_ok(&[
        "cut-sheet",
        "examples/thesis-C.toml",
        "-o",
        want_dir.to_str().unwrap(),
        "--format",
        "svg",
    ]);
    let want = outputs(&want_dir);
    let moves = want.len() + 2; // the intent log, every file, the manifest
    for (k, signal) in [
        (1, libc::SIGINT),
        (moves / 2, libc::SIGTERM),
        (moves, libc::SIGINT),
    ] {
        let out = dir.path().join(format!("k{k}"));
        let mut child = bin()
            .env("ACTUATOR_CAM_PAUSE_AFTER_MOVE", k.to_string())
            .args([
                "cut-sheet",
                "examples/thesis-C.toml",
                "-o",
                out.to_str().unwrap(),
                "--format",
                "svg",
            ])
            .stderr(std::process::Stdio::piped())
            .stdout(std::process::Stdio::null())
            .spawn()
            .unwrap();
        let mut stderr = std::io::BufReader::new(child.stderr.take().unwrap());
        let mut line = String::new();
        loop {
            line.clear();
            let n = std::io::BufRead::read_line(&mut stderr, &mut line).unwrap();
            assert!(n > 0, "move {k}: the run ended before its pause");
            if line.starts_with(&format!("paused after move {k}")) {
                break;
            }
        }
        // SAFETY: a plain kill(2) of our own child.
        assert_eq!(unsafe { libc::kill(child.id() as i32, signal) }, 0);
        let status = child.wait().unwrap();
        assert!(status.success(), "signal {signal} after move {k}: {status}");
        assert_eq!(outputs(&out), want, "signal {signal} after move {k}");
    }
}

const LOCK: &str = ".actuator-cam-lock";
const INTENT: &str = ".actuator-cam-intent";

/// A design outside the output folder, and the folder `out` beside it (made, empty).
fn design_and_folder() -> (tempfile::TempDir, std::path::PathBuf, std::path::PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let design = dir.path().join("d.toml");
    fs::copy(example("thesis-C.toml"), &design).unwrap();
    let out = dir.path().join("out");
    fs::create_dir(&out).unwrap();
    (dir, design, out)
}

#[test]
fn a_link_under_one_of_the_tools_names_is_refused_and_what_it_names_is_untouched() {
    // Each of the tool's own names in the folder, as a link to the run's own design, as a hard link
    // to it, and as a link to a file inside the folder: refused naming it, the design whole.
    for name in [LOCK, INTENT, MANIFEST] {
        for kind in ["symlink", "hard link", "symlink inside"] {
            let (_dir, design, out) = design_and_folder();
            let before = fs::read(&design).unwrap();
            let inside = out.join("notes.txt");
            match kind {
                "symlink" => std::os::unix::fs::symlink("../d.toml", out.join(name)).unwrap(),
                "hard link" => fs::hard_link(&design, out.join(name)).unwrap(),
                _ => {
                    fs::write(&inside, "lab notes\n").unwrap();
                    std::os::unix::fs::symlink("notes.txt", out.join(name)).unwrap();
                }
            }
            let o = cut_sheet(design.to_str().unwrap(), &out, &["--force"]);
            let err = refused_in_one_line(&o);
            assert!(err.contains(name), "{name} as a {kind}: {err}");
            assert_eq!(fs::read(&design).unwrap(), before, "{name} as a {kind}");
            if kind == "symlink inside" {
                assert_eq!(fs::read_to_string(&inside).unwrap(), "lab notes\n");
            }
            assert!(
                !out.join("report.md").exists(),
                "{name} as a {kind}: written"
            );
        }
    }
    // The lock or the intent log as a directory: refused naming it.
    for name in [LOCK, INTENT] {
        let (_dir, design, out) = design_and_folder();
        fs::create_dir(out.join(name)).unwrap();
        let o = cut_sheet(design.to_str().unwrap(), &out, &["--force"]);
        let err = refused_in_one_line(&o);
        assert!(err.contains(name) && err.contains("directory"), "{err}");
    }
}

/// A folder written by cut-sheet (40 actuators, svg), with the user's notes and optimize's design.
fn written_before(dir: &Path) -> std::path::PathBuf {
    let before = dir.join("before");
    run_ok(&[
        "cut-sheet",
        "examples/thesis-C.toml",
        "-o",
        before.to_str().unwrap(),
        "--quantity",
        "40",
        "--format",
        "svg",
    ]);
    fs::write(before.join("notes.txt"), "mine").unwrap();
    run_ok(&[
        "optimize",
        "examples/optimize-thesis.toml",
        "-o",
        before.to_str().unwrap(),
    ]);
    before
}

/// cut-sheet of 2 actuators into `out`, stopped (or paused, `hook`) after move `k`.
fn cut_two(out: &Path, hook: &str, k: usize) -> Command {
    let mut c = bin();
    c.env(hook, k.to_string()).args([
        "cut-sheet",
        "examples/thesis-C.toml",
        "-o",
        out.to_str().unwrap(),
        "--quantity",
        "2",
        "--format",
        "svg",
    ]);
    c
}

/// optimize's design written into `out` (another command's run into the same folder).
fn optimize_into(out: &Path) -> std::process::Output {
    run(&[
        "optimize",
        "examples/optimize-thesis.toml",
        "-o",
        out.to_str().unwrap(),
    ])
}

/// Every file under `dir`, by its path inside it, with its bytes.
fn every_file(dir: &Path) -> std::collections::BTreeMap<std::path::PathBuf, Vec<u8>> {
    let mut found = std::collections::BTreeMap::new();
    let mut folders = vec![dir.to_path_buf()];
    while let Some(folder) = folders.pop() {
        for e in fs::read_dir(&folder).unwrap() {
            let path = e.unwrap().path();
            if path.is_dir() {
                folders.push(path);
            } else {
                let bytes = fs::read(&path).unwrap();
                found.insert(path.strip_prefix(dir).unwrap().to_path_buf(), bytes);
            }
        }
    }
    found
}

#[test]
fn an_intent_log_cut_short_or_damaged_is_refused_and_the_manifest_kept() {
    let dir = tempfile::tempdir().unwrap();
    let before = written_before(dir.path());
    type Cut = fn(&str) -> String;
    let cuts: [(&str, Cut); 3] = [
        ("empty", |_| String::new()),
        ("half its lines", |t| {
            let lines: Vec<&str> = t.lines().collect();
            lines[..lines.len() / 2].join("\n") + "\n"
        }),
        ("one byte changed", |t| t.replacen("put\t", "put\tx", 1)),
    ];
    for (what, cut) in cuts {
        let out = dir.path().join("k");
        copy_folder(&before, &out);
        // Killed after it moved its log and 3 files into place.
        assert!(!cut_two(&out, "ACTUATOR_CAM_STOP_AFTER_MOVE", 4)
            .output()
            .unwrap()
            .status
            .success());
        let log = fs::read_to_string(out.join(INTENT)).unwrap();
        fs::write(out.join(INTENT), cut(&log)).unwrap();
        let manifest = fs::read(out.join(MANIFEST)).unwrap();
        let left = every_file(&out);
        let o = optimize_into(&out);
        let err = refused_in_one_line(&o);
        assert!(
            err.contains(INTENT) && err.contains("delete"),
            "{what}: {err}"
        );
        assert_eq!(fs::read(out.join(MANIFEST)).unwrap(), manifest, "{what}");
        // Every file as it was (the lock aside: the refused run held the folder, and let it go).
        let unlocked = |mut files: std::collections::BTreeMap<std::path::PathBuf, Vec<u8>>| {
            files.remove(Path::new(LOCK));
            files
        };
        assert!(
            unlocked(every_file(&out)) == unlocked(left),
            "{what}: the folder changed"
        );
        fs::remove_dir_all(&out).unwrap();
    }
}

#[test]
fn a_damaged_manifest_is_named_not_read_as_empty() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o");
    run_ok(&[
        "cut-sheet",
        "examples/thesis-C.toml",
        "-o",
        out.to_str().unwrap(),
    ]);
    let whole = fs::read_to_string(out.join(MANIFEST)).unwrap();
    for damaged in [String::new(), whole[..whole.len() - 3].to_string()] {
        fs::write(out.join(MANIFEST), &damaged).unwrap();
        let o = cut_sheet_into(&out, &[]);
        let err = refused_in_one_line(&o);
        assert!(err.contains(MANIFEST) && err.contains("damaged"), "{err}");
        assert_eq!(fs::read_to_string(out.join(MANIFEST)).unwrap(), damaged);
    }
}

/// An intent log as a run writes it, around `records` (each a line of tab-separated fields): the end
/// record counts them and carries the FNV-1a 64-bit hash of every byte before it (the format
/// `crates/cam/src/output/intent.rs` documents, written here independently).
fn sealed_log(records: &[&str]) -> String {
    let mut text = String::from("# a log\n");
    for r in records {
        text.push_str(r);
        text.push('\n');
    }
    let hash = text.bytes().fold(0xcbf2_9ce4_8422_2325_u64, |h, b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    });
    format!("{text}end\t{}\t{hash:016x}\n", records.len())
}

#[test]
fn an_intent_log_that_asks_for_more_than_a_run_could_is_refused() {
    let staging = ".actuator-cam-staging-dead";
    // A remove of the user's file, which the manifest never listed.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o");
    run_ok(&[
        "cut-sheet",
        "examples/thesis-C.toml",
        "-o",
        out.to_str().unwrap(),
    ]);
    fs::write(out.join("notes.txt"), "mine").unwrap();
    let log = sealed_log(&[&format!("staging\t{staging}"), "remove\tnotes.txt"]);
    fs::write(out.join(INTENT), log).unwrap();
    let err = refused_in_one_line(&optimize_into(&out));
    assert!(err.contains(INTENT) && err.contains("line 3"), "{err}");
    assert_eq!(fs::read_to_string(out.join("notes.txt")).unwrap(), "mine");

    // A staging folder outside the output folder, whose file a put would bring in.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o");
    run_ok(&[
        "cut-sheet",
        "examples/thesis-C.toml",
        "-o",
        out.to_str().unwrap(),
    ]);
    let victim = dir.path().join("victim/new");
    fs::create_dir_all(&victim).unwrap();
    fs::write(victim.join("secret.txt"), "secret").unwrap();
    fs::create_dir(out.join(staging)).unwrap();
    let log = sealed_log(&[
        &format!("staging\t{staging}/../../victim"),
        "put\tsecret.txt",
        "owner\tcut-sheet\tsecret.txt",
    ]);
    fs::write(out.join(INTENT), log).unwrap();
    let err = refused_in_one_line(&optimize_into(&out));
    assert!(err.contains(INTENT) && err.contains("line 2"), "{err}");
    assert_eq!(fs::read(victim.join("secret.txt")).unwrap(), b"secret");
    assert!(!out.join("secret.txt").exists());

    // The staging folder gone and the manifest a link to the design: nothing written through it.
    let (_dir, design, out) = design_and_folder();
    let before = fs::read(&design).unwrap();
    std::os::unix::fs::symlink("../d.toml", out.join(MANIFEST)).unwrap();
    let log = sealed_log(&[&format!("staging\t{staging}"), "owner\tcut-sheet\tx.svg"]);
    fs::write(out.join(INTENT), log).unwrap();
    let err = refused_in_one_line(&optimize_into(&out));
    assert!(err.contains(MANIFEST), "{err}");
    assert_eq!(fs::read(&design).unwrap(), before);
}

#[test]
fn a_users_folder_named_like_a_staging_folder_is_left_alone() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o");
    run_ok(&[
        "cut-sheet",
        "examples/thesis-C.toml",
        "-o",
        out.to_str().unwrap(),
    ]);
    let photos = out.join(".actuator-cam-staging-photos");
    fs::create_dir(&photos).unwrap();
    fs::write(photos.join("a.jpg"), "jpeg").unwrap();
    run_ok(&[
        "cut-sheet",
        "examples/thesis-C.toml",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(fs::read(photos.join("a.jpg")).unwrap(), b"jpeg");
    // In a folder the tool never wrote, it is the user's like any other entry.
    let fresh = dir.path().join("fresh");
    fs::create_dir(&fresh).unwrap();
    fs::create_dir(fresh.join(".actuator-cam-staging-photos")).unwrap();
    fs::write(fresh.join(".actuator-cam-staging-photos/a.jpg"), "jpeg").unwrap();
    let err = refused_in_one_line(&cut_sheet_into(&fresh, &[]));
    assert!(err.contains(".actuator-cam-staging-photos/"), "{err}");
}

/// Start `command` paused after move `k`; SIGKILL it during the pause. False when the run ended first
/// (it has fewer moves).
fn kill_during_pause(mut command: Command, k: usize) -> bool {
    let mut child = command
        .stderr(Stdio::piped())
        .stdout(Stdio::null())
        .spawn()
        .unwrap();
    let mut stderr = std::io::BufReader::new(child.stderr.take().unwrap());
    let mut line = String::new();
    let paused = loop {
        line.clear();
        if std::io::BufRead::read_line(&mut stderr, &mut line).unwrap() == 0 {
            break false;
        }
        if line.starts_with(&format!("paused after move {k}")) {
            break true;
        }
    };
    if paused {
        child.kill().unwrap();
    }
    child.wait().unwrap();
    paused
}

#[test]
#[ignore = "study: three minutes of killed runs"]
fn a_run_killed_while_it_finishes_a_killed_runs_moves_is_finished_by_the_next() {
    let dir = tempfile::tempdir().unwrap();
    let before = written_before(dir.path());
    let meant = dir.path().join("meant");
    copy_folder(&before, &meant);
    let mut whole = cut_two(&meant, "ACTUATOR_CAM_PAUSE_AFTER_MOVE", 0);
    whole.env_remove("ACTUATOR_CAM_PAUSE_AFTER_MOVE");
    assert!(whole.output().unwrap().status.success());
    let want = outputs(&meant);
    // The first run (some 45 moves) is killed (SIGKILL) early, half-way and late in its moves; the
    // second while it finishes them, after each of its moves; a third run then finds the folder as the
    // first meant.
    for first in [2, 20, 40] {
        for second in 1.. {
            let out = dir.path().join(format!("k{first}-{second}"));
            copy_folder(&before, &out);
            let paused = cut_two(&out, "ACTUATOR_CAM_PAUSE_AFTER_MOVE", first);
            assert!(
                kill_during_pause(paused, first),
                "ended before move {first}"
            );
            let mut optimize = bin();
            optimize
                .env("ACTUATOR_CAM_PAUSE_AFTER_MOVE", second.to_string())
                .args([
                    "optimize",
                    "examples/optimize-thesis.toml",
                    "-o",
                    out.to_str().unwrap(),
                ]);
            let killed = kill_during_pause(optimize, second);
            let o = optimize_into(&out);
            assert!(o.status.success(), "{first}/{second}: {}", stderr(&o));
            assert_eq!(
                outputs(&out),
                want,
                "killed after moves {first}, then {second}"
            );
            let listed = listed(&out);
            for name in outputs(&out).keys().filter(|n| *n != "notes.txt") {
                assert!(listed.contains(name), "{first}/{second}: {name} not listed");
            }
            assert!(staging_left(&out).is_empty() && !out.join(INTENT).exists());
            fs::remove_dir_all(&out).unwrap();
            if !killed {
                break;
            }
        }
    }
}

#[test]
fn a_dangling_link_as_the_output_folder_is_named_as_one() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    std::os::unix::fs::symlink("missing", &out).unwrap();
    let err = refused_in_one_line(&cut_sheet_into(&out, &[]));
    assert!(
        err.contains("symbolic link to missing") && !err.contains("exists"),
        "{err}"
    );
    assert!(!dir.path().join("missing").exists());
}

#[test]
fn a_file_flag_given_a_folder_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    fs::create_dir(dir.path().join("existing")).unwrap();
    for given in ["somedir/", "existing/", "existing/."] {
        let o = bin()
            .current_dir(dir.path())
            .args(["sweep", &example("sweep-table-3-2.toml"), "--csv", given])
            .output()
            .unwrap();
        let err = refused_in_one_line(&o);
        assert!(err.contains("takes a file path"), "{given}: {err}");
        assert!(!dir.path().join("somedir").exists(), "{given}");
    }
    let mut names: Vec<_> = fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(names, ["existing"]);
}

#[test]
fn a_file_size_limit_is_an_error_in_words_and_leaves_nothing() {
    use std::os::unix::process::CommandExt;
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o");
    let mut c = bin();
    c.args([
        "cut-sheet",
        "examples/thesis-C.toml",
        "-o",
        out.to_str().unwrap(),
    ]);
    // SAFETY: setrlimit is async-signal-safe; it only limits the child about to exec.
    unsafe {
        c.pre_exec(|| {
            let limit = libc::rlimit {
                rlim_cur: 4096,
                rlim_max: 4096,
            };
            if libc::setrlimit(libc::RLIMIT_FSIZE, &limit) != 0 {
                return Err(std::io::Error::last_os_error());
            }
            Ok(())
        });
    }
    let o = c.output().unwrap();
    assert_eq!(o.status.code(), Some(1), "{:?}: {}", o.status, stderr(&o));
    let err = refused_in_one_line(&o);
    assert!(err.contains("file size limit"), "{err}");
    assert!(
        !out.exists() || files(&out).is_empty(),
        "half-written output"
    );
}
