//! Why the output could not be written, each reason said in the user's words.

use std::io;

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
    /// The output path, or a folder on its way, is a symbolic link to nothing.
    #[error("{flag} {shown}: {link} is a symbolic link to {target}, which does not exist; make that folder, or choose another {flag}")]
    DanglingLink {
        /// The flag.
        flag: String,
        /// The path as given.
        shown: String,
        /// The link.
        link: String,
        /// Where it points.
        target: String,
    },
    /// A flag that takes a file was given a folder (`somedir/`).
    #[error("{flag} {shown}: names a folder, and {flag} takes a file path; add a file name")]
    FolderNotFile {
        /// The flag.
        flag: String,
        /// The path as given.
        shown: String,
    },
    /// One of the tool's own names in the folder (lock, intent log, manifest) holds something else.
    #[error(
        "{flag} {shown}: {path} is {what}; actuator-cam keeps its own plain file under that name and never \
         follows or writes through a link there; remove it, or choose another {flag}"
    )]
    OwnName {
        /// The flag.
        flag: String,
        /// The path as given.
        shown: String,
        /// The name in the folder.
        path: String,
        /// What is there instead ("a symbolic link", "a hard link …", "a directory").
        what: String,
    },
    /// The intent log of a stopped run cannot be acted on.
    #[error(
        "{flag} {shown}: the moves of a run that stopped mid-way are not finished: its intent log {path} \
         {why}; look over the folder, then delete {path} to go on (files the manifest does not list are \
         then kept as yours)"
    )]
    Journal {
        /// The flag.
        flag: String,
        /// The path as given.
        shown: String,
        /// The log.
        path: String,
        /// What is wrong with it.
        why: String,
    },
    /// The folder's manifest is not one the tool wrote.
    #[error(
        "{flag} {shown}: the manifest {path} is damaged ({why}); restore it, or delete it to keep every \
         file in the folder as yours"
    )]
    ManifestDamaged {
        /// The flag.
        flag: String,
        /// The path as given.
        shown: String,
        /// The manifest.
        path: String,
        /// Where it is damaged.
        why: String,
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
        K::FileTooLarge => {
            "a file is larger than this process may write (the file size limit, ulimit -f) or the file \
             system holds"
        }
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
