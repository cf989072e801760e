//! Every class of misspelt key in every file kind is named as the user wrote it, with the key it misses
//! (docs/limits.md §8 lists the classes and the message each gets). The shipped examples and templates are
//! copied to a temporary folder, one key is misspelt there, and the command that reads the file is run.

use crate::common;
use common::*;
use std::path::Path;

/// A copy of `examples/` (with `parts/`) and of the shipped templates in a fresh folder.
fn examples_copy() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    for sub in ["examples", "examples/parts", "templates"] {
        std::fs::create_dir_all(dir.path().join(sub)).unwrap();
        for entry in std::fs::read_dir(root.join(sub)).unwrap() {
            let path = entry.unwrap().path();
            if path.is_file() {
                std::fs::copy(&path, dir.path().join(sub).join(path.file_name().unwrap())).unwrap();
            }
        }
    }
    dir
}

/// In the copy, replace every `from` by `to` in `file`.
fn misspell(dir: &Path, file: &str, from: &str, to: &str) {
    let path = dir.join(file);
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.contains(from), "{file} holds {from:?}");
    std::fs::write(&path, text.replace(from, to)).unwrap();
}

/// Run `command` in the copy (arguments with a `/` are paths in it, `OUT` its output folder) and return
/// its one-line refusal; the refused run leaves no output.
fn refusal(dir: &Path, command: &[&str]) -> String {
    let out = dir.join("out");
    let args: Vec<String> = command
        .iter()
        .map(|a| match *a {
            "OUT" => out.to_str().unwrap().to_string(),
            a if a.contains('/') => dir.join(a).to_str().unwrap().to_string(),
            a => a.to_string(),
        })
        .collect();
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let err = refused_in_one_line(&run(&args));
    assert!(!out.exists(), "a refused run left output: {err}");
    err
}

/// One misspelling: its class, the file and text misspelt, the command that reads it, the field as
/// the refusal must name it and the key it must offer.
struct Case {
    class: &'static str,
    file: &'static str,
    from: &'static str,
    to: &'static str,
    command: &'static [&'static str],
    written: &'static str,
    meant: &'static str,
}

const PREDICT: [&str; 2] = ["predict", "examples/thesis-C.toml"];
const DRIVE: [&str; 2] = ["drive", "examples/drive-hawkmoth.toml"];
const NEST: [&str; 4] = ["nest", "examples/batch-with-parts.toml", "-o", "OUT"];
const OPTIMIZE: [&str; 2] = ["optimize", "examples/optimize-thesis.toml"];

/// Each class of misspelling once (docs/limits.md §8).
const CASES: [Case; 14] = [
    Case {
        class: "letter dropped",
        file: "examples/thesis-C.toml",
        from: "length_mm",
        to: "length_m",
        command: &PREDICT,
        written: "geometry.length_m",
        meant: "length_mm",
    },
    Case {
        class: "letter case",
        file: "examples/thesis-C.toml",
        from: "width_ratio",
        to: "Width_ratio",
        command: &PREDICT,
        written: "geometry.Width_ratio",
        meant: "width_ratio",
    },
    Case {
        class: "two letters swapped, short required key",
        file: "examples/thesis-C.toml",
        from: "mode =",
        to: "omde =",
        command: &PREDICT,
        written: "drive.omde",
        meant: "mode",
    },
    Case {
        class: "two letters swapped, name",
        file: "examples/thesis-C.toml",
        from: "name =",
        to: "nmae =",
        command: &PREDICT,
        written: "nmae",
        meant: "name",
    },
    Case {
        class: "member of an exactly-one-of group",
        file: "examples/thesis-C.toml",
        from: "field_V_per_mm",
        to: "field_V_pe_rmm",
        command: &PREDICT,
        written: "drive.field_V_pe_rmm",
        meant: "field_V_per_mm",
    },
    Case {
        class: "table name",
        file: "examples/thesis-C.toml",
        from: "[geometry]",
        to: "[geomtery]",
        command: &PREDICT,
        written: "geomtery",
        meant: "geometry",
    },
    Case {
        class: "array-of-tables name",
        file: "examples/batch-with-parts.toml",
        from: "[[item]]",
        to: "[[tiem]]",
        command: &NEST,
        written: "tiem",
        meant: "item",
    },
    Case {
        class: "two letters swapped, part file",
        file: "examples/batch-with-parts.toml",
        from: "file = \"parts/spar.dxf\"",
        to: "ifle = \"parts/spar.dxf\"",
        command: &NEST,
        written: "part[1].ifle",
        meant: "file",
    },
    Case {
        class: "group member, wing planform",
        file: "examples/drive-hawkmoth.toml",
        from: "span_mm",
        to: "sapn_mm",
        command: &DRIVE,
        written: "wing.sapn_mm",
        meant: "span_mm",
    },
    Case {
        class: "two letters swapped, wing chord",
        file: "examples/drive-hawkmoth.toml",
        from: "chord =",
        to: "chrod =",
        command: &DRIVE,
        written: "wing.chrod",
        meant: "chord",
    },
    Case {
        class: "letter doubled, optional key",
        file: "examples/drive-hawkmoth.toml",
        from: "chord_mm",
        to: "chordd_mm",
        command: &DRIVE,
        written: "wing.chordd_mm",
        meant: "chord_mm",
    },
    Case {
        class: "either-or requirement",
        file: "examples/optimize-thesis.toml",
        from: "energy_mJ =",
        to: "enrgy_mJ =",
        command: &OPTIMIZE,
        written: "requirement.enrgy_mJ",
        meant: "energy_mJ",
    },
    Case {
        class: "two letters swapped, effect kind",
        file: "examples/effects-clamp-width.toml",
        from: "{ kind = \"clamp",
        to: "{ kidn = \"clamp",
        command: &[
            "calibrate",
            "examples/measured-thesis-like.csv",
            "--effects",
            "examples/effects-clamp-width.toml",
            "-o",
            "OUT",
        ],
        written: "effect[1].primitives[1].kidn",
        meant: "kind",
    },
    Case {
        class: "a valid neighbour is not blamed",
        file: "templates/method-2.toml",
        from: "window_width_mm",
        to: "windoww_idth_mm",
        command: &["cut-sheet", "examples/thesis-C.toml", "-o", "OUT"],
        written: "clamp.windoww_idth_mm",
        meant: "window_width_mm",
    },
];

#[test]
fn every_misspelling_class_is_named_as_written_with_the_key_it_misses() {
    for c in &CASES {
        let dir = examples_copy();
        misspell(dir.path(), c.file, c.from, c.to);
        if c.file.starts_with("templates/") {
            // The design names the copied template by path, and the refusal names the template.
            misspell(
                dir.path(),
                "examples/thesis-C.toml",
                "process = \"method-2\"",
                "process = \"../templates/method-2.toml\"",
            );
        }
        let err = refusal(dir.path(), c.command);
        assert!(
            err.contains(&format!(": {} = ", c.written))
                && err.contains(&format!("did you mean `{}`?", c.meant))
                && err.contains(c.file.rsplit('/').next().unwrap()),
            "{}: {err}",
            c.class
        );
    }
}
