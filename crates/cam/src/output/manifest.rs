//! The manifest: the list, kept in each folder the tool writes into, of the files it wrote there and which
//! command wrote each. It is how a later run tells its own files (which it may replace, and remove when a
//! run of the same command no longer writes them) from everything a user keeps in the folder (which it
//! never touches unasked).

use super::own_file::{self, OwnFileError};
use std::collections::BTreeSet;
use std::fs;
use std::io;
use std::path::{Path, PathBuf};

/// File name of the manifest in every folder the tool writes into.
pub const MANIFEST: &str = ".actuator-cam-manifest";

const HEADER: &str = "# actuator-cam: the files it wrote in this folder (command, file). \
It replaces or removes only these; delete this file to keep them as your own.\n";

/// Why a folder's manifest cannot be read.
#[derive(Debug)]
pub(super) enum ManifestError {
    /// The name holds something other than the tool's plain file.
    OwnFile(OwnFileError),
    /// The file is not one the tool could have written: `why` says where.
    Damaged { path: PathBuf, why: String },
}

/// The files the tool wrote in one folder, as `(command, file name)`.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Manifest {
    entries: BTreeSet<(String, String)>,
}

impl Manifest {
    /// The manifest of `dir`, `None` when the folder has none. A manifest the tool could not have
    /// written (empty, cut short, a line that is not `command<TAB>file`) is an error naming it, never
    /// read as a list of fewer files: that would make the tool's files the user's, and the next run
    /// would refuse the folder or keep a stale file for good.
    pub(super) fn read(dir: &Path) -> Result<Option<Manifest>, ManifestError> {
        let Some(bytes) = own_file::read(dir, MANIFEST).map_err(ManifestError::OwnFile)? else {
            return Ok(None);
        };
        let damaged = |why: String| ManifestError::Damaged {
            path: dir.join(MANIFEST),
            why,
        };
        let text = String::from_utf8(bytes).map_err(|_| damaged("not text".into()))?;
        if !text.ends_with('\n') {
            let why = if text.is_empty() {
                "empty"
            } else {
                "cut short"
            };
            return Err(damaged(why.into()));
        }
        let mut entries = BTreeSet::new();
        for (at, line) in text.lines().enumerate() {
            if line.starts_with('#') {
                continue;
            }
            match line.split_once('\t') {
                Some((command, name))
                    if !command.is_empty() && super::name::is_plain_file_name(name) =>
                {
                    entries.insert((command.to_string(), name.to_string()));
                }
                _ => return Err(damaged(format!("line {}: {line:?}", at + 1))),
            }
        }
        Ok(Some(Manifest { entries }))
    }

    /// A manifest of these `(command, file name)` entries.
    pub fn from_entries(entries: impl IntoIterator<Item = (String, String)>) -> Manifest {
        Manifest {
            entries: entries.into_iter().collect(),
        }
    }

    /// Every `(command, file name)` entry, sorted.
    pub fn entries(&self) -> impl Iterator<Item = (&str, &str)> {
        self.entries.iter().map(|(c, n)| (c.as_str(), n.as_str()))
    }

    /// The entries whose file is in `dir`.
    pub fn present_in(self, dir: &Path) -> Manifest {
        Manifest::from_entries(
            self.entries
                .into_iter()
                .filter(|(_, n)| fs::symlink_metadata(dir.join(n)).is_ok()),
        )
    }

    /// True when some run of the tool wrote `name` here.
    pub fn lists(&self, name: &str) -> bool {
        name == MANIFEST || self.entries.iter().any(|(_, n)| n == name)
    }

    /// The command that wrote `name` here, if the tool did.
    pub fn owner(&self, name: &str) -> Option<&str> {
        self.entries
            .iter()
            .find(|(_, n)| n == name)
            .map(|(c, _)| c.as_str())
    }

    /// Files `command` wrote here before that this run of it does not write: stale, to be removed.
    pub fn stale<'a>(
        &'a self,
        command: &'a str,
        now: &'a BTreeSet<&str>,
    ) -> impl Iterator<Item = &'a str> {
        self.entries
            .iter()
            .filter(move |(c, n)| c == command && !now.contains(n.as_str()))
            .map(|(_, n)| n.as_str())
    }

    /// The manifest after this run: `command` now owns exactly `written` among the names it owns (when
    /// `whole` is true, as for an `-o` folder, its other names are stale and go), any name written now
    /// changes owner to `command`, and names whose file is gone are dropped.
    pub fn after(
        &self,
        dir: &Path,
        command: &str,
        written: &BTreeSet<&str>,
        whole: bool,
    ) -> Manifest {
        let kept = self.entries.iter().filter(|(c, n)| {
            let replaced_now = written.contains(n.as_str()) || (whole && c == command);
            !replaced_now && fs::symlink_metadata(dir.join(n)).is_ok()
        });
        let entries = kept
            .cloned()
            .chain(written.iter().map(|n| (command.to_string(), n.to_string())))
            .collect();
        Manifest { entries }
    }

    /// The manifest as the bytes of its file, sorted, so the same runs give the same file.
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut text = HEADER.to_string();
        for (command, name) in &self.entries {
            text.push_str(command);
            text.push('\t');
            text.push_str(name);
            text.push('\n');
        }
        text.into_bytes()
    }
}

/// Every entry of a folder that the tool did not write: what a run without `--force` refuses to write
/// beside. The tool's own staging folders (with its marker) and the files named in `ours` (its lock, its intent log) are
/// not counted.
pub fn foreign_entries(
    dir: &Path,
    manifest: Option<&Manifest>,
    ours: &[&str],
) -> io::Result<Vec<String>> {
    let mut names = Vec::new();
    for entry in fs::read_dir(dir)? {
        let entry = entry?;
        let mut name = entry.file_name().to_string_lossy().into_owned();
        // A folder with the staging prefix is the tool's only if it carries the tool's marker.
        if (name.starts_with(super::staging::STAGING_PREFIX)
            && super::staging::is_ours(&entry.path()))
            || ours.contains(&name.as_str())
            || manifest.is_some_and(|m| m.lists(&name))
        {
            continue;
        }
        if entry.file_type().is_ok_and(|t| t.is_dir()) {
            name.push('/');
        }
        names.push(name);
    }
    names.sort();
    Ok(names)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn set<'a>(names: &[&'a str]) -> BTreeSet<&'a str> {
        names.iter().copied().collect()
    }

    #[test]
    fn round_trip_and_ownership() {
        let dir = tempfile::tempdir().unwrap();
        for n in ["a.svg", "b.svg", "best.toml"] {
            fs::write(dir.path().join(n), "x").unwrap();
        }
        let m = Manifest::default()
            .after(dir.path(), "cut-sheet", &set(&["a.svg", "b.svg"]), true)
            .after(dir.path(), "optimize", &set(&["best.toml"]), false);
        fs::write(dir.path().join(MANIFEST), m.to_bytes()).unwrap();
        let back = Manifest::read(dir.path()).unwrap().unwrap();
        assert_eq!(back, m);
        assert!(back.lists("a.svg") && back.lists(MANIFEST) && !back.lists("notes.txt"));
        // cut-sheet again, writing only a.svg: b.svg is stale, optimize's file is not.
        let now = set(&["a.svg"]);
        assert_eq!(back.stale("cut-sheet", &now).collect::<Vec<_>>(), ["b.svg"]);
        let next = back.after(dir.path(), "cut-sheet", &now, true);
        assert!(next.lists("best.toml") && !next.lists("b.svg"));
    }

    #[test]
    fn foreign_entries_skip_listed_files_and_staging() {
        let dir = tempfile::tempdir().unwrap();
        fs::write(dir.path().join("a.svg"), "x").unwrap();
        fs::write(dir.path().join("notes.txt"), "x").unwrap();
        fs::create_dir(dir.path().join("sub")).unwrap();
        fs::create_dir(
            dir.path()
                .join(format!("{}x", super::super::staging::STAGING_PREFIX)),
        )
        .unwrap();
        let m = Manifest::default().after(dir.path(), "cut-sheet", &set(&["a.svg"]), true);
        assert_eq!(
            foreign_entries(dir.path(), Some(&m), &[]).unwrap(),
            ["notes.txt", "sub/"]
        );
        assert_eq!(
            foreign_entries(dir.path(), None, &[]).unwrap(),
            ["a.svg", "notes.txt", "sub/"]
        );
    }
}
