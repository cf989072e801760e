//! Rendering a cut sheet: every file as bytes in memory, named, in a fixed order. Writing them is the
//! one output writer's job ([`crate::output`]), so nothing reaches the disk before every file rendered.

use super::{CutSheet, Formats, SheetDrawing};
use crate::cam::dxf::{to_dxf_with, DxfError};
use crate::cam::svg::{to_svg, SvgOptions};

/// Why a drawing or report could not be rendered.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// A drawing has no DXF form.
    #[error("{stem}: {reason}")]
    Dxf {
        /// The drawing's file stem.
        stem: String,
        /// The DXF writer's reason.
        reason: DxfError,
    },
    /// The report has no JSON form.
    #[error(transparent)]
    Json(#[from] serde_json::Error),
}

/// File names and bytes of layer drawings (SVG and/or DXF per drawing, colours from `opts.palette`), in
/// drawing order.
pub fn render_drawings(
    drawings: &[SheetDrawing],
    formats: Formats,
    opts: &SvgOptions,
) -> Result<Vec<(String, Vec<u8>)>, RenderError> {
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
                to_dxf_with(&d.drawing, &opts.palette).map_err(|reason| RenderError::Dxf {
                    stem: d.stem.clone(),
                    reason,
                })?,
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
) -> Result<Vec<(String, Vec<u8>)>, RenderError> {
    let opts = SvgOptions {
        stroke_mm,
        palette: sheet.palette.clone(),
    };
    let mut files = render_drawings(&sheet.drawings, formats, &opts)?;
    files.push((
        "preview-actuator.svg".into(),
        super::preview::preview_svg(&sheet.preview, stroke_mm, &sheet.palette).into_bytes(),
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
