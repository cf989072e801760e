//! Every sheet names its stock: each SVG and DXF a run writes (but the preview, which is not cut) says
//! its material, thickness and sheet size, a mold sheet says its own film, and the stock list of the
//! report counts every cut file once.

use crate::common;
use common::*;
use std::collections::BTreeMap;
use std::path::Path;

/// The stock an SVG states in its metadata: (material, thickness mm, width mm, height mm).
fn svg_stock(svg: &str) -> Option<(String, f64, f64, f64)> {
    let doc = start_tag(svg, "<stock ")?;
    let num = |k: &str| attr(&doc, k).and_then(|v| v.parse().ok());
    Some((
        attr(&doc, "material")?,
        num("thickness_mm")?,
        num("width_mm")?,
        num("height_mm")?,
    ))
}

/// The start tag beginning with `open`, if any.
fn start_tag(text: &str, open: &str) -> Option<String> {
    let start = text.find(open)?;
    let end = start + text[start..].find('>')?;
    Some(text[start..end].to_string())
}

/// A double-quoted attribute of a start tag, XML entities for `&` and `"` undone.
fn attr(tag: &str, key: &str) -> Option<String> {
    let k = format!(" {key}=\"");
    let start = tag.find(&k)? + k.len();
    let len = tag[start..].find('"')?;
    Some(
        tag[start..start + len]
            .replace("&quot;", "\"")
            .replace("&amp;", "&"),
    )
}

/// The points of an SVG path's `d` (absolute M/L commands), and whether it is closed.
fn path_points(d: &str) -> (Vec<[f64; 2]>, bool) {
    let nums: Vec<f64> = d
        .split(|c: char| c.is_ascii_alphabetic() || c == ' ' || c == ',')
        .filter_map(|t| t.parse().ok())
        .collect();
    (
        nums.chunks(2).map(|c| [c[0], c[1]]).collect(),
        d.contains('Z'),
    )
}

/// The straight-segment paths of the SVG layer with `id`, each as its points and whether it is closed.
fn layer_paths(svg: &str, id: &str) -> Vec<(Vec<[f64; 2]>, bool)> {
    let Some(start) = svg.find(&format!("id=\"{id}\"")) else {
        return Vec::new();
    };
    let layer = &svg[start..start + svg[start..].find("</g>").unwrap()];
    layer
        .split("<path d=\"")
        .skip(1)
        .map(|p| &p[..p.find('"').unwrap()])
        // Arcs (holes and vias, inside their parts) carry radii and flags among their points.
        .filter(|d| !d.contains('A'))
        .map(path_points)
        .collect()
}

/// The stock label of a part sheet (the open paths of its reference layer) lies within the sheet and
/// clear of every part: no closed cut outline's box and no score line comes within its box. Returns
/// whether the sheet has a label.
fn check_sheet_label(name: &str, svg: &str, w: f64, h: f64) -> bool {
    let label: Vec<[f64; 2]> = layer_paths(svg, "layer-reference")
        .into_iter()
        .filter(|(_, closed)| !closed)
        .flat_map(|(pts, _)| pts)
        .collect();
    if label.is_empty() {
        return false;
    }
    let bbox = |pts: &[[f64; 2]]| {
        pts.iter().fold(
            ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]),
            |(lo, hi), p| {
                (
                    [lo[0].min(p[0]), lo[1].min(p[1])],
                    [hi[0].max(p[0]), hi[1].max(p[1])],
                )
            },
        )
    };
    let (lo, hi) = bbox(&label);
    assert!(
        lo[0] > 0.0 && lo[1] > 0.0 && hi[0] < w && hi[1] < h,
        "{name}: the stock label leaves the sheet"
    );
    let inside = |p: &[f64; 2]| p[0] > lo[0] && p[0] < hi[0] && p[1] > lo[1] && p[1] < hi[1];
    for (pts, closed) in layer_paths(svg, "layer-cut") {
        if closed {
            let (a, b) = bbox(&pts);
            assert!(
                a[0] >= hi[0] || b[0] <= lo[0] || a[1] >= hi[1] || b[1] <= lo[1],
                "{name}: the stock label {lo:?}-{hi:?} runs into a part {a:?}-{b:?}"
            );
        }
    }
    for (pts, _) in layer_paths(svg, "layer-score") {
        for seg in pts.windows(2) {
            for k in 0..=200 {
                let t = k as f64 / 200.0;
                let p = [
                    seg[0][0] + t * (seg[1][0] - seg[0][0]),
                    seg[0][1] + t * (seg[1][1] - seg[0][1]),
                ];
                assert!(!inside(&p), "{name}: a score line crosses the stock label");
            }
        }
    }
    true
}

/// The file `name` (SVG `text`, at `path`) states its stock `material`, `t` mm thick, in its title and its
/// DXF twin's leading comments; a carbon-fibre sheet, cured or not (and no other), says which way its
/// fibres must lie, in the title and as data: its parts were placed for that direction. A linkage panel's
/// (or coupon's) carbon layer has its links, and so its fibres, along x.
fn check_title_and_dxf_stock(name: &str, text: &str, path: &Path, material: &str, t: f64) {
    let title = &text[text.find("<title>").unwrap()..text.find("</title>").unwrap()];
    assert!(
        title.contains(&format!("{t} mm thick")),
        "{name}: the title names no thickness: {title}"
    );
    // A carbon-fibre sheet, cured or not (and no other), says which way its fibres must lie, in the
    // title and as data; its parts were placed for that direction.
    // A linkage panel's (or coupon's) carbon layer has its links, and so its fibres, along x.
    let prepreg = material.contains("carbon-fibre");
    let linkage_carbon = !prepreg && name.starts_with("linkage-") && name.contains("-carbon-");
    let axis = if prepreg {
        Some("y")
    } else {
        linkage_carbon.then_some("x")
    };
    assert_eq!(
        axis.map(|a| title.contains(&format!("0° fibres along the sheet's {a} axis"))),
        (prepreg || linkage_carbon).then_some(true),
        "{name}: the fibre direction in the title: {title}"
    );
    assert_eq!(
        title.contains("0° fibres"),
        prepreg || linkage_carbon,
        "{name}: {title}"
    );
    let stock_tag = start_tag(text, "<stock ").unwrap();
    assert_eq!(attr(&stock_tag, "fibre_axis").as_deref(), axis, "{name}");
    // The DXF twin states the same stock in its leading comments.
    let dxf = std::fs::read_to_string(path.with_extension("dxf")).unwrap();
    let head: String = dxf.lines().take(4).collect::<Vec<_>>().join("\n");
    assert!(
        head.starts_with("999"),
        "{name}: the DXF has no stock comment"
    );
    assert!(
        head.contains(&format!("{t} mm thick")),
        "{name}: the DXF's stock comment: {head}"
    );
}

/// The sheet size (as the stock list writes it) of the stock line of the file `name` (SVG `text`, its
/// stock `(material, t, w, h)` with `w × h` the page) among `rows`: the line of its material and
/// thickness that holds its page and the outermost through-cut path (cut and second pass) with its
/// kerf. A path that runs past the page (an outline cut outside its panel) takes a sheet larger than
/// the path's span by the kerf, at most the templates' largest, 0.1 mm; else the sheet is the page.
fn stock_line_for(
    name: &str,
    text: &str,
    rows: &[(String, f64, f64, f64)],
    (material, t, w, h): (&str, f64, f64, f64),
) -> (String, String) {
    let points: Vec<[f64; 2]> = ["layer-cut", "layer-secondary"]
        .iter()
        .flat_map(|id| layer_paths(text, id))
        .flat_map(|(pts, _)| pts)
        .collect();
    let span = |i: usize, page: f64| {
        let lo = points.iter().map(|p| p[i]).fold(0.0f64, f64::min);
        let hi = points.iter().map(|p| p[i]).fold(page, f64::max);
        hi - lo
    };
    let holds = |sheet: f64, page: f64, i: usize| {
        let s = span(i, page);
        if s > page + 1e-9 {
            sheet > s + 1e-9 && sheet - s <= 0.1 + 1e-9
        } else {
            sheet == page
        }
    };
    let row = rows
        .iter()
        .find(|r| r.0 == material && r.1 == t && holds(r.2, w, 0) && holds(r.3, h, 1))
        .unwrap_or_else(|| {
            panic!(
                "{name}: no stock line of {material} {t} mm holds its cuts ({} x {} mm of path on a {w} x {h} mm page): {rows:?}",
                span(0, w),
                span(1, h)
            )
        });
    (row.2.to_string(), row.3.to_string())
}

/// Every cut file of `out` with the stock it states, and the stock list of its report; every part
/// sheet with its stock label clear of its parts, but as many as the report says had no room.
fn check_folder(out: &Path, report: &str) {
    let mut unlabelled = 0;
    let json = {
        let text = std::fs::read_to_string(out.join(report)).unwrap();
        serde_json::from_str::<serde_json::Value>(&text).unwrap()
    };
    let mut counted: BTreeMap<(String, String, String, String), usize> = BTreeMap::new();
    let rows: Vec<(String, f64, f64, f64)> = json["stock_list"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| {
            let n = |k: &str| r[k].as_f64().unwrap();
            (
                r["material"].as_str().unwrap().to_string(),
                n("thickness_mm"),
                n("width_mm"),
                n("height_mm"),
            )
        })
        .collect();
    for entry in std::fs::read_dir(out).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        if name.ends_with(".svg") {
            let text = std::fs::read_to_string(&path).unwrap();
            let stock = svg_stock(&text);
            if name.starts_with("preview") {
                assert!(stock.is_none(), "{name}: the preview is not cut from stock");
                continue;
            }
            let (material, t, w, h) =
                stock.unwrap_or_else(|| panic!("{name}: no stock in the file"));
            assert!(t > 0.0 && w > 0.0 && h > 0.0, "{name}");
            // The file's name alone says what to put on the bed: the material's first word and the
            // thickness follow the sheet's name.
            let (_, stock_part) = name
                .trim_end_matches(".svg")
                .split_once('_')
                .unwrap_or_else(|| panic!("{name}: no stock in the file name"));
            let first_word: String = material
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric())
                .collect::<String>()
                .to_ascii_lowercase();
            assert!(
                stock_part.starts_with(&first_word) && stock_part.ends_with(&format!("-{t}mm")),
                "{name}: the file name does not carry its stock ({material}, {t} mm)"
            );
            check_title_and_dxf_stock(&name, &text, &path, &material, t);
            // A nest's linkage coupon drawing (`linkage-<design>-<N>-<layer>-1`) shows one coupon as
            // it is nested; the coupons are cut on the sheets the stock list counts.
            let coupon = name.strip_prefix("linkage-").is_some_and(|rest| {
                !rest.starts_with(|c: char| c.is_ascii_digit())
                    && rest
                        .split_once('_')
                        .map_or(rest, |(stem, _)| stem)
                        .split('-')
                        .filter(|part| part.parse::<usize>().is_ok())
                        .count()
                        >= 2
            });
            // The PZT test coupon is scored on an offcut of the stock: the stock list buys no sheet for it.
            // A remnant drawing (`remnant-passive-1_…`) is what is left of a sheet counted here.
            if coupon || name.starts_with("pzt-coupon-") || name.starts_with("remnant-") {
                continue;
            }
            // A clamp file of a run of identical panels (`mold-1-1to6_…`) is cut once per panel.
            let copies = name
                .split_once('_')
                .and_then(|(stem, _)| stem.rsplit_once('-'))
                .and_then(|(_, run)| run.split_once("to"))
                .map_or(1, |(a, b)| {
                    b.parse::<usize>().unwrap() - a.parse::<usize>().unwrap() + 1
                });
            let (sheet_w, sheet_h) = stock_line_for(&name, &text, &rows, (&material, t, w, h));
            *counted
                .entry((material, t.to_string(), sheet_w, sheet_h))
                .or_default() += copies;
            // A part sheet is named by its layer and one number (`pzt-3`, `linkage-carbon-1`); a
            // clamp or linkage panel's name has a number inside it (`mold-1-1`, `linkage-1-carbon-1`).
            let part_sheet = name.split_once('_').is_some_and(|(stem, _)| {
                stem.rsplit_once('-').is_some_and(|(layer, n)| {
                    n.parse::<usize>().is_ok()
                        && layer.chars().all(|c| c.is_ascii_lowercase() || c == '-')
                })
            });
            if part_sheet && !check_sheet_label(&name, &text, w, h) {
                unlabelled += 1;
            }
        }
    }
    let listed: BTreeMap<(String, String, String, String), usize> = json["stock_list"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| {
            let n = |k: &str| r[k].as_f64().unwrap().to_string();
            (
                (
                    r["material"].as_str().unwrap().to_string(),
                    n("thickness_mm"),
                    n("width_mm"),
                    n("height_mm"),
                ),
                r["sheets"].as_u64().unwrap() as usize,
            )
        })
        .collect();
    assert_eq!(counted, listed, "the stock list counts every cut file once");
    assert_eq!(
        json["sheets_without_stock_label"].as_u64(),
        Some(unlabelled),
        "the report counts the part sheets without a stock label"
    );
}

#[test]
fn every_cut_sheet_file_names_its_stock_and_molds_their_own_film() {
    for design in ["thesis-C", "thesis-A", "thesis-C-method-1"] {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("out");
        let o = cut_sheet(&format!("examples/{design}.toml"), &out, &[]);
        assert!(o.status.success(), "{design}: {}", stderr(&o));
        check_folder(&out, "report.json");
        let report = report_json(&out);
        for (k, film) in report["mold"]["films_mm"]
            .as_array()
            .unwrap()
            .iter()
            .enumerate()
        {
            let svg = std::fs::read_to_string(layer_file(&out, &format!("mold-{}-1.svg", k + 1)))
                .unwrap();
            let (_, t, _, _) = svg_stock(&svg).unwrap();
            assert_eq!(t, film.as_f64().unwrap(), "{design}: mold-{}", k + 1);
        }
    }
}

#[test]
fn a_run_of_identical_panels_counts_a_sheet_per_panel() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = cut_sheet("examples/thesis-7.toml", &out, &["--quantity", "20"]);
    assert!(o.status.success(), "{}", stderr(&o));
    check_folder(&out, "report.json");
    // Its four PZT sheets and one passive sheet all have room for their stock label.
    assert_eq!(report_json(&out)["sheets_without_stock_label"], 0);
}

#[test]
fn every_nest_file_of_a_batch_with_linkages_names_its_stock() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    nest_ok("examples/batch-linkage.toml", &out, "50");
    check_folder(&out, "nest-report.json");
}

#[test]
fn every_nest_file_names_its_stock() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let json = nest_ok("examples/batch.toml", &out, "50");
    check_folder(&out, "nest-report.json");
    for panel in json["clamp_panels"].as_array().unwrap() {
        let molds = panel["stacking_order"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|s| s.as_str().unwrap().starts_with("mold-"))
            .count();
        assert_eq!(
            panel["mold_films_mm"].as_array().unwrap().len(),
            molds,
            "each mold sheet of a panel has its film"
        );
    }
}
