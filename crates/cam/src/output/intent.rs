//! The intent log's text: what a run is about to move into a folder, written so that a log cut short
//! (a power failure, a full disk) or changed by hand is told from a whole one. One record a line, fields
//! split by a tab:
//!
//! | record                 | meaning                                                         |
//! |------------------------|-----------------------------------------------------------------|
//! | `# …`                  | a comment for a reader who finds the file                       |
//! | `staging NAME`         | the run's staging folder in the same folder (exactly one)        |
//! | `remove NAME`          | a stale file of the same command, taken away                    |
//! | `put NAME`             | a file moved in from the staging folder's `new/` (manifest last) |
//! | `owner COMMAND NAME`   | one entry of the manifest after the run                         |
//! | `end COUNT CHECKSUM`   | the last line: how many records came before it (comments not counted) and the FNV-1a 64-bit hash of every byte before it, 16 hex digits |
//!
//! A log without its `end` line, with another count or hash, or with any other line is refused whole:
//! the next run acts on a log only when it is exactly what a run wrote.

use super::manifest::Manifest;

const HEADER: &str =
    "# actuator-cam: files being moved into this folder; the next run finishes the moves.\n";

/// The moves one log asks for.
#[derive(Debug, Default, PartialEq, Eq)]
pub(super) struct Intent {
    /// The staging folder's name, with its line number.
    pub staging: (usize, String),
    /// Stale files to take away, with their line numbers (1-based), for a refusal to name.
    pub remove: Vec<(usize, String)>,
    /// Files to put in place, with their line numbers.
    pub put: Vec<(usize, String)>,
    /// The manifest after the run, as `(command, name)`, with their line numbers.
    pub owner: Vec<(usize, String, String)>,
}

/// The text of the log for a run staged in `staging` (a name in the folder).
pub(super) fn to_text(
    staging: &str,
    remove: &[String],
    put: &[String],
    manifest: &Manifest,
) -> String {
    let mut text = format!("{HEADER}staging\t{staging}\n");
    for name in remove {
        text.push_str(&format!("remove\t{name}\n"));
    }
    for name in put {
        text.push_str(&format!("put\t{name}\n"));
    }
    for (command, name) in manifest.entries() {
        text.push_str(&format!("owner\t{command}\t{name}\n"));
    }
    let records = 1 + remove.len() + put.len() + manifest.entries().count();
    let sum = checksum(text.as_bytes());
    text.push_str(&format!("end\t{records}\t{sum:016x}\n"));
    text
}

/// Read a log; `Err` says what is wrong with it, for a refusal.
pub(super) fn parse(bytes: &[u8]) -> Result<Intent, String> {
    let text = std::str::from_utf8(bytes).map_err(|_| "is damaged (not text)".to_string())?;
    let body_end = sealed_body(text)?;
    let mut intent = Intent::default();
    let mut staging_seen = false;
    for (at, line) in text[..body_end].lines().enumerate() {
        let number = at + 1;
        if line.starts_with('#') {
            continue;
        }
        let fields: Vec<&str> = line.split('\t').collect();
        match fields[..] {
            ["staging", name] if !staging_seen => {
                staging_seen = true;
                intent.staging = (number, name.to_string());
            }
            ["remove", name] => intent.remove.push((number, name.to_string())),
            ["put", name] => intent.put.push((number, name.to_string())),
            ["owner", command, name] => {
                intent
                    .owner
                    .push((number, command.to_string(), name.to_string()));
            }
            _ => {
                return Err(format!(
                    "holds a line no run writes (line {number}: {line:?})"
                ))
            }
        }
    }
    if !staging_seen {
        return Err("names no staging folder".into());
    }
    Ok(intent)
}

/// Where the records end (the `end` line begins), once the `end` line is found to seal them.
fn sealed_body(text: &str) -> Result<usize, String> {
    let cut_short = || "is cut short (its end record is missing)".to_string();
    let without_newline = text.strip_suffix('\n').ok_or_else(cut_short)?;
    let body_end = without_newline.rfind('\n').map_or(0, |at| at + 1);
    let last = &without_newline[body_end..];
    let mut fields = last.split('\t');
    let (Some("end"), Some(count), Some(sum), None) =
        (fields.next(), fields.next(), fields.next(), fields.next())
    else {
        return Err(cut_short());
    };
    let body = &text[..body_end];
    let records = body.lines().filter(|l| !l.starts_with('#')).count();
    if count != records.to_string() || sum != format!("{:016x}", checksum(body.as_bytes())) {
        return Err("is damaged (its end record does not match what comes before it)".into());
    }
    Ok(body_end)
}

/// FNV-1a, 64 bits: enough to tell a damaged or edited log from the one a run wrote (not a defence
/// against someone forging one; the rules recovery follows are).
fn checksum(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |hash, &b| {
        (hash ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> String {
        let manifest = Manifest::from_entries([("cut-sheet".to_string(), "a.svg".to_string())]);
        to_text(
            ".actuator-cam-staging-x",
            &["b.svg".to_string()],
            &["a.svg".to_string(), ".actuator-cam-manifest".to_string()],
            &manifest,
        )
    }

    #[test]
    fn a_log_reads_back_as_written() {
        let intent = parse(sample().as_bytes()).unwrap();
        assert_eq!(intent.staging, (2, ".actuator-cam-staging-x".to_string()));
        assert_eq!(intent.remove, [(3, "b.svg".to_string())]);
        assert_eq!(intent.put.len(), 2);
        assert_eq!(
            intent.owner,
            [(6, "cut-sheet".to_string(), "a.svg".to_string())]
        );
    }

    #[test]
    fn a_log_cut_short_or_changed_anywhere_is_refused() {
        let text = sample();
        // Every cut, at every byte (the empty file among them).
        for at in 0..text.len() {
            let e = parse(&text.as_bytes()[..at]).unwrap_err();
            assert!(
                e.contains("cut short") || e.contains("damaged"),
                "{at}: {e}"
            );
        }
        // Every byte changed.
        for at in 0..text.len() {
            let mut bytes = text.clone().into_bytes();
            bytes[at] ^= 0x01;
            assert!(parse(&bytes).is_err(), "byte {at} changed");
        }
        // A line taken out, or one added.
        let lines: Vec<&str> = text.lines().collect();
        for skip in 0..lines.len() {
            let mut cut: Vec<&str> = lines.clone();
            cut.remove(skip);
            assert!(parse((cut.join("\n") + "\n").as_bytes()).is_err(), "{skip}");
        }
        let added = text.replacen("put\t", "remove\tnotes.txt\nput\t", 1);
        assert!(parse(added.as_bytes()).is_err());
    }

    #[test]
    fn the_checksum_is_fnv1a_64() {
        // The published test vectors of FNV-1a 64 (Fowler, Noll, Vo): "" and "a".
        assert_eq!(checksum(b""), 0xcbf2_9ce4_8422_2325);
        assert_eq!(checksum(b"a"), 0xaf63_dc4c_8601_ec8c);
    }
}
