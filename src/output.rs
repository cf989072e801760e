//! The one writer of output files. Every command that writes files (cut-sheet, nest, calibrate,
//! optimize `-o`/`--pareto`, sweep `--csv`) renders them in memory and hands them here, so one behaviour
//! holds for all of them:
//!
//! - Every file is first written into a staging folder beside its destination (a name starting with
//!   [`STAGING_PREFIX`]); only when all of them are written does anything move into place.
//! - A destination folder that does not exist yet is made by renaming its staging folder (missing parents
//!   are made, like `mkdir -p`). In a folder that exists, only the files this run writes are replaced, one
//!   rename each; everything else in the folder is left alone.
//! - If a move fails, the moves already made are undone (replaced files come back, new ones go), so a
//!   failure leaves no half-written output.
//!
//! The checks on what may be overwritten live in one place, `check_destination`, which runs for every
//! destination before anything is staged; a rule such as a manifest of the files a previous run wrote, or
//! `--force` (a field beside `-o` in `commands::flags::OutputDir`), belongs there. Staging folders are made
//! only in `stage` and carry [`STAGING_PREFIX`], so cleaning up after an interrupted run is one place too.

use std::fs;
use std::io;
use std::path::{Path, PathBuf};

/// Name prefix of the staging folders, so a leftover one (after a killed run) can be recognised.
pub const STAGING_PREFIX: &str = ".actuator-cam-staging-";

/// Why the output could not be written. Each message starts with the flag and the path as the user wrote
/// them.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    /// The destination folder is a file.
    #[error("{flag} {shown}: exists and is not a directory")]
    NotADirectory {
        /// The flag that named it.
        flag: String,
        /// The path as given.
        shown: String,
    },
    /// A file of this run would replace a folder of the same name.
    #[error("{flag} {shown}: {name} exists and is a directory")]
    FolderInTheWay {
        /// The flag that named the destination.
        flag: String,
        /// The path as given.
        shown: String,
        /// The file name.
        name: String,
    },
    /// The file name cannot be a file in a folder (`..`, `/`, empty).
    #[error("{flag} {shown}: not a file name")]
    NotAFileName {
        /// The flag.
        flag: String,
        /// The path as given.
        shown: String,
    },
    /// The folder that holds the destination (or the staging folder) cannot be made.
    #[error("{flag} {shown}: cannot create the directory {dir}")]
    CreateDir {
        /// The flag.
        flag: String,
        /// The path as given.
        shown: String,
        /// The folder.
        dir: String,
        /// The system's reason.
        #[source]
        source: io::Error,
    },
    /// Staging failed.
    #[error("{flag} {shown}: cannot write {what}")]
    Stage {
        /// The flag.
        flag: String,
        /// The path as given.
        shown: String,
        /// The file or folder being written.
        what: String,
        /// The system's reason.
        #[source]
        source: io::Error,
    },
    /// Moving the staged files into place failed (and was undone).
    #[error("{flag} {shown}: cannot move the finished files into place")]
    Commit {
        /// The flag.
        flag: String,
        /// The path as given.
        shown: String,
        /// The system's reason.
        #[source]
        source: io::Error,
    },
}

/// Where a destination's staging folder goes, and how its files move into place.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    /// `-o DIR`: staged beside the folder; a new folder arrives in one rename.
    Folder,
    /// A single named file (`-o best.toml`, `--csv designs.csv`): staged in the file's own folder, which
    /// may not let us write beside it (a home folder's parent).
    File,
}

/// One destination: a folder and the files this run puts into it.
#[derive(Debug)]
struct Destination {
    flag: String,
    shown: String,
    dir: PathBuf,
    kind: Kind,
    files: Vec<(String, Vec<u8>)>,
}

impl Destination {
    fn error_stage(&self, what: impl Into<String>, source: io::Error) -> OutputError {
        OutputError::Stage {
            flag: self.flag.clone(),
            shown: self.shown.clone(),
            what: what.into(),
            source,
        }
    }

    fn error_create(&self, dir: &Path, source: io::Error) -> OutputError {
        OutputError::CreateDir {
            flag: self.flag.clone(),
            shown: self.shown.clone(),
            dir: dir.display().to_string(),
            source,
        }
    }
}

/// Every file one run writes, gathered first and written together by [`Output::write`].
#[derive(Debug, Default)]
pub struct Output {
    destinations: Vec<Destination>,
}

impl Output {
    /// Nothing to write yet.
    pub fn new() -> Output {
        Output::default()
    }

    /// `files` (name, bytes) into the folder `dir`, named on the command line by `flag` (e.g. `-o`).
    pub fn folder(mut self, flag: &str, dir: &Path, files: Vec<(String, Vec<u8>)>) -> Output {
        self.destinations.push(Destination {
            flag: flag.into(),
            shown: dir.display().to_string(),
            dir: dir.to_path_buf(),
            kind: Kind::Folder,
            files,
        });
        self
    }

    /// One file at `path`, named on the command line by `flag` (e.g. `--csv`).
    pub fn file(mut self, flag: &str, path: &Path, bytes: impl Into<Vec<u8>>) -> Output {
        let dir = match path.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        };
        let name = path
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        self.destinations.push(Destination {
            flag: flag.into(),
            shown: path.display().to_string(),
            dir,
            kind: Kind::File,
            files: vec![(name, bytes.into())],
        });
        self
    }

    /// Write everything: check every destination, stage every file, then move them all into place. On an
    /// error nothing of this run is left in any destination.
    pub fn write(self) -> Result<(), OutputError> {
        for d in &self.destinations {
            check_destination(d)?;
        }
        let staged = self
            .destinations
            .into_iter()
            .map(stage)
            .collect::<Result<Vec<_>, _>>()?;
        let mut done: Vec<Undo> = Vec::new();
        for s in &staged {
            if let Err(source) = commit(s, &mut done) {
                for undo in done.into_iter().rev() {
                    undo.apply();
                }
                return Err(OutputError::Commit {
                    flag: s.dest.flag.clone(),
                    shown: s.dest.shown.clone(),
                    source,
                });
            }
        }
        // Dropping the staging folders removes them with the replaced files they hold.
        drop(staged);
        Ok(())
    }
}

/// What may be written where. Today: a folder destination must be a folder (or not exist), every name is
/// a plain file name, and no file of this run replaces a folder. This is the one place for any further
/// rule on overwriting.
fn check_destination(d: &Destination) -> Result<(), OutputError> {
    if d.dir.exists() && !d.dir.is_dir() {
        return Err(OutputError::NotADirectory {
            flag: d.flag.clone(),
            shown: d.shown.clone(),
        });
    }
    for (name, _) in &d.files {
        if !is_plain_file_name(name) {
            return Err(OutputError::NotAFileName {
                flag: d.flag.clone(),
                shown: d.shown.clone(),
            });
        }
        if d.dir.join(name).is_dir() {
            return Err(OutputError::FolderInTheWay {
                flag: d.flag.clone(),
                shown: d.shown.clone(),
                name: name.clone(),
            });
        }
    }
    Ok(())
}

/// A name that stays inside its folder: one component, not `.` or `..`.
fn is_plain_file_name(name: &str) -> bool {
    let mut components = Path::new(name).components();
    matches!(
        (components.next(), components.next()),
        (Some(std::path::Component::Normal(_)), None)
    )
}

/// A destination whose files are written into `staging/new`; replaced files go to `staging/old`.
struct Staged {
    dest: Destination,
    staging: tempfile::TempDir,
}

impl Staged {
    fn new_dir(&self) -> PathBuf {
        self.staging.path().join("new")
    }

    fn old_dir(&self) -> PathBuf {
        self.staging.path().join("old")
    }
}

/// Write a destination's files into a fresh staging folder beside it.
fn stage(dest: Destination) -> Result<Staged, OutputError> {
    let near = match dest.kind {
        Kind::File => dest.dir.clone(),
        Kind::Folder => match dest.dir.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        },
    };
    fs::create_dir_all(&near).map_err(|e| dest.error_create(&near, e))?;
    let staging = tempfile::Builder::new()
        .prefix(STAGING_PREFIX)
        .tempdir_in(&near)
        .map_err(|e| dest.error_stage(format!("in {}", near.display()), e))?;
    let staged = Staged { dest, staging };
    for dir in [staged.new_dir(), staged.old_dir()] {
        fs::create_dir(&dir)
            .map_err(|e| staged.dest.error_stage(format!("in {}", dir.display()), e))?;
    }
    for (name, bytes) in &staged.dest.files {
        fs::write(staged.new_dir().join(name), bytes)
            .map_err(|e| staged.dest.error_stage(name.clone(), e))?;
    }
    Ok(staged)
}

/// One move made into a destination, and how to take it back.
enum Undo {
    /// The destination folder was made by this run: remove it whole.
    CreatedFolder(PathBuf),
    /// A file was put at `target`; `previous` holds the file it replaced, if any.
    Placed {
        target: PathBuf,
        previous: Option<PathBuf>,
    },
}

impl Undo {
    /// Best effort: an undo that fails leaves the file as the run wrote it.
    fn apply(self) {
        match self {
            Undo::CreatedFolder(dir) => {
                let _ = fs::remove_dir_all(dir);
            }
            Undo::Placed { target, previous } => {
                let _ = match previous {
                    Some(old) => fs::rename(old, &target),
                    None => fs::remove_file(&target),
                };
            }
        }
    }
}

/// Move one destination's staged files into place, recording each move in `done`.
fn commit(s: &Staged, done: &mut Vec<Undo>) -> io::Result<()> {
    let dir = &s.dest.dir;
    if s.dest.kind == Kind::Folder && !dir.exists() {
        fs::rename(s.new_dir(), dir)?;
        done.push(Undo::CreatedFolder(dir.clone()));
        return Ok(());
    }
    for (name, _) in &s.dest.files {
        let target = dir.join(name);
        let previous = if fs::symlink_metadata(&target).is_ok() {
            let old = s.old_dir().join(name);
            fs::rename(&target, &old)?;
            Some(old)
        } else {
            None
        };
        if let Err(e) = fs::rename(s.new_dir().join(name), &target) {
            if let Some(old) = previous {
                let _ = fs::rename(old, &target);
            }
            return Err(e);
        }
        done.push(Undo::Placed { target, previous });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
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
        let o = Output::new().folder("-o", &out, files(&[("x.txt", "1"), ("y.txt", "2")]));
        o.write().unwrap();
        assert_eq!(listing(&out), ["x.txt", "y.txt"]);
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
        let o = Output::new().folder("-o", &out, files(&[("x.txt", "new"), ("y.txt", "2")]));
        o.write().unwrap();
        assert_eq!(listing(&out), ["notes.txt", "sub", "x.txt", "y.txt"]);
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
        let o = Output::new()
            .file("-o", &root.path().join("best.toml"), "a")
            .file("--pareto", &root.path().join("new/front.csv"), "b");
        o.write().unwrap();
        assert_eq!(listing(root.path()), ["best.toml", "new", "other.toml"]);
        assert_eq!(listing(&root.path().join("new")), ["front.csv"]);
    }

    #[test]
    fn a_failed_move_puts_everything_back() {
        let root = tempfile::tempdir().unwrap();
        let out = root.path().join("out");
        fs::create_dir(&out).unwrap();
        fs::write(out.join("x.txt"), "old").unwrap();
        let blocked = root.path().join("blocked");
        let o = Output::new()
            .folder("-o", &out, files(&[("x.txt", "new"), ("y.txt", "2")]))
            .folder("-o", &blocked, files(&[("z.txt", "3")]));
        let mut staged: Vec<Staged> = o
            .destinations
            .into_iter()
            .map(|d| stage(d).unwrap())
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
        assert_eq!(listing(&out), ["x.txt"]);
        assert_eq!(fs::read_to_string(out.join("x.txt")).unwrap(), "old");
        assert_eq!(listing(root.path()), ["blocked", "out"]);
    }

    #[test]
    fn a_file_where_a_folder_should_be_is_refused_before_anything_is_written() {
        let root = tempfile::tempdir().unwrap();
        let plain = root.path().join("plain");
        fs::write(&plain, "x").unwrap();
        let o = Output::new().folder("-o", &plain, files(&[("x.txt", "1")]));
        let e = o.write().unwrap_err().to_string();
        assert!(e.contains("not a directory"), "{e}");
        let out = root.path().join("out");
        fs::create_dir_all(out.join("x.txt")).unwrap();
        let o = Output::new().folder("-o", &out, files(&[("x.txt", "1")]));
        let e = o.write().unwrap_err().to_string();
        assert!(e.contains("is a directory"), "{e}");
        assert_eq!(listing(root.path()), ["out", "plain"]);
        let o = Output::new().folder("-o", &out, files(&[("../x.txt", "1")]));
        assert!(o.write().is_err());
    }
}
