//! Staging folders: where a run writes its files before they move into place, how an interrupted run's
//! folder is cleaned up (SIGINT/SIGTERM: by the run itself; SIGKILL, which cannot be caught: by the next
//! run that stages in the same place).

use std::fs;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// Name prefix of the staging folders, so a leftover one can be recognised.
pub const STAGING_PREFIX: &str = ".actuator-cam-staging-";

/// File inside a staging folder holding the process id of the run that made it.
const OWNER_FILE: &str = "pid";

/// Staging folders of this process that exist now, for the interrupt handler.
static ACTIVE: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// Held while staged files move into place, so an interrupt waits for the moves (and their undo) to end
/// instead of cutting them in half.
pub(super) static MOVING: Mutex<()> = Mutex::new(());

/// A staging folder of this run; removed with everything in it when dropped.
#[derive(Debug)]
pub(super) struct Staging {
    dir: Option<tempfile::TempDir>,
}

impl Staging {
    /// A fresh staging folder in `near`, after removing the ones killed runs left there. It is made and
    /// registered under one lock, so an interrupt either finds it registered or comes before it exists.
    pub(super) fn new_in(near: &Path) -> std::io::Result<Staging> {
        remove_leftovers(near);
        let mut active = lock(&ACTIVE);
        let dir = tempfile::Builder::new()
            .prefix(STAGING_PREFIX)
            .tempdir_in(near)?;
        fs::write(dir.path().join(OWNER_FILE), std::process::id().to_string())?;
        active.push(dir.path().to_path_buf());
        Ok(Staging { dir: Some(dir) })
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

    /// Write a file inside the staging folder (under the lock, see [`Staging::create_dir`]).
    pub(super) fn write(&self, path: &Path, bytes: &[u8]) -> std::io::Result<()> {
        let _active = lock(&ACTIVE);
        fs::write(path, bytes)
    }
}

impl Drop for Staging {
    fn drop(&mut self) {
        // Removed under the lock, so an interrupt cannot exit half-way through the removal.
        let mut active = lock(&ACTIVE);
        if let Some(dir) = self.dir.take() {
            active.retain(|p| p != dir.path());
            let _ = dir.close();
        }
    }
}

/// Remove every staging folder of this process: for the SIGINT/SIGTERM handler, which exits right after.
/// Waits for files being moved into place to finish (or be undone) first.
pub fn remove_after_interrupt() {
    let _moving = lock(&MOVING);
    // Held until the process exits: no write into a staging folder can start after this point.
    let mut active = lock(&ACTIVE);
    for dir in active.drain(..) {
        let _ = fs::remove_dir_all(dir);
    }
    std::mem::forget(active);
}

fn lock<T>(m: &Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    // A panic while holding the lock leaves plain data behind; use it anyway.
    m.lock().unwrap_or_else(|e| e.into_inner())
}

/// Remove staging folders in `near` whose run is no longer alive (a SIGKILL, a power cut). A folder whose
/// owner cannot be told (no pid file yet, no /proc) is left, unless it is over a day old.
fn remove_leftovers(near: &Path) {
    let Ok(entries) = fs::read_dir(near) else {
        return;
    };
    for entry in entries.flatten() {
        let name = entry.file_name();
        if !name.to_string_lossy().starts_with(STAGING_PREFIX) {
            continue;
        }
        let path = entry.path();
        if !entry.file_type().is_ok_and(|t| t.is_dir()) {
            continue;
        }
        let pid = fs::read_to_string(path.join(OWNER_FILE)).ok();
        let dead = match pid.as_deref().map(str::trim) {
            Some(pid) if Path::new("/proc/self").exists() => {
                pid != std::process::id().to_string() && !Path::new("/proc").join(pid).exists()
            }
            _ => older_than_a_day(&path),
        };
        if dead {
            let _ = fs::remove_dir_all(&path);
        }
    }
}

fn older_than_a_day(path: &Path) -> bool {
    fs::metadata(path)
        .and_then(|m| m.modified())
        .ok()
        .and_then(|t| t.elapsed().ok())
        .is_some_and(|age| age.as_secs() > 24 * 3600)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_dead_runs_staging_is_removed_and_a_live_ones_kept() {
        let near = tempfile::tempdir().unwrap();
        let dead = near.path().join(format!("{STAGING_PREFIX}dead"));
        fs::create_dir(&dead).unwrap();
        // No process has this id: pid_max on Linux is at most 2^22.
        fs::write(dead.join(OWNER_FILE), "99999999").unwrap();
        let live = near.path().join(format!("{STAGING_PREFIX}live"));
        fs::create_dir(&live).unwrap();
        fs::write(live.join(OWNER_FILE), "1").unwrap();
        let user = near.path().join("my-folder");
        fs::create_dir(&user).unwrap();
        let s = Staging::new_in(near.path()).unwrap();
        assert!(!dead.exists() && live.exists() && user.exists() && s.path().exists());
        let kept = s.path().to_path_buf();
        drop(s);
        assert!(!kept.exists());
    }
}
