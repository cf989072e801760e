//! The PZT plates' snappable layout of score lines, planned by [`crate::layout::layout_plates`]
//! and checked by the verifier before the score lines are drawn ([`crate::pipeline::score_lines`]).

use super::refusal::sheet_too_small;
use super::{promised, sheet_of, ROUNDING_MM};
use crate::layout::{
    layout_plates, verify_break_order, verify_offcuts, verify_snappable, LayoutError, PlateSpec,
};
use crate::pipeline::jobs::{format_violations, Job, Names};
use crate::pipeline::BuildError;
use crate::process::template::SheetSpec;
use cam_nest::{
    verify_copies, verify_sheet, verify_stock, Clearance, NestBin, NestItem, NestedBin,
};

/// Lay out two plates per actuator of every job on `spec` sheets (at most `stock`) as a snappable
/// layout, and verify it: every copy once, the score lines snappable and listed in break order, each
/// plate its nominal trapezoid placed, the kerf between plates and the margin to the sheet edge.
pub(crate) fn place_plates(
    jobs: &[Job<'_>],
    spec: &SheetSpec,
    stock: Option<usize>,
    names: &Names,
) -> Result<Vec<NestedBin>, BuildError> {
    let plates: Vec<PlateSpec> = jobs
        .iter()
        .map(|j| PlateSpec {
            length_mm: j.geometry.plate_length_mm(),
            base_width_mm: j.geometry.plate_base_width_mm(),
            tip_width_mm: j.geometry.plate_tip_width_mm(),
            count: 2 * j.quantity,
        })
        .collect();
    let copies: usize = plates.iter().map(|p| p.count).sum();
    let sheet = sheet_of(spec, stock.unwrap_or(copies.max(1)));
    // The narrowest snappable strip scales with the plate thickness (docs/cam.md §4).
    let thickness_mm = jobs
        .iter()
        .map(|j| j.design.pzt_thickness * 1e3)
        .fold(0.0, f64::max);
    let min_strip_mm = spec.min_snap_strip_thicknesses * thickness_mm;
    let layout = layout_plates(
        &plates,
        &sheet,
        spec.kerf_mm,
        spec.edge_margin_mm,
        min_strip_mm,
    )
    .map_err(|e| match e {
        LayoutError::TooLarge {
            item,
            width_mm,
            height_mm,
            sheet_width_mm,
            sheet_height_mm,
            usable_width_mm,
            usable_height_mm,
        } => {
            // The planner's own answer for the plate alone on a sheet of the size to name.
            let alone = [PlateSpec {
                count: 1,
                ..plates[item]
            }];
            let takes = |width_mm: f64, height_mm: f64| {
                let sheet = NestBin {
                    width_mm,
                    height_mm,
                    stock: 1,
                };
                layout_plates(
                    &alone,
                    &sheet,
                    spec.kerf_mm,
                    spec.edge_margin_mm,
                    min_strip_mm,
                )
                .is_ok()
            };
            sheet_too_small(
                spec,
                &format!("a {width_mm:.2} x {height_mm:.2} mm PZT plate"),
                [width_mm, height_mm],
                [
                    sheet_width_mm - usable_width_mm,
                    sheet_height_mm - usable_height_mm,
                ],
                true,
                Some(&takes),
            )
        }
        other => names.error(format!("pzt layout: {other}")),
    })?;
    let fail = |what: String| names.error(format!("pzt (verifier) layout: {what}"));
    // PZT is in-plane isotropic: strips may run either way, so any quarter turn is allowed.
    let items: Vec<NestItem> = jobs
        .iter()
        .zip(&plates)
        .map(|(j, p)| NestItem {
            outline: j.geometry.pzt_outline(),
            demand: p.count,
            rotations_deg: vec![0.0, 90.0, 180.0, 270.0],
        })
        .collect();
    verify_stock(&layout.bins, sheet.stock).map_err(|v| fail(v.to_string()))?;
    verify_copies(&items, &layout.bins).map_err(|v| fail(v.to_string()))?;
    // Scored plates keep the kerf between each other but only the margin to the sheet edge.
    let clearance = Clearance {
        between_parts_mm: promised(spec.kerf_mm),
        to_edge_mm: promised(spec.edge_margin_mm),
    };
    for bin in &layout.bins {
        verify_sheet(
            &items,
            &sheet,
            clearance,
            bin.index,
            &bin.parts,
            ROUNDING_MM,
        )
        .map_err(|v| fail(v.to_string()))?;
        let snap = |v: Vec<crate::layout::Violation>| fail(format_violations(&v));
        verify_snappable(bin, &sheet).map_err(snap)?;
        verify_break_order(bin, &sheet).map_err(snap)?;
        verify_offcuts(bin, &sheet, min_strip_mm).map_err(snap)?;
    }
    Ok(layout.bins)
}
