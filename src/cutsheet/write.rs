//! Writing a cut sheet: every file is rendered in memory, written into a temporary directory beside the
//! target, and the directory renamed into place, so a failure leaves no half-written output.

use super::{CutSheet, Formats, SheetDrawing};
use crate::cam::dxf::to_dxf_with;
use crate::cam::svg::{to_svg, SvgOptions};
use anyhow::{anyhow, Context};
use std::path::Path;

/// File names and bytes of layer drawings (SVG and/or DXF per drawing, colours from `opts.palette`), in
/// drawing order.
pub fn render_drawings(
    drawings: &[SheetDrawing],
    formats: Formats,
    opts: &SvgOptions,
) -> anyhow::Result<Vec<(String, Vec<u8>)>> {
    let mut files = Vec::new();
    for d in drawings {
        if formats.svg {
            files.push((
                format!("{}.svg", d.stem),
                to_svg(&d.drawing, opts).into_bytes(),
            ));
        }
        if formats.dxf {
            files.push((
                format!("{}.dxf", d.stem),
                to_dxf_with(&d.drawing, &opts.palette).map_err(|e| anyhow!("{}: {e}", d.stem))?,
            ));
        }
    }
    Ok(files)
}

/// File names and bytes of a cut sheet, in a fixed order.
pub fn render(
    sheet: &CutSheet,
    formats: Formats,
    stroke_mm: f64,
) -> anyhow::Result<Vec<(String, Vec<u8>)>> {
    let opts = SvgOptions {
        stroke_mm,
        palette: sheet.palette.clone(),
    };
    let mut files = render_drawings(&sheet.drawings, formats, &opts)?;
    files.push((
        "preview-actuator.svg".into(),
        to_svg(&sheet.preview, &opts).into_bytes(),
    ));
    let mut report = sheet.report.clone();
    report.files = files
        .iter()
        .map(|(n, _)| n.clone())
        .chain(["report.json".into(), "report.md".into()])
        .collect();
    files.push((
        "report.json".into(),
        (serde_json::to_string_pretty(&report)? + "\n").into_bytes(),
    ));
    files.push(("report.md".into(), report.markdown().into_bytes()));
    Ok(files)
}

/// Write files into `out_dir` atomically: all or nothing. An existing `out_dir` is replaced only after the
/// new one is complete.
pub fn write_atomically(out_dir: &Path, files: &[(String, Vec<u8>)]) -> anyhow::Result<()> {
    let parent = match out_dir.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => std::path::PathBuf::from("."),
    };
    // Missing parents are made (like `mkdir -p`); only now, when every file has rendered.
    std::fs::create_dir_all(&parent).with_context(|| {
        format!(
            "-o {}: cannot create the directory {}",
            out_dir.display(),
            parent.display()
        )
    })?;
    if out_dir.exists() && !out_dir.is_dir() {
        return Err(anyhow!(
            "-o {}: exists and is not a directory",
            out_dir.display()
        ));
    }
    let staging = tempfile::Builder::new()
        .prefix(".cut-sheet-")
        .tempdir_in(&parent)
        .with_context(|| {
            format!(
                "-o {}: cannot write in {}",
                out_dir.display(),
                parent.display()
            )
        })?;
    for (name, bytes) in files {
        std::fs::write(staging.path().join(name), bytes)
            .with_context(|| format!("-o {}: cannot write {name}", out_dir.display()))?;
    }
    let staged = staging.keep();
    let result = (|| -> anyhow::Result<()> {
        if out_dir.exists() {
            let old = tempfile::Builder::new()
                .prefix(".cut-sheet-old-")
                .tempdir_in(&parent)?
                .keep();
            std::fs::remove_dir(&old)?;
            std::fs::rename(out_dir, &old)?;
            std::fs::rename(&staged, out_dir)?;
            std::fs::remove_dir_all(&old)?;
        } else {
            std::fs::rename(&staged, out_dir)?;
        }
        Ok(())
    })();
    if result.is_err() {
        let _ = std::fs::remove_dir_all(&staged);
    }
    result.with_context(|| {
        format!(
            "-o {}: cannot move the finished files into place",
            out_dir.display()
        )
    })
}
