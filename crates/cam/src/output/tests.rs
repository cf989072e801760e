//! Unit tests of the output writer and its policy.
use super::*;
use std::fs;

fn files(names: &[(&str, &str)]) -> Vec<(String, Vec<u8>)> {
    names
        .iter()
        .map(|(n, t)| (n.to_string(), t.as_bytes().to_vec()))
        .collect()
}

fn listing(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

#[test]
fn a_new_folder_is_made_with_parents_and_no_staging_is_left() {
    let root = tempfile::tempdir().unwrap();
    let out = root.path().join("a/b/out");
    let o = Output::new("test").folder("-o", &out, files(&[("x.txt", "1"), ("y.txt", "2")]));
    o.write().unwrap();
    assert_eq!(listing(&out), [MANIFEST, "x.txt", "y.txt"]);
    assert_eq!(listing(&root.path().join("a/b")), ["out"]);
}

#[test]
fn an_existing_folder_keeps_what_the_run_does_not_write() {
    let root = tempfile::tempdir().unwrap();
    let out = root.path().join("out");
    fs::create_dir_all(out.join("sub")).unwrap();
    fs::write(out.join("notes.txt"), "mine").unwrap();
    fs::write(out.join("sub/keep.txt"), "mine too").unwrap();
    fs::write(out.join("x.txt"), "old").unwrap();
    let o = Output::new("test").folder("-o", &out, files(&[("x.txt", "new"), ("y.txt", "2")]));
    // The folder holds files the tool did not write: refused, and untouched.
    let e = o.write().unwrap_err().to_string();
    assert!(
        e.contains("did not write (notes.txt, sub/, x.txt)") && e.contains("--force"),
        "{e}"
    );
    assert_eq!(listing(&out), ["notes.txt", "sub", "x.txt"]);
    assert_eq!(fs::read_to_string(out.join("x.txt")).unwrap(), "old");
    let o = Output::new("test").force(true).folder(
        "-o",
        &out,
        files(&[("x.txt", "new"), ("y.txt", "2")]),
    );
    o.write().unwrap();
    assert_eq!(
        listing(&out),
        [MANIFEST, "notes.txt", "sub", "x.txt", "y.txt"]
    );
    assert_eq!(fs::read_to_string(out.join("x.txt")).unwrap(), "new");
    assert_eq!(fs::read_to_string(out.join("notes.txt")).unwrap(), "mine");
    assert_eq!(
        fs::read_to_string(out.join("sub/keep.txt")).unwrap(),
        "mine too"
    );
    assert_eq!(listing(root.path()), ["out"]);
}

#[test]
fn single_files_land_beside_their_neighbours() {
    let root = tempfile::tempdir().unwrap();
    fs::write(root.path().join("other.toml"), "keep").unwrap();
    let o = Output::new("test")
        .file("-o", &root.path().join("best.toml"), "a")
        .file("--pareto", &root.path().join("new/front.csv"), "b");
    o.write().unwrap();
    assert_eq!(
        listing(root.path()),
        [MANIFEST, "best.toml", "new", "other.toml"]
    );
    assert_eq!(listing(&root.path().join("new")), [MANIFEST, "front.csv"]);
    // The user's own file of an output's name is not replaced unasked; the tool's own is.
    let e = Output::new("test")
        .file("-o", &root.path().join("other.toml"), "z")
        .write()
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("other.toml exists and actuator-cam did not write it"),
        "{e}"
    );
    Output::new("test")
        .file("-o", &root.path().join("best.toml"), "again")
        .write()
        .unwrap();
    assert_eq!(
        fs::read_to_string(root.path().join("other.toml")).unwrap(),
        "keep"
    );
    assert_eq!(
        fs::read_to_string(root.path().join("best.toml")).unwrap(),
        "again"
    );
}

#[test]
fn a_failed_move_puts_everything_back() {
    let root = tempfile::tempdir().unwrap();
    let out = root.path().join("out");
    fs::create_dir(&out).unwrap();
    fs::write(out.join("x.txt"), "old").unwrap();
    fs::write(out.join(MANIFEST), "test\tx.txt\n").unwrap();
    let blocked = root.path().join("blocked");
    let o = Output::new("test")
        .folder("-o", &out, files(&[("x.txt", "new"), ("y.txt", "2")]))
        .folder("-o", &blocked, files(&[("z.txt", "3")]));
    let run = o.run.clone();
    let mut staged: Vec<Staged> = o
        .destinations
        .into_iter()
        .map(|(mut d, files)| {
            let claim = d.claim(&run).unwrap();
            let mut s = Staged::open(d, claim).unwrap();
            for (name, bytes) in &files {
                s.put(name, bytes).unwrap();
            }
            s.seal(&run).unwrap();
            s
        })
        .collect();
    // The second destination's staged files vanish before its moves: its first move fails, after the
    // first destination's moves are made.
    fs::remove_dir_all(staged[1].new_dir()).unwrap();
    let e = commit_all(&mut staged).unwrap_err().to_string();
    assert!(
        e.contains("cannot move the finished files into place"),
        "{e}"
    );
    drop(staged);
    assert_eq!(listing(&out), [MANIFEST, "x.txt"]);
    assert_eq!(fs::read_to_string(out.join("x.txt")).unwrap(), "old");
    assert_eq!(
        fs::read_to_string(out.join(MANIFEST)).unwrap(),
        "test\tx.txt\n"
    );
    // The folder made for the second destination is gone again.
    assert_eq!(listing(root.path()), ["out"]);
}

#[test]
fn a_second_run_waits_then_is_refused_naming_the_first() {
    let root = tempfile::tempdir().unwrap();
    let out = root.path().join("out");
    let mut first = Destination::new("-o", "out".into(), out.clone(), Kind::Folder);
    let held = first.claim(&Output::new("nest").run).unwrap();
    let started = std::time::Instant::now();
    let e = Output::new("cut-sheet")
        .folder("-o", &out, files(&[("x.txt", "1")]))
        .write()
        .unwrap_err()
        .to_string();
    assert!(started.elapsed() >= std::time::Duration::from_secs(2));
    let pid = std::process::id();
    assert_eq!(
        e,
        format!(
            "-o {}: another run (actuator-cam nest, pid {pid}) is writing into this folder; wait for it to \
             end, or choose another -o",
            out.display()
        )
    );
    drop(held);
    // Let go: the folder made for the first run is gone, and the second run goes ahead.
    assert_eq!(listing(root.path()), Vec::<String>::new());
    Output::new("cut-sheet")
        .folder("-o", &out, files(&[("x.txt", "1")]))
        .write()
        .unwrap();
    assert_eq!(listing(&out), [MANIFEST, "x.txt"]);
}

#[test]
fn another_commands_file_is_replaced_only_with_force() {
    let root = tempfile::tempdir().unwrap();
    let out = root.path().join("out");
    Output::new("calibrate")
        .folder("-o", &out, files(&[("report.md", "calibrate")]))
        .write()
        .unwrap();
    let cut = || Output::new("cut-sheet").folder("-o", &out, files(&[("report.md", "cut")]));
    let e = cut().write().unwrap_err().to_string();
    assert!(
        e.contains("report.md was written by `actuator-cam calibrate`") && e.contains("--force"),
        "{e}"
    );
    assert_eq!(
        fs::read_to_string(out.join("report.md")).unwrap(),
        "calibrate"
    );
    cut().force(true).write().unwrap();
    assert_eq!(fs::read_to_string(out.join("report.md")).unwrap(), "cut");
    assert!(fs::read_to_string(out.join(MANIFEST))
        .unwrap()
        .ends_with("cut-sheet\treport.md\n"));
}

#[test]
fn two_flags_naming_one_file_are_refused() {
    let root = tempfile::tempdir().unwrap();
    let x = root.path().join("X");
    let e = Output::new("optimize")
        .file("-o", &x, "design")
        .file("--pareto", &x, "front")
        .write()
        .unwrap_err()
        .to_string();
    assert_eq!(
        e,
        format!(
            "--pareto {}: the same file as -o; give each its own name",
            x.display()
        )
    );
    assert!(listing(root.path()).is_empty());
}

#[test]
fn the_next_run_finishes_the_moves_a_killed_run_left() {
    let root = tempfile::tempdir().unwrap();
    let out = root.path().join("out");
    Output::new("test")
        .folder("-o", &out, files(&[("a.txt", "1"), ("b.txt", "1")]))
        .write()
        .unwrap();
    // A run that meant to replace a.txt, remove b.txt and add c.txt died after its first two moves:
    // b.txt is gone, a.txt is in the staging folder's old/, its new a.txt still staged.
    let staging = out.join(format!("{STAGING_PREFIX}dead"));
    for sub in ["new", "old"] {
        fs::create_dir_all(staging.join(sub)).unwrap();
    }
    fs::write(staging.join("new/a.txt"), "2").unwrap();
    fs::write(staging.join("new/c.txt"), "2").unwrap();
    fs::write(
        staging.join(format!("new/{MANIFEST}")),
        "test\ta.txt\ntest\tc.txt\n",
    )
    .unwrap();
    fs::rename(out.join("b.txt"), staging.join("old/b.txt")).unwrap();
    fs::rename(out.join("a.txt"), staging.join("old/a.txt")).unwrap();
    staging::mark(&staging);
    let owners = [("test", "a.txt"), ("test", "c.txt")].map(|(c, n)| (c.into(), n.into()));
    let log = intent::to_text(
        &format!("{STAGING_PREFIX}dead"),
        &["b.txt".into()],
        &["a.txt".into(), "c.txt".into(), MANIFEST.into()],
        &manifest::Manifest::from_entries(owners),
    );
    fs::write(out.join(INTENT), log).unwrap();
    // Another staging folder, of a run killed while staging.
    let other = out.join(format!("{STAGING_PREFIX}other"));
    fs::create_dir(&other).unwrap();
    staging::mark(&other);
    // A user's folder that only looks like one.
    let photos = out.join(format!("{STAGING_PREFIX}photos"));
    fs::create_dir(&photos).unwrap();
    fs::write(photos.join("a.jpg"), "jpeg").unwrap();
    // Any run that claims the folder finishes the moves first.
    Output::new("other")
        .file("-o", &out.join("d.txt"), "3")
        .write()
        .unwrap();
    assert_eq!(
        listing(&out),
        [
            MANIFEST.to_string(),
            format!("{STAGING_PREFIX}photos"),
            "a.txt".into(),
            "c.txt".into(),
            "d.txt".into()
        ]
    );
    assert_eq!(fs::read(photos.join("a.jpg")).unwrap(), b"jpeg");
    assert_eq!(fs::read_to_string(out.join("a.txt")).unwrap(), "2");
    assert_eq!(
        fs::read_to_string(out.join(MANIFEST))
            .unwrap()
            .lines()
            .filter(|l| !l.starts_with('#'))
            .collect::<Vec<_>>(),
        ["other\td.txt", "test\ta.txt", "test\tc.txt"]
    );
}

#[test]
fn a_file_where_a_folder_should_be_is_refused_before_anything_is_written() {
    let root = tempfile::tempdir().unwrap();
    let plain = root.path().join("plain");
    fs::write(&plain, "x").unwrap();
    let o = Output::new("test").folder("-o", &plain, files(&[("x.txt", "1")]));
    let e = o.write().unwrap_err().to_string();
    assert!(e.contains("not a directory"), "{e}");
    let out = root.path().join("out");
    fs::create_dir_all(out.join("x.txt")).unwrap();
    let o = Output::new("test").folder("-o", &out, files(&[("x.txt", "1")]));
    let e = o.write().unwrap_err().to_string();
    assert!(e.contains("is a directory"), "{e}");
    assert_eq!(listing(root.path()), ["out", "plain"]);
    let o = Output::new("test").folder("-o", &out, files(&[("../x.txt", "1")]));
    assert!(o.write().is_err());
}

#[test]
fn a_second_run_removes_only_its_own_stale_files() {
    let root = tempfile::tempdir().unwrap();
    let out = root.path().join("out");
    let first = files(&[("a.svg", "1"), ("b.svg", "2"), ("report.md", "r")]);
    Output::new("cut-sheet")
        .folder("-o", &out, first)
        .write()
        .unwrap();
    Output::new("optimize")
        .file("-o", &out.join("best.toml"), "d")
        .write()
        .unwrap();
    fs::write(out.join("notes.txt"), "mine").unwrap();
    let second = files(&[("a.svg", "1'"), ("report.md", "r'")]);
    Output::new("cut-sheet")
        .folder("-o", &out, second)
        .write()
        .unwrap();
    assert_eq!(
        listing(&out),
        [MANIFEST, "a.svg", "best.toml", "notes.txt", "report.md"]
    );
    let m = fs::read_to_string(out.join(MANIFEST)).unwrap();
    assert!(
        m.ends_with("cut-sheet\ta.svg\ncut-sheet\treport.md\noptimize\tbest.toml\n"),
        "{m}"
    );
    assert_eq!(listing(root.path()), ["out"]);
}

#[test]
fn inputs_are_never_replaced_even_with_force() {
    let root = tempfile::tempdir().unwrap();
    let out = root.path().join("out");
    fs::create_dir(&out).unwrap();
    fs::write(out.join("design.toml"), "input").unwrap();
    let e = Output::new("cut-sheet")
        .force(true)
        .inputs([out.join("design.toml")])
        .folder("-o", &out, files(&[("design.toml", "x")]))
        .write()
        .unwrap_err()
        .to_string();
    assert!(e.contains("design.toml is an input of this run"), "{e}");
    assert_eq!(
        fs::read_to_string(out.join("design.toml")).unwrap(),
        "input"
    );
    assert_eq!(listing(&out), ["design.toml"]);
}

#[test]
fn a_stream_writes_what_a_batch_writes_and_an_unfinished_one_leaves_nothing() {
    let root = tempfile::tempdir().unwrap();
    let batch = root.path().join("batch");
    let some = files(&[("a.svg", "1"), ("b.dxf", "2"), ("report.md", "r")]);
    Output::new("cut-sheet")
        .folder("-o", &batch, some.clone())
        .write()
        .unwrap();
    let streamed = root.path().join("new/deep/streamed");
    let mut s = Output::new("cut-sheet")
        .stream_folder("-o", &streamed)
        .unwrap();
    for (name, bytes) in &some {
        s.add(name, bytes).unwrap();
    }
    assert_eq!(s.len(), 3);
    s.finish().unwrap();
    assert_eq!(listing(&streamed), listing(&batch));
    for name in listing(&batch) {
        assert_eq!(
            fs::read(streamed.join(&name)).unwrap(),
            fs::read(batch.join(&name)).unwrap(),
            "{name}"
        );
    }
    // Dropped half-way (an error in the run): no staging folder, no output, and the folders made to
    // hold it are gone again.
    let other = root.path().join("made/for/other");
    let mut s = Output::new("cut-sheet")
        .stream_folder("-o", &other)
        .unwrap();
    s.add("a.svg", b"1").unwrap();
    assert!(root.path().join("made/for").is_dir());
    drop(s);
    assert_eq!(listing(root.path()), ["batch", "new"]);
}

#[test]
fn a_stream_checks_the_folder_first_and_each_name_as_it_comes() {
    let root = tempfile::tempdir().unwrap();
    let out = root.path().join("out");
    fs::create_dir(&out).unwrap();
    fs::write(out.join("notes.txt"), "mine").unwrap();
    // A folder the tool did not write: refused before any work.
    let e = Output::new("cut-sheet")
        .stream_folder("-o", &out)
        .unwrap_err()
        .to_string();
    assert!(e.contains("did not write (notes.txt)"), "{e}");
    // With --force, a file of the same name as an input is refused when it comes; nothing is left.
    let mut s = Output::new("cut-sheet")
        .force(true)
        .inputs([out.join("notes.txt")])
        .stream_folder("-o", &out)
        .unwrap();
    s.add("a.svg", b"1").unwrap();
    let e = s.add("notes.txt", b"x").unwrap_err().to_string();
    assert!(e.contains("notes.txt is an input of this run"), "{e}");
    drop(s);
    assert_eq!(listing(&out), ["notes.txt"]);
    assert_eq!(listing(root.path()), ["out"]);
}

#[test]
fn system_errors_are_said_in_words() {
    // Linux error numbers (asm-generic/errno-base.h), whose raw messages ("Invalid cross-device link",
    // "No such file or directory") say nothing a user can act on.
    let said = |errno: i32| in_words(&std::io::Error::from_raw_os_error(errno));
    assert_eq!(said(13), "the folder is read-only (permission denied)");
    assert_eq!(
        said(30),
        "the folder is read-only (a read-only file system)"
    );
    assert_eq!(
        said(18),
        "the files would have to move to another file system"
    );
    assert_eq!(
        said(2),
        "a folder on the way does not exist (was it removed?)"
    );
    assert_eq!(said(28), "the disk is full");
    assert!(
        said(27).contains("file size limit, ulimit -f"),
        "{}",
        said(27)
    );
    for errno in [2, 13, 18, 27, 28, 30] {
        assert!(!said(errno).contains("os error"), "{}", said(errno));
    }
}

#[test]
fn the_look_ahead_refuses_what_the_write_would_and_holds_nothing() {
    let root = tempfile::tempdir().unwrap();
    let run = || Output::new("test").inputs([root.path().join("in/spec.toml")]);
    // A new folder, and one the same command wrote: nothing to refuse, and nothing made.
    let fresh = root.path().join("fresh");
    run().check_folder_ahead("-o", &fresh, &["x.txt"]).unwrap();
    assert!(!fresh.exists());
    let ours = root.path().join("ours");
    run()
        .folder("-o", &ours, files(&[("x.txt", "1")]))
        .write()
        .unwrap();
    run().check_folder_ahead("-o", &ours, &["x.txt"]).unwrap();
    assert_eq!(listing(&ours), [MANIFEST, "x.txt"]);
    // A file where the folder should be.
    let file = root.path().join("file");
    fs::write(&file, "mine").unwrap();
    let e = run().check_folder_ahead("-o", &file, &[]).unwrap_err();
    assert!(
        e.to_string().ends_with("exists and is not a directory"),
        "{e}"
    );
    // A folder of the user's, refused without --force and taken with it; neither holds it (no lock).
    let theirs = root.path().join("theirs");
    fs::create_dir(&theirs).unwrap();
    fs::write(theirs.join("notes.txt"), "mine").unwrap();
    let e = run().check_folder_ahead("-o", &theirs, &[]).unwrap_err();
    assert!(e.to_string().contains("did not write (notes.txt)"), "{e}");
    run()
        .force(true)
        .check_folder_ahead("-o", &theirs, &["x.txt"])
        .unwrap();
    assert_eq!(listing(&theirs), ["notes.txt"]);
    // An input under a name the run writes, refused even with --force; under another name, not.
    fs::create_dir(root.path().join("in")).unwrap();
    fs::write(root.path().join("in/spec.toml"), "mine").unwrap();
    let e = run()
        .force(true)
        .check_folder_ahead("-o", &root.path().join("in"), &["spec.toml"])
        .unwrap_err();
    assert!(
        e.to_string().contains("spec.toml is an input of this run"),
        "{e}"
    );
    run()
        .force(true)
        .check_folder_ahead("-o", &root.path().join("in"), &["x.txt"])
        .unwrap();
    assert_eq!(listing(&root.path().join("in")), ["spec.toml"]);
}
