//! Whose folder it is: a folder holding a user's files is refused unless `--force`, which still never
//! replaces an input; a folder the tool wrote before is updated in place; a path that cannot be a folder
//! or a file is named as what it is.

use super::*;

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

#[test]
fn a_folder_the_policy_refuses_is_refused_before_the_work() {
    // optimize and drive print their report before they write: a refusal with nothing on stdout
    // came before the work. nest and calibrate are refused by the same look ahead.
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("a-file");
    fs::write(&file, "mine").unwrap();
    let theirs = dir.path().join("theirs");
    fs::create_dir(&theirs).unwrap();
    fs::write(theirs.join("notes.txt"), "mine").unwrap();
    let commands: [&[&str]; 5] = [
        &["optimize", "examples/optimize-thesis.toml"],
        &["optimize", "examples/optimize-hawkmoth-wing.toml"],
        &["drive", "examples/drive-hawkmoth.toml"],
        &["nest", "examples/batch.toml"],
        &["calibrate", "examples/measured-thesis-like.csv"],
    ];
    for command in commands {
        for (out, says) in [
            (&file, "exists and is not a directory"),
            (&theirs, "did not write (notes.txt)"),
        ] {
            let mut args = command.to_vec();
            args.extend(["-o", out.to_str().unwrap()]);
            let o = run(&args);
            let err = refused_in_one_line(&o);
            assert!(err.contains(says), "{args:?}: {err}");
            assert_eq!(stdout(&o), "", "{args:?}");
        }
    }
    assert_eq!(fs::read_to_string(&file).unwrap(), "mine");
    assert_eq!(fs::read_dir(&theirs).unwrap().count(), 1);
    // An input under a name optimize writes, refused before the search even with --force.
    fs::copy(example("optimize-thesis.toml"), theirs.join("design.toml")).unwrap();
    let spec = theirs.join("design.toml");
    let o = run(&[
        "optimize",
        spec.to_str().unwrap(),
        "-o",
        theirs.to_str().unwrap(),
        "--force",
    ]);
    let err = refused_in_one_line(&o);
    assert!(err.contains("design.toml is an input of this run"), "{err}");
    assert_eq!(stdout(&o), "");
}
