//! Unit tests of the output writer and its policy.
use super::*;

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
            check_folder(&mut d).unwrap();
            let mut s = Staged::open(d).unwrap();
            for (name, bytes) in &files {
                s.put(name, bytes).unwrap();
            }
            s.seal(&run).unwrap();
            s
        })
        .collect();
    let mut done = Vec::new();
    commit(&staged[0], &mut done).unwrap();
    // The second destination's staged file vanishes before its move: that move fails.
    fs::remove_dir_all(staged[1].new_dir()).unwrap();
    fs::create_dir(&blocked).unwrap();
    assert!(commit(&staged[1], &mut done).is_err());
    for undo in done.into_iter().rev() {
        undo.apply();
    }
    staged.clear();
    assert_eq!(listing(&out), [MANIFEST, "x.txt"]);
    assert_eq!(fs::read_to_string(out.join("x.txt")).unwrap(), "old");
    assert_eq!(
        fs::read_to_string(out.join(MANIFEST)).unwrap(),
        "test\tx.txt\n"
    );
    assert_eq!(listing(root.path()), ["blocked", "out"]);
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
