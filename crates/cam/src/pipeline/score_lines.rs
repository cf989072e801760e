//! PZT score sheets: drawing the snappable layout of every job's plates (docs/cam.md §4) once it is
//! verified. The score lines are planned in [`crate::layout::plates`] (its `planner`, which places the
//! plates and the lines between them) and checked in [`super::place`]; here they are only drawn, in
//! break order.

use super::jobs::{Drawn, Job, Names, PartRecord, SheetRecord};
use super::panel::{on_sheet_edge, rect};
use super::place::PlacedPlates;
use super::sheet_label::part_box;
use crate::drawing::model::{file_stem, Drawing, Shape, Stock};
use crate::process::template::SheetSpec;
use crate::process::{Feature, FeatureMap};
use cam_geometry::{place_ring, signed_area, Point};
use cam_nest::SheetShape;

/// Draw verified PZT layouts ([`super::place::place_plates`]) of `jobs` on `spec` sheets of `stock`: the score
/// lines in break order and the stock's edge (the sheet's, or a remnant's) as an alignment reference, each
/// feature with the operation `features` gives it; record every plate on its sheet and in the placement
/// map, and the rest of each sheet to keep as its remnant.
pub(crate) fn draw_pzt_sheets(
    jobs: &[Job<'_>],
    spec: &SheetSpec,
    stock: &Stock,
    placed: &PlacedPlates,
    names: &Names,
    features: &FeatureMap,
    drawn: &mut Drawn,
) {
    let sheet = spec;
    let nominal: Vec<_> = jobs.iter().map(|j| j.geometry.pzt_outline()).collect();
    for (k, layout) in placed.bins.iter().enumerate() {
        // A remnant's layout lies where the remnant lies on the sheet it was cut from.
        let remnant_of = placed.drawn.get(k).map(|&d| &spec.drawn[d]);
        let edge = match remnant_of {
            Some(d) => {
                let b = cam_geometry::Bounds::of(&d.shape.outline);
                [b.min, b.max]
            }
            None => [[0.0, 0.0], [sheet.width_mm, sheet.height_mm]],
        };
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
                Shape::Polyline(overrun(*line, edge, sheet.score_overrun_mm).to_vec()),
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
            .chain(outside(edge, sheet.width_mm, sheet.height_mm))
            .collect();
        drawn.label_sheet(
            &mut d,
            &format!("pzt-{n}"),
            sheet.edge_margin_mm,
            &parts,
            features.op(Feature::SheetLabel),
        );
        // The stock's edge as an alignment reference (green, not a cut, by default).
        d.add(
            features.op(Feature::PztSheetOutline),
            Shape::Polygon(rect(
                edge[0],
                edge[1][0] - edge[0][0],
                edge[1][1] - edge[0][1],
            )),
        );
        let mut record = SheetRecord {
            stem: format!("pzt-{n}"),
            file_stem: file_stem(&format!("pzt-{n}"), d.stock.as_ref()),
            layer: "pzt".into(),
            material: spec.material.clone(),
            width_mm: sheet.width_mm,
            height_mm: sheet.height_mm,
            parts: Vec::new(),
            stock_file: remnant_of.map(|d| d.file.clone()),
            remnant: placed.remnants[k].map(|[lo, hi]| SheetShape {
                outline: rect(lo, hi[0] - lo[0], hi[1] - lo[1]),
                keep_outs: Vec::new(),
            }),
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
        // A remnant is stock the lab has, not stock to buy.
        let copies = usize::from(remnant_of.is_none());
        drawn.push_copies(format!("pzt-{n}"), "pzt", d, copies);
    }
}

/// The page outside the stock's `edge` rectangle, as boxes the sheet label keeps off (a remnant's page is
/// the whole sheet it was cut from).
fn outside(edge: [Point; 2], width_mm: f64, height_mm: f64) -> Vec<super::sheet_label::Box2> {
    let [lo, hi] = edge;
    [
        ([0.0, 0.0], [lo[0], height_mm]),
        ([hi[0], 0.0], [width_mm, height_mm]),
        ([0.0, 0.0], [width_mm, lo[1]]),
        ([0.0, hi[1]], [width_mm, height_mm]),
    ]
    .into_iter()
    .filter(|(a, b)| b[0] - a[0] > 0.0 && b[1] - a[1] > 0.0)
    .map(|(a, b)| part_box(&[a, b]))
    .collect()
}

/// A score line as the laser runs it: each end on the stock's edge (the rectangle `edge`, `[min, max]`)
/// carried `run` mm past it along the line, so the score reaches the edge although the laser is still
/// accelerating where a path starts (docs/cam.md §4). An end on an earlier score line stays there:
/// running on would score the plate across that line. The verified layout keeps the exact lines; only
/// the drawing overruns.
pub(super) fn overrun(line: [Point; 2], edge: [Point; 2], run: f64) -> [Point; 2] {
    let [lo, hi] = edge;
    let on_edge =
        |p: Point| on_sheet_edge([p[0] - lo[0], p[1] - lo[1]], hi[0] - lo[0], hi[1] - lo[1]);
    let [a, b] = line;
    let length = (b[0] - a[0]).hypot(b[1] - a[1]);
    if length == 0.0 {
        return line;
    }
    let unit = [(b[0] - a[0]) / length, (b[1] - a[1]) / length];
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

    /// The overrun on the whole of `s`.
    fn on_sheet(line: [Point; 2], s: &SheetSpec) -> [Point; 2] {
        overrun(
            line,
            [[0.0, 0.0], [s.width_mm, s.height_mm]],
            s.score_overrun_mm,
        )
    }

    #[test]
    fn a_remnant_runs_over_its_own_edges() {
        // A remnant 20 x 30 mm at (10, 5) of its sheet: a line across it runs past its edges, not the sheet's.
        let edge = [[10.0, 5.0], [30.0, 35.0]];
        assert_eq!(
            overrun([[10.0, 20.0], [30.0, 20.0]], edge, 0.5),
            [[9.5, 20.0], [30.5, 20.0]]
        );
        // A line that ends on the sheet's edge line but inside the remnant is an inner end.
        let inner = [[15.0, 0.0], [15.0, 20.0]];
        assert_eq!(overrun(inner, edge, 0.5)[0], [15.0, 0.0]);
    }

    #[test]
    fn only_ends_on_the_sheet_edge_run_over() {
        let s = sheet(0.5);
        // Edge to edge across the sheet: both ends run 0.5 mm past it.
        assert_eq!(
            on_sheet([[0.0, 10.0], [50.0, 10.0]], &s),
            [[-0.5, 10.0], [50.5, 10.0]]
        );
        // From the bottom edge up to an earlier line at y = 10: only the edge end runs over.
        assert_eq!(
            on_sheet([[20.0, 0.0], [20.0, 10.0]], &s),
            [[20.0, -0.5], [20.0, 10.0]]
        );
        // A slanted line between two earlier lines: untouched.
        let inner = [[5.0, 10.0], [7.0, 30.0]];
        assert_eq!(on_sheet(inner, &s), inner);
        // A slanted line from the top edge runs on along its own direction.
        let [a, _] = on_sheet([[10.0, 40.0], [13.0, 36.0]], &s);
        assert!(
            (a[0] - (10.0 - 0.3)).abs() < 1e-12 && (a[1] - 40.4).abs() < 1e-12,
            "{a:?}"
        );
        // No overrun asked: the line as laid out.
        let line = [[0.0, 10.0], [50.0, 10.0]];
        assert_eq!(on_sheet(line, &sheet(0.0)), line);
    }
}
