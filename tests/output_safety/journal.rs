//! The writer's own files (lock, intent log, manifest, staging folders): a link, a damaged or hand-edited
//! log and a user's folder under the staging prefix are refused or left alone, never acted on.

use super::*;

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
