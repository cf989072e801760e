//! Which names a run may write into a folder: a plain file name, never a path that leaves the folder. The
//! writer checks each output name with it, and the journal each name a dead run's log asks it to move.

use std::path::Path;

/// A name that stays inside its folder: one component, not `.` or `..`.
pub(super) fn is_plain_file_name(name: &str) -> bool {
    let mut components = Path::new(name).components();
    matches!(
        (components.next(), components.next()),
        (Some(std::path::Component::Normal(_)), None)
    )
}
