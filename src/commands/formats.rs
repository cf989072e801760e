//! `--format svg,dxf`, shared by the commands that write layer files.

use crate::cutsheet::Formats;
use anyhow::bail;

/// Parse `--format`.
pub fn parse_formats(list: &[String]) -> anyhow::Result<Formats> {
    let mut formats = Formats {
        svg: false,
        dxf: false,
    };
    for f in list {
        match f.as_str() {
            "svg" => formats.svg = true,
            "dxf" => formats.dxf = true,
            other => bail!("--format {other:?}: expected svg, dxf or svg,dxf"),
        }
    }
    Ok(formats)
}
