//! The one writer of output files. Every command that writes files (cut-sheet, nest, calibrate,
//! optimize `-o`/`--pareto`, sweep `--csv`) hands them here, so one policy holds for all of them: nothing
//! a user owns is deleted or overwritten unasked. Most render their files in memory first; a run too large
//! for that streams them ([`Output::stream_folder`] file by file, [`Output::stream_file`] bit by bit)
//! under the same policy.
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
mod destination;
mod error;
mod hooks;
mod intent;
mod journal;
mod manifest;
mod name;
mod own_file;
mod staged;
mod staging;

pub use claim::LOCK;
pub use journal::INTENT;
pub use manifest::MANIFEST;
pub use staging::{remove_after_interrupt, STAGING_PREFIX};

pub use error::{in_words, OutputError};
pub use hooks::pause_after_interrupted_search;

use destination::{check_occupied, check_replace, check_target, Destination, Files, Kind, Run};
use staged::{commit_all, Staged};
use std::path::{Path, PathBuf};

/// Every file one run writes, gathered first and written together by [`Output::write`]; or, for a run
/// too large to hold in memory, one folder written file by file ([`Output::stream_folder`]).
#[derive(Debug)]
pub struct Output {
    run: Run,
    destinations: Vec<(Destination, Files)>,
    /// The first error found while the files were gathered (two flags that named one file, a file path
    /// that names a folder), returned by [`Output::write`].
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
        if let (Err(e), None) = (file_path(flag, path), &self.conflict) {
            self.conflict = Some(e);
        }
        let (dir, name) = split_file(path);
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
            let claim = d.claim(&run)?;
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

    /// Check the folder `dir` (named by `flag`) against the policy before the run's work, with the
    /// names of the files the run writes there whatever it finds: a run of minutes that
    /// [`Output::write`] would refuse is refused at its start. Nothing is held or written, and
    /// [`Output::write`] checks again.
    pub fn check_folder_ahead(
        &self,
        flag: &str,
        dir: &Path,
        names: &[&str],
    ) -> Result<(), OutputError> {
        let run = self.run.resolved_quietly();
        let mut d = Destination::new(
            flag,
            dir.display().to_string(),
            dir.to_path_buf(),
            Kind::Folder,
        );
        if !d.look()? {
            return Ok(());
        }
        for name in names {
            check_target(&d, name, &run)?;
        }
        check_occupied(&d, run.force)?;
        for name in names {
            check_replace(&d, name, &run)?;
        }
        Ok(())
    }

    /// Write the folder `dir` (named by `flag`) file by file, for a run whose files together would not
    /// fit in memory: each file goes into the staging folder as it is added, and nothing moves into place
    /// before `FolderStream::finish`. The folder is held and checked against the policy now, before any
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
        let claim = d.claim(&run)?;
        check_occupied(&d, run.force)?;
        Ok(FolderStream {
            run,
            staged: Staged::open(d, claim)?,
        })
    }

    /// Write one file at `path` (named by `flag`) bit by bit, for a file too large to hold in memory
    /// (a sweep's CSV of every design): the destination is held and checked against the policy now,
    /// before any work, and the file moves into place only at `FileStream::finish`. Dropping the
    /// stream unfinished removes what it staged. Destinations added with [`Output::folder`] or
    /// [`Output::file`] are not written by a stream.
    pub fn stream_file(self, flag: &str, path: &Path) -> Result<FileStream, OutputError> {
        if let Some(e) = self.conflict {
            return Err(e);
        }
        file_path(flag, path)?;
        let mut run = self.run;
        run.resolve();
        let (dir, name) = split_file(path);
        let mut d = Destination::new(flag, path.display().to_string(), dir, Kind::Files);
        let claim = d.claim(&run)?;
        check_target(&d, &name, &run)?;
        check_occupied(&d, run.force)?;
        check_replace(&d, &name, &run)?;
        let mut staged = Staged::open(d, claim)?;
        let file = staged.create(&name)?;
        Ok(FileStream {
            run,
            staged,
            name,
            writer: std::io::BufWriter::with_capacity(1 << 16, file),
        })
    }
}

/// A path given for one file must not name a folder by its form (`out/`, `out/.`, `.`): split into
/// folder and name it would become a file named like the folder.
fn file_path(flag: &str, path: &Path) -> Result<(), OutputError> {
    use std::os::unix::ffi::OsStrExt;
    let bytes = path.as_os_str().as_bytes();
    if bytes.ends_with(b"/") || bytes.ends_with(b"/.") || bytes == b"." {
        return Err(OutputError::FolderNotFile {
            flag: flag.into(),
            shown: path.display().to_string(),
        });
    }
    Ok(())
}

/// The folder of a single output file (`.` for a bare name) and its name.
fn split_file(path: &Path) -> (PathBuf, String) {
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    (dir, name)
}

/// One file being written bit by bit ([`Output::stream_file`]): a [`std::io::Write`] into its staging
/// folder, moved into place by [`FileStream::finish`].
#[derive(Debug)]
pub struct FileStream {
    run: Run,
    staged: Staged,
    name: String,
    writer: std::io::BufWriter<std::fs::File>,
}

impl std::io::Write for FileStream {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.writer.write(buf)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        self.writer.flush()
    }
}

impl FileStream {
    /// Flush the file and move it into place (with the updated manifest); on an error nothing of this
    /// run is left.
    pub fn finish(self) -> Result<(), OutputError> {
        let FileStream {
            run,
            mut staged,
            name,
            writer,
        } = self;
        let file = writer
            .into_inner()
            .map_err(|e| staged.dest.error_stage(&name, e.into_error()))?;
        // On the disk before the intent log says it is there.
        file.sync_all()
            .map_err(|e| staged.dest.error_stage(&name, e))?;
        drop(file);
        staged.seal(&run)?;
        commit_all(std::slice::from_mut(&mut staged))
    }

    /// The error of a write into the stream, said as the writer says its own.
    pub fn error(&self, e: std::io::Error) -> OutputError {
        self.staged.dest.error_stage(&self.name, e)
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

#[cfg(test)]
mod tests;
