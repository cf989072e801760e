//! Parts in holes: tiles nested in the window of a frame drawn as an extra part, read back from the
//! sheet's SVG and checked with `geo`, independent of the nester and its verifier.

use super::*;
use actuator_cam::Operation;
use geo::{Distance, Euclidean};

/// Method 2's prepreg kerf and spacing (templates/method-2.toml).
const KERF_MM: f64 = 0.05;
const SPACING_MM: f64 = 0.5;

#[test]
fn tiles_in_a_frames_window_take_one_sheet_where_their_outlines_need_two() {
    let dir = tempfile::tempdir().unwrap();
    let svg = |name: &str, size: u32, inside: &str| {
        let text = format!(
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{size}mm\" height=\"{size}mm\" viewBox=\"0 0 {size} {size}\">\n\
             <rect id=\"{name}\" x=\"0\" y=\"0\" width=\"{size}\" height=\"{size}\"/>\n{inside}</svg>\n"
        );
        std::fs::write(dir.path().join(format!("{name}.svg")), text).unwrap();
    };
    // A 90 mm frame with an 80 mm window, and 16 tiles of 18 mm: 4 x 4 of them fit the window at
    // 18.55 mm pitch (74.75 mm with the gaps to its edges).
    svg(
        "frame",
        90,
        "<rect id=\"window\" x=\"5\" y=\"5\" width=\"80\" height=\"80\"/>\n",
    );
    svg("tile", 18, "");
    let part = |file: &str, quantity: usize| {
        format!("[[part]]\nfile = \"{file}\"\nquantity = {quantity}\nlayup_deg = [0, 90, 0]\nfibre_axis_deg = 0\n")
    };
    let batch = dir.path().join("batch.toml");
    std::fs::write(
        &batch,
        format!(
            "name = \"holes\"\niterations = 200\n[[item]]\ndesign = {:?}\nquantity = 1\n{}{}\
             [sheets]\nprepreg = {{ width_mm = 100, height_mm = 130 }}\n",
            example_path("thesis-C.toml"),
            part("frame.svg", 1),
            part("tile.svg", 16),
        ),
    )
    .unwrap();
    let out = dir.path().join("out");
    nest_ok(&batch, &out, "200");
    let r = nest_report_json(&out);
    let passive = passive_sheets(&r);
    assert_eq!(passive.len(), 1, "{passive:?}");
    let stem = passive[0]["file_stem"].as_str().unwrap();
    let text = std::fs::read_to_string(out.join(format!("{stem}.svg"))).unwrap();
    let cuts: Vec<Vec<[f64; 2]>> = read_svg_polygons(&text)
        .unwrap()
        .into_iter()
        .filter(|(op, _)| *op == Operation::Cut)
        .map(|(_, r)| r)
        .collect();
    // The window's cut path lies kerf/2 inside the drawn window.
    let side = |r: &[[f64; 2]], mm: f64| (area(r) - mm * mm).abs() < 1e-3;
    let window = cuts.iter().position(|r| side(r, 80.0 - KERF_MM)).unwrap();
    let frame = cuts.iter().position(|r| side(r, 90.0 + KERF_MM)).unwrap();
    let (w, f) = (polygon(&cuts[window]), polygon(&cuts[frame]));
    // The outer cut outlines read back (all but the window) exceed the sheet's 13,000 mm² (the
    // frame's 8,100 and the tiles' 5,184 mm² alone): without parts in holes they need two sheets.
    let outer: f64 = (0..cuts.len())
        .filter(|&k| k != window)
        .map(|k| area(&cuts[k]))
        .sum();
    assert!(outer > 100.0 * 130.0, "{outer}");
    let mut inside = 0;
    for (k, tile) in cuts
        .iter()
        .enumerate()
        .filter(|(_, r)| side(r, 18.0 + KERF_MM))
    {
        let t = polygon(tile);
        if w.contains(&t) {
            inside += 1;
            // Cut before the window that frees it, the spacing (cut path to cut path) from its edge.
            assert!(k < window, "tile {k} cut after the window {window}");
            let d = Euclidean.distance(t.exterior(), w.exterior());
            assert!(
                d >= SPACING_MM - 1e-6,
                "tile {k}: {d} mm from the window's edge"
            );
        } else {
            // Kerf + spacing between nominal outlines: the spacing between cut paths.
            let d = Euclidean.distance(&t, &f);
            assert!(d >= SPACING_MM - 1e-6, "tile {k}: {d} mm from the frame");
        }
    }
    assert!(inside >= 12, "{inside} tiles in the window");
}
