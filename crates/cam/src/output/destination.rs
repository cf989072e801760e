//! A destination folder and the policy checks made on it before anything is written: whose files are in
//! it, which names a run may write, what is stale, and which paths are the run's inputs.

use super::claim::{Claim, ClaimError};
use super::error::{in_words, OutputError};
use super::journal::RecoverError;
use super::manifest::{foreign_entries, Manifest, ManifestError};
use super::name::is_plain_file_name;
use super::own_file::{file_id, OwnFileError};
use super::{INTENT, LOCK, MANIFEST, STAGING_PREFIX};
use std::collections::BTreeSet;
use std::fs;
use std::io;
use std::path::{Path, PathBuf};

/// Where a destination's files come from on the command line.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Kind {
    /// `-o DIR`: the whole folder is this command's output.
    Folder,
    /// Named files (`-o best.toml`, `--csv designs.csv`) in a folder that is otherwise the user's.
    Files,
}

/// One destination folder: where it is, how it was named, and what the policy found there.
#[derive(Debug)]
pub(super) struct Destination {
    pub(super) flag: String,
    pub(super) shown: String,
    pub(super) dir: PathBuf,
    pub(super) kind: Kind,
    /// The folder's manifest as the run found it (read once the folder is held).
    pub(super) manifest: Option<Manifest>,
    /// Files the same command wrote here before and does not write now, found when the run is sealed.
    pub(super) stale: Vec<String>,
    /// Names in the folder once it is held, in lower case (`None`: not read, or unreadable). A name not
    /// among them needs no look-up of its own: a cut sheet writes a few hundred thousand files into a
    /// new folder, and a look-up each in a folder that large is a good share of the run. Lower case, so
    /// that on a file system that ignores case `Report.md` still counts as there for `report.md`.
    present: Option<BTreeSet<String>>,
}

impl Destination {
    pub(super) fn new(flag: &str, shown: String, dir: PathBuf, kind: Kind) -> Destination {
        Destination {
            flag: flag.into(),
            shown,
            dir,
            kind,
            manifest: None,
            stale: Vec::new(),
            present: None,
        }
    }

    /// True when `name` may exist in the held folder (it was there when the folder was held, or the
    /// folder could not be listed).
    fn may_hold(&self, name: &str) -> bool {
        self.present
            .as_ref()
            .is_none_or(|names| names.contains(&name.to_lowercase()))
    }

    pub(super) fn error_stage(&self, what: impl Into<String>, source: io::Error) -> OutputError {
        OutputError::Stage {
            flag: self.flag.clone(),
            shown: self.shown.clone(),
            what: what.into(),
            reason: in_words(&source),
        }
    }

    /// Check that the destination is a folder (or nothing yet), hold it, and read its manifest.
    pub(super) fn claim(&mut self, run: &Run) -> Result<Claim, OutputError> {
        self.check_folder()?;
        let claim =
            Claim::take(&self.dir, &run.command, &run.ids).map_err(|e| self.claim_error(e))?;
        // Held from here on: no other run of the tool adds to it.
        self.read_contents()?;
        Ok(claim)
    }

    /// What [`Destination::claim`] finds, without holding the folder: for the checks a run makes
    /// before its work ([`super::Output::check_folder_ahead`]). False when there is nothing to judge
    /// yet: no folder (the write makes it, and says why if it cannot), or a killed run's intent log
    /// (the write finishes its moves, which the manifest does not list until then).
    pub(super) fn look(&mut self) -> Result<bool, OutputError> {
        self.check_folder()?;
        if fs::symlink_metadata(&self.dir).is_err()
            || fs::symlink_metadata(self.dir.join(INTENT)).is_ok()
        {
            return Ok(false);
        }
        self.read_contents()?;
        Ok(true)
    }

    /// The destination is a folder, or nothing yet (and not a link to nothing).
    fn check_folder(&self) -> Result<(), OutputError> {
        if let Some((link, target)) = dangling_link(&self.dir) {
            return Err(OutputError::DanglingLink {
                flag: self.flag.clone(),
                shown: self.shown.clone(),
                link: link.display().to_string(),
                target: target.display().to_string(),
            });
        }
        if self.dir.exists() && !self.dir.is_dir() {
            return Err(OutputError::NotADirectory {
                flag: self.flag.clone(),
                shown: self.shown.clone(),
            });
        }
        Ok(())
    }

    /// The folder's manifest and the names in it.
    fn read_contents(&mut self) -> Result<(), OutputError> {
        self.manifest = Manifest::read(&self.dir).map_err(|e| self.manifest_error(e))?;
        self.present = fs::read_dir(&self.dir).ok().and_then(|entries| {
            entries
                .map(|e| e.map(|e| e.file_name().to_string_lossy().to_lowercase()))
                .collect::<io::Result<BTreeSet<String>>>()
                .ok()
        });
        Ok(())
    }
}

impl Destination {
    fn claim_error(&self, e: ClaimError) -> OutputError {
        let (flag, shown) = (self.flag.clone(), self.shown.clone());
        match e {
            ClaimError::Busy { command, pid } => OutputError::Busy {
                flag,
                shown,
                command,
                pid,
            },
            ClaimError::Io { dir, source } => self.cannot_write(&dir, &source),
            ClaimError::OwnFile(e) => self.own_file_error(e),
            ClaimError::Recover(RecoverError::Refused { path, why }) => OutputError::Journal {
                flag,
                shown,
                path: path.display().to_string(),
                why,
            },
            ClaimError::Recover(RecoverError::OwnFile(e)) => self.own_file_error(e),
            ClaimError::Recover(RecoverError::Manifest(e)) => self.manifest_error(e),
            ClaimError::Recover(RecoverError::Io(source)) => self.cannot_write(&self.dir, &source),
        }
    }

    fn cannot_write(&self, dir: &Path, source: &io::Error) -> OutputError {
        OutputError::CreateDir {
            flag: self.flag.clone(),
            shown: self.shown.clone(),
            dir: dir.display().to_string(),
            reason: in_words(source),
        }
    }

    fn own_file_error(&self, e: OwnFileError) -> OutputError {
        match e {
            OwnFileError::Taken { path, what } => OutputError::OwnName {
                flag: self.flag.clone(),
                shown: self.shown.clone(),
                path: path.display().to_string(),
                what: what.to_string(),
            },
            OwnFileError::Io { path, source } => self.cannot_write(&path, &source),
        }
    }

    fn manifest_error(&self, e: ManifestError) -> OutputError {
        match e {
            ManifestError::OwnFile(e) => self.own_file_error(e),
            ManifestError::Damaged { path, why } => OutputError::ManifestDamaged {
                flag: self.flag.clone(),
                shown: self.shown.clone(),
                path: path.display().to_string(),
                why,
            },
        }
    }
}

/// The first component of `dir` (or `dir` itself) that is a symbolic link to nothing, and where it
/// points: making the folder would fail there with a bare "file exists".
fn dangling_link(dir: &Path) -> Option<(PathBuf, PathBuf)> {
    let mut ancestors: Vec<&Path> = dir
        .ancestors()
        .filter(|a| !a.as_os_str().is_empty())
        .collect();
    ancestors.reverse();
    ancestors.into_iter().find_map(|a| {
        let is_link = fs::symlink_metadata(a).is_ok_and(|m| m.file_type().is_symlink());
        if is_link && fs::metadata(a).is_err() {
            Some((a.to_path_buf(), fs::read_link(a).unwrap_or_default()))
        } else {
            None
        }
    })
}

/// Files of a destination as (name, bytes), in order.
pub(super) type Files = Vec<(String, Vec<u8>)>;

/// What every destination of one run shares: the command that writes, `--force`, the run's inputs.
#[derive(Debug, Clone)]
pub(super) struct Run {
    pub(super) command: String,
    pub(super) force: bool,
    pub(super) inputs: Vec<PathBuf>,
    /// The inputs as (device, inode), found when the writing starts: a file of the run is an input if it
    /// is one of them under any name (a symlink, a hard link, `./sub/..`).
    pub(super) ids: Vec<(u64, u64)>,
}

impl Run {
    /// Every input: the paths named, and every file read so far (listed on stderr by a test hook,
    /// [`super::hooks`]).
    pub(super) fn resolve(&mut self) {
        let all = self.all_inputs();
        super::hooks::list_inputs(&all);
        self.ids = ids(&all);
    }

    /// The run as [`Run::resolve`] leaves it, for a look before the work: the inputs are listed once,
    /// when the files are written.
    pub(super) fn resolved_quietly(&self) -> Run {
        Run {
            ids: ids(&self.all_inputs()),
            ..self.clone()
        }
    }

    /// The paths named and every file read so far, each once.
    fn all_inputs(&self) -> Vec<PathBuf> {
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
        all
    }

    /// True when `path` is (the same file as) one of the run's inputs.
    pub(super) fn is_input(&self, path: &Path) -> bool {
        fs::metadata(path).is_ok_and(|m| self.ids.contains(&file_id(&m)))
    }
}

/// The (device, inode) of each path that exists.
fn ids(paths: &[PathBuf]) -> Vec<(u64, u64)> {
    paths
        .iter()
        .filter_map(|p| fs::metadata(p).ok())
        .map(|m| file_id(&m))
        .collect()
}

/// The policy for one file name: a plain name, not a folder, not an input of the run.
pub(super) fn check_target(d: &Destination, name: &str, run: &Run) -> Result<(), OutputError> {
    let ours = [MANIFEST, LOCK, INTENT];
    if !is_plain_file_name(name) || ours.contains(&name) || name.starts_with(STAGING_PREFIX) {
        return Err(OutputError::NotAFileName {
            flag: d.flag.clone(),
            shown: d.shown.clone(),
        });
    }
    let target = d.dir.join(name);
    if !d.may_hold(name) || fs::symlink_metadata(&target).is_err() {
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
pub(super) fn check_occupied(d: &Destination, force: bool) -> Result<(), OutputError> {
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
pub(super) fn check_replace(d: &Destination, name: &str, run: &Run) -> Result<(), OutputError> {
    if run.force || !d.may_hold(name) || fs::symlink_metadata(d.dir.join(name)).is_err() {
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
pub(super) fn stale_files(d: &Destination, run: &Run, written: &BTreeSet<&str>) -> Vec<String> {
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
pub(super) fn listing(names: &[String]) -> String {
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
