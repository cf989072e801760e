//! The one writer of output files. Every command that writes files (cut-sheet, nest, calibrate,
//! optimize `-o`/`--pareto`, sweep `--csv`) renders them in memory and hands them here, so one policy
//! holds for all of them: nothing a user owns is deleted or overwritten unasked.
//!
//! - **Where it writes.** Into a folder that does not exist, an empty folder, or a folder it wrote before,
//!   which it recognises by the [`MANIFEST`] it leaves there (the files it wrote, and which command wrote
//!   each). Any other folder is refused with the folder, what is in the way, and how to go on (another
//!   `-o`, or `--force`). A single named file (`-o best.toml`, `--csv designs.csv`) may replace only a
//!   file the tool wrote, unless `--force`.
//! - **What it replaces.** Only the files this run writes. In a folder it wrote before, the files the same
//!   command wrote there last time and does not write now (a sheet fewer) are removed; nothing the manifest
//!   does not list is ever removed, with or without `--force`, and an input file of the run is never
//!   overwritten.
//! - **How.** Every file is first written into a staging folder beside its destination (a name starting
//!   with [`STAGING_PREFIX`]); only when all are written does anything move into place. If a move fails,
//!   the moves already made are undone, so a failure leaves no half-written output. SIGINT and SIGTERM
//!   remove the staging folder ([`remove_after_interrupt`], called by the command layer's handler); one left
//!   by a SIGKILL is removed by the next run that stages in the same place.

mod manifest;
mod staging;

pub use manifest::MANIFEST;
pub use staging::{remove_after_interrupt, STAGING_PREFIX};

use manifest::{foreign_entries, Manifest};
use staging::{Staging, MOVING};
use std::collections::BTreeSet;
use std::fs;
use std::io;
use std::path::{Path, PathBuf};

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
    /// The folder holds files the tool did not write.
    #[error(
        "{flag} {shown}: the folder holds files actuator-cam did not write ({listing}); choose another \
         {flag}, or pass --force to write beside them (it replaces only files of the same name, never an input)"
    )]
    Occupied {
        /// The flag that named it.
        flag: String,
        /// The path as given.
        shown: String,
        /// The first few entries in the way.
        listing: String,
    },
    /// A file of the same name exists and the tool did not write it.
    #[error(
        "{flag} {shown}: {name} exists and actuator-cam did not write it; choose another {flag}, or pass \
         --force to replace it"
    )]
    WouldReplace {
        /// The flag.
        flag: String,
        /// The path as given.
        shown: String,
        /// The file's name.
        name: String,
    },
    /// A file of this run would replace one of the run's inputs.
    #[error("{flag} {shown}: {name} is an input of this run and is never overwritten; choose another {flag}")]
    InputInTheWay {
        /// The flag.
        flag: String,
        /// The path as given.
        shown: String,
        /// The file's name.
        name: String,
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
    /// The folder cannot be read to see what is in it.
    #[error("{flag} {shown}: cannot read the folder")]
    Unreadable {
        /// The flag.
        flag: String,
        /// The path as given.
        shown: String,
        /// The system's reason.
        #[source]
        source: io::Error,
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
    /// `-o DIR`: the whole folder is this command's output; staged beside the folder, and a new folder
    /// arrives in one rename.
    Folder,
    /// Named files (`-o best.toml`, `--csv designs.csv`) in a folder that is otherwise the user's: staged in
    /// that folder, which may not let us write beside it (a home folder's parent).
    Files,
}

/// One destination folder and the files this run puts into it.
#[derive(Debug)]
struct Destination {
    flag: String,
    shown: String,
    dir: PathBuf,
    kind: Kind,
    files: Vec<(String, Vec<u8>)>,
    /// Files the same command wrote here before and does not write now, found by the policy check.
    stale: Vec<String>,
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
#[derive(Debug)]
pub struct Output {
    command: String,
    force: bool,
    inputs: Vec<PathBuf>,
    destinations: Vec<Destination>,
}

impl Output {
    /// Nothing to write yet, for a run of `command` (the name the manifest records).
    pub fn new(command: &str) -> Output {
        Output {
            command: command.into(),
            force: false,
            inputs: Vec::new(),
            destinations: Vec::new(),
        }
    }

    /// `--force`: write into a folder that holds other files, and replace files of the same name the tool
    /// did not write. Never an input, never a file the run does not write.
    pub fn force(mut self, force: bool) -> Output {
        self.force = force;
        self
    }

    /// Files this run reads: never overwritten, never removed, whatever the flags.
    pub fn inputs<P: AsRef<Path>>(mut self, paths: impl IntoIterator<Item = P>) -> Output {
        self.inputs.extend(
            paths
                .into_iter()
                .filter_map(|p| p.as_ref().canonicalize().ok()),
        );
        self
    }

    /// `files` (name, bytes) into the folder `dir`, named on the command line by `flag` (e.g. `-o`).
    pub fn folder(mut self, flag: &str, dir: &Path, files: Vec<(String, Vec<u8>)>) -> Output {
        self.destinations.push(Destination {
            flag: flag.into(),
            shown: dir.display().to_string(),
            dir: dir.to_path_buf(),
            kind: Kind::Folder,
            files,
            stale: Vec::new(),
        });
        self
    }

    /// One file at `path`, named on the command line by `flag` (e.g. `--csv`). Files of one run in the same
    /// folder share one destination, so the folder's manifest is written once.
    pub fn file(mut self, flag: &str, path: &Path, bytes: impl Into<Vec<u8>>) -> Output {
        let dir = match path.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        };
        let name = path
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        let file = (name, bytes.into());
        match self
            .destinations
            .iter_mut()
            .find(|d| d.kind == Kind::Files && d.dir == dir)
        {
            Some(d) => d.files.push(file),
            None => self.destinations.push(Destination {
                flag: flag.into(),
                shown: path.display().to_string(),
                dir,
                kind: Kind::Files,
                files: vec![file],
                stale: Vec::new(),
            }),
        }
        self
    }

    /// Write everything: check every destination against the policy, stage every file (with the updated
    /// manifest), then move them all into place. On an error nothing of this run is left anywhere.
    pub fn write(mut self) -> Result<(), OutputError> {
        for d in &mut self.destinations {
            check_destination(d, &self.command, &self.inputs, self.force)?;
            let manifest = manifest_after(d, &self.command);
            d.files.push((MANIFEST.to_string(), manifest));
        }
        let staged = self
            .destinations
            .into_iter()
            .map(stage)
            .collect::<Result<Vec<_>, _>>()?;
        let _moving = MOVING.lock().unwrap_or_else(|e| e.into_inner());
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
        // Dropping the staging folders removes them with the replaced and stale files they hold.
        drop(staged);
        Ok(())
    }
}

/// The policy: what may be written where. Runs for every destination before anything is staged, and
/// records the stale files a folder run will remove.
fn check_destination(
    d: &mut Destination,
    command: &str,
    inputs: &[PathBuf],
    force: bool,
) -> Result<(), OutputError> {
    let refuse = |make: fn(String, String, String) -> OutputError, what: String| {
        Err(make(d.flag.clone(), d.shown.clone(), what))
    };
    if d.dir.exists() && !d.dir.is_dir() {
        return Err(OutputError::NotADirectory {
            flag: d.flag.clone(),
            shown: d.shown.clone(),
        });
    }
    for (name, _) in &d.files {
        if !is_plain_file_name(name) || name == MANIFEST {
            return Err(OutputError::NotAFileName {
                flag: d.flag.clone(),
                shown: d.shown.clone(),
            });
        }
        let target = d.dir.join(name);
        if target.is_dir() {
            return refuse(
                |flag, shown, name| OutputError::FolderInTheWay { flag, shown, name },
                name.clone(),
            );
        }
        if is_input(&target, inputs) {
            return refuse(
                |flag, shown, name| OutputError::InputInTheWay { flag, shown, name },
                name.clone(),
            );
        }
    }
    if !d.dir.exists() {
        return Ok(());
    }
    let manifest = Manifest::read(&d.dir);
    if d.kind == Kind::Folder && manifest.is_none() && !force {
        let foreign = foreign_entries(&d.dir, None).map_err(|source| OutputError::Unreadable {
            flag: d.flag.clone(),
            shown: d.shown.clone(),
            source,
        })?;
        if !foreign.is_empty() {
            return refuse(
                |flag, shown, listing| OutputError::Occupied {
                    flag,
                    shown,
                    listing,
                },
                listing(&foreign),
            );
        }
    }
    if !force {
        let ours = |name: &str| manifest.as_ref().is_some_and(|m| m.lists(name));
        if let Some((name, _)) = d
            .files
            .iter()
            .find(|(name, _)| fs::symlink_metadata(d.dir.join(name)).is_ok() && !ours(name))
        {
            return refuse(
                |flag, shown, name| OutputError::WouldReplace { flag, shown, name },
                name.clone(),
            );
        }
    }
    if d.kind == Kind::Folder {
        if let Some(m) = &manifest {
            let now: BTreeSet<&str> = d.files.iter().map(|(n, _)| n.as_str()).collect();
            d.stale = m
                .stale(command, &now)
                .filter(|n| is_plain_file_name(n))
                .filter(|n| {
                    let p = d.dir.join(n);
                    p.is_file() && !is_input(&p, inputs)
                })
                .map(str::to_string)
                .collect();
        }
    }
    Ok(())
}

/// The bytes of the destination's manifest after this run.
fn manifest_after(d: &Destination, command: &str) -> Vec<u8> {
    let written: BTreeSet<&str> = d.files.iter().map(|(n, _)| n.as_str()).collect();
    Manifest::read(&d.dir)
        .unwrap_or_default()
        .after(&d.dir, command, &written, d.kind == Kind::Folder)
        .to_bytes()
}

/// The first few names, for an error line.
fn listing(names: &[String]) -> String {
    const SHOWN: usize = 4;
    let mut text = names
        .iter()
        .take(SHOWN)
        .cloned()
        .collect::<Vec<_>>()
        .join(", ");
    if names.len() > SHOWN {
        text.push_str(&format!(" and {} more", names.len() - SHOWN));
    }
    text
}

/// True when `path` is (the same file as) one of the run's inputs.
fn is_input(path: &Path, inputs: &[PathBuf]) -> bool {
    path.canonicalize().is_ok_and(|p| inputs.contains(&p))
}

/// A name that stays inside its folder: one component, not `.` or `..`.
fn is_plain_file_name(name: &str) -> bool {
    let mut components = Path::new(name).components();
    matches!(
        (components.next(), components.next()),
        (Some(std::path::Component::Normal(_)), None)
    )
}

/// A destination whose files are written into `staging/new`; replaced and stale files go to
/// `staging/old`, and vanish with it.
struct Staged {
    dest: Destination,
    staging: Staging,
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
        Kind::Files => dest.dir.clone(),
        Kind::Folder => match dest.dir.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        },
    };
    fs::create_dir_all(&near).map_err(|e| dest.error_create(&near, e))?;
    let staging = Staging::new_in(&near)
        .map_err(|e| dest.error_stage(format!("in {}", near.display()), e))?;
    let staged = Staged { dest, staging };
    for dir in [staged.new_dir(), staged.old_dir()] {
        staged
            .staging
            .create_dir(&dir)
            .map_err(|e| staged.dest.error_stage(format!("in {}", dir.display()), e))?;
    }
    for (name, bytes) in &staged.dest.files {
        staged
            .staging
            .write(&staged.new_dir().join(name), bytes)
            .map_err(|e| staged.dest.error_stage(name.clone(), e))?;
    }
    Ok(staged)
}

/// One move made into a destination, and how to take it back.
enum Undo {
    /// The destination folder was made by this run: remove it whole.
    CreatedFolder(PathBuf),
    /// A file was put at `target` (or, for a stale file, taken away); `previous` holds the file that was
    /// there, if any.
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

/// Move one destination's staged files into place and its stale files out, recording each move in
/// `done`.
fn commit(s: &Staged, done: &mut Vec<Undo>) -> io::Result<()> {
    let dir = &s.dest.dir;
    if s.dest.kind == Kind::Folder && !dir.exists() {
        fs::rename(s.new_dir(), dir)?;
        done.push(Undo::CreatedFolder(dir.clone()));
        return Ok(());
    }
    for name in &s.dest.stale {
        let target = dir.join(name);
        let old = s.old_dir().join(name);
        fs::rename(&target, &old)?;
        done.push(Undo::Placed {
            target,
            previous: Some(old),
        });
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
mod tests;
