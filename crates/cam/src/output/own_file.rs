//! The tool's own files in a folder it writes into (its lock, intent log and manifest) and every file it
//! creates there: opened without following a link, so that no name in the folder can make the writer
//! read, truncate or write a file elsewhere (an input, a user's file). A symbolic link, a hard link (a
//! regular file with more than one name), a directory or anything but a plain file under one of the
//! tool's names is refused, naming it; the user removes it or chooses another folder.

use std::fs::{self, File, OpenOptions};
use std::io::{self, Write};
use std::os::unix::fs::{MetadataExt, OpenOptionsExt};
use std::path::{Path, PathBuf};

/// Why one of the tool's names in a folder is not a file the tool may use.
#[derive(Debug)]
pub(super) enum OwnFileError {
    /// The name holds something the tool did not make: `what` says what ("a symbolic link", …).
    Taken { path: PathBuf, what: &'static str },
    /// The file cannot be opened or read.
    Io { path: PathBuf, source: io::Error },
}

/// Open the tool's file `name` in `dir` to read it (`create`: to lock and write it, made if missing).
/// `Ok(None)` when it does not exist and `create` is false.
pub(super) fn open(dir: &Path, name: &str, create: bool) -> Result<Option<File>, OwnFileError> {
    let path = dir.join(name);
    let mut options = OpenOptions::new();
    options.read(true);
    if create {
        options.write(true).create(true).truncate(false);
    }
    // O_NONBLOCK: a FIFO under the name must not hang the run before it is refused.
    options.custom_flags(libc::O_NOFOLLOW | libc::O_NONBLOCK);
    match options.open(&path) {
        Ok(file) => {
            let meta = file.metadata().map_err(|source| OwnFileError::Io {
                path: path.clone(),
                source,
            })?;
            match taken(&meta) {
                Some(what) => Err(OwnFileError::Taken { path, what }),
                None => Ok(Some(file)),
            }
        }
        Err(e) if e.kind() == io::ErrorKind::NotFound && !create => Ok(None),
        Err(source) => match fs::symlink_metadata(&path).ok().as_ref().and_then(taken) {
            Some(what) => Err(OwnFileError::Taken { path, what }),
            None => Err(OwnFileError::Io { path, source }),
        },
    }
}

/// What makes `meta` something other than a plain file of one name, if anything.
fn taken(meta: &fs::Metadata) -> Option<&'static str> {
    let kind = meta.file_type();
    if kind.is_symlink() {
        Some("a symbolic link")
    } else if kind.is_dir() {
        Some("a directory")
    } else if !kind.is_file() {
        Some("not a plain file")
    } else if meta.nlink() > 1 {
        Some("a hard link (one file under two names)")
    } else {
        None
    }
}

/// Read the tool's file `name` in `dir` whole; `Ok(None)` when there is none.
pub(super) fn read(dir: &Path, name: &str) -> Result<Option<Vec<u8>>, OwnFileError> {
    let Some(mut file) = open(dir, name, false)? else {
        return Ok(None);
    };
    let mut bytes = Vec::new();
    io::Read::read_to_end(&mut file, &mut bytes).map_err(|source| OwnFileError::Io {
        path: dir.join(name),
        source,
    })?;
    Ok(Some(bytes))
}

/// Create the file `path`, which must not exist yet (never through a link), ready to write.
pub(super) fn create_new(path: &Path) -> io::Result<File> {
    OpenOptions::new()
        .write(true)
        .create_new(true)
        .custom_flags(libc::O_NOFOLLOW)
        .open(path)
}

/// Create `path` holding `bytes`, on the disk before this returns: the journal moves it into place
/// after a log that says it is written, and a power failure must not leave that log true of an empty file.
pub(super) fn write_new(path: &Path, bytes: &[u8]) -> io::Result<()> {
    let mut file = create_new(path)?;
    file.write_all(bytes)?;
    file.sync_all()
}

/// Create `path` holding `bytes`, to be put on the disk with the rest of its folder by [`sync_files`]:
/// a cut sheet stages hundreds of thousands of files, and a sync each would multiply its time.
pub(super) fn write_new_unsynced(path: &Path, bytes: &[u8]) -> io::Result<()> {
    create_new(path)?.write_all(bytes)
}

/// Put every file in `dir` (written by [`write_new_unsynced`]) and its entries on the disk. On Linux one
/// `syncfs` of the file system holding it, far cheaper than a sync per file; elsewhere a sync per file.
pub(super) fn sync_files(dir: &Path) -> io::Result<()> {
    let folder = File::open(dir)?;
    #[cfg(target_os = "linux")]
    {
        use std::os::fd::AsRawFd;
        // SAFETY: a plain system call on a descriptor this function owns.
        if unsafe { libc::syncfs(folder.as_raw_fd()) } != 0 {
            return Err(io::Error::last_os_error());
        }
    }
    #[cfg(not(target_os = "linux"))]
    for entry in fs::read_dir(dir)? {
        File::open(entry?.path())?.sync_all()?;
    }
    folder.sync_all()
}

/// Put the entries of `dir` (names made, renamed or removed there) on the disk.
pub(super) fn sync_dir(dir: &Path) -> io::Result<()> {
    File::open(dir)?.sync_all()
}

/// Let a write past the process's file size limit (`ulimit -f`) fail with EFBIG, said in words like a
/// full disk, instead of the default SIGXFSZ that ends the process with no message and its staging
/// folder left behind. Set once, before the first file is staged; nothing else in the tool counts on
/// the signal.
pub(super) fn file_size_limit_as_error() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        // SAFETY: SIG_IGN installs no handler; changing a disposition is safe with threads running.
        unsafe {
            libc::signal(libc::SIGXFSZ, libc::SIG_IGN);
        }
    });
}

/// A file's identity on its file system (device, inode): the same file under any name or link.
pub(super) fn file_id(m: &std::fs::Metadata) -> (u64, u64) {
    use std::os::unix::fs::MetadataExt;
    (m.dev(), m.ino())
}
