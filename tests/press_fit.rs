//! Every part is pressed: measured from the drawn mold files alone, not from the code that chose them.
//!
//! For every example design, the mold sheets of the cut are read back; at each point of a fine grid
//! over the panel the column of mold layers cut away there is the cavity a part sits in. With the film
//! thickness of each sheet from report.json and the design's plate and core thicknesses, the void under
//! each part and the height it stands proud of the film over it must both be within the template's
//! tolerance (docs/cam.md §1, "Mold layers"), and no cavity may be deeper than its part.

use crate::common;
use common::svg_read::read_svg_polygons;
use common::*;
use geo::{BoundingRect, Contains, Coord, Rect};
use std::collections::BTreeSet;

/// Grid step, mm: well under the narrowest extension of the examples (about 0.5 mm).
const STEP_MM: f64 = 0.1;

/// The bond thickness from report.json's `bond` ("name 0.0254 mm"), mm; 0 without a bond.
fn bond_mm(design: &serde_json::Value) -> f64 {
    design["bond"]
        .as_str()
        .and_then(|b| b.split_whitespace().rev().nth(1))
        .map(|t| t.parse().unwrap())
        .unwrap_or(0.0)
}

/// A mold cavity, with its bounding box looked at before the cavity itself: a grid point outside
/// every box has an empty column, which the grid skips anyway.
struct Cavity {
    bounds: Rect<f64>,
    outline: geo::Polygon<f64>,
}

impl Cavity {
    fn holds(&self, p: &Coord<f64>) -> bool {
        let (lo, hi) = (self.bounds.min(), self.bounds.max());
        lo.x <= p.x && p.x <= hi.x && lo.y <= p.y && p.y <= hi.y && self.outline.contains(p)
    }
}

/// The cavities of each mold sheet (panel 1), bottom to top: every closed polygon but the panel
/// outline, which encloses the rest.
fn cavities(out: &std::path::Path, sheets: usize) -> Vec<Vec<Cavity>> {
    (1..=sheets)
        .map(|k| {
            let svg = std::fs::read_to_string(layer_file(out, &format!("mold-{k}-1.svg"))).unwrap();
            let mut rings: Vec<Vec<[f64; 2]>> = read_svg_polygons(&svg)
                .unwrap()
                .into_iter()
                .map(|(_, ring)| ring)
                .collect();
            rings.sort_by(|a, b| area(b).total_cmp(&area(a)));
            rings
                .iter()
                .skip(1)
                .map(|r| {
                    let outline = polygon(r);
                    Cavity {
                        bounds: outline.bounding_rect().unwrap(),
                        outline,
                    }
                })
                .collect()
        })
        .collect()
}

#[test]
fn every_example_presses_every_part_within_the_tolerance() {
    for design in [
        "thesis-1",
        "thesis-7",
        "thesis-21",
        "thesis-A",
        "thesis-B",
        "thesis-C",
        "thesis-C-method-1",
    ] {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("out");
        let o = cut_sheet(&format!("examples/{design}.toml"), &out, &[]);
        assert!(o.status.success(), "{design}: {}", stderr(&o));
        let report = report_json(&out);
        let films: Vec<f64> = report["mold"]["films_mm"]
            .as_array()
            .unwrap()
            .iter()
            .map(|t| t.as_f64().unwrap())
            .collect();
        let tolerance_mm = report["mold"]["tolerance_um"].as_f64().unwrap() / 1e3;
        let d = &report["design"];
        let plate_mm = d["pzt_thickness_mm"].as_f64().unwrap();
        let plies = d["layup_deg"].as_array().unwrap().len() as f64;
        let core_mm = d["ply_thickness_mm"].as_f64().unwrap() * plies + 2.0 * bond_mm(d);
        let laminate_mm = 2.0 * plate_mm + core_mm;

        let cavities = cavities(&out, films.len());
        let (w, h) = (100.0, 100.0);
        let mut columns: BTreeSet<Vec<usize>> = BTreeSet::new();
        let mut y = 0.013;
        while y < h {
            let mut x = 0.017;
            while x < w {
                let p = Coord { x, y };
                let column: Vec<usize> = (0..films.len())
                    .filter(|&k| cavities[k].iter().any(|c| c.holds(&p)))
                    .collect();
                if !column.is_empty() {
                    columns.insert(column);
                }
                x += STEP_MM;
            }
            y += STEP_MM;
        }
        // Passive plies with no PZT over them: the extension, and the base tab (the design's own or
        // the process's ground tab, both in the report's design).
        let has_extension = d["extension_length_mm"].as_f64().unwrap() > 0.0
            || d["base_tab_mm"].as_f64().unwrap() > 0.0;
        let mut extension_seen = false;
        let top_layer = films.len() - 1;
        let height_below = |k: usize| films[..k].iter().sum::<f64>();
        for column in &columns {
            // A stacking window runs from some level to the top sheet; a part's cavity does not
            // reach the top sheet unless it also starts at the bottom (the whole laminate).
            if column.contains(&top_layer) && !column.contains(&0) {
                continue;
            }
            let (lo, hi) = (column[0], *column.last().unwrap());
            assert_eq!(
                column.len(),
                hi - lo + 1,
                "{design}: a cavity column with a gap {column:?}"
            );
            let (bottom, top) = (height_below(lo), height_below(hi + 1));
            // The passive part alone over the extension: a bond part lies only on its plate, so the
            // passive part lies from the lower bond's top to the upper bond's underside.
            let (part_bottom, part_top) = if lo == 0 {
                (0.0, laminate_mm)
            } else {
                extension_seen = true;
                (plate_mm + bond_mm(d), plate_mm + core_mm - bond_mm(d))
            };
            let void = part_bottom - bottom;
            let proud = part_top - top;
            assert!(
                proud >= -1e-9,
                "{design}: layers {column:?} are {:.1} µm deeper than the part",
                -proud * 1e3
            );
            assert!(
                proud <= tolerance_mm + 1e-9 && void <= tolerance_mm + 1e-9,
                "{design}: layers {column:?}: the part stands {:.1} µm proud with {:.1} µm void under it",
                proud * 1e3,
                void * 1e3
            );
        }
        assert_eq!(
            extension_seen, has_extension,
            "{design}: a passive-only region has a cavity of its own, a design without one has none"
        );
    }
}
