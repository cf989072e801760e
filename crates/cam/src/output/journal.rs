//! Moves that survive a kill. Before the first move into a folder the run writes an intent log,
//! [`INTENT`]: its staging folder, the files it will remove (stale files of the same command) and put
//! (new and replaced files, the manifest last), and the new manifest itself. The moves are renames within
//! the folder. If the run dies half-way (SIGKILL, a crash), the next run that claims the folder
//! ([`super::claim`]) finds the log and finishes the moves from the staging folder, whose files were all
//! written before the log was, so the folder ends as the dead run meant it, every file in it listed by
//! its manifest. Any other staging folder there is a dead run's unfinished staging, and goes.
//!
//! Test hooks: `ACTUATOR_CAM_STOP_AFTER_MOVE=k` aborts the process right after its k-th move (the intent
//! log going into place is move 1), as a SIGKILL would, so tests can stop a run at every stage.
//! `ACTUATOR_CAM_PAUSE_AFTER_MOVE=k` says `paused after move k` on stderr and sleeps two seconds after
//! its k-th move, so a test can send SIGINT or SIGTERM while the files move.

use super::manifest::{Manifest, MANIFEST};
use super::staging::STAGING_PREFIX;
use std::fs;
use std::io;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::OnceLock;

/// File name of the intent log in a folder whose files are being moved into place.
pub const INTENT: &str = ".actuator-cam-intent";

const HEADER: &str =
    "# actuator-cam: files being moved into this folder; the next run finishes the moves.\n";

/// One move made, and how to take it back if a later move fails (not after a kill: that is finished).
pub(super) enum Undo {
    /// The intent log went into place: remove it.
    Intent(PathBuf),
    /// A file was put at `target` (or, for a stale file, taken away); `previous` holds the file that was
    /// there, if any.
    Placed {
        target: PathBuf,
        previous: Option<PathBuf>,
    },
}

impl Undo {
    /// Best effort: an undo that fails leaves the file as the run wrote it.
    pub(super) fn apply(self) {
        let _ = match self {
            Undo::Intent(path) => fs::remove_file(path),
            Undo::Placed { target, previous } => match previous {
                Some(old) => fs::rename(old, &target),
                None => fs::remove_file(&target),
            },
        };
    }
}

/// What one folder's moves are: from `staging` (with `new/` and `old/` inside) into `dir`.
pub(super) struct Moves<'a> {
    pub dir: &'a Path,
    pub staging: &'a Path,
    /// Stale files to take away.
    pub remove: &'a [String],
    /// Files to put in place from `staging/new`, the manifest last.
    pub put: &'a [String],
    /// The manifest after the run.
    pub manifest: &'a Manifest,
}

impl Moves<'_> {
    /// Write the intent log, then make every move, recording each in `done`.
    pub(super) fn run(&self, done: &mut Vec<Undo>) -> io::Result<()> {
        self.write_intent()?;
        done.push(Undo::Intent(self.dir.join(INTENT)));
        let old = self.staging.join("old");
        let new = self.staging.join("new");
        for name in self.remove {
            let target = self.dir.join(name);
            fs::rename(&target, old.join(name))?;
            done.push(Undo::Placed {
                target,
                previous: Some(old.join(name)),
            });
            moved();
        }
        for name in self.put {
            let target = self.dir.join(name);
            let previous = if fs::symlink_metadata(&target).is_ok() {
                fs::rename(&target, old.join(name))?;
                moved();
                Some(old.join(name))
            } else {
                None
            };
            if let Err(e) = fs::rename(new.join(name), &target) {
                if let Some(old) = previous {
                    let _ = fs::rename(old, &target);
                }
                return Err(e);
            }
            done.push(Undo::Placed { target, previous });
            moved();
        }
        Ok(())
    }

    fn write_intent(&self) -> io::Result<()> {
        let mut text = format!("{HEADER}staging\t{}\n", file_name(self.staging));
        for name in self.remove {
            text.push_str(&format!("remove\t{name}\n"));
        }
        for name in self.put {
            text.push_str(&format!("put\t{name}\n"));
        }
        for (command, name) in self.manifest.entries() {
            text.push_str(&format!("owner\t{command}\t{name}\n"));
        }
        // Written whole beside, then renamed: a kill never leaves half a log.
        let draft = self.staging.join("intent");
        fs::write(&draft, text)?;
        fs::rename(&draft, self.dir.join(INTENT))?;
        moved();
        Ok(())
    }
}

/// Every move is done: the log goes.
pub(super) fn finished(dir: &Path) -> io::Result<()> {
    fs::remove_file(dir.join(INTENT))
}

/// Finish the moves a dead run left half-done in `dir` (which this run holds), and remove every staging
/// folder there: with the folder held, none belongs to a live run.
pub(super) fn recover(dir: &Path) -> io::Result<()> {
    let intent = dir.join(INTENT);
    if let Ok(text) = fs::read_to_string(&intent) {
        let mut staging = None;
        let mut manifest = Vec::new();
        for line in text.lines().filter(|l| !l.starts_with('#')) {
            let mut parts = line.splitn(3, '\t');
            match (parts.next(), parts.next(), parts.next()) {
                (Some("staging"), Some(name), None) if name.starts_with(STAGING_PREFIX) => {
                    staging = Some(dir.join(name));
                }
                (Some("remove"), Some(name), None) if plain(name) => {
                    let target = dir.join(name);
                    if fs::symlink_metadata(&target).is_ok_and(|m| m.is_file()) {
                        fs::remove_file(target)?;
                    }
                }
                (Some("put"), Some(name), None) if plain(name) => {
                    if let Some(new) = staging.as_ref().map(|s| s.join("new").join(name)) {
                        if fs::symlink_metadata(&new).is_ok() {
                            fs::rename(new, dir.join(name))?;
                        }
                    }
                }
                (Some("owner"), Some(command), Some(name)) => {
                    manifest.push((command.to_string(), name.to_string()));
                }
                _ => {}
            }
        }
        // The staging folder was taken away by hand: the manifest still says what the run meant.
        if staging.as_ref().is_none_or(|s| !s.exists()) {
            fs::write(
                dir.join(MANIFEST),
                Manifest::from_entries(manifest).present_in(dir).to_bytes(),
            )?;
        }
        fs::remove_file(&intent)?;
    }
    for entry in fs::read_dir(dir)?.flatten() {
        let leftover = entry
            .file_name()
            .to_string_lossy()
            .starts_with(STAGING_PREFIX);
        if leftover && entry.file_type().is_ok_and(|t| t.is_dir()) {
            fs::remove_dir_all(entry.path())?;
        }
    }
    Ok(())
}

fn plain(name: &str) -> bool {
    super::name::is_plain_file_name(name)
}

fn file_name(path: &Path) -> String {
    path.file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default()
}

/// Count one move; the test hook stops the process after the k-th.
fn moved() {
    static STOP_AFTER: OnceLock<Option<usize>> = OnceLock::new();
    static MOVES: AtomicUsize = AtomicUsize::new(0);
    let stop = STOP_AFTER.get_or_init(|| {
        std::env::var("ACTUATOR_CAM_STOP_AFTER_MOVE")
            .ok()
            .and_then(|k| k.parse().ok())
    });
    static PAUSE_AFTER: OnceLock<Option<usize>> = OnceLock::new();
    let pause = PAUSE_AFTER.get_or_init(|| {
        std::env::var("ACTUATOR_CAM_PAUSE_AFTER_MOVE")
            .ok()
            .and_then(|k| k.parse().ok())
    });
    let n = MOVES.fetch_add(1, Ordering::SeqCst) + 1;
    if *stop == Some(n) {
        std::process::abort();
    }
    if *pause == Some(n) {
        eprintln!("paused after move {n}");
        std::thread::sleep(std::time::Duration::from_secs(2));
    }
}
