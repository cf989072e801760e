//! Reading a user file, and the list of every file this process has read. Every reader of a user file
//! (design, template, batch, part drawing, spec, sweep factors, measured or failure CSV, effects file,
//! `--model` file) reads through [`read_text`], so that list is complete by construction: the output
//! writer takes it as the run's inputs, which no output may replace.

use super::InputError;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// Every file read so far, as given (the writer resolves them when it checks).
static READ: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// The text of a user file, recorded as an input of the run.
pub fn read_text(path: &Path) -> Result<String, InputError> {
    record(path);
    std::fs::read_to_string(path).map_err(|e| InputError::io(path, &e))
}

/// Record `path` as an input of the run without reading it here.
pub fn record(path: &Path) {
    let mut read = READ.lock().unwrap_or_else(|e| e.into_inner());
    if !read.iter().any(|p| p == path) {
        read.push(path.to_path_buf());
    }
}

/// Every file read so far, in the order first read.
pub fn files_read() -> Vec<PathBuf> {
    READ.lock().unwrap_or_else(|e| e.into_inner()).clone()
}
