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

/// One destination folder: where it is, how it was named, and what the policy found there.
#[derive(Debug)]
struct Destination {
    flag: String,
    shown: String,
    dir: PathBuf,
    kind: Kind,
    /// The folder's manifest as the run found it.
    manifest: Option<Manifest>,
    /// Files the same command wrote here before and does not write now, found when the run is sealed.
    stale: Vec<String>,
}

impl Destination {
    fn new(flag: &str, shown: String, dir: PathBuf, kind: Kind) -> Destination {
        Destination {
            flag: flag.into(),
            shown,
            dir,
            kind,
            manifest: None,
            stale: Vec::new(),
        }
    }

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

/// Files of a destination as (name, bytes), in order.
type Files = Vec<(String, Vec<u8>)>;

/// What every destination of one run shares: the command that writes, `--force`, the run's inputs.
#[derive(Debug, Clone)]
struct Run {
    command: String,
    force: bool,
    inputs: Vec<PathBuf>,
}

/// Every file one run writes, gathered first and written together by [`Output::write`]; or, for a run
/// too large to hold in memory, one folder written file by file ([`Output::stream_folder`]).
#[derive(Debug)]
pub struct Output {
    run: Run,
    destinations: Vec<(Destination, Files)>,
}

impl Output {
    /// Nothing to write yet, for a run of `command` (the name the manifest records).
    pub fn new(command: &str) -> Output {
        Output {
            run: Run {
                command: command.into(),
                force: false,
                inputs: Vec::new(),
            },
            destinations: Vec::new(),
        }
    }

    /// `--force`: write into a folder that holds other files, and replace files of the same name the tool
    /// did not write. Never an input, never a file the run does not write.
    pub fn force(mut self, force: bool) -> Output {
        self.run.force = force;
        self
    }

    /// Files this run reads: never overwritten, never removed, whatever the flags.
    pub fn inputs<P: AsRef<Path>>(mut self, paths: impl IntoIterator<Item = P>) -> Output {
        self.run.inputs.extend(
            paths
                .into_iter()
                .filter_map(|p| p.as_ref().canonicalize().ok()),
        );
        self
    }

    /// `files` (name, bytes) into the folder `dir`, named on the command line by `flag` (e.g. `-o`).
    pub fn folder(mut self, flag: &str, dir: &Path, files: Vec<(String, Vec<u8>)>) -> Output {
        let shown = dir.display().to_string();
        self.destinations.push((
            Destination::new(flag, shown, dir.to_path_buf(), Kind::Folder),
            files,
        ));
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
            .find(|(d, _)| d.kind == Kind::Files && d.dir == dir)
        {
            Some((_, files)) => files.push(file),
            None => self.destinations.push((
                Destination::new(flag, path.display().to_string(), dir, Kind::Files),
                vec![file],
            )),
        }
        self
    }

    /// Write everything: check every destination against the policy, stage every file (with the updated
    /// manifest), then move them all into place. On an error nothing of this run is left anywhere.
    pub fn write(self) -> Result<(), OutputError> {
        let run = self.run;
        let mut checked = Vec::with_capacity(self.destinations.len());
        for (mut d, files) in self.destinations {
            check_folder(&mut d)?;
            for (name, _) in &files {
                check_target(&d, name, &run.inputs)?;
            }
            check_occupied(&d, run.force)?;
            for (name, _) in &files {
                check_replace(&d, name, run.force)?;
            }
            checked.push((d, files));
        }
        let mut staged = Vec::with_capacity(checked.len());
        for (d, files) in checked {
            let mut s = Staged::open(d)?;
            for (name, bytes) in &files {
                s.put(name, bytes)?;
            }
            staged.push(s);
        }
        for s in &mut staged {
            s.seal(&run)?;
        }
        commit_all(&mut staged)
    }

    /// Write the folder `dir` (named by `flag`) file by file, for a run whose files together would not
    /// fit in memory: each file goes into the staging folder as it is added, and nothing moves into place
    /// before [`FolderStream::finish`]. The folder is checked against the policy now, before any work;
    /// each file's name when it is added. Dropping the stream unfinished (an error half-way) removes
    /// everything it staged. Destinations added with [`Output::folder`] or [`Output::file`] are not
    /// written by a stream.
    pub fn stream_folder(self, flag: &str, dir: &Path) -> Result<FolderStream, OutputError> {
        let mut d = Destination::new(
            flag,
            dir.display().to_string(),
            dir.to_path_buf(),
            Kind::Folder,
        );
        check_folder(&mut d)?;
        check_occupied(&d, self.run.force)?;
        Ok(FolderStream {
            run: self.run,
            dest: Some(d),
            staged: None,
        })
    }
}

/// A folder being written file by file ([`Output::stream_folder`]).
#[derive(Debug)]
pub struct FolderStream {
    run: Run,
    /// The destination until the first file is added, which makes its staging folder.
    dest: Option<Destination>,
    staged: Option<Staged>,
}

impl FolderStream {
    /// Check `name` against the policy and write `bytes` into the staging folder; the caller may drop
    /// its bytes afterwards.
    pub fn add(&mut self, name: &str, bytes: &[u8]) -> Result<(), OutputError> {
        let d = match (&self.staged, &self.dest) {
            (Some(s), _) => &s.dest,
            (None, Some(d)) => d,
            (None, None) => unreachable!("a stream holds its destination until it finishes"),
        };
        check_target(d, name, &self.run.inputs)?;
        check_replace(d, name, self.run.force)?;
        if self.staged.is_none() {
            let d = self.dest.take().expect("checked above");
            self.staged = Some(Staged::open(d)?);
        }
        self.staged.as_mut().expect("opened above").put(name, bytes)
    }

    /// Files added so far.
    pub fn len(&self) -> usize {
        self.staged.as_ref().map_or(0, |s| s.written.len())
    }

    /// True before the first file is added.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Move every added file into place (with the updated manifest), removing the same command's stale
    /// files; on an error nothing of this run is left.
    pub fn finish(mut self) -> Result<(), OutputError> {
        let mut staged = match (self.staged.take(), self.dest.take()) {
            (Some(s), _) => s,
            (None, Some(d)) => Staged::open(d)?,
            (None, None) => unreachable!("a stream holds its destination until it finishes"),
        };
        staged.seal(&self.run)?;
        commit_all(std::slice::from_mut(&mut staged))
    }
}

/// Move every staged destination into place; if one move fails, undo all moves made.
fn commit_all(staged: &mut [Staged]) -> Result<(), OutputError> {
    let _moving = MOVING.lock().unwrap_or_else(|e| e.into_inner());
    let mut done: Vec<Undo> = Vec::new();
    for s in staged.iter() {
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
    // Made folders now hold the output: they stay. Dropping the staging folders (by the caller) removes
    // them with the replaced and stale files they hold.
    for s in staged.iter_mut() {
        s.created.clear();
    }
    Ok(())
}

/// The policy, first step: the destination is a folder (or nothing yet); read its manifest.
fn check_folder(d: &mut Destination) -> Result<(), OutputError> {
    if d.dir.exists() && !d.dir.is_dir() {
        return Err(OutputError::NotADirectory {
            flag: d.flag.clone(),
            shown: d.shown.clone(),
        });
    }
    d.manifest = Manifest::read(&d.dir);
    Ok(())
}

/// The policy for one file name: a plain name, not a folder, not an input of the run.
fn check_target(d: &Destination, name: &str, inputs: &[PathBuf]) -> Result<(), OutputError> {
    if !is_plain_file_name(name) || name == MANIFEST {
        return Err(OutputError::NotAFileName {
            flag: d.flag.clone(),
            shown: d.shown.clone(),
        });
    }
    let target = d.dir.join(name);
    if target.is_dir() {
        return Err(OutputError::FolderInTheWay {
            flag: d.flag.clone(),
            shown: d.shown.clone(),
            name: name.into(),
        });
    }
    if is_input(&target, inputs) {
        return Err(OutputError::InputInTheWay {
            flag: d.flag.clone(),
            shown: d.shown.clone(),
            name: name.into(),
        });
    }
    Ok(())
}

/// The policy for an `-o` folder: one the tool did not write, holding anything, is refused unless
/// `--force`.
fn check_occupied(d: &Destination, force: bool) -> Result<(), OutputError> {
    if d.kind != Kind::Folder || !d.dir.exists() || d.manifest.is_some() || force {
        return Ok(());
    }
    let foreign = foreign_entries(&d.dir, None).map_err(|source| OutputError::Unreadable {
        flag: d.flag.clone(),
        shown: d.shown.clone(),
        source,
    })?;
    if foreign.is_empty() {
        return Ok(());
    }
    Err(OutputError::Occupied {
        flag: d.flag.clone(),
        shown: d.shown.clone(),
        listing: listing(&foreign),
    })
}

/// The policy for replacing a file: only one the tool wrote, unless `--force`.
fn check_replace(d: &Destination, name: &str, force: bool) -> Result<(), OutputError> {
    let ours = d.manifest.as_ref().is_some_and(|m| m.lists(name));
    if force || ours || fs::symlink_metadata(d.dir.join(name)).is_err() {
        return Ok(());
    }
    Err(OutputError::WouldReplace {
        flag: d.flag.clone(),
        shown: d.shown.clone(),
        name: name.into(),
    })
}

/// Files the same command wrote in an `-o` folder before and does not write now: to be removed (never
/// an input, never anything but a plain file the manifest lists).
fn stale_files(d: &Destination, run: &Run, written: &BTreeSet<&str>) -> Vec<String> {
    match (&d.manifest, d.kind) {
        (Some(m), Kind::Folder) => m
            .stale(&run.command, written)
            .filter(|n| is_plain_file_name(n))
            .filter(|n| {
                let p = d.dir.join(n);
                p.is_file() && !is_input(&p, &run.inputs)
            })
            .map(str::to_string)
            .collect(),
        _ => Vec::new(),
    }
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
#[derive(Debug)]
struct Staged {
    dest: Destination,
    staging: Option<Staging>,
    /// Names written into `staging/new`, in order.
    written: Vec<String>,
    /// Folders made to hold the staging folder, outermost first: removed again unless the run commits.
    created: Vec<PathBuf>,
}

impl Staged {
    /// A fresh staging folder beside the destination (making the folders that hold it).
    fn open(dest: Destination) -> Result<Staged, OutputError> {
        let near = match dest.kind {
            Kind::Files => dest.dir.clone(),
            Kind::Folder => match dest.dir.parent() {
                Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
                _ => PathBuf::from("."),
            },
        };
        let created = missing_folders(&near);
        fs::create_dir_all(&near).map_err(|e| dest.error_create(&near, e))?;
        let mut staged = Staged {
            dest,
            staging: None,
            written: Vec::new(),
            created,
        };
        let staging = Staging::new_in(&near)
            .map_err(|e| staged.dest.error_stage(format!("in {}", near.display()), e))?;
        staged.staging = Some(staging);
        for dir in [staged.new_dir(), staged.old_dir()] {
            staged
                .staging()
                .create_dir(&dir)
                .map_err(|e| staged.dest.error_stage(format!("in {}", dir.display()), e))?;
        }
        Ok(staged)
    }

    fn staging(&self) -> &Staging {
        self.staging
            .as_ref()
            .expect("a staged destination has its staging folder")
    }

    fn new_dir(&self) -> PathBuf {
        self.staging().path().join("new")
    }

    fn old_dir(&self) -> PathBuf {
        self.staging().path().join("old")
    }

    /// Write one file into the staging folder.
    fn put(&mut self, name: &str, bytes: &[u8]) -> Result<(), OutputError> {
        self.staging()
            .write(&self.new_dir().join(name), bytes)
            .map_err(|e| self.dest.error_stage(name, e))?;
        self.written.push(name.to_string());
        Ok(())
    }

    /// After the last file: find the stale files and write the manifest after this run.
    fn seal(&mut self, run: &Run) -> Result<(), OutputError> {
        let written: BTreeSet<&str> = self.written.iter().map(String::as_str).collect();
        self.dest.stale = stale_files(&self.dest, run, &written);
        let manifest = self
            .dest
            .manifest
            .clone()
            .unwrap_or_default()
            .after(
                &self.dest.dir,
                &run.command,
                &written,
                self.dest.kind == Kind::Folder,
            )
            .to_bytes();
        self.put(MANIFEST, &manifest)
    }
}

impl Drop for Staged {
    fn drop(&mut self) {
        // The staging folder first, then the folders made to hold it (empty unless a user filled them
        // meanwhile, and then `remove_dir` leaves them).
        drop(self.staging.take());
        for dir in self.created.iter().rev() {
            let _ = fs::remove_dir(dir);
        }
    }
}

/// The folders `create_dir_all(dir)` would make, outermost first.
fn missing_folders(dir: &Path) -> Vec<PathBuf> {
    let mut missing: Vec<PathBuf> = dir
        .ancestors()
        .take_while(|a| !a.as_os_str().is_empty() && fs::symlink_metadata(a).is_err())
        .map(Path::to_path_buf)
        .collect();
    missing.reverse();
    missing
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
    for name in &s.written {
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
