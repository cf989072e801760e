//! Moves that survive a kill or a power failure. Before the first move into a folder the run writes an
//! intent log, [`INTENT`] (its text: [`super::intent`]): its staging folder, the files it will remove
//! (stale files of the same command) and put (new and replaced files, the manifest last), and the new
//! manifest itself. The moves are renames within the folder. If the run dies half-way (SIGKILL, a crash),
//! the next run that claims the folder ([`super::claim`]) finds the log and finishes the moves from the
//! staging folder, so the folder ends as the dead run meant it, every file in it listed by its manifest.
//! Any other staging folder of the tool there is a dead run's unfinished staging, and goes.
//!
//! What the log relies on is on the disk before the log is: every staged file and the folders holding
//! them are synced first, and the log is synced before it goes into place; the moves are synced before
//! it goes away. A log that is not whole, or that asks for a move its run could not have made, is not
//! acted on: recovery touches only plain names inside the folder, removes only files the manifest lists,
//! and puts only files from that run's own staging folder (one carrying the tool's marker) under names
//! the log's manifest lists. Anything else is refused, naming the log and what is wrong, and the user
//! decides.

use super::hooks::moved;
use super::intent::{self, Intent};
use super::manifest::{Manifest, ManifestError, MANIFEST};
use super::own_file::{self, sync_dir, OwnFileError};
use super::staging::{self, Staging, STAGING_PREFIX};
use std::fs;
use std::io;
use std::path::{Path, PathBuf};

/// File name of the intent log in a folder whose files are being moved into place.
pub const INTENT: &str = ".actuator-cam-intent";

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
        // The staged files, their names and the staging folder's own go on the disk before the log
        // that says they are there.
        own_file::sync_files(&self.staging.join("new"))?;
        sync_dir(self.staging)?;
        sync_dir(self.dir)?;
        let text = intent::to_text(
            &file_name(self.staging),
            self.remove,
            self.put,
            self.manifest,
        );
        // Written whole beside, then renamed: a kill never leaves half a log.
        let draft = self.staging.join("intent");
        own_file::write_new(&draft, text.as_bytes())?;
        fs::rename(&draft, self.dir.join(INTENT))?;
        sync_dir(self.dir)?;
        moved();
        Ok(())
    }
}

/// Every move is done (and on the disk): the log goes.
pub(super) fn finished(dir: &Path) -> io::Result<()> {
    sync_dir(dir)?;
    fs::remove_file(dir.join(INTENT))
}

/// Why the moves a dead run left could not be finished.
#[derive(Debug)]
pub(super) enum RecoverError {
    /// The log is not whole, or asks for something its run could not have done: `why` says what.
    Refused { path: PathBuf, why: String },
    /// One of the tool's names in the folder is not its file.
    OwnFile(OwnFileError),
    /// The folder's manifest is damaged.
    Manifest(ManifestError),
    /// A move failed.
    Io(io::Error),
}

impl From<io::Error> for RecoverError {
    fn from(e: io::Error) -> Self {
        RecoverError::Io(e)
    }
}

/// Finish the moves a dead run left half-done in `dir` (which this run holds), and remove every staging
/// folder of the tool there: with the folder held, none belongs to a live run.
pub(super) fn recover(dir: &Path) -> Result<(), RecoverError> {
    if let Some(bytes) = own_file::read(dir, INTENT).map_err(RecoverError::OwnFile)? {
        let path = dir.join(INTENT);
        let refuse = |why: String| RecoverError::Refused {
            path: path.clone(),
            why,
        };
        let intent = intent::parse(&bytes).map_err(refuse)?;
        // Read even when no record needs it: recovery may replace it, and a link there is refused.
        let manifest = Manifest::read(dir).map_err(RecoverError::Manifest)?;
        let staging = check(dir, &intent, manifest.as_ref()).map_err(refuse)?;
        finish(dir, &intent, staging.as_deref())?;
        fs::remove_file(&path)?;
        sync_dir(dir)?;
    }
    for entry in fs::read_dir(dir)?.flatten() {
        let prefixed = entry
            .file_name()
            .to_string_lossy()
            .starts_with(STAGING_PREFIX);
        if prefixed && staging::is_ours(&entry.path()) {
            fs::remove_dir_all(entry.path())?;
        }
    }
    Ok(())
}

/// Check every record of the log against what its run could have asked for; the staging folder, if it
/// is still there. Reads only: nothing is touched before the whole log has passed.
fn check(
    dir: &Path,
    intent: &Intent,
    manifest: Option<&Manifest>,
) -> Result<Option<PathBuf>, String> {
    let line =
        |number: usize, what: &str| format!("asks for what no run does (line {number}: {what})");
    let (number, name) = &intent.staging;
    if !plain(name) || !name.starts_with(STAGING_PREFIX) {
        return Err(line(
            *number,
            &format!("names {name:?}, not a staging folder"),
        ));
    }
    let staging = dir.join(name);
    let present = fs::symlink_metadata(&staging).is_ok();
    if present && !staging::is_ours(&staging) {
        return Err(line(
            *number,
            &format!("names {name}, which actuator-cam did not make"),
        ));
    }
    for (number, command, name) in &intent.owner {
        if command.is_empty() || !plain(name) || reserved(name) {
            return Err(line(*number, &format!("lists {name:?}, not a file name")));
        }
    }
    for (number, name) in &intent.put {
        let listed = name == MANIFEST || intent.owner.iter().any(|(_, _, n)| n == name);
        if !plain(name) || !listed {
            return Err(line(
                *number,
                &format!("puts {name:?}, which its manifest does not list"),
            ));
        }
        let staged = staging.join("new").join(name);
        if fs::symlink_metadata(&staged).is_ok_and(|m| !m.is_file()) {
            return Err(line(
                *number,
                &format!("puts {name}, whose staged copy is not a plain file"),
            ));
        }
    }
    for (number, name) in &intent.remove {
        let exists = plain(name) && fs::symlink_metadata(dir.join(name)).is_ok();
        let listed = manifest.is_some_and(|m| m.owner(name).is_some());
        if !plain(name) || reserved(name) || (exists && !listed) {
            return Err(line(
                *number,
                &format!("removes {name:?}, which the manifest does not list"),
            ));
        }
    }
    Ok(present.then_some(staging))
}

/// Make the moves a checked log asks for.
fn finish(dir: &Path, intent: &Intent, staging: Option<&Path>) -> Result<(), RecoverError> {
    for (_, name) in &intent.remove {
        let target = dir.join(name);
        if fs::symlink_metadata(&target).is_ok_and(|m| m.is_file()) {
            fs::remove_file(target)?;
            moved();
        }
    }
    match staging {
        Some(staging) => {
            for (_, name) in &intent.put {
                let new = staging.join("new").join(name);
                if fs::symlink_metadata(&new).is_ok() {
                    fs::rename(new, dir.join(name))?;
                    moved();
                }
            }
        }
        // The staging folder was taken away by hand: the log still says what the run meant.
        None => {
            let entries = intent.owner.iter().map(|(_, c, n)| (c.clone(), n.clone()));
            let manifest = Manifest::from_entries(entries).present_in(dir);
            let draft = Staging::new_in(dir)?;
            let path = draft.path().join(MANIFEST);
            own_file::write_new(&path, &manifest.to_bytes())?;
            fs::rename(&path, dir.join(MANIFEST))?;
            moved();
        }
    }
    sync_dir(dir)?;
    Ok(())
}

/// A name that stays inside the folder.
fn plain(name: &str) -> bool {
    super::name::is_plain_file_name(name)
}

/// The tool's own names, which no record may remove or list as an output.
fn reserved(name: &str) -> bool {
    [MANIFEST, INTENT, super::LOCK].contains(&name) || name.starts_with(STAGING_PREFIX)
}

fn file_name(path: &Path) -> String {
    path.file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default()
}
