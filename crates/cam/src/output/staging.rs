//! Staging folders: where a run writes its files, inside the destination folder it holds
//! ([`super::claim`]), before they move into place; and what an interrupted run removes. SIGINT and
//! SIGTERM are handled by the run itself ([`remove_after_interrupt`]); what a SIGKILL leaves is finished
//! or removed by the next run that claims the folder ([`super::journal::recover`]).
//!
//! The name prefix alone does not make a folder the tool's: a user may keep
//! `.actuator-cam-staging-photos/` in an output folder. Each staging folder the tool makes carries its
//! [`MARKER`] file, written as soon as the folder exists, and only a folder with it (or an empty one, all
//! a kill in between can leave) is ever removed as a leftover.

use std::fs;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Mutex;

/// Name prefix of the staging folders, so a leftover one can be recognised.
pub const STAGING_PREFIX: &str = ".actuator-cam-staging-";

/// The file inside each staging folder that says the tool made it.
const MARKER: &str = "made-by-actuator-cam";

/// What the marker file holds.
const MARKER_TEXT: &str =
    "actuator-cam staging folder: the next run into the folder around it removes it\n";

/// What an interrupt must take away: everything this run made that is not output yet.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(super) enum Cleanup {
    /// A folder made to hold the output: removed if empty.
    Created(PathBuf),
    /// The lock file of a claimed folder.
    Lock(PathBuf),
    /// A staging folder, removed whole.
    Staging(PathBuf),
}

/// What this process made that is not output yet, in the order made (undone in reverse).
static ACTIVE: Mutex<Vec<Cleanup>> = Mutex::new(Vec::new());

/// Held while staged files move into place, so an interrupt waits for the moves (and their undo) to end
/// instead of cutting them in half.
pub(super) static MOVING: Mutex<()> = Mutex::new(());

/// Set when every file of the run is in place: an interrupt after that changes nothing.
pub(super) static COMPLETE: AtomicBool = AtomicBool::new(false);

/// Record something an interrupt must take away.
pub(super) fn register(item: Cleanup) {
    lock(&ACTIVE).push(item);
}

/// It is output now, or removed already.
pub(super) fn unregister(item: &Cleanup) {
    lock(&ACTIVE).retain(|i| i != item);
}

/// A staging folder of this run; removed with everything in it when dropped.
#[derive(Debug)]
pub(super) struct Staging {
    dir: Option<tempfile::TempDir>,
}

impl Staging {
    /// A fresh staging folder in `dir`, which this run holds. It is made and registered under one lock,
    /// so an interrupt either finds it registered or comes before it exists.
    pub(super) fn new_in(dir: &Path) -> std::io::Result<Staging> {
        let mut active = lock(&ACTIVE);
        let staging = tempfile::Builder::new()
            .prefix(STAGING_PREFIX)
            .tempdir_in(dir)?;
        // On an error the folder goes with `staging` (a TempDir); nothing to unregister yet.
        super::own_file::write_new(&staging.path().join(MARKER), MARKER_TEXT.as_bytes())?;
        active.push(Cleanup::Staging(staging.path().to_path_buf()));
        Ok(Staging { dir: Some(staging) })
    }

    pub(super) fn path(&self) -> &Path {
        self.dir.as_ref().map(|d| d.path()).unwrap_or(Path::new(""))
    }

    /// Make a folder inside the staging folder. Under the lock, like every write into it: an interrupt
    /// that is removing the folder must not race a write that adds to it.
    pub(super) fn create_dir(&self, dir: &Path) -> std::io::Result<()> {
        let _active = lock(&ACTIVE);
        fs::create_dir(dir)
    }

    /// Create a file inside the staging folder to write into bit by bit (made under the lock, see
    /// [`Staging::create_dir`]; a write after an interrupt removed the folder goes to a file no longer
    /// in it, and is lost with it).
    pub(super) fn create(&self, path: &Path) -> std::io::Result<fs::File> {
        let _active = lock(&ACTIVE);
        super::own_file::create_new(path)
    }

    /// Write a file inside the staging folder (under the lock, see [`Staging::create_dir`]); the journal
    /// syncs the folder's files before its log says they are there.
    pub(super) fn write(&self, path: &Path, bytes: &[u8]) -> std::io::Result<()> {
        let _active = lock(&ACTIVE);
        super::own_file::write_new_unsynced(path, bytes)
    }
}

impl Drop for Staging {
    fn drop(&mut self) {
        // Removed under the lock, so an interrupt cannot exit half-way through the removal.
        let mut active = lock(&ACTIVE);
        if let Some(dir) = self.dir.take() {
            let path = dir.path().to_path_buf();
            active.retain(|i| *i != Cleanup::Staging(path.clone()));
            let _ = dir.close();
        }
    }
}

/// True when `path` is a staging folder the tool made: a directory (not a link to one) holding its
/// marker, or an empty directory with the prefix (a kill between making the folder and its marker).
/// Anything else with the prefix is a user's.
pub(super) fn is_ours(path: &Path) -> bool {
    if !fs::symlink_metadata(path).is_ok_and(|m| m.is_dir()) {
        return false;
    }
    let marker = path.join(MARKER);
    if fs::symlink_metadata(&marker).is_ok_and(|m| m.is_file()) {
        // A kill while the marker is written leaves it empty or cut short.
        return fs::read(&marker).is_ok_and(|b| MARKER_TEXT.as_bytes().starts_with(&b));
    }
    fs::read_dir(path).is_ok_and(|mut entries| entries.next().is_none())
}

/// Mark `path` as a staging folder the tool made (for tests that lay out a dead run's folder by hand).
#[cfg(test)]
pub(super) fn mark(path: &Path) {
    fs::write(path.join(MARKER), MARKER_TEXT).unwrap();
}

/// For the SIGINT/SIGTERM handler. Waits for files being moved into place to finish (or be undone);
/// then, if every file of the run is in place, returns true and changes nothing (the run goes on to its
/// end and exits 0). Otherwise removes every staging folder, lock and made folder of this process and
/// returns false; the handler exits right after.
pub fn remove_after_interrupt() -> bool {
    let moving = lock(&MOVING);
    if COMPLETE.load(Ordering::SeqCst) {
        return true;
    }
    // Both held until the process exits: no write or move can start after this point.
    let mut active = lock(&ACTIVE);
    for item in active.drain(..).rev() {
        let _ = match item {
            Cleanup::Staging(dir) => fs::remove_dir_all(dir),
            Cleanup::Lock(file) => fs::remove_file(file),
            Cleanup::Created(dir) => fs::remove_dir(dir),
        };
    }
    std::mem::forget(active);
    std::mem::forget(moving);
    false
}

pub(super) fn lock<T>(m: &Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    // A panic while holding the lock leaves plain data behind; use it anyway.
    m.lock().unwrap_or_else(|e| e.into_inner())
}
