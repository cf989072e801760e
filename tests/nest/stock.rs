//! Drawn stock (`[[stock]]`): a batch nested first on the remnant an earlier run wrote, and on a sheet
//! drawing with a flaw; the files read back with this crate's own SVG reader and checked with `geo`,
//! independent of the nester and of its verifier.

use super::*;
use actuator_cam::Operation;
use common::svg_read::{read_svg_polygons, svg_paths};
use geo::Intersects;

/// Template values of method 2's passive sheet (templates/method-2.toml) with the batch's spacing.
const SHEET_MM: f64 = 150.0;
const SPACING_MM: f64 = 0.3;

/// The rings of `op` in an SVG the run wrote.
fn rings(file: &Path, op: Operation) -> Vec<Vec<[f64; 2]>> {
    let svg = std::fs::read_to_string(file).unwrap_or_else(|e| panic!("{file:?}: {e}"));
    read_svg_polygons(&svg)
        .unwrap()
        .into_iter()
        .filter(|(o, _)| *o == op)
        .map(|(_, r)| r)
        .collect()
}

/// Every cut ring of `sheet` keeps at least `gap_mm` from every ring of `keep_outs` and touches none:
/// the cut rings and the least distance found.
fn clear_of(sheet: &Path, keep_outs: &[Vec<[f64; 2]>], gap_mm: f64) -> (usize, f64) {
    let cuts = rings(sheet, Operation::Cut);
    let mut nearest = f64::INFINITY;
    for cut in &cuts {
        let c = polygon(cut);
        for k in keep_outs {
            let k = polygon(k);
            assert!(!c.intersects(&k), "{sheet:?}: a cut touches a keep-out");
            let d = Euclidean.distance(&c, &k);
            assert!(
                d >= gap_mm - 1e-6,
                "{sheet:?}: a cut {d} mm from a keep-out"
            );
            nearest = nearest.min(d);
        }
    }
    (cuts.len(), nearest)
}

/// A batch of `quantity` thesis-C actuators (layup 0/90/0) in `dir`, its `[[stock]]` table `stock`.
fn batch_on_stock(dir: &Path, quantity: usize, stock: &str) -> std::path::PathBuf {
    let batch = dir.join("second.toml");
    std::fs::write(
        &batch,
        format!(
            "name = \"second\"\niterations = 200\n[[item]]\ndesign = {:?}\nquantity = {quantity}\n\
             [[stock]]\n{stock}\n[sheets]\nspacing_mm = {SPACING_MM}\n",
            example_path("thesis-C.toml")
        ),
    )
    .unwrap();
    batch
}

/// An SVG drawing in mm of a `size` sheet (its outline a rect from the origin) with `inside` in it.
fn sheet_svg(path: &Path, [w, h]: [u32; 2], inside: &str) {
    let svg = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}mm\" height=\"{h}mm\" viewBox=\"0 0 {w} {h}\">\n\
         <rect id=\"sheet\" x=\"0\" y=\"0\" width=\"{w}\" height=\"{h}\"/>\n{inside}\n</svg>\n"
    );
    std::fs::write(path, svg).unwrap();
}

/// The report's passive sheets.
fn passive_sheets(report: &serde_json::Value) -> Vec<serde_json::Value> {
    report["sheets"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|s| s["layer"] == "passive")
        .cloned()
        .collect()
}

#[test]
fn a_batch_nests_first_on_the_remnant_an_earlier_run_wrote() {
    let dir = tempfile::tempdir().unwrap();
    let first = dir.path().join("first");
    let o = nest(Path::new(&example("batch.toml")), &first, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let sheet = passive_sheets(&nest_report_json(&first))
        .into_iter()
        .find(|s| s["material"].as_str().unwrap().contains("0/90/0"))
        .unwrap();
    let remnant = sheet["remnant"]["file_stem"].as_str().unwrap().to_string();
    let free = sheet["remnant"]["free_area_mm2"].as_f64().unwrap();
    assert!(
        free > 0.5 * SHEET_MM * SHEET_MM && free < SHEET_MM * SHEET_MM,
        "{free}"
    );
    // The remnant: the sheet's edge, and as keep-outs the cut outline of every part on the sheet.
    let drawn = rings(&first.join(format!("{remnant}.svg")), Operation::Reference);
    let placed = sheet["parts"].as_array().unwrap().len();
    assert_eq!(drawn.len(), 1 + placed);
    let keep_outs = &drawn[1..];

    let batch = batch_on_stock(
        dir.path(),
        6,
        &format!("file = \"first/{remnant}.svg\"\nlayup_deg = [0, 90, 0]"),
    );
    let second = dir.path().join("out");
    let o = nest(&batch, &second, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let sheets = passive_sheets(&nest_report_json(&second));
    // Six parts fit the remnant: no whole sheet is cut, and none is on the stock list.
    assert_eq!(sheets.len(), 1, "{sheets:?}");
    assert_eq!(sheets[0]["stock"], format!("first/{remnant}.svg"));
    assert_eq!(sheets[0]["parts"].as_array().unwrap().len(), 6);
    let stem = sheets[0]["file_stem"].as_str().unwrap();
    // Parts keep the kerf and spacing from the earlier cuts: cut path to cut path, kerf/2 + spacing.
    let (cuts, _) = clear_of(
        &second.join(format!("{stem}.svg")),
        keep_outs,
        PREPREG_KERF_MM / 2.0 + SPACING_MM,
    );
    assert!(cuts >= 6, "{cuts}");
    let stock = nest_report_json(&second)["stock_list"].to_string();
    assert!(!stock.contains("prepreg"), "{stock}");
    // Its own remnant holds the earlier keep-outs and the six new parts.
    let again = sheets[0]["remnant"]["file_stem"].as_str().unwrap();
    let drawn_again = rings(&second.join(format!("{again}.svg")), Operation::Reference);
    assert_eq!(drawn_again.len(), 1 + placed + 6);
}

#[test]
fn a_sheet_drawn_with_a_flaw_is_cut_round_the_flaw() {
    let dir = tempfile::tempdir().unwrap();
    // A 150 mm sheet with a 39 x 148 mm flawed band along its left edge (the same with y up or
    // down), where the fill, which starts at the lower left corner, would otherwise put parts.
    sheet_svg(
        &dir.path().join("flawed.svg"),
        [150, 150],
        "<path id=\"crack\" d=\"M 1 1 L 40 1 L 40 149 L 1 149 Z\"/>",
    );
    let batch = batch_on_stock(
        dir.path(),
        12,
        "file = \"flawed.svg\"\nlayup_deg = [0, 90, 0]",
    );
    let out = dir.path().join("out");
    let o = nest(&batch, &out, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let sheets = passive_sheets(&nest_report_json(&out));
    assert_eq!(sheets[0]["stock"], "flawed.svg");
    let stem = sheets[0]["file_stem"].as_str().unwrap();
    // The sheet file draws the flaw (and the sheet's outline) for the technician.
    let flaw = vec![[1.0, 1.0], [40.0, 1.0], [40.0, 149.0], [1.0, 149.0]];
    let drawn = rings(&out.join(format!("{stem}.svg")), Operation::Reference);
    assert!(
        drawn.iter().any(|r| (area(r) - area(&flaw)).abs() < 1e-6),
        "{drawn:?}"
    );
    let (cuts, nearest) = clear_of(
        &out.join(format!("{stem}.svg")),
        &[flaw],
        PREPREG_KERF_MM / 2.0 + SPACING_MM,
    );
    assert!(cuts >= 12, "{cuts}");
    // The fill packs up against the flaw, as against a sheet edge.
    assert!(nearest < 1.0, "{nearest}");
}

#[test]
fn bad_stock_is_refused_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    sheet_svg(&dir.path().join("large.svg"), [200, 100], "");
    sheet_svg(&dir.path().join("small.svg"), [40, 30], "");
    sheet_svg(
        &dir.path().join("flawed.svg"),
        [40, 30],
        "<path id=\"crack\" d=\"M 1 1 L 5 1 L 5 5 Z\"/>",
    );
    std::fs::write(
        dir.path().join("wedge.svg"),
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"40mm\" height=\"30mm\" viewBox=\"0 0 40 30\">\n\
         <path id=\"sheet\" d=\"M 0 0 L 40 0 L 40 30 L 10 30 Z\"/>\n</svg>\n",
    )
    .unwrap();
    for (stock, expect) in [
        (
            "file = \"large.svg\"\nsheet = \"pzt\"\npzt_thickness_mm = 0.267",
            "larger than the pzt sheet (72.4 x 72.4 mm)",
        ),
        (
            "file = \"small.svg\"\nsheet = \"pzt\"\npzt_thickness_mm = 0.127",
            "stock[1].pzt_thickness_mm = 0.127: no design of the batch has these PZT plates",
        ),
        (
            "file = \"flawed.svg\"\nsheet = \"pzt\"\npzt_thickness_mm = 0.267",
            "a PZT sheet has no keep-outs",
        ),
        (
            "file = \"wedge.svg\"\nsheet = \"pzt\"\npzt_thickness_mm = 0.267",
            "a PZT sheet is a rectangle",
        ),
        (
            "file = \"large.svg\"\nlayup_deg = [0, 90, 0]",
            "larger than the prepreg sheet (150 x 150 mm)",
        ),
        (
            "file = \"large.svg\"\nlayup_deg = [0, 0, 90]",
            "no design of the batch has this layup",
        ),
    ] {
        let batch = batch_on_stock(dir.path(), 1, stock);
        let o = nest(&batch, &dir.path().join("out"), &[]);
        let err = refused_in_one_line(&o);
        assert!(err.contains(expect), "{expect:?} not in {err}");
    }
}

/// The score lines of a PZT sheet file, as drawn (ends on an edge run past it by the overrun).
fn score_lines(file: &Path) -> Vec<[[f64; 2]; 2]> {
    let svg = std::fs::read_to_string(file).unwrap_or_else(|e| panic!("{file:?}: {e}"));
    svg_paths(&svg, "SCORE")
        .into_iter()
        .map(|(p, _)| [p[0], p[1]])
        .collect()
}

#[test]
fn a_batch_lays_its_plates_out_first_on_the_pzt_remnant_an_earlier_run_wrote() {
    const SHEET: f64 = 72.4; // method 2's PZT sheet (templates/method-2.toml)
    const OVERRUN: f64 = 0.5;
    let dir = tempfile::tempdir().unwrap();
    let first = dir.path().join("first");
    let batch = dir.path().join("first.toml");
    std::fs::write(
        &batch,
        format!(
            "name = \"first\"\niterations = 200\n[[item]]\ndesign = {:?}\nquantity = 3\n",
            example_path("thesis-C.toml")
        ),
    )
    .unwrap();
    let o = nest(&batch, &first, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let report = nest_report_json(&first);
    let pzt = report["sheets"]
        .as_array()
        .unwrap()
        .iter()
        .find(|s| s["layer"] == "pzt")
        .unwrap();
    let remnant = pzt["remnant"]["file_stem"].as_str().unwrap().to_string();
    // The remnant is one rectangle, the whole width (or height) of the sheet on one side of a score
    // line of the first sheet that runs from edge to edge: snapping that line first frees it.
    let drawn = rings(&first.join(format!("{remnant}.svg")), Operation::Reference);
    assert_eq!(drawn.len(), 1, "{drawn:?}");
    let (lo, hi) = bounds(&drawn[0]);
    assert!((area(&drawn[0]) - (hi[0] - lo[0]) * (hi[1] - lo[1])).abs() < 1e-6);
    let stem = pzt["file_stem"].as_str().unwrap();
    let lines = score_lines(&first.join(format!("{stem}.svg")));
    let across = |k: usize, c: f64| {
        lines.iter().any(|[a, b]| {
            (a[k] - c).abs() < 1e-6
                && (b[k] - c).abs() < 1e-6
                && a[1 - k].min(b[1 - k]) <= -OVERRUN + 1e-6
                && a[1 - k].max(b[1 - k]) >= SHEET + OVERRUN - 1e-6
        })
    };
    let inner: Vec<(usize, f64)> = (0..2)
        .flat_map(|k| [(k, lo[k]), (k, hi[k])])
        .filter(|&(_, c)| c > 1e-6 && c < SHEET - 1e-6)
        .collect();
    assert_eq!(inner.len(), 1, "one snapped side: {lo:?} {hi:?}");
    assert!(
        across(inner[0].0, inner[0].1),
        "{inner:?} not on a line across: {lines:?}"
    );

    // The next batch names it: its plates go there, and no PZT sheet is on its stock list.
    let stock =
        format!("file = \"first/{remnant}.svg\"\nsheet = \"pzt\"\npzt_thickness_mm = 0.267");
    let batch = batch_on_stock(dir.path(), 2, &stock);
    let second = dir.path().join("second");
    let o = nest(&batch, &second, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let report = nest_report_json(&second);
    let pzt: Vec<_> = report["sheets"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|s| s["layer"] == "pzt")
        .collect();
    assert_eq!(pzt.len(), 1);
    assert_eq!(pzt[0]["stock"], format!("first/{remnant}.svg"));
    assert_eq!(pzt[0]["parts"].as_array().unwrap().len(), 4);
    let stock_list = report["stock_list"].to_string();
    assert!(!stock_list.contains("PZT"), "{stock_list}");
    // The book tells where the piece goes: on its outline, where it lay on its sheet.
    let md = std::fs::read_to_string(second.join("nest-report.md")).unwrap();
    assert!(
        md.contains(&format!("is cut from the drawn sheet `first/{remnant}.svg`: lay that piece on the outline the file draws")),
        "{md}"
    );
    // Every score line lies on the remnant, and each end on its edge runs past that edge, not the
    // sheet's: the plates are laid out from the remnant's own straight edges.
    let stem = pzt[0]["file_stem"].as_str().unwrap();
    let lines = score_lines(&second.join(format!("{stem}.svg")));
    assert!(lines.len() >= 4, "{lines:?}");
    for [a, b] in &lines {
        for p in [a, b] {
            for k in 0..2 {
                assert!(
                    p[k] >= lo[k] - OVERRUN - 1e-6 && p[k] <= hi[k] + OVERRUN + 1e-6,
                    "{p:?} off the remnant {lo:?}-{hi:?}"
                );
            }
        }
    }
    // The layout starts from the snapped edge as from a sheet edge: its first line along that edge is
    // the trim, one narrowest snappable strip (5 plate thicknesses, 1.335 mm) off it.
    let (k, c) = inner[0];
    let nearest = lines
        .iter()
        .filter(|[a, b]| (a[k] - b[k]).abs() < 1e-9)
        .map(|[a, _]| (a[k] - c).abs())
        .fold(f64::INFINITY, f64::min);
    assert!(
        (nearest - 5.0 * 0.267).abs() < 1e-6,
        "{nearest} from the snapped edge"
    );
}

/// The corners of a ring's bounding box.
fn bounds(ring: &[[f64; 2]]) -> ([f64; 2], [f64; 2]) {
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    for q in ring {
        for k in 0..2 {
            lo[k] = lo[k].min(q[k]);
            hi[k] = hi[k].max(q[k]);
        }
    }
    (lo, hi)
}

#[test]
fn a_pzt_stock_two_materials_share_must_name_its_material() {
    // thesis-C beside a PZT-5A copy of it: 0.267 mm plates of two materials.
    let dir = tempfile::tempdir().unwrap();
    let c = std::fs::read_to_string(example_path("thesis-C.toml")).unwrap();
    let five_a = dir.path().join("c-5a.toml");
    std::fs::write(
        &five_a,
        c.replace("pzt = \"PZT-5H\"", "pzt = \"PZT-5A\"")
            .replace("name = \"thesis-C\"", "name = \"thesis-C-5A\""),
    )
    .unwrap();
    sheet_svg(&dir.path().join("small.svg"), [40, 30], "");
    let batch = |stock: &str| {
        let path = dir.path().join("two.toml");
        std::fs::write(
            &path,
            format!(
                "name = \"two\"\niterations = 50\n[[item]]\ndesign = {:?}\nquantity = 1\n[[item]]\n\
                 design = {five_a:?}\nquantity = 1\n[[stock]]\nfile = \"small.svg\"\nsheet = \"pzt\"\n\
                 pzt_thickness_mm = 0.267\n{stock}",
                example_path("thesis-C.toml")
            ),
        )
        .unwrap();
        path
    };
    let o = nest(&batch(""), &dir.path().join("out"), &[]);
    let err = refused_in_one_line(&o);
    assert!(
        err.contains("designs of two PZT materials have plates this thick: name one with pzt"),
        "{err}"
    );
    // Named, the remnant takes that material's plates.
    let o = nest(&batch("pzt = \"PZT-5A\"\n"), &dir.path().join("out"), &[]);
    assert!(o.status.success(), "{}", stderr(&o));
}
