//! PZT score sheets: drawing the snappable layout of every job's plates (docs/cam.md §4) once it is
//! verified.

use super::jobs::{Drawn, Job, Names, PartRecord, SheetRecord};
use super::panel::rect;
use crate::cam::drawing::{Drawing, Shape, Stock};
use crate::process::template::SheetSpec;
use crate::process::{Feature, FeatureMap};
use cam_geometry::signed_area;
use cam_nest::NestedBin;

/// Draw verified PZT layouts ([`super::place::place_plates`]) of `jobs` on `spec` sheets of `stock`: the score
/// lines in break order and the sheet edge as an alignment reference, each feature with the operation
/// `features` gives it; record every plate on its sheet and in the placement map.
pub(crate) fn draw_pzt_sheets(
    jobs: &[Job<'_>],
    spec: &SheetSpec,
    stock: &Stock,
    layouts: &[NestedBin],
    names: &Names,
    features: &FeatureMap,
    drawn: &mut Drawn,
) {
    let sheet = spec;
    let nominal: Vec<_> = jobs.iter().map(|j| j.geometry.pzt_outline()).collect();
    for layout in layouts {
        let n = drawn.next_number("pzt");
        let mut d = Drawing::on_stock(
            &format!("{} PZT plates, sheet {n}: score, then snap", names.title),
            sheet.width_mm,
            sheet.height_mm,
            stock.clone(),
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
        for p in &layout.parts {
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
                offset: p.translation,
                area_mm2: signed_area(&nominal[p.item]),
            });
        }
        drawn.sheets.push(record);
        drawn.push(format!("pzt-{n}"), "pzt", d);
    }
}
