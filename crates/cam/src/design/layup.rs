//! A layup as the lab writes it, `0/90/0`: ply angles in degrees from the actuator axis, root side first.
//! One parser (the `--layup` flag of `laminate`, the `layup` column of measured data) and one writer
//! (reports, file names, sweep and optimize labels), so a layup reads and prints the same everywhere.

use crate::input::limits::{MAX_PLIES, PLY_ANGLE_DEG};

/// Why a layup text is not a layup.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LayupError {
    /// One entry is not a number in the ply-angle range.
    #[error("{0:?} is not a ply angle in the {PLY_ANGLE_DEG} (write e.g. 0/90/0)")]
    NotAnAngle(String),
    /// More plies than a design file allows.
    #[error("{0} plies: at most {MAX_PLIES}")]
    TooMany(usize),
}

/// `0/90/0` → `[0, 90, 0]`: every entry a number in [`PLY_ANGLE_DEG`], at most [`MAX_PLIES`] of them
/// (there is always at least one entry; an empty text is an entry that is not a number).
pub fn parse_layup(text: &str) -> Result<Vec<f64>, LayupError> {
    let angles = text
        .split('/')
        .map(|s| {
            s.trim()
                .parse::<f64>()
                .ok()
                .filter(|a| PLY_ANGLE_DEG.contains(*a))
                .ok_or_else(|| LayupError::NotAnAngle(s.to_string()))
        })
        .collect::<Result<Vec<f64>, _>>()?;
    if angles.len() > MAX_PLIES {
        return Err(LayupError::TooMany(angles.len()));
    }
    Ok(angles)
}

/// `[0, 90, 0]` → `0/90/0`, each angle in Rust's shortest round-trip form.
pub fn layup_text(layup_deg: &[f64]) -> String {
    layup_deg
        .iter()
        .map(|a| a.to_string())
        .collect::<Vec<_>>()
        .join("/")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_layup_reads_and_prints_the_same() {
        for text in ["0/90/0", "45/-45", "0", "22.5/0/-22.5"] {
            assert_eq!(layup_text(&parse_layup(text).unwrap()), text);
        }
        assert_eq!(parse_layup(" 0 / 90 ").unwrap(), vec![0.0, 90.0]);
    }

    #[test]
    fn a_bad_entry_is_named() {
        assert_eq!(
            parse_layup("0/x/0"),
            Err(LayupError::NotAnAngle("x".into()))
        );
        assert_eq!(
            parse_layup("0/200"),
            Err(LayupError::NotAnAngle("200".into()))
        );
        assert_eq!(parse_layup(""), Err(LayupError::NotAnAngle(String::new())));
        let many = vec!["0"; MAX_PLIES + 1].join("/");
        assert_eq!(parse_layup(&many), Err(LayupError::TooMany(MAX_PLIES + 1)));
    }
}
