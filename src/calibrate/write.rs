//! Writing calibrate's files. Kept apart until the one output writer of the command layer replaces it.

use anyhow::Context;
use std::path::Path;

/// Write the files into a temporary directory beside `dir`, then move them into place.
pub fn write_atomically(dir: &Path, files: &[(String, String)]) -> anyhow::Result<()> {
    let parent = match dir.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => std::path::PathBuf::from("."),
    };
    std::fs::create_dir_all(&parent).with_context(|| format!("creating {}", parent.display()))?;
    let tmp = tempfile::Builder::new()
        .prefix(".calibrate-")
        .tempdir_in(&parent)
        .with_context(|| format!("creating a temporary directory in {}", parent.display()))?;
    for (name, text) in files {
        std::fs::write(tmp.path().join(name), text).with_context(|| format!("writing {name}"))?;
    }
    if !dir.exists() {
        let staged = tmp.keep();
        std::fs::rename(&staged, dir)
            .with_context(|| format!("moving the results to {}", dir.display()))?;
    } else {
        for (name, _) in files {
            std::fs::rename(tmp.path().join(name), dir.join(name))
                .with_context(|| format!("moving {name} into {}", dir.display()))?;
        }
    }
    Ok(())
}
