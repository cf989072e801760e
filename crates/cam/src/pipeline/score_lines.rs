//! PZT score sheets: drawing the snappable layout of every job's plates (docs/cam.md §4) once it is
//! verified. The score lines are planned in [`crate::layout::plates`] (its `planner`, which places the
//! plates and the lines between them) and checked in [`super::place`]; here they are only drawn, in
//! break order.

use super::jobs::{Drawn, Job, Names, PartRecord, SheetRecord};
use super::panel::{on_sheet_edge, rect};
use super::sheet_label::part_box;
use crate::drawing::model::{file_stem, Drawing, Shape, Stock};
use crate::process::template::SheetSpec;
use crate::process::{Feature, FeatureMap};
use cam_geometry::{place_ring, signed_area, Point};
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
                Shape::Polyline(overrun(*line, sheet).to_vec()),
            );
        }
        // The plates as placed: what the stock label keeps clear of, and what the snapping guide draws.
        let plates: Vec<Vec<Point>> = layout
            .parts
            .iter()
            .map(|p| place_ring(&nominal[p.item], p.rotation_deg, p.translation))
            .collect();
        // Every plate is bonded on one face (the lower plate + face up against the passive part, the
        // upper plate on its - face), and either face may be the one up on the bed: the whole plate is
        // a bonded zone, written into the SVG as data so that no mark goes there.
        for ring in &plates {
            d.add_guide("bonded-zone", ring.clone());
        }
        let parts: Vec<_> = plates
            .iter()
            .map(|ring| part_box(ring))
            .chain(layout.score_lines.iter().map(|l| part_box(l)))
            .collect();
        drawn.label_sheet(
            &mut d,
            &format!("pzt-{n}"),
            sheet.edge_margin_mm,
            &parts,
            features.op(Feature::SheetLabel),
        );
        // The sheet edge as an alignment reference (green, not a cut, by default).
        d.add(
            features.op(Feature::PztSheetOutline),
            Shape::Polygon(rect([0.0, 0.0], sheet.width_mm, sheet.height_mm)),
        );
        let mut record = SheetRecord {
            stem: format!("pzt-{n}"),
            file_stem: file_stem(&format!("pzt-{n}"), d.stock.as_ref()),
            layer: "pzt".into(),
            material: spec.material.clone(),
            width_mm: sheet.width_mm,
            height_mm: sheet.height_mm,
            parts: Vec::new(),
            stock_file: None,
            remnant: None,
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
        drawn.snap_guides.push((
            super::snap_guide::file_name(&format!("pzt-{n}")),
            super::snap_guide::snap_guide(
                &format!("{} PZT sheet {n}", names.title),
                sheet.width_mm,
                sheet.height_mm,
                &plates,
                &layout.score_lines,
            ),
        ));
        drawn.sheets.push(record);
        drawn.push(format!("pzt-{n}"), "pzt", d);
    }
}

/// A score line as the laser runs it: each end on the sheet edge carried `spec.score_overrun_mm` past
/// it along the line, so the score reaches the edge although the laser is still accelerating where a
/// path starts (docs/cam.md §4). An end on an earlier score line stays there: running on would score
/// the plate across that line. The verified layout keeps the exact lines; only the drawing overruns.
pub(super) fn overrun(line: [Point; 2], spec: &SheetSpec) -> [Point; 2] {
    let on_edge = |p: Point| on_sheet_edge(p, spec.width_mm, spec.height_mm);
    let [a, b] = line;
    let length = (b[0] - a[0]).hypot(b[1] - a[1]);
    if length == 0.0 {
        return line;
    }
    let unit = [(b[0] - a[0]) / length, (b[1] - a[1]) / length];
    let run = spec.score_overrun_mm;
    let a = if on_edge(a) {
        [a[0] - unit[0] * run, a[1] - unit[1] * run]
    } else {
        a
    };
    let b = if on_edge(b) {
        [b[0] + unit[0] * run, b[1] + unit[1] * run]
    } else {
        b
    };
    [a, b]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sheet(overrun_mm: f64) -> SheetSpec {
        let design = std::path::Path::new("design.toml");
        let mut spec = crate::process::template::Template::resolve("method-2", design)
            .unwrap()
            .pzt;
        spec.width_mm = 50.0;
        spec.height_mm = 40.0;
        spec.score_overrun_mm = overrun_mm;
        spec
    }

    #[test]
    fn only_ends_on_the_sheet_edge_run_over() {
        let s = sheet(0.5);
        // Edge to edge across the sheet: both ends run 0.5 mm past it.
        assert_eq!(
            overrun([[0.0, 10.0], [50.0, 10.0]], &s),
            [[-0.5, 10.0], [50.5, 10.0]]
        );
        // From the bottom edge up to an earlier line at y = 10: only the edge end runs over.
        assert_eq!(
            overrun([[20.0, 0.0], [20.0, 10.0]], &s),
            [[20.0, -0.5], [20.0, 10.0]]
        );
        // A slanted line between two earlier lines: untouched.
        let inner = [[5.0, 10.0], [7.0, 30.0]];
        assert_eq!(overrun(inner, &s), inner);
        // A slanted line from the top edge runs on along its own direction.
        let [a, _] = overrun([[10.0, 40.0], [13.0, 36.0]], &s);
        assert!(
            (a[0] - (10.0 - 0.3)).abs() < 1e-12 && (a[1] - 40.4).abs() < 1e-12,
            "{a:?}"
        );
        // No overrun asked: the line as laid out.
        let line = [[0.0, 10.0], [50.0, 10.0]];
        assert_eq!(overrun(line, &sheet(0.0)), line);
    }
}
