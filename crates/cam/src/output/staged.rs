//! A held destination staged file by file, and the moves that put every staged destination in place
//! together (undone together if one fails).

use super::claim::Claim;
use super::destination::{stale_files, Destination, Kind, Run};
use super::error::{in_words, OutputError};
use super::journal::{self, Moves, Undo};
use super::manifest::Manifest;
use super::staging::{lock, Staging, COMPLETE, MOVING};
use super::MANIFEST;
use std::collections::BTreeSet;
use std::path::PathBuf;
use std::sync::atomic::Ordering;

/// A held destination whose files are written into `staging/new`; replaced and stale files go to
/// `staging/old`, and vanish with it.
#[derive(Debug)]
pub(super) struct Staged {
    pub(super) dest: Destination,
    pub(super) staging: Option<Staging>,
    /// Names written into `staging/new`, in order (the manifest last, once sealed).
    pub(super) written: Vec<String>,
    /// The manifest after this run, once sealed.
    pub(super) manifest: Manifest,
    /// The destination's lock and the folders made for it; let go after the staging folder is removed.
    pub(super) claim: Claim,
}

impl Staged {
    /// A fresh staging folder inside the held destination.
    pub(super) fn open(dest: Destination, claim: Claim) -> Result<Staged, OutputError> {
        super::own_file::file_size_limit_as_error();
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

    pub(super) fn staging(&self) -> &Staging {
        self.staging
            .as_ref()
            .expect("a staged destination has its staging folder")
    }

    pub(super) fn new_dir(&self) -> PathBuf {
        self.staging().path().join("new")
    }

    pub(super) fn old_dir(&self) -> PathBuf {
        self.staging().path().join("old")
    }

    /// Write one file into the staging folder.
    pub(super) fn put(&mut self, name: &str, bytes: &[u8]) -> Result<(), OutputError> {
        self.staging()
            .write(&self.new_dir().join(name), bytes)
            .map_err(|e| self.dest.error_stage(name, e))?;
        self.written.push(name.to_string());
        Ok(())
    }

    /// Create one file in the staging folder, to be written by the caller.
    pub(super) fn create(&mut self, name: &str) -> Result<std::fs::File, OutputError> {
        let file = self
            .staging()
            .create(&self.new_dir().join(name))
            .map_err(|e| self.dest.error_stage(name, e))?;
        self.written.push(name.to_string());
        Ok(file)
    }

    /// After the last file: find the stale files and write the manifest after this run.
    pub(super) fn seal(&mut self, run: &Run) -> Result<(), OutputError> {
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

/// Move every staged destination into place; if one move fails, undo all moves made.
pub(super) fn commit_all(staged: &mut [Staged]) -> Result<(), OutputError> {
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
