//! The one writer of output files. Every command that writes files (cut-sheet, nest, calibrate,
//! optimize `-o`/`--pareto`, sweep `--csv`) renders them in memory and hands them here, so one policy
//! holds for all of them: nothing a user owns is deleted or overwritten unasked.
//!
//! - **Where it writes.** Into a folder that does not exist, an empty folder, or a folder it wrote before,
//!   which it recognises by the [`MANIFEST`] it leaves there (the files it wrote, and which command wrote
//!   each). Any other folder is refused with the folder, what is in the way, and how to go on (another
//!   `-o`, or `--force`). A single named file (`-o best.toml`, `--csv designs.csv`) may replace only a
//!   file the tool wrote, unless `--force`.
//! - **What it replaces.** Only the files this run writes, and of those only files the same command
//!   wrote (the manifest says which command wrote each) unless `--force`. In a folder it wrote before, the
//!   files the same command wrote there last time and does not write now (a sheet fewer) are removed;
//!   nothing the manifest does not list is ever removed, with or without `--force`, and no input of the
//!   run (every file it read: `crate::input::files_read`, plus any the command names) is ever overwritten.
//! - **One owner.** A run holds a lock in each folder it writes into ([`LOCK`], `claim`) from its first
//!   look to its last move: a second run waits a moment, then is refused naming the first.
//! - **How.** Every file is first written into a staging folder inside its destination (a name starting
//!   with [`STAGING_PREFIX`]); only when all are written does anything move into place, after an intent
//!   log ([`INTENT`], `journal`) that lets the next run finish moves a killed run left half-done. If a
//!   move fails, the moves already made are undone, so a failure leaves no half-written output. SIGINT and
//!   SIGTERM remove the staging folder ([`remove_after_interrupt`], called by the command layer's
//!   handler) unless every file is in place already.

mod claim;
mod journal;
mod manifest;
mod staging;

pub use claim::LOCK;
pub use journal::INTENT;
pub use manifest::MANIFEST;
pub use staging::{remove_after_interrupt, STAGING_PREFIX};

use claim::{Claim, ClaimError};
use journal::{Moves, Undo};
use manifest::{foreign_entries, Manifest};
use staging::{lock, Staging, COMPLETE, MOVING};
use std::collections::BTreeSet;
use std::fs;
use std::io;
use std::path::{Path, PathBuf};
use std::sync::atomic::Ordering;

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
    /// A file of the same name was written by another command.
    #[error(
        "{flag} {shown}: {name} was written by `actuator-cam {command}`; choose another {flag}, or pass \
         --force to replace it"
    )]
    OtherCommands {
        /// The flag.
        flag: String,
        /// The path as given.
        shown: String,
        /// The file's name.
        name: String,
        /// The command the manifest says wrote it.
        command: String,
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
    /// Two flags of one run name the same file.
    #[error("{flag} {shown}: the same file as {first}; give each its own name")]
    SameFile {
        /// The later flag.
        flag: String,
        /// The path as given.
        shown: String,
        /// The flag that named it first.
        first: String,
    },
    /// Another run is writing into the folder.
    #[error(
        "{flag} {shown}: another run (actuator-cam {command}, pid {pid}) is writing into this folder; \
         wait for it to end, or choose another {flag}"
    )]
    Busy {
        /// The flag.
        flag: String,
        /// The path as given.
        shown: String,
        /// The other run's command.
        command: String,
        /// The other run's process id.
        pid: String,
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
    #[error("{flag} {shown}: cannot read the folder: {reason}")]
    Unreadable {
        /// The flag.
        flag: String,
        /// The path as given.
        shown: String,
        /// The system's reason, in words.
        reason: String,
    },
    /// The destination folder (or its lock) cannot be made.
    #[error("{flag} {shown}: cannot write into the folder {dir}: {reason}")]
    CreateDir {
        /// The flag.
        flag: String,
        /// The path as given.
        shown: String,
        /// The folder.
        dir: String,
        /// The system's reason, in words.
        reason: String,
    },
    /// Staging failed.
    #[error("{flag} {shown}: cannot write {what}: {reason}")]
    Stage {
        /// The flag.
        flag: String,
        /// The path as given.
        shown: String,
        /// The file or folder being written.
        what: String,
        /// The system's reason, in words.
        reason: String,
    },
    /// Moving the staged files into place failed (and was undone).
    #[error("{flag} {shown}: cannot move the finished files into place: {reason}")]
    Commit {
        /// The flag.
        flag: String,
        /// The path as given.
        shown: String,
        /// The system's reason, in words.
        reason: String,
    },
}

/// A system error said in words a user acts on, without the `(os error N)` of the raw message.
pub fn in_words(e: &io::Error) -> String {
    use io::ErrorKind as K;
    let words = match e.kind() {
        K::PermissionDenied => "the folder is read-only (permission denied)",
        K::ReadOnlyFilesystem => "the folder is read-only (a read-only file system)",
        K::StorageFull => "the disk is full",
        K::QuotaExceeded => "the disk quota is used up",
        K::NotFound => "a folder on the way does not exist (was it removed?)",
        K::NotADirectory => "a part of the path is a file, not a folder",
        K::CrossesDevices => "the files would have to move to another file system",
        K::FileTooLarge => "a file is too large for the file system",
        K::TooManyLinks => "the folder holds too many entries",
        _ => {
            let text = e.to_string();
            return match text.find(" (os error") {
                Some(at) => text[..at].to_lowercase(),
                None => text,
            };
        }
    };
    words.to_string()
}

/// Where a destination's files come from on the command line.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    /// `-o DIR`: the whole folder is this command's output.
    Folder,
    /// Named files (`-o best.toml`, `--csv designs.csv`) in a folder that is otherwise the user's.
    Files,
}

/// One destination folder: where it is, how it was named, and what the policy found there.
#[derive(Debug)]
struct Destination {
    flag: String,
    shown: String,
    dir: PathBuf,
    kind: Kind,
    /// The folder's manifest as the run found it (read once the folder is held).
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
            reason: in_words(&source),
        }
    }

    /// Check that the destination is a folder (or nothing yet), hold it, and read its manifest.
    fn claim(&mut self, command: &str) -> Result<Claim, OutputError> {
        if self.dir.exists() && !self.dir.is_dir() {
            return Err(OutputError::NotADirectory {
                flag: self.flag.clone(),
                shown: self.shown.clone(),
            });
        }
        let claim = Claim::take(&self.dir, command).map_err(|e| match e {
            ClaimError::Busy { command, pid } => OutputError::Busy {
                flag: self.flag.clone(),
                shown: self.shown.clone(),
                command,
                pid,
            },
            ClaimError::Io { dir, source } => OutputError::CreateDir {
                flag: self.flag.clone(),
                shown: self.shown.clone(),
                dir: dir.display().to_string(),
                reason: in_words(&source),
            },
        })?;
        self.manifest = Manifest::read(&self.dir);
        Ok(claim)
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
    /// The inputs as (device, inode), found when the writing starts: a file of the run is an input if it
    /// is one of them under any name (a symlink, a hard link, `./sub/..`).
    ids: Vec<(u64, u64)>,
}

impl Run {
    /// Every input: the paths named, and every file read so far. Test hook: with
    /// `ACTUATOR_CAM_LIST_INPUTS` set, each is printed on stderr (`input: PATH`), so a test can aim the
    /// outputs at every one of them.
    fn resolve(&mut self) {
        let mut all: Vec<PathBuf> = Vec::new();
        for p in self
            .inputs
            .iter()
            .cloned()
            .chain(crate::input::files_read())
        {
            if !all.contains(&p) {
                all.push(p);
            }
        }
        if std::env::var_os("ACTUATOR_CAM_LIST_INPUTS").is_some() {
            for p in &all {
                eprintln!("input: {}", p.display());
            }
        }
        self.ids = all
            .iter()
            .filter_map(|p| fs::metadata(p).ok())
            .map(|m| file_id(&m))
            .collect();
    }

    /// True when `path` is (the same file as) one of the run's inputs.
    fn is_input(&self, path: &Path) -> bool {
        fs::metadata(path).is_ok_and(|m| self.ids.contains(&file_id(&m)))
    }
}

fn file_id(m: &fs::Metadata) -> (u64, u64) {
    use std::os::unix::fs::MetadataExt;
    (m.dev(), m.ino())
}

/// Every file one run writes, gathered first and written together by [`Output::write`]; or, for a run
/// too large to hold in memory, one folder written file by file ([`Output::stream_folder`]).
#[derive(Debug)]
pub struct Output {
    run: Run,
    destinations: Vec<(Destination, Files)>,
    /// Two flags that named one file.
    conflict: Option<OutputError>,
}

impl Output {
    /// Nothing to write yet, for a run of `command` (the name the manifest records).
    pub fn new(command: &str) -> Output {
        Output {
            run: Run {
                command: command.into(),
                force: false,
                inputs: Vec::new(),
                ids: Vec::new(),
            },
            destinations: Vec::new(),
            conflict: None,
        }
    }

    /// `--force`: write into a folder that holds other files, and replace files of the same name the tool
    /// did not write, or another command wrote. Never an input, never a file the run does not write.
    pub fn force(mut self, force: bool) -> Output {
        self.run.force = force;
        self
    }

    /// Files this run reads, besides those read through `crate::input::read_text` (which are inputs
    /// already): never overwritten, never removed, whatever the flags.
    pub fn inputs<P: AsRef<Path>>(mut self, paths: impl IntoIterator<Item = P>) -> Output {
        self.run
            .inputs
            .extend(paths.into_iter().map(|p| p.as_ref().to_path_buf()));
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
            Some((d, files)) => {
                if files.iter().any(|(n, _)| *n == file.0) && self.conflict.is_none() {
                    self.conflict = Some(OutputError::SameFile {
                        flag: flag.into(),
                        shown: path.display().to_string(),
                        first: d.flag.clone(),
                    });
                }
                files.push(file)
            }
            None => self.destinations.push((
                Destination::new(flag, path.display().to_string(), dir, Kind::Files),
                vec![file],
            )),
        }
        self
    }

    /// Write everything: hold every destination, check it against the policy, stage every file (with
    /// the updated manifest), then move them all into place. On an error nothing of this run is left
    /// anywhere.
    pub fn write(self) -> Result<(), OutputError> {
        if let Some(e) = self.conflict {
            return Err(e);
        }
        let mut run = self.run;
        run.resolve();
        let mut staged = Vec::with_capacity(self.destinations.len());
        for (mut d, files) in self.destinations {
            let claim = d.claim(&run.command)?;
            for (name, _) in &files {
                check_target(&d, name, &run)?;
            }
            check_occupied(&d, run.force)?;
            for (name, _) in &files {
                check_replace(&d, name, &run)?;
            }
            let mut s = Staged::open(d, claim)?;
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
    /// before [`FolderStream::finish`]. The folder is held and checked against the policy now, before any
    /// work; each file's name when it is added. Dropping the stream unfinished (an error half-way) removes
    /// everything it staged. Destinations added with [`Output::folder`] or [`Output::file`] are not
    /// written by a stream.
    pub fn stream_folder(self, flag: &str, dir: &Path) -> Result<FolderStream, OutputError> {
        let mut run = self.run;
        run.resolve();
        let mut d = Destination::new(
            flag,
            dir.display().to_string(),
            dir.to_path_buf(),
            Kind::Folder,
        );
        let claim = d.claim(&run.command)?;
        check_occupied(&d, run.force)?;
        Ok(FolderStream {
            run,
            staged: Staged::open(d, claim)?,
        })
    }
}

/// A folder being written file by file ([`Output::stream_folder`]).
#[derive(Debug)]
pub struct FolderStream {
    run: Run,
    staged: Staged,
}

impl FolderStream {
    /// Check `name` against the policy and write `bytes` into the staging folder; the caller may drop
    /// its bytes afterwards.
    pub fn add(&mut self, name: &str, bytes: &[u8]) -> Result<(), OutputError> {
        check_target(&self.staged.dest, name, &self.run)?;
        check_replace(&self.staged.dest, name, &self.run)?;
        self.staged.put(name, bytes)
    }

    /// Files added so far.
    pub fn len(&self) -> usize {
        self.staged.written.len()
    }

    /// True before the first file is added.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Move every added file into place (with the updated manifest), removing the same command's stale
    /// files; on an error nothing of this run is left.
    pub fn finish(mut self) -> Result<(), OutputError> {
        self.staged.seal(&self.run)?;
        commit_all(std::slice::from_mut(&mut self.staged))
    }
}

/// Move every staged destination into place; if one move fails, undo all moves made.
fn commit_all(staged: &mut [Staged]) -> Result<(), OutputError> {
    let _moving = lock(&MOVING);
    let mut done: Vec<Undo> = Vec::new();
    for s in staged.iter() {
        let moves = Moves {
            dir: &s.dest.dir,
            staging: s.staging().path(),
            remove: &s.dest.stale,
            put: &s.written,
            manifest: &s.manifest,
        };
        if let Err(source) = moves.run(&mut done) {
            for undo in done.into_iter().rev() {
                undo.apply();
            }
            return Err(OutputError::Commit {
                flag: s.dest.flag.clone(),
                shown: s.dest.shown.clone(),
                reason: in_words(&source),
            });
        }
    }
    // Every file is in place: the logs go (a log left by a failure here has nothing left to move), and
    // an interrupt from now on changes nothing. The folders made now hold the output, and stay; dropping
    // the staging folders (by the caller) removes them with the replaced and stale files they hold.
    for s in staged.iter_mut() {
        let _ = journal::finished(&s.dest.dir);
        s.claim.keep();
    }
    COMPLETE.store(true, Ordering::SeqCst);
    Ok(())
}

/// The policy for one file name: a plain name, not a folder, not an input of the run.
fn check_target(d: &Destination, name: &str, run: &Run) -> Result<(), OutputError> {
    let ours = [MANIFEST, LOCK, INTENT];
    if !is_plain_file_name(name) || ours.contains(&name) || name.starts_with(STAGING_PREFIX) {
        return Err(OutputError::NotAFileName {
            flag: d.flag.clone(),
            shown: d.shown.clone(),
        });
    }
    let target = d.dir.join(name);
    if fs::symlink_metadata(&target).is_err() {
        return Ok(());
    }
    if target.is_dir() {
        return Err(OutputError::FolderInTheWay {
            flag: d.flag.clone(),
            shown: d.shown.clone(),
            name: name.into(),
        });
    }
    if run.is_input(&target) {
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
    if d.kind != Kind::Folder || d.manifest.is_some() || force {
        return Ok(());
    }
    let foreign = foreign_entries(&d.dir, None, &[LOCK, INTENT]).map_err(|source| {
        OutputError::Unreadable {
            flag: d.flag.clone(),
            shown: d.shown.clone(),
            reason: in_words(&source),
        }
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

/// The policy for replacing a file: only one the same command wrote, unless `--force`.
fn check_replace(d: &Destination, name: &str, run: &Run) -> Result<(), OutputError> {
    if run.force || fs::symlink_metadata(d.dir.join(name)).is_err() {
        return Ok(());
    }
    match d.manifest.as_ref().and_then(|m| m.owner(name)) {
        Some(command) if command == run.command => Ok(()),
        Some(command) => Err(OutputError::OtherCommands {
            flag: d.flag.clone(),
            shown: d.shown.clone(),
            name: name.into(),
            command: command.into(),
        }),
        None => Err(OutputError::WouldReplace {
            flag: d.flag.clone(),
            shown: d.shown.clone(),
            name: name.into(),
        }),
    }
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
                p.is_file() && !run.is_input(&p)
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

/// A name that stays inside its folder: one component, not `.` or `..`.
fn is_plain_file_name(name: &str) -> bool {
    let mut components = Path::new(name).components();
    matches!(
        (components.next(), components.next()),
        (Some(std::path::Component::Normal(_)), None)
    )
}

/// A held destination whose files are written into `staging/new`; replaced and stale files go to
/// `staging/old`, and vanish with it.
#[derive(Debug)]
struct Staged {
    dest: Destination,
    staging: Option<Staging>,
    /// Names written into `staging/new`, in order (the manifest last, once sealed).
    written: Vec<String>,
    /// The manifest after this run, once sealed.
    manifest: Manifest,
    /// The destination's lock and the folders made for it; let go after the staging folder is removed.
    claim: Claim,
}

impl Staged {
    /// A fresh staging folder inside the held destination.
    fn open(dest: Destination, claim: Claim) -> Result<Staged, OutputError> {
        let mut staged = Staged {
            dest,
            staging: None,
            written: Vec::new(),
            manifest: Manifest::default(),
            claim,
        };
        let staging = Staging::new_in(&staged.dest.dir)
            .map_err(|e| staged.dest.error_stage("its staging folder", e))?;
        staged.staging = Some(staging);
        for dir in [staged.new_dir(), staged.old_dir()] {
            staged
                .staging()
                .create_dir(&dir)
                .map_err(|e| staged.dest.error_stage("its staging folder", e))?;
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
        self.manifest = self.dest.manifest.clone().unwrap_or_default().after(
            &self.dest.dir,
            &run.command,
            &written,
            self.dest.kind == Kind::Folder,
        );
        let bytes = self.manifest.to_bytes();
        self.put(MANIFEST, &bytes)
    }
}

impl Drop for Staged {
    fn drop(&mut self) {
        // The staging folder first; the claim (a field) goes after, with the lock and any folder made
        // for the run that is empty again.
        drop(self.staging.take());
    }
}

#[cfg(test)]
mod tests;
