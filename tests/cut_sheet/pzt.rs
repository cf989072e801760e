//! The PZT sheet: score lines end on edges, strips between them snap, the edge margin insets the plates, and
//! each sheet carries its snapping order.

use super::*;

#[test]
fn pzt_score_lines_end_on_edges_and_parts_keep_their_spacing() {
    let dir = tempfile::tempdir().unwrap();
    for design in EXAMPLES {
        let out = dir.path().join(design);
        let o = cut_sheet(&example(design), &out, &["--quantity", "20"]);
        assert!(o.status.success(), "{design}: {}", stderr(&o));
        for (name, bytes) in files(&out) {
            if !name.ends_with(".svg") {
                continue;
            }
            let svg = String::from_utf8(bytes).unwrap();
            let vb = view_box(&svg);
            let (w, h) = (vb[2], vb[3]);
            if name.starts_with("pzt-") {
                let lines: Vec<[[f64; 2]; 2]> = svg_paths(&svg, "SCORE")
                    .into_iter()
                    .map(|(p, closed)| {
                        assert!(
                            !closed && p.len() == 2,
                            "{name}: score lines are straight open segments"
                        );
                        [p[0], p[1]]
                    })
                    .collect();
                assert!(!lines.is_empty());
                // The page is the sheet; an end on its edge runs past it by the overrun (tests/scoring.rs).
                let on_edge =
                    |p: [f64; 2]| p[0] < 1e-6 || p[1] < 1e-6 || p[0] > w - 1e-6 || p[1] > h - 1e-6;
                let on_line = |p: [f64; 2], l: &[[f64; 2]; 2]| {
                    let seg = geo::Line::new((l[0][0], l[0][1]), (l[1][0], l[1][1]));
                    Euclidean.distance(&geo::Point::new(p[0], p[1]), &seg) < 1e-6
                };
                for (i, l) in lines.iter().enumerate() {
                    for end in l {
                        assert!(
                            on_edge(*end)
                                || lines
                                    .iter()
                                    .enumerate()
                                    .any(|(j, m)| j != i && on_line(*end, m)),
                            "{name}: score line {i} ends in mid-air at {end:?}"
                        );
                    }
                }
            }
            if name.starts_with("passive-") || name.starts_with("pyralux-") {
                let gap = 0.5; // template spacing between cut paths (method-1 and method-2 both 0.5 mm)
                let parts: Vec<Polygon<f64>> = svg_paths(&svg, "CUT")
                    .into_iter()
                    .map(|(r, _)| polygon(&r))
                    .collect();
                for (i, a) in parts.iter().enumerate() {
                    for b in &parts[i + 1..] {
                        assert!(!a.intersects(b), "{name}: parts overlap");
                        assert!(
                            Euclidean.distance(a, b) >= gap - 1e-6,
                            "{name}: gap {}",
                            Euclidean.distance(a, b)
                        );
                    }
                }
            }
        }
    }
}

#[test]
fn pzt_edge_margin_insets_the_plates_inside_the_passive_part() {
    // docs/cam.md §1: a clearance between plate edge and passive edge. With the template's margin m, every
    // corner of the plate (preview, kerf 0) lies inside the passive outline, exactly m from its edge.
    let dir = tempfile::tempdir().unwrap();
    let with_margin = |m: &str| {
        method_2_with(
            "passive_edge_margin_mm = 0.0",
            &format!("passive_edge_margin_mm = {m}"),
        )
    };
    let tab = [("base_tab_mm", "base_tab_mm = 1.0")];
    let design = design_on_template(dir.path(), "inset.toml", &with_margin("0.15"), &tab);
    let out = dir.path().join("out");
    let o = cut_sheet(design.to_str().unwrap(), &out, &["--kerf-mm", "0"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let (passive, plate, scale) = &preview_at_true_size(&out);
    let scale = *scale;
    assert_eq!(plate.len(), 4);
    let outer = polygon(passive);
    for corner in plate {
        let p = geo::Point::new(corner[0], corner[1]);
        assert!(outer.intersects(&p), "{corner:?} outside the passive part");
        let d = Euclidean.distance(&p, outer.exterior());
        assert!(
            (d - 0.15).abs() < 1e-6,
            "{corner:?} is {d} mm from the edge"
        );
    }
    let r = report_json(&out);
    let pzt_area = r["layers"][0]["part_area_mm2"].as_f64().unwrap();
    // The SVG holds 6 decimals: each corner within 5e-7 mm / scale, so the area within perimeter x 5e-7.
    let bound = perimeter(plate) * 5e-7 / scale;
    assert!(
        (pzt_area - area(plate)).abs() < bound,
        "{pzt_area} vs {} (bound {bound})",
        area(plate)
    );
    assert_eq!(r["pzt_edge_margin_mm"].as_f64(), Some(0.15));
    let geometry = r["mass_from_geometry_mg"].as_f64().unwrap();
    assert!(geometry < r["predicted"]["mass_mg"].as_f64().unwrap());
    assert!(std::fs::read_to_string(out.join("report.md"))
        .unwrap()
        .contains("insets the PZT plates 0.15 mm"));

    // A margin that eats the 1 mm tip of design C: refused, nothing written.
    let design = design_on_template(dir.path(), "inset.toml", &with_margin("0.5"), &tab);
    let out2 = dir.path().join("out2");
    let o = cut_sheet(design.to_str().unwrap(), &out2, &[]);
    let err = stderr(&o);
    assert!(!o.status.success());
    assert!(
        err.contains("d.toml") && err.contains("edge margin"),
        "{err}"
    );
    assert!(!out2.exists());
}

/// The strips between the PZT sheet edges and the full-width score lines, and between neighbouring
/// full-width lines, are either nothing (a line on the edge) or at least the narrowest snappable strip,
/// 5 PZT thicknesses (docs/cam.md §4, "Snappable strips": a plain 0.3 mm edge margin would leave a
/// 0.3 - 0.03/2 = 0.285 mm root edge strip, which chips). Read back from the files, for every example.
#[test]
fn pzt_sheet_strips_between_full_width_score_lines_can_be_snapped() {
    let dir = tempfile::tempdir().unwrap();
    for design in EXAMPLES {
        let out = dir.path().join(design);
        let o = cut_sheet(&example(design), &out, &[]);
        assert!(o.status.success(), "{design}: {}", stderr(&o));
        let t = report_json(&out)["design"]["pzt_thickness_mm"]
            .as_f64()
            .unwrap();
        let min_strip = 5.0 * t;
        for (name, bytes) in files(&out) {
            if !(name.starts_with("pzt-") && name.ends_with(".svg")) {
                continue;
            }
            let svg = String::from_utf8(bytes).unwrap();
            let vb = view_box(&svg);
            let size = [vb[2], vb[3]];
            let lines = svg_paths(&svg, "SCORE");
            for axis in 0..2 {
                // Lines across the whole sheet, square to `axis`: their position on `axis`.
                let mut at: Vec<f64> = lines
                    .iter()
                    .filter(|(p, _)| {
                        let (a, b) = (p[0], p[p.len() - 1]);
                        (a[axis] - b[axis]).abs() < 1e-9
                            && (a[1 - axis] - b[1 - axis]).abs() > size[1 - axis] - 1e-6
                    })
                    .map(|(p, _)| p[0][axis])
                    .chain([0.0, size[axis]])
                    .collect();
                at.sort_by(f64::total_cmp);
                for pair in at.windows(2) {
                    let strip = pair[1] - pair[0];
                    assert!(
                        strip < 1e-6 || strip >= min_strip - 1e-6,
                        "{design} {name}: a {strip:.4} mm strip between {:.4} and {:.4} mm (axis {axis}), narrower than {min_strip:.3} mm",
                        pair[0],
                        pair[1]
                    );
                }
            }
        }
    }
}

#[test]
fn each_pzt_sheet_has_a_snapping_order_picture_numbering_its_score_lines() {
    // Every example: one picture per PZT sheet, numbering each score line of the sheet's file once,
    // 1 to n, with nothing a laser follows (no stroke) and not at true size; the book names it.
    for design in ["thesis-C", "thesis-7", "thesis-C-method-1"] {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("out");
        let o = cut_sheet(&format!("examples/{design}.toml"), &out, &[]);
        assert!(o.status.success(), "{}", stderr(&o));
        let r = report_json(&out);
        let sheets = r["stock_list"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|s| s["material"].as_str().unwrap().starts_with("PZT"))
            .map(|s| s["sheets"].as_u64().unwrap())
            .sum::<u64>();
        assert!(sheets > 0);
        let book = r["build_book"].to_string();
        for n in 1..=sheets {
            let name = format!("preview-snap-order-pzt-{n}.svg");
            let guide = std::fs::read_to_string(out.join(&name)).unwrap();
            let pzt = std::fs::read_to_string(layer_file(&out, &format!("pzt-{n}.svg"))).unwrap();
            let lines = svg_paths(&pzt, "SCORE").len();
            assert!(lines > 0, "{design}: pzt-{n} has score lines");
            let numbers: Vec<usize> = guide
                .split("</text>")
                .filter_map(|t| t.rsplit('>').next().and_then(|n| n.parse().ok()))
                .collect();
            assert_eq!(numbers, (1..=lines).collect::<Vec<_>>(), "{design}: {name}");
            assert!(
                !guide.contains("stroke=\"#"),
                "{design}: {name} has a stroke"
            );
            assert!(guide.contains("drawn at 4:1") && guide.contains("not for cutting"));
            assert!(book.contains(&name), "{design}: the book names {name}");
        }
    }
}
