//! Roll stock (`strip = true`): one strip, its used length, its cost against cut sheets, and bad prices.

use super::*;

#[test]
fn a_roll_nests_one_strip_and_reports_its_used_length() {
    let tail = "[sheets]\nprepreg = { width_mm = 80, strip = true }\n";
    let (dir, batch) = scratch(0.05, ITEMS, &format!("{PARTS}\n{tail}"));
    let out = dir.path().join("out");
    let o = nest_ok(&batch, &out, "60");
    let r = nest_report_json(&out);
    let passive = passive_sheets(&r);
    // One strip per layup, each the roll's width, as long as it was used.
    assert_eq!(passive.len(), 2);
    for (s, b) in passive.iter().zip(r["baseline"].as_array().unwrap()) {
        assert_eq!(s["roll"], true);
        assert_eq!(s["width_mm"], 80.0);
        let length = s["height_mm"].as_f64().unwrap();
        assert_eq!(b["strip_length_mm"].as_f64().unwrap(), length);
        // At least the part area over the width, at most the bounding-box baseline's length
        // plus the 0.1 mm rounding.
        let part_area: f64 = s["utilization"].as_f64().unwrap() * 80.0 * length;
        assert!(length >= part_area / 80.0);
        assert!(length <= b["baseline_strip_length_mm"].as_f64().unwrap() + 0.1);
        // The drawing is the used strip: the SVG page and the DXF extents.
        let stem = s["file_stem"].as_str().unwrap();
        let svg = std::fs::read_to_string(out.join(format!("{stem}.svg"))).unwrap();
        assert!(
            svg.contains(&format!("height=\"{}mm\"", actuator_cam::fmt_mm(length))),
            "{stem}: {}",
            &svg[..300.min(svg.len())]
        );
        let rings = dxf_rings(&out.join(format!("{stem}.dxf")));
        let top = rings.iter().flatten().map(|p| p[1]).fold(0.0, f64::max);
        assert!(
            top <= length && top > length - 5.0,
            "top {top}, length {length}"
        );
    }
    let md = std::fs::read_to_string(out.join("nest-report.md")).unwrap();
    assert!(md.contains("is a strip of roll stock 80 mm wide"), "{md}");
    assert!(stdout(&o).contains("mm of roll"), "{}", stdout(&o));
}

#[test]
fn a_priced_roll_reports_its_cost_beside_the_same_parts_on_cut_sheets() {
    // 80 mm roll at 47.5 per metre, compared with 80 x 60 mm sheets at 3.25 each.
    let tail = "[sheets]\nprepreg = { width_mm = 80, strip = true, price_per_m = 47.5, \
                compare_with = { width_mm = 80, height_mm = 60, price_per_sheet = 3.25 } }\n";
    let (dir, batch) = scratch(0.05, ITEMS, &format!("{PARTS}\n{tail}"));
    let out = dir.path().join("out");
    let o = nest_ok(&batch, &out, "40");
    let r = nest_report_json(&out);
    let sheets = r["sheets"].as_array().unwrap();
    let rolls = r["rolls"].as_array().unwrap();
    assert_eq!(rolls.len(), 2, "one strip per layup");
    // The summary line on stdout gives each roll's cost (its length times the batch's 47.5 per
    // metre, recomputed here) beside the sheets it is compared with and their cost (3.25 each).
    let line = stdout(&o);
    for roll in rolls {
        let length = roll["length_mm"].as_f64().unwrap();
        let n = roll["on_sheets"]["sheets"].as_u64().unwrap();
        let expected = format!(
            "passive roll {length:.1} mm at 47.50/m costs {:.2} (instead {n} sheet(s) of 80 x 60 mm, {:.2})",
            length / 1000.0 * 47.5,
            3.25 * n as f64
        );
        assert!(line.contains(&expected), "{expected:?} not in {line}");
    }
    let mut roll_total = 0.0;
    for roll in rolls {
        let stem = roll["file_stem"].as_str().unwrap();
        let sheet = sheets.iter().find(|s| s["file_stem"] == stem).unwrap();
        // The length priced is the strip as drawn: the sheet row and the SVG page.
        let length = roll["length_mm"].as_f64().unwrap();
        assert_eq!(sheet["height_mm"].as_f64().unwrap(), length);
        let svg = std::fs::read_to_string(out.join(format!("{stem}.svg"))).unwrap();
        assert!(svg.contains(&format!("height=\"{}mm\"", actuator_cam::fmt_mm(length))));
        assert_eq!(roll["width_mm"], 80.0);
        assert_eq!(roll["price_per_m"], 47.5);
        let cost = roll["cost"].as_f64().unwrap();
        assert!(
            (cost - length / 1000.0 * 47.5).abs() < 1e-12,
            "{cost} for {length} mm"
        );
        roll_total += cost;
        // The same parts on 80 x 60 mm sheets: at least their area's worth of sheets (part area
        // from the strip's utilisation), at most one sheet per part.
        let alt = &roll["on_sheets"];
        assert_eq!(
            (alt["width_mm"].as_f64(), alt["height_mm"].as_f64()),
            (Some(80.0), Some(60.0))
        );
        let n = alt["sheets"].as_u64().unwrap() as f64;
        let part_area = sheet["utilization"].as_f64().unwrap() * 80.0 * length;
        assert!(n >= (part_area / (80.0 * 60.0)).ceil(), "{n} sheets");
        assert!(n <= sheet["parts"].as_array().unwrap().len() as f64);
        assert_eq!(alt["cost"].as_f64().unwrap(), 3.25 * n);
        // The material the roll's strip is of, in the totals.
        let total = r["totals"]
            .as_array()
            .unwrap()
            .iter()
            .find(|t| t["material"] == roll["material"])
            .unwrap();
        assert_eq!(total["roll_length_mm"].as_f64().unwrap(), length);
        assert_eq!(total["cost"].as_f64().unwrap(), cost);
    }
    // Nothing else is priced: the batch's cost is the roll's.
    assert!((r["total_cost"].as_f64().unwrap() - roll_total).abs() < 1e-12);
    let md = std::fs::read_to_string(out.join("nest-report.md")).unwrap();
    assert!(md.contains("## Roll stock against cut sheets"), "{md}");
    let first = &rolls[0];
    assert!(
        md.contains(&format!(
            "| `{}` | {} | 80 | {:.1} | 47.50 | {:.2} | 80 x 60 mm: {} | {:.2} |",
            first["file_stem"].as_str().unwrap(),
            first["material"].as_str().unwrap(),
            first["length_mm"].as_f64().unwrap(),
            first["cost"].as_f64().unwrap(),
            first["on_sheets"]["sheets"],
            first["on_sheets"]["cost"].as_f64().unwrap()
        )),
        "{md}"
    );
}

#[test]
fn a_roll_without_compare_with_is_compared_with_the_template_sheet() {
    // The scratch template's prepreg sheet is 150 x 150 mm with no price: the sheets are counted,
    // their cost is unknown. An unpriced roll has no comparison and no cost.
    let tail = "[sheets]\nprepreg = { width_mm = 80, strip = true, price_per_m = 40 }\n";
    let (dir, batch) = scratch(0.05, ITEMS, &format!("{PARTS}\n{tail}"));
    let out = dir.path().join("out");
    nest_ok(&batch, &out, "20");
    let r = nest_report_json(&out);
    for roll in r["rolls"].as_array().unwrap() {
        let alt = &roll["on_sheets"];
        assert_eq!(
            (alt["width_mm"].as_f64(), alt["height_mm"].as_f64()),
            (Some(150.0), Some(150.0))
        );
        assert!(alt["sheets"].as_u64().unwrap() >= 1);
        assert!(alt["cost"].is_null() && alt["price_per_sheet"].is_null());
    }
    let tail = "[sheets]\nprepreg = { width_mm = 80, strip = true }\n";
    let (dir, batch) = scratch(0.05, ITEMS, &format!("{PARTS}\n{tail}"));
    let out = dir.path().join("out");
    nest_ok(&batch, &out, "20");
    let r = nest_report_json(&out);
    for roll in r["rolls"].as_array().unwrap() {
        assert!(
            roll["cost"].is_null() && roll["on_sheets"].is_null(),
            "{roll}"
        );
        assert!(roll["length_mm"].as_f64().unwrap() > 0.0);
    }
    assert!(r["total_cost"].is_null());
}

#[test]
fn bad_roll_prices_are_refused_in_one_line() {
    let cases = [
        (
            "prepreg = { width_mm = 80, strip = true, price_per_m = -1 }",
            "sheets.prepreg.price_per_m = -1: outside the allowed range [0, 1000000000] per m",
        ),
        (
            "prepreg = { width_mm = 80, strip = true, price_per_m = nan }",
            "sheets.prepreg.price_per_m = NaN: outside the allowed range [0, 1000000000] per m",
        ),
        (
            "prepreg = { width_mm = 80, strip = true, price_per_sheet = 3 }",
            "sheets.prepreg.price_per_sheet = (given): a roll (strip = true) is priced by its length: price_per_m",
        ),
        (
            "prepreg = { width_mm = 80, strip = true, compare_with = { width_mm = 80, height_mm = 60 } }",
            "sheets.prepreg.compare_with = (given): the sheet comparison is of costs: give the roll's price_per_m too",
        ),
        (
            "prepreg = { width_mm = 80, height_mm = 80, price_per_m = 3 }",
            "sheets.prepreg.price_per_m = (given): only roll stock (strip = true) is priced by the metre",
        ),
        (
            "prepreg = { width_mm = 80, strip = true, price_per_m = 3, compare_with = { width_mm = 80, height_mm = 0 } }",
            "sheets.prepreg.compare_with.height_mm = 0: outside the allowed range [1, 2000] mm",
        ),
        (
            "prepreg = { width_mm = 80, strip = true, price_per_m = 3, compare_with = { width_mm = 80, height_mm = 60, price_per_m = 2 } }",
            "sheets.prepreg.compare_with.price_per_m = 2: unknown key",
        ),
    ];
    for (line, want) in cases {
        let (_dir, batch) = scratch(0.05, ITEMS, &format!("[sheets]\n{line}\n"));
        let err = refusal(&batch);
        assert!(
            err.starts_with(&format!("error: {}: {want}", batch.display())),
            "{line}: {err}"
        );
    }
}

#[test]
fn the_cost_comparison_nests_count_on_after_the_roll_jobs() {
    // examples/batch-roll.toml: two layups on a priced roll, each compared with cut sheets; the
    // comparison nests are jobs 3 and 4 of 4, not a second count from 1.
    let (planned, recorder) = observed("batch-roll.toml", 20);
    let layers = recorder.layers.borrow();
    let jobs: Vec<(usize, usize)> = layers.iter().map(|l| (l.0, l.1)).collect();
    assert_eq!(jobs, vec![(0, 2), (1, 2), (2, 4), (3, 4)]);
    assert_eq!(planned.report.rolls.len(), 2);
    for (l, roll) in layers[2..].iter().zip(&planned.report.rolls) {
        assert_eq!(
            l.2,
            format!("{} on 150 x 150 mm sheets instead of the roll", roll.layer)
        );
    }
    // Each comparison job reports its own nest, ending finished.
    let reports = recorder.reports.borrow();
    for job in 3..=4 {
        let last = reports.iter().rev().find(|(l, _)| *l == job).unwrap().1;
        assert!(last.finished, "{last:?}");
    }
}
