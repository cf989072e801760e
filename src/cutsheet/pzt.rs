//! PZT score sheets: the plates of every job in one snappable layout (CAM-NOTES §4), verified before
//! anything is drawn.

use super::features::{Feature, FeatureMap};
use super::jobs::{format_violations, Drawn, Job, Names, PartRecord, SheetRecord};
use super::panel::rect;
use super::template::SheetSpec;
use super::CutSheetError;
use crate::cam::drawing::{Drawing, Shape};
use crate::layout::{
    layout_plates, verify_break_order, verify_copies, verify_outlines, verify_sheet_edges,
    verify_snappable, PlateSpec, Sheet, Violation,
};
use cam_geometry::signed_area;

/// Lay out two plates per actuator of every job on `spec` sheets (at most `stock`), verify each sheet
/// and draw its score lines, each feature with the operation `features` gives it. Returns the number of
/// sheets.
pub fn pzt_sheets(
    jobs: &[Job<'_>],
    spec: &SheetSpec,
    stock: Option<usize>,
    names: &Names,
    features: &FeatureMap,
    drawn: &mut Drawn,
) -> Result<usize, CutSheetError> {
    let sheet = Sheet {
        width_mm: spec.width_mm,
        height_mm: spec.height_mm,
    };
    let items: Vec<PlateSpec> = jobs
        .iter()
        .map(|j| PlateSpec {
            length_mm: j.geometry.plate_length_mm(),
            base_width_mm: j.geometry.plate_base_width_mm(),
            tip_width_mm: j.geometry.plate_tip_width_mm(),
            count: 2 * j.quantity,
        })
        .collect();
    let counts: Vec<usize> = items.iter().map(|i| i.count).collect();
    let layouts = layout_plates(&items, &sheet, spec.kerf_mm, spec.edge_margin_mm, stock)
        .map_err(|e| names.error(format!("pzt layout: {e}")))?;
    // Check the layout independently of the code that made it before anything is drawn.
    let fail = |v: Vec<Violation>| {
        names.error(format!("pzt (verifier) layout: {}", format_violations(&v)))
    };
    verify_copies(&layouts, &counts).map_err(fail)?;
    let nominal: Vec<_> = jobs.iter().map(|j| j.geometry.pzt_outline()).collect();
    for layout in &layouts {
        verify_snappable(layout, &sheet).map_err(fail)?;
        verify_break_order(layout, &sheet).map_err(fail)?;
        verify_outlines(layout, &|item| nominal[item].clone(), 1e-9).map_err(fail)?;
        // PZT is in-plane isotropic: strips may run either way, so any quarter turn is allowed.
        verify_sheet_edges(
            layout,
            &sheet,
            (spec.kerf_mm - 1e-9).max(0.0),
            (spec.edge_margin_mm - 1e-9).max(0.0),
            &|_| vec![0.0, 90.0, 180.0, 270.0],
        )
        .map_err(fail)?;
        let n = drawn.next_number("pzt");
        let mut d = Drawing::new(
            &format!("{} PZT plates, sheet {n}: score, then snap", names.title),
            sheet.width_mm,
            sheet.height_mm,
        );
        for line in &layout.score_lines {
            d.add(
                features.op(Feature::PztScoreLine),
                Shape::Polyline(vec![line[0], line[1]]),
            );
        }
        // The sheet edge as an alignment reference (green, not a cut, by default).
        d.add(
            features.op(Feature::PztSheetOutline),
            Shape::Polygon(rect([0.0, 0.0], sheet.width_mm, sheet.height_mm)),
        );
        let mut record = SheetRecord {
            stem: format!("pzt-{n}"),
            layer: "pzt".into(),
            material: spec.material.clone(),
            width_mm: sheet.width_mm,
            height_mm: sheet.height_mm,
            parts: Vec::new(),
        };
        for p in &layout.placements {
            let job = &jobs[p.item];
            drawn.placement_map.push(format!(
                "{} plate {}: PZT sheet {n}",
                names.actuator(job.design, p.copy / 2),
                p.copy % 2 + 1
            ));
            record.parts.push(PartRecord {
                job: p.item,
                actuator: p.copy / 2,
                part: format!("pzt-plate-{}", p.copy % 2 + 1),
                rotation_deg: p.rotation_deg,
                offset: p.offset,
                area_mm2: signed_area(&nominal[p.item]),
            });
        }
        drawn.sheets.push(record);
        drawn.push(format!("pzt-{n}"), "pzt", d);
    }
    Ok(layouts.len())
}
