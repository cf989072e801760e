//! Interrupted runs: after a signal or a SIGKILL at any point of a run, once the next run has looked, the
//! folder holds the files of the run before it or of the interrupted run in full; two runs into one folder
//! never mix.

use super::*;

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
