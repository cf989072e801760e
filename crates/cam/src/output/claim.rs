//! One folder, one owner: a run holds a lock file in each folder it writes into from its first look at
//! the folder to its last move, so two runs (of any commands) never check, stage or move in one folder at
//! once. The lock is an advisory `flock` on [`LOCK`], which the system releases when the process ends
//! however it ends; the file also holds the pid and the command, to name the owner to a second run.

use super::journal::{self, RecoverError};
use super::own_file::{self, file_id, OwnFileError};
use super::staging::{register, unregister, Cleanup};
use std::fs::{self, File};
use std::io::{self, Write};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// File name of the lock in a folder being written.
pub const LOCK: &str = ".actuator-cam-lock";

/// How long a second run waits for the first before it is refused.
const WAIT: Duration = Duration::from_secs(3);

/// Why a folder could not be claimed.
pub(super) enum ClaimError {
    /// Another live run holds the folder.
    Busy { command: String, pid: String },
    /// The folder (or the lock in it) cannot be made.
    Io { dir: PathBuf, source: io::Error },
    /// The lock's name holds something the tool did not make (a link, a directory), or an input.
    OwnFile(OwnFileError),
    /// A dead run's moves could not be finished.
    Recover(RecoverError),
}

/// A folder this run holds: its lock, and the folders made to hold it (removed again unless the run
/// keeps them).
#[derive(Debug)]
pub(super) struct Claim {
    dir: PathBuf,
    lock: Option<File>,
    created: Vec<PathBuf>,
}

impl Claim {
    /// Make `dir` (and its parents) if needed, take its lock (waiting up to [`WAIT`] for a live owner),
    /// then finish whatever move a dead run left half-done there ([`journal::recover`]). The lock is
    /// opened without following a link, and is never one of the run's `inputs` (device, inode): it is
    /// written in place.
    pub(super) fn take(
        dir: &Path,
        command: &str,
        inputs: &[(u64, u64)],
    ) -> Result<Claim, ClaimError> {
        let created = missing_folders(dir);
        for folder in &created {
            register(Cleanup::Created(folder.clone()));
        }
        let mut claim = Claim {
            dir: dir.to_path_buf(),
            lock: None,
            created,
        };
        fs::create_dir_all(dir).map_err(|source| ClaimError::Io {
            dir: dir.to_path_buf(),
            source,
        })?;
        let path = dir.join(LOCK);
        let io_error = |source| ClaimError::Io {
            dir: dir.to_path_buf(),
            source,
        };
        let start = Instant::now();
        loop {
            let file = own_file::open(dir, LOCK, true)
                .map_err(ClaimError::OwnFile)?
                .expect("a lock opened to create is a file");
            let id = file.metadata().map(|m| file_id(&m)).map_err(io_error)?;
            if inputs.contains(&id) {
                return Err(ClaimError::OwnFile(OwnFileError::Taken {
                    path,
                    what: "an input of this run",
                }));
            }
            match file.try_lock() {
                Ok(()) if same_file(&file, &path) => {
                    register(Cleanup::Lock(path.clone()));
                    let mut file = file;
                    file.set_len(0).map_err(io_error)?;
                    writeln!(file, "{}\t{command}", std::process::id()).map_err(io_error)?;
                    claim.lock = Some(file);
                    break;
                }
                // Locked, and then removed by its owner before we got it: take the new one.
                Ok(()) => continue,
                Err(fs::TryLockError::WouldBlock) if start.elapsed() < WAIT => {
                    std::thread::sleep(Duration::from_millis(25));
                }
                Err(fs::TryLockError::WouldBlock) => {
                    let text = fs::read_to_string(&path).unwrap_or_default();
                    let (pid, command) = text.trim().split_once('\t').unwrap_or(("?", "?"));
                    return Err(ClaimError::Busy {
                        command: command.to_string(),
                        pid: pid.to_string(),
                    });
                }
                Err(fs::TryLockError::Error(source)) => return Err(io_error(source)),
            }
        }
        journal::recover(dir).map_err(ClaimError::Recover)?;
        Ok(claim)
    }

    /// The run's files are in place: the folders made for it stay.
    pub(super) fn keep(&mut self) {
        for folder in self.created.drain(..) {
            unregister(&Cleanup::Created(folder));
        }
    }
}

impl Drop for Claim {
    fn drop(&mut self) {
        // The file goes before the lock is let go: a run waiting on it then sees it gone and makes its own.
        if let Some(file) = self.lock.take() {
            let path = self.dir.join(LOCK);
            let _ = fs::remove_file(&path);
            unregister(&Cleanup::Lock(path));
            drop(file);
        }
        for folder in self.created.iter().rev() {
            let _ = fs::remove_dir(folder);
            unregister(&Cleanup::Created(folder.clone()));
        }
    }
}

/// True when the open `file` is still the one at `path` (its owner did not remove it meanwhile).
fn same_file(file: &File, path: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    match (file.metadata(), fs::metadata(path)) {
        (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
        _ => false,
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
