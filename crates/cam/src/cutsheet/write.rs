//! Rendering a cut sheet: every file as bytes, named, in a fixed order: the layer files drawing by
//! drawing, then the preview and the report. Writing them is the one output writer's job
//! ([`crate::output`]); a large cut sheet hands each drawing's files to it as they are rendered, so only
//! one drawing's bytes are held at a time.

use super::{CutSheet, Formats, SheetDrawing};
use crate::drawing::dxf::{to_dxf_with, DxfError};
use crate::drawing::palette::Palette;
use crate::drawing::svg::{to_svg, SvgOptions};

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

/// File names and bytes of one layer drawing (SVG and/or DXF, colours from `opts.palette`).
pub fn render_drawing(
    d: &SheetDrawing,
    formats: Formats,
    opts: &SvgOptions,
) -> Result<Vec<(String, Vec<u8>)>, RenderError> {
    let mut files = Vec::with_capacity(2);
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
    Ok(files)
}

/// File names and bytes of layer drawings, in drawing order.
pub fn render_drawings(
    drawings: &[SheetDrawing],
    formats: Formats,
    opts: &SvgOptions,
) -> Result<Vec<(String, Vec<u8>)>, RenderError> {
    let mut files = Vec::new();
    for d in drawings {
        files.extend(render_drawing(d, formats, opts)?);
    }
    Ok(files)
}

/// The layer files' SVG settings of a cut sheet.
pub fn svg_options(palette: &Palette, stroke_mm: f64) -> SvgOptions {
    SvgOptions {
        stroke_mm,
        palette: palette.clone(),
    }
}

/// The files after the layer files: the preview, the PZT sheets' snapping-order pictures,
/// `report.json` (listing `layer_files`, the names of the layer files written before, then these) and
/// `report.md`.
pub fn render_report(
    sheet: &CutSheet,
    layer_files: &[String],
    stroke_mm: f64,
) -> Result<Vec<(String, Vec<u8>)>, RenderError> {
    let preview = "preview-actuator.svg";
    let mut report = sheet.report.clone();
    report.files = layer_files
        .iter()
        .map(String::as_str)
        .chain([preview])
        .chain(sheet.snap_guides.iter().map(|(name, _)| name.as_str()))
        .chain(["report.json", "report.md"])
        .map(str::to_string)
        .collect();
    let mut files = vec![(
        preview.into(),
        super::preview::preview_svg(&sheet.preview, stroke_mm, &sheet.palette).into_bytes(),
    )];
    files.extend(
        sheet
            .snap_guides
            .iter()
            .map(|(name, svg)| (name.clone(), svg.clone().into_bytes())),
    );
    files.push((
        "report.json".into(),
        (serde_json::to_string_pretty(&report)? + "\n").into_bytes(),
    ));
    files.push(("report.md".into(), report.markdown().into_bytes()));
    Ok(files)
}

/// File names and bytes of a cut sheet held in memory ([`super::plan`]), in a fixed order.
pub fn render(
    sheet: &CutSheet,
    formats: Formats,
    stroke_mm: f64,
) -> Result<Vec<(String, Vec<u8>)>, RenderError> {
    let opts = svg_options(&sheet.palette, stroke_mm);
    let mut files = render_drawings(&sheet.drawings, formats, &opts)?;
    let names: Vec<String> = files.iter().map(|(n, _)| n.clone()).collect();
    files.extend(render_report(sheet, &names, stroke_mm)?);
    Ok(files)
}
