//! `[sheets] edge_gap_mm`: the gap from the parts to the sheet edge apart from the gap between parts
//! (`spacing_mm`), both on top of the kerf, checked on the written report with geometry rebuilt from
//! the design files.

use super::*;
use actuator_cam::Operation;
use common::svg_read::read_svg_polygons;

/// The example batch's designs in a scratch folder with `sheets` as its `[sheets]` table.
fn example_batch_with(sheets: &str) -> tempfile::TempDir {
    let batch = std::fs::read_to_string(example("batch.toml")).unwrap();
    let items: String = batch
        .split("[sheets]")
        .next()
        .unwrap()
        .lines()
        .filter(|l| !l.trim_start().starts_with("name"))
        .map(|l| format!("{l}\n"))
        .collect();
    let designs: Vec<(String, String)> = example_designs()
        .values()
        .map(|(f, _)| {
            (
                f.file_name().unwrap().to_string_lossy().into_owned(),
                std::fs::read_to_string(f).unwrap(),
            )
        })
        .collect();
    let refs: Vec<(&str, &str)> = designs
        .iter()
        .map(|(n, t)| (n.as_str(), t.as_str()))
        .collect();
    scratch_batch(
        &format!("name = \"edge\"\niterations = 200\n{items}[sheets]\n{sheets}\n"),
        &refs,
    )
}

/// The least distance of any cut vertex on a passive sheet from its sheet's edge, read back from the
/// SVG files the report names, mm.
fn nearest_cut_to_edge(out: &Path) -> f64 {
    let report = nest_report_json(out);
    let mut nearest = f64::INFINITY;
    for sheet in report["sheets"].as_array().unwrap() {
        if sheet["layer"] == "pzt" {
            continue;
        }
        let (w, h) = (
            sheet["width_mm"].as_f64().unwrap(),
            sheet["height_mm"].as_f64().unwrap(),
        );
        let stem = sheet["file_stem"].as_str().unwrap();
        let svg = std::fs::read_to_string(out.join(format!("{stem}.svg"))).unwrap();
        for (op, ring) in read_svg_polygons(&svg).unwrap() {
            if op != Operation::Cut {
                continue;
            }
            for q in ring {
                nearest = nearest.min(q[0].min(q[1]).min(w - q[0]).min(h - q[1]));
            }
        }
    }
    nearest
}

#[test]
fn a_wide_edge_gap_keeps_parts_off_the_edge_and_no_further() {
    let dir = example_batch_with("spacing_mm = 0.3\nedge_gap_mm = 4.0");
    let out = dir.path().join("out");
    let o = nest(&dir.path().join("batch.toml"), &out, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    check_report_with_edge(&out, &example_designs(), 0.3, 4.0);
    // The cut path lies half a kerf outside the nominal outline: 4.025 mm from the edge at least,
    // and the nester packs toward the corner, so some part comes that near.
    let nearest = nearest_cut_to_edge(&out);
    assert!((4.02..4.1).contains(&nearest), "{nearest}");
}

#[test]
fn an_edge_gap_below_the_spacing_lets_parts_nearer_the_edge_than_each_other() {
    let dir = example_batch_with("spacing_mm = 2.0\nedge_gap_mm = 0.0");
    let out = dir.path().join("out");
    let o = nest(&dir.path().join("batch.toml"), &out, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    check_report_with_edge(&out, &example_designs(), 2.0, 0.0);
    // The kerf alone to the edge, where the parts keep 2.05 mm from each other.
    let nearest = nearest_cut_to_edge(&out);
    assert!((0.02..0.1).contains(&nearest), "{nearest}");
}

#[test]
fn a_bad_edge_gap_is_one_line_naming_the_field() {
    let dir = example_batch_with("edge_gap_mm = -1");
    fails_without_output(&dir, &["sheets.edge_gap_mm = -1", "[0, 50] mm"]);
    let err = stderr(&nest(
        &dir.path().join("batch.toml"),
        &dir.path().join("out"),
        &[],
    ));
    assert_eq!(err.trim().lines().count(), 1, "{err}");
}
