//! The build book is the thesis' process (§3.2.1, §3.2.2, §4.9) for the files written: every layer file
//! is named with its stock, the steps come in the thesis' order for each method, the parts go into the
//! mold after the sheets that hold them, and the checks and wiring follow each design.

use crate::common;
use common::*;
use serde_json::Value;
use std::path::Path;

/// The book's steps, in order, each with the title of its section.
pub(crate) fn steps(book: &Value) -> Vec<(String, String)> {
    book["sections"]
        .as_array()
        .unwrap()
        .iter()
        .flat_map(|s| {
            let title = s["title"].as_str().unwrap().to_string();
            s["steps"]
                .as_array()
                .unwrap()
                .iter()
                .map(move |t| (title.clone(), t.as_str().unwrap().to_string()))
        })
        .collect()
}

/// Index of the first step containing `text`.
pub(crate) fn first(steps: &[(String, String)], text: &str) -> usize {
    steps
        .iter()
        .position(|(_, s)| s.contains(text))
        .unwrap_or_else(|| panic!("no step says {text:?}"))
}

/// Every layer file of `out` (stem) is named in the book's Cut section.
fn every_file_is_cut(out: &Path, steps: &[(String, String)]) {
    let cut: String = steps
        .iter()
        .filter(|(t, _)| t == "Cut")
        .map(|(_, s)| s.as_str())
        .collect();
    for name in files(out).into_keys() {
        if let Some(stem) = name.strip_suffix(".svg") {
            // A remnant drawing is stock for a later batch, not a file to cut.
            if stem.starts_with("preview") || stem.starts_with("remnant-") {
                continue;
            }
            assert!(
                cut.contains(&format!("`{stem}`")),
                "{stem} is not cut in the book"
            );
        }
    }
}

/// In each clamp section, the plates and the core go in right after the last mold sheet of their band.
fn parts_go_in_after_their_band(steps: &[(String, String)], holds: &[Value]) {
    let last = |band: &str| {
        holds
            .iter()
            .rposition(|h| h.as_str() == Some(band))
            .map(|j| format!("Lay mold-{}:", j + 1))
            .unwrap()
    };
    let stack: Vec<&String> = steps
        .iter()
        .filter(|(t, _)| t == "Stack clamp 1 (panel 1)")
        .map(|(_, s)| s)
        .collect();
    assert!(!stack.is_empty(), "no stacking section");
    let after = |band: &str| {
        let at = stack
            .iter()
            .position(|s| s.starts_with(&last(band)))
            .unwrap();
        stack[at + 1].as_str()
    };
    assert!(after("lower plate")
        .starts_with("Put a PZT plate from the lower tray in each cavity, + face up"));
    assert!(after("core").contains("passive part"));
    assert!(after("upper plate").starts_with("Put the second PZT plate"));
    polarity_mark_stays_free(steps);
}

/// The polarity mark goes only on a face that stays free (docs/cam.md §6): both plates go in + face up,
/// so the lower plate's + face is bonded to the passive layer and the upper plate's is the actuator's
/// outer face. The upper plates are dotted on their + face, the lower plates carry no mark, and the
/// wiring finds + by the dot.
fn polarity_mark_stays_free(steps: &[(String, String)]) {
    let snap = &steps[first(steps, "Snap the plates off")].1;
    assert!(
        snap.contains("Dot the + face of every upper plate")
            && snap.contains("Mark no lower plate"),
        "{snap}"
    );
    let lower = &steps[first(steps, "from the lower tray")].1;
    assert!(lower.contains("carries no mark"), "{lower}");
    let upper = &steps[first(steps, "Put the second PZT plate")].1;
    assert!(upper.contains("from the upper tray, dot up"), "{upper}");
    let wires = &steps[first(steps, "wires on with silver epoxy")].1;
    assert!(
        wires.contains("red to the + face (the dotted face)"),
        "{wires}"
    );
    // No step marks a plate where it is bonded.
    assert!(
        !steps
            .iter()
            .any(|(_, t)| t.contains("dot at its root")
                || t.contains("dot on its + face at its root")),
        "a step marks the bonded face"
    );
}

#[test]
fn method_2_cuts_the_prepreg_last_and_presses_it_between_the_plates() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = cut_sheet("examples/thesis-C.toml", &out, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let r = report_json(&out);
    let s = steps(&r["build_book"]);
    every_file_is_cut(&out, &s);
    // Thesis §3.2.2: PZT scored and snapped, molds, covers (porous Teflon, bleeder), prepreg last.
    let (score, snap, mold, cover, prepreg) = (
        first(&s, "score it along the blue lines"),
        first(&s, "Snap the plates off"),
        first(&s, "Cut the mold sheets"),
        first(&s, "bleeder cloth"),
        first(&s, "Lay up the prepreg plies"),
    );
    assert!(score < snap && snap < mold && mold < cover && cover < prepreg);
    assert!(s[prepreg].1.contains("last"));
    assert!(!s.iter().any(|(_, t)| t.contains("Pyralux")));
    parts_go_in_after_their_band(&s, r["mold"]["holds"].as_array().unwrap());
    // The cure is the template's: 2 h at 176.7 °C (350 F), cooled in the clamp.
    let cure = first(&s, "Cure in the oven");
    assert!(s[cure].1.contains("2 h at 177 °C (350 F)"), "{}", s[cure].1);
    assert!(s[cure + 1].1.contains("cool"));
    // Squeeze-out is scraped before the electrical checks, which name the predicted capacitance.
    let c = r["predicted"]["capacitance_nF"].as_f64().unwrap();
    let scrape = first(&s, "Scrape the squeeze-out");
    let capacitance = first(&s, &format!("{c:.2} nF"));
    let short = first(&s, "Check for shorts");
    let wires = first(&s, "wires on with silver epoxy");
    assert!(scrape < capacitance && capacitance < short && short < wires);
    // Design C has no base tab: the process adds its ground tab, and the wiring puts the ground there.
    assert!(
        s[wires]
            .1
            .contains("ground tab behind the PZT root (1.5 mm of bare carbon, added"),
        "{}",
        s[wires].1
    );
}

#[test]
fn a_design_without_a_tab_gets_the_process_ground_tab_with_its_mass() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = cut_sheet("examples/thesis-C.toml", &out, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let r = report_json(&out);
    let tab = r["ground_tab"]["length_mm"].as_f64().unwrap();
    assert_eq!(tab, 1.5, "the shipped templates' ground_tab_mm");
    assert_eq!(r["design"]["base_tab_mm"].as_f64().unwrap(), tab);
    // Its mass is the passive plies' over the tab, l_tab x w_0 x t x rho (no PZT, no bond there).
    let passive = r["layers"]
        .as_array()
        .unwrap()
        .iter()
        .find(|l| l["layer"] == "passive")
        .unwrap();
    let t_mm = passive["thickness_mm"].as_f64().unwrap();
    let rho = passive["density_kg_per_m3"].as_f64().unwrap();
    let w0 = r["design"]["base_width_mm"].as_f64().unwrap();
    let expected_mg = tab * w0 * t_mm * rho * 1e-3; // mm³ x kg/m³ = 1e-9 kg = 1e-3 mg
    let mass = r["ground_tab"]["mass_mg"].as_f64().unwrap();
    assert!(
        (mass - expected_mg).abs() < 1e-9,
        "{mass} against {expected_mg}"
    );
    // The drawn parts include it: the geometry mass and the model's still agree.
    let geometry = r["mass_from_geometry_mg"].as_f64().unwrap();
    let model = r["predicted"]["mass_mg"].as_f64().unwrap();
    assert!(
        (geometry - model).abs() < 1e-6 * model,
        "{geometry} against {model}"
    );

    // A design with its own tab keeps it; a template with ground_tab_mm = 0 adds none, and the book
    // sends the ground wire to the laminate's edge.
    let (dir, design) = write_temp(
        "c.toml",
        &design_c_with(&[("base_tab_mm", "base_tab_mm = 2.0")]),
    );
    let out = dir.path().join("out");
    assert!(cut_sheet(design.to_str().unwrap(), &out, &[])
        .status
        .success());
    let r = report_json(&out);
    assert!(r.get("ground_tab").is_none());
    assert_eq!(r["design"]["base_tab_mm"].as_f64().unwrap(), 2.0);
    let template =
        shipped_template("method-2.toml").replace("ground_tab_mm = 1.5\n", "ground_tab_mm = 0\n");
    assert!(template.contains("ground_tab_mm = 0\n"));
    std::fs::write(dir.path().join("no-tab.toml"), template).unwrap();
    let text = design_c_with(&[(
        "process",
        &format!("process = \"{}\"", dir.path().join("no-tab.toml").display()),
    )]);
    std::fs::write(&design, text).unwrap();
    let out = dir.path().join("out2");
    let o = cut_sheet(design.to_str().unwrap(), &out, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let r = report_json(&out);
    assert!(r.get("ground_tab").is_none());
    let s = steps(&r["build_book"]);
    let wires = first(&s, "wires on with silver epoxy");
    assert!(
        s[wires].1.contains("edge at the root end"),
        "{}",
        s[wires].1
    );
}

#[test]
fn method_1_cures_the_passive_first_and_fills_the_vias_at_stacking() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = cut_sheet("examples/thesis-C-method-1.toml", &out, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let r = report_json(&out);
    let s = steps(&r["build_book"]);
    every_file_is_cut(&out, &s);
    // Thesis §3.2.1: cure the layup, cut it, cut the Pyralux on porous Teflon, score the PZT.
    let (cure, cut, pyralux, score, mold) = (
        first(&s, "cure the layup before cutting it"),
        first(&s, "Cut the passive parts from the cured layup"),
        first(&s, "Peel the Pyralux"),
        first(&s, "score it along the blue lines"),
        first(&s, "Cut the mold sheets"),
    );
    assert!(cure < cut && cut < pyralux && pyralux < score && score < mold);
    assert!(s[cure].1.contains("192 °C"), "{}", s[cure].1);
    // The vias are filled when the Pyralux goes into the mold, not when it is cut.
    assert!(s[pyralux].1.contains("Leave the vias empty"));
    // Each Pyralux part is tacked onto its plate, in the plate's band, with the via's own volume of
    // epoxy: π (0.25 mm)² x 0.025 mm = 0.0049 mm³.
    let bond = first(&s, "Onto each lower plate, a Pyralux part");
    assert!(s[bond].0.starts_with("Stack clamp"));
    assert!(s[bond - 1]
        .1
        .starts_with("Put a PZT plate from the lower tray"));
    assert!(s[bond].1.contains("0.0049 mm³"), "{}", s[bond].1);
    assert!((std::f64::consts::PI * 0.25f64.powi(2) * 0.025 - 0.0049).abs() < 5e-5);
    parts_go_in_after_their_band(&s, r["mold"]["holds"].as_array().unwrap());
    assert!(s[first(&s, "Cure in the oven")].1.contains("1 h at 177 °C"));
}

/// `nest examples/batch.toml` into `dir/nest`; the output folder.
fn nest_example_batch(dir: &Path) -> std::path::PathBuf {
    let out = dir.join("nest");
    let o = bin()
        .args(["nest", "examples/batch.toml", "-o"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    out
}

#[test]
fn a_nest_batch_writes_the_same_book_for_every_design() {
    let dir = tempfile::tempdir().unwrap();
    let out = nest_example_batch(dir.path());
    let r: Value = nest_report_json(&out);
    let s = steps(&r["build_book"]);
    every_file_is_cut(&out, &s);
    let stacks = s
        .iter()
        .filter(|(t, _)| t.starts_with("Stack clamp"))
        .map(|(t, _)| t)
        .collect::<std::collections::BTreeSet<_>>();
    let laminates = r["clamp_panels"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["mold_films_mm"].to_string())
        .collect::<std::collections::BTreeSet<_>>();
    assert!(stacks.len() >= laminates.len() && !stacks.is_empty());
    for item in r["items"].as_array().unwrap() {
        let name = item["design"].as_str().unwrap();
        first(&s, &format!("{name}: measure each PZT layer's capacitance"));
        first(&s, &format!("{name}: wires on"));
    }
    let md = std::fs::read_to_string(out.join("nest-report.md")).unwrap();
    assert!(md.contains("## Build book") && md.contains("### Cure and clamp"));
}

/// The Build book section of a report, as `docs/build-book.md` quotes it.
fn book_section(report_md: &str, end: &str) -> String {
    let start = report_md.find("## Build book").expect("a build book");
    let body = &report_md[start..];
    let body = &body[body.find('\n').unwrap() + 1..body.find(end).unwrap()];
    body.trim_matches('\n').to_string()
}

#[test]
fn the_books_in_the_docs_are_what_the_tool_writes() {
    // docs/build-book.md quotes the books of three shipped examples in full: it must not drift from them.
    let doc = std::fs::read_to_string("docs/build-book.md").unwrap();
    let dir = tempfile::tempdir().unwrap();
    for (i, (example, end)) in [
        ("thesis-C.toml", "\nKerf values"),
        ("thesis-C-method-1.toml", "\nKerf values"),
    ]
    .into_iter()
    .enumerate()
    {
        let out = dir.path().join(format!("c{i}"));
        let o = cut_sheet(&format!("examples/{example}"), &out, &[]);
        assert!(o.status.success(), "{}", stderr(&o));
        let md = std::fs::read_to_string(out.join("report.md")).unwrap();
        assert!(
            doc.contains(&book_section(&md, end)),
            "docs/build-book.md does not hold the book of {example}"
        );
    }
    let out = nest_example_batch(dir.path());
    let md = std::fs::read_to_string(out.join("nest-report.md")).unwrap();
    assert!(
        doc.contains(&book_section(&md, "\n## Parts on each sheet")),
        "docs/build-book.md does not hold the batch's book"
    );
    // The linkage's steps: on the clamp panel (cut-sheet --drive) and nested as coupons on their jig.
    let between = |md: &str, start: &str, end: &str| {
        let a = md.find(start).unwrap_or_else(|| panic!("no {start:?}"));
        md[a..a + md[a..].find(end).unwrap()]
            .trim_matches('\n')
            .to_string()
    };
    let out = dir.path().join("linkage");
    cut_linkage_example(&out);
    let md = std::fs::read_to_string(out.join("report.md")).unwrap();
    let steps = between(&md, "### Linkage build checklist", "\nKerf values");
    assert!(steps.contains("Joint B folds"), "{steps}");
    assert!(
        doc.contains(&steps),
        "docs/build-book.md does not hold the linkage's steps"
    );
    let out = dir.path().join("nest-linkage");
    nest_ok("examples/batch-linkage.toml", &out, "100");
    let md = std::fs::read_to_string(out.join("nest-report.md")).unwrap();
    let steps = between(&md, "### Linkages of thesis-7", "\n## Parts on each sheet");
    assert!(steps.contains("The jig `jig-1-linkage-coupons_"), "{steps}");
    assert!(
        doc.contains(&steps),
        "docs/build-book.md does not hold the nested linkages' steps"
    );
}

#[test]
fn a_design_name_is_written_into_the_book_as_literal_text() {
    // A name with Markdown's table, emphasis and HTML characters must not become a table cell,
    // emphasis or a vanishing tag in the checklist.
    let (dir, design) = write_temp(
        "c.toml",
        &design_c_with(&[("name = \"thesis-C\"", "name = \"C|*x*_<b>\"")]),
    );
    let out = dir.path().join("out");
    let o = cut_sheet(design.to_str().unwrap(), &out, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let md = std::fs::read_to_string(out.join("report.md")).unwrap();
    let book = book_section(&md, "### Wiring");
    assert!(
        book.contains(r"C\|\*x\*\_\<b\>: measure each PZT layer"),
        "{book}"
    );
    assert!(!book.contains("C|*x*"), "{book}");
}
