//! `nest` with linkages (`drive` on an `[[item]]`, docs/cam.md §7): the coupons of
//! examples/batch-linkage.toml checked on their sheets from the report alone, independent of the
//! planner: every coupon once per layer and linkage, inside its sheet and apart from every other part
//! by kerf and spacing, the carbon only half-turned with its links along the sheet's fibres.

use crate::common;
use common::*;
use geo::{Distance, Euclidean};
use std::collections::BTreeMap;
use std::path::Path;

/// templates/method-2.toml: `[linkage] kerf_mm`, `slot_overrun_mm`; `[clamp] pin_radius_mm`.
const LINKAGE_KERF_MM: f64 = 0.02;
const OVERRUN_MM: f64 = 0.5;
const PIN_RADIUS_MM: f64 = 0.79;
/// examples/batch-linkage.toml `[sheets] spacing_mm`.
const SPACING_MM: f64 = 0.3;

/// A coupon's outline about its centre, links along +x: the clamp panel's outline (docs/cam.md §2),
/// chamfered at the top-left corner by twice the pin inset, at most a quarter of a side.
fn coupon(w: f64, h: f64) -> Vec<[f64; 2]> {
    let inset = 2.0 * PIN_RADIUS_MM + OVERRUN_MM;
    let c = (2.0 * inset).min(w / 4.0).min(h / 4.0);
    [[0.0, 0.0], [w, 0.0], [w, h], [c, h], [0.0, h - c]]
        .iter()
        .map(|q| [q[0] - w / 2.0, q[1] - h / 2.0])
        .collect()
}

fn turned(ring: &[[f64; 2]], deg: f64, at: [f64; 2]) -> Vec<[f64; 2]> {
    let (s, c) = deg.to_radians().sin_cos();
    ring.iter()
        .map(|q| [c * q[0] - s * q[1] + at[0], s * q[0] + c * q[1] + at[1]])
        .collect()
}

#[test]
fn actuators_with_their_linkages_nest_and_every_coupon_checks_out() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let batch = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/batch-linkage.toml");
    let report = nest_ok(batch.to_str().unwrap(), &out, "200");
    let linkages = report["linkages"].as_array().unwrap();
    assert_eq!(linkages.len(), 2);
    let mut want: BTreeMap<String, (usize, [f64; 2])> = BTreeMap::new();
    for l in linkages {
        let design = l["design"].as_str().unwrap();
        let q = l["quantity"].as_u64().unwrap() as usize;
        let size = [
            l["coupon_width_mm"].as_f64().unwrap(),
            l["coupon_height_mm"].as_f64().unwrap(),
        ];
        // The coupon holds the linkage, its slot overrun and a pin border on each side.
        let length = l["length_mm"].as_f64().unwrap();
        assert!(size[0] > length + 2.0 * OVERRUN_MM + 4.0 * PIN_RADIUS_MM);
        for (layer, per) in [("carbon", 2), ("adhesive", 2), ("film", 1)] {
            want.insert(format!("{design}-linkage-{layer}"), (per * q, size));
        }
        // Its coupon files were checked across layers before writing; they are all there.
        let prefix = l["prefix"].as_str().unwrap();
        let files: Vec<_> = std::fs::read_dir(&out)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|n| n.starts_with(prefix) && n.ends_with(".dxf"))
            .collect();
        assert_eq!(files.len(), 6, "{files:?}");
    }
    let mut seen: BTreeMap<String, Vec<usize>> = BTreeMap::new();
    for sheet in report["sheets"].as_array().unwrap() {
        let layer = sheet["layer"].as_str().unwrap();
        if !layer.starts_with("linkage-") {
            // Actuators' parts share no sheet with a coupon here: no design has the linkage's layup.
            assert!(sheet["parts"]
                .as_array()
                .unwrap()
                .iter()
                .all(|p| !p["design"].as_str().unwrap().contains("-linkage-")));
            continue;
        }
        let (w, h) = (
            sheet["width_mm"].as_f64().unwrap(),
            sheet["height_mm"].as_f64().unwrap(),
        );
        let gap = LINKAGE_KERF_MM + SPACING_MM;
        let mut placed = Vec::new();
        for p in sheet["parts"].as_array().unwrap() {
            let name = p["design"].as_str().unwrap().to_string();
            assert!(
                name.ends_with(&layer["linkage-".len()..]),
                "{name} on {layer}"
            );
            let (_, size) = want[&name];
            seen.entry(name.clone())
                .or_default()
                .push(p["actuator"].as_u64().unwrap() as usize);
            let rot = p["rotation_deg"].as_f64().unwrap();
            let allowed: &[f64] = if layer == "linkage-carbon" {
                &[0.0, 180.0]
            } else {
                &[0.0, 90.0, 180.0, 270.0]
            };
            assert!(allowed.contains(&rot), "{name}: rotation {rot}");
            // The part is the coupon turned a quarter (links along +y), then by its rotation.
            let at = [p["x_mm"].as_f64().unwrap(), p["y_mm"].as_f64().unwrap()];
            let ring = turned(&coupon(size[0], size[1]), 90.0 + rot, at);
            if layer == "linkage-carbon" {
                // Fibres along the sheet's y axis: the links (the coupon's long side) run along y.
                let ys: Vec<f64> = ring.iter().map(|q| q[1]).collect();
                let span = ys.iter().cloned().fold(f64::MIN, f64::max)
                    - ys.iter().cloned().fold(f64::MAX, f64::min);
                assert!((span - size[0]).abs() < 1e-9, "{name}: links not along y");
            }
            for q in &ring {
                assert!(
                    q[0] >= gap - 1e-6
                        && q[1] >= gap - 1e-6
                        && q[0] <= w - gap + 1e-6
                        && q[1] <= h - gap + 1e-6,
                    "{name} vertex {q:?} within {gap} mm of the sheet's edge"
                );
            }
            placed.push((name, polygon(&ring)));
        }
        for i in 0..placed.len() {
            for j in i + 1..placed.len() {
                let d = Euclidean.distance(&placed[i].1, &placed[j].1);
                assert!(
                    d >= gap - 1e-6,
                    "{} and {} are {d} mm apart (gap {gap})",
                    placed[i].0,
                    placed[j].0
                );
            }
        }
    }
    for (name, (count, _)) in &want {
        let mut copies = seen.remove(name).unwrap_or_default();
        copies.sort();
        assert_eq!(copies, (1..=*count).collect::<Vec<_>>(), "{name}");
    }
    assert!(seen.is_empty(), "{seen:?}");
    // The build book has a section for each item's linkages.
    let sections: Vec<&str> = report["build_book"]["sections"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["title"].as_str().unwrap())
        .collect();
    assert!(sections.contains(&"Linkages of thesis-7 (docs/cam.md §7)"));
    assert!(sections.contains(&"Linkages of robobee-jafferis2016-derated (docs/cam.md §7)"));
}

/// The hawk-moth batch in `dir` with a template whose linkage carbon is laid up as thesis-7's prepreg
/// (`[0, 0, 90, 0, 0]` of CF-thesis) and a drive file with flexures of at least two prepreg kerfs:
/// `passive_cut` as given. Returns the batch file.
fn shared_prepreg(dir: &Path, passive_cut: &str) -> std::path::PathBuf {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let read = |p: &str| std::fs::read_to_string(root.join(p)).unwrap();
    let template = read("templates/method-2.toml")
        .replace(
            "carbon_layup_deg = [0, 90, 0]",
            "carbon_layup_deg = [0, 0, 90, 0, 0]",
        )
        .replace(
            "passive_cut = \"stack\"",
            &format!("passive_cut = \"{passive_cut}\""),
        );
    std::fs::write(dir.join("tpl.toml"), template).unwrap();
    let design = read("examples/thesis-7.toml")
        .replace("process = \"method-2\"", "process = \"tpl.toml\"")
        .replace("base_tab_mm = 0.0", "base_tab_mm = 2.0");
    std::fs::write(dir.join("thesis-7.toml"), design).unwrap();
    let drive = read("examples/drive-hawkmoth.toml")
        .replace(
            "flexure_stiffness_uNm_per_rad = 250",
            "flexure_length_um = [240, 256, 120]",
        )
        .replace("link_inertia_mg_mm2 = 0", "")
        .replace("mass_mg = 20", "");
    std::fs::write(dir.join("drive.toml"), drive).unwrap();
    let batch = dir.join("batch.toml");
    std::fs::write(
        &batch,
        "name = \"shared\"\n[[item]]\ndesign = \"thesis-7.toml\"\nquantity = 2\ndrive = \"drive.toml\"\n",
    )
    .unwrap();
    batch
}

#[test]
fn the_carbon_shares_the_prepreg_sheets_of_a_design_laid_up_alike() {
    for cut in ["stack", "ply-by-ply"] {
        let dir = tempfile::tempdir().unwrap();
        let batch = shared_prepreg(dir.path(), cut);
        let out = dir.path().join("out");
        let report = nest_ok(batch.to_str().unwrap(), &out, "100");
        let l = &report["linkages"][0];
        assert!(
            l["sheets"][0]
                .as_str()
                .unwrap()
                .starts_with("layer 1 and 5 on prepreg, layup 0/0/90/0/0"),
            "{cut}: {}",
            l["sheets"][0]
        );
        // Designed with the prepreg's kerf, the larger.
        assert_eq!(l["kerf_mm"].as_f64().unwrap(), 0.05);
        // Every prepreg sheet holds actuators' parts and carbon coupons together, each coupon half-turned;
        // ply by ply, one sheet per ply, each with every coupon (2 per linkage).
        let sheets: Vec<&serde_json::Value> = report["sheets"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|s| s["layer"].as_str().unwrap().starts_with("passive"))
            .collect();
        assert_eq!(sheets.len(), if cut == "stack" { 1 } else { 5 }, "{cut}");
        for s in sheets {
            let parts = s["parts"].as_array().unwrap();
            let coupons: Vec<&serde_json::Value> = parts
                .iter()
                .filter(|p| p["design"] == "thesis-7-linkage-carbon")
                .collect();
            assert_eq!(coupons.len(), 4, "{cut}: {}", s["file_stem"]);
            assert_eq!(
                parts.len() - coupons.len(),
                2,
                "{cut}: the actuators' parts"
            );
            for c in coupons {
                // The rotation on top of the ply's turn (the sheet of a ply at θ turns its parts by
                // -θ first, as the actuators' plies): half turns only.
                let r = c["rotation_deg"].as_f64().unwrap();
                assert!(r == 0.0 || r == 180.0, "{cut} {}: rotation {r}", s["layer"]);
            }
        }
    }
}

#[test]
fn a_design_with_a_transmission_nests_its_linkage_without_a_drive_file() {
    let dir = tempfile::tempdir().unwrap();
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    let drive =
        std::fs::read_to_string(root.join("drive-robobee-jafferis2016-linkage.toml")).unwrap();
    let table = &drive[drive.find("[transmission]").unwrap()..];
    let design = std::fs::read_to_string(root.join("robobee-jafferis2016-derated.toml")).unwrap()
        + "\n"
        + &table.replace("[transmission]", "[transmission]\nstroke_deg = 20");
    std::fs::write(dir.path().join("bee.toml"), design).unwrap();
    let batch = dir.path().join("batch.toml");
    std::fs::write(
        &batch,
        "name = \"own\"\n[[item]]\ndesign = \"bee.toml\"\nquantity = 2\n",
    )
    .unwrap();
    let out = dir.path().join("out");
    let o = run(&["nest", batch.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let report = nest_report_json(&out);
    let l = &report["linkages"][0];
    assert!(l["drive_file"].as_str().unwrap().ends_with("bee.toml"));
    assert_eq!(l["quantity"], 2);
    // The same flexures as the drive file's: 112.5, 120 and 50 µm.
    let lengths: Vec<f64> = l["flexures"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f["length_um"].as_f64().unwrap())
        .collect();
    assert_eq!(lengths, vec![112.5, 120.0, 50.0]);
    // A drive file on the item that asks for another stroke is refused, naming the design file.
    std::fs::write(
        dir.path().join("drive.toml"),
        drive
            .replace(
                "design = \"robobee-jafferis2016-derated.toml\"",
                "design = \"bee.toml\"",
            )
            .replace("stroke_deg = 20", "stroke_deg = 15"),
    )
    .unwrap();
    std::fs::write(
        &batch,
        "name = \"own\"\n[[item]]\ndesign = \"bee.toml\"\nquantity = 2\ndrive = \"drive.toml\"\n",
    )
    .unwrap();
    let out = dir.path().join("out2");
    let o = run(&["nest", batch.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    assert!(!o.status.success());
    let err = stderr(&o);
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(err.contains("bee.toml: transmission = (given)"), "{err}");
    assert!(!out.exists());
}

/// The CUT-layer circles of a DXF: centre and radius, mm.
fn cut_circles(path: &Path) -> Vec<([f64; 2], f64)> {
    use dxf::entities::EntityType as E;
    let doc = dxf::Drawing::load_file(path).unwrap();
    doc.entities()
        .filter(|e| e.common.layer == "CUT")
        .filter_map(|e| match &e.specific {
            E::Circle(c) => Some(([c.center.x, c.center.y], c.radius)),
            _ => None,
        })
        .collect()
}

/// The jig the coupons stack, cure and release on (docs/cam.md §7): read back from its DXF, each
/// linkage's coupons have their pin pattern on it, as many times as the linkage's quantity, read back
/// from the coupon's own carbon file; each jig hole is cut to the template's Ø1.5 mm dowel
/// (`clamp.dowel_diameter_mm`: the drawn radius and half the linkage kerf), where the coupons' holes
/// clear it; the jig is on the stock list and every linkage's stacking step names it.
#[test]
fn the_coupons_jig_holds_each_linkages_pin_pattern_at_the_dowel_size() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let batch = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/batch-linkage.toml");
    let report = nest_ok(batch.to_str().unwrap(), &out, "100");
    let names: Vec<String> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    let jig = names
        .iter()
        .find(|n| n.starts_with("jig-1-linkage-coupons_") && n.ends_with(".dxf"))
        .expect("a jig file");
    let stem = jig.trim_end_matches(".dxf");
    let holes = cut_circles(&out.join(jig));
    let half = LINKAGE_KERF_MM / 2.0;
    for (_, r) in &holes {
        assert!((2.0 * (r + half) - 1.5).abs() < 1e-6, "jig hole radius {r}");
    }
    // The pattern of four holes relative to the first, as a file draws them.
    let pattern = |four: &[([f64; 2], f64)]| -> Vec<[f64; 2]> {
        four.iter()
            .map(|(q, _)| [q[0] - four[0].0[0], q[1] - four[0].0[1]])
            .collect()
    };
    let mut groups = holes.chunks(4);
    let mut total = 0;
    for l in report["linkages"].as_array().unwrap() {
        let prefix = l["prefix"].as_str().unwrap();
        let carbon = names
            .iter()
            .find(|n| n.starts_with(&format!("{prefix}1-carbon-1_")) && n.ends_with(".dxf"))
            .unwrap();
        let pins = cut_circles(&out.join(carbon));
        assert_eq!(pins.len(), 4);
        for (_, r) in &pins {
            assert!(2.0 * (r + half) > 1.5 + 0.05, "coupon hole radius {r}");
        }
        let want = pattern(&pins);
        for _ in 0..l["quantity"].as_u64().unwrap() {
            let got = pattern(groups.next().expect("a group of jig holes per coupon"));
            for (g, w) in got.iter().zip(&want) {
                assert!(
                    (g[0] - w[0]).abs() < 1e-6 && (g[1] - w[1]).abs() < 1e-6,
                    "{prefix}: {got:?} vs {want:?}"
                );
            }
            total += 1;
        }
        let steps = l["build_steps"].to_string();
        assert!(
            steps.contains(&format!("on the jig's four dowels (`{stem}`)")),
            "{steps}"
        );
    }
    assert_eq!(holes.len(), 4 * total);
    assert_eq!(total, 7);
    let stock = report["stock_list"].to_string();
    assert!(stock.contains("glass-polyimide laminate"), "{stock}");
    the_nest_book_names_the_linkage_files_and_marks_the_reference_ones(&report, &out, &names);
}

/// The nest's linkage steps name every nested linkage sheet file and lay up the carbon's own prepreg;
/// each per-coupon stack-layer file says in its SVG title and DXF comment that it is reference only,
/// and the book says so too; the release file engraves nothing over layer 5's label; every nested
/// linkage sheet engraves its coupons (where, off the bonded zones, the file-pair tests check).
fn the_nest_book_names_the_linkage_files_and_marks_the_reference_ones(
    report: &serde_json::Value,
    out: &Path,
    names: &[String],
) {
    let sheets: Vec<&String> = names
        .iter()
        .filter(|n| {
            ["carbon", "adhesive", "film"]
                .iter()
                .any(|p| n.starts_with(&format!("linkage-{p}-1_")))
                && n.ends_with(".svg")
        })
        .collect();
    assert_eq!(sheets.len(), 3, "{names:?}");
    for l in report["linkages"].as_array().unwrap() {
        let steps: Vec<&str> = l["build_steps"]
            .as_array()
            .unwrap()
            .iter()
            .map(|s| s.as_str().unwrap())
            .collect();
        for sheet in &sheets {
            let stem = sheet.trim_end_matches(".svg");
            assert!(
                steps[0].contains(&format!("`{stem}`")),
                "{stem}: {}",
                steps[0]
            );
            let svg = std::fs::read_to_string(out.join(sheet)).unwrap();
            let engrave = &svg[svg.find("id=\"layer-engrave\"").unwrap()..];
            let strokes = engrave
                .split("</g>")
                .next()
                .unwrap()
                .matches("<path")
                .count();
            assert!(strokes > 20, "{sheet}: {strokes} engraved strokes");
        }
        assert!(
            steps[1]
                .starts_with("Lay up the linkage carbon's prepreg: 3 plies of CF-thesis at 0/90/0"),
            "{}",
            steps[1]
        );
        let prefix = l["prefix"].as_str().unwrap();
        assert!(
            steps[0].contains("reference only, never to be cut"),
            "{}",
            steps[0]
        );
        for n in names.iter().filter(|n| n.starts_with(prefix)) {
            let text = std::fs::read_to_string(out.join(n)).unwrap();
            let reference = text.contains("REFERENCE ONLY, not to be cut");
            assert_eq!(reference, !n.contains("-release-"), "{n}");
            if n.contains("-release-") && n.ends_with(".svg") {
                let engrave = text.find("id=\"layer-engrave\"");
                assert!(
                    engrave.is_none_or(|at| !text[at..]
                        .split("</g>")
                        .next()
                        .unwrap()
                        .contains("<path")),
                    "{n} engraves over layer 5's label"
                );
            }
        }
    }
}
