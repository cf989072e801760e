//! `cut-sheet --drive`: the drive's flexure linkage cut with the actuator (docs/cam.md §7). The linkage
//! layers are written beside the actuator's, one set per panel, and listed in the report with their
//! mass; `drive` with flexures takes the drawn linkage's stiffness and mass; a flexure that cannot be
//! made is one line and nothing is written.

use crate::common;

use common::{
    cut_linkage_example, cut_sheet, example, example_path, files, refused_in_one_line, report_json,
    run, sheet_files, sheet_name, stderr,
};

/// Every linkage sheet of `out` engraves its label; the carbon layers say which way their fibres lie,
/// along the links (x), and the other layers name no fibres; a carbon slot crosses the strip, so it is
/// narrower in x than in y: the links run along x, the stated fibre direction.
fn linkage_sheets_carry_their_labels_and_fibre_direction(out: &std::path::Path) {
    for (name, bytes) in sheet_files(out) {
        if !name.starts_with("linkage-") || !name.ends_with(".svg") {
            continue;
        }
        let svg = String::from_utf8(bytes).unwrap();
        // Each stack layer engraves its layer, film and panel number on its border, as a clamp panel
        // does; the release file nothing, as it runs on the stack whose top layer carries its label.
        let engraved = svg.find("id=\"layer-engrave\"").map(|at| {
            svg[at..]
                .split("</g>")
                .next()
                .unwrap()
                .matches("<path")
                .count()
        });
        if name.contains("-release-") {
            assert_eq!(
                engraved.unwrap_or(0),
                0,
                "{name}: engraved over layer 5's label"
            );
        } else {
            assert!(engraved.unwrap_or(0) > 5, "{name}: no panel label");
        }
        let carbon = name.contains("-carbon-");
        assert_eq!(
            svg.contains("0° fibres along the sheet's x axis") && svg.contains("fibre_axis=\"x\""),
            carbon,
            "{name}"
        );
        assert!(!svg.contains("fibre_axis=\"y\""), "{name}");
        if carbon {
            let cut = &svg[svg.find("id=\"layer-cut\"").unwrap()..];
            let slots: Vec<(f64, f64)> = cut
                .split("<path d=\"")
                .skip(1)
                .filter_map(|p| {
                    let d = &p[..p.find('"').unwrap()];
                    let nums: Vec<f64> = d
                        .split(|c: char| c.is_ascii_alphabetic() || c == ' ')
                        .filter_map(|t| t.parse().ok())
                        .collect();
                    (!d.contains('A') && nums.len() >= 8).then(|| {
                        let (xs, ys): (Vec<f64>, Vec<f64>) =
                            nums.chunks(2).map(|c| (c[0], c[1])).unzip();
                        let span = |v: &[f64]| {
                            v.iter().cloned().fold(f64::MIN, f64::max)
                                - v.iter().cloned().fold(f64::MAX, f64::min)
                        };
                        (span(&xs), span(&ys))
                    })
                })
                .filter(|(w, h)| *w < 50.0 && *h < 50.0)
                .collect();
            assert!(!slots.is_empty(), "{name}: no slots");
            for (w, h) in slots {
                assert!(
                    w < h,
                    "{name}: a slot {w} x {h} mm does not cross a strip along x"
                );
            }
        }
    }
}

#[test]
fn the_insect_scale_linkage_is_cut_with_its_actuator() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("bee");
    let drive = example("drive-robobee-jafferis2016-linkage.toml");
    let o = cut_sheet(
        &example("robobee-jafferis2016-derated.toml"),
        &out,
        &["--drive", &drive, "--quantity", "12"],
    );
    assert!(o.status.success(), "{}", common::stderr(&o));
    let written = files(&out);
    let report = report_json(&out);
    let l = &report["linkage"];
    let panels = l["panels"].as_u64().unwrap() as usize;
    assert!(panels >= 1);
    for p in 1..=panels {
        for stem in [
            "linkage-1-carbon",
            "linkage-2-adhesive",
            "linkage-3-film",
            "linkage-4-adhesive",
            "linkage-5-carbon",
            "linkage-6-release",
        ] {
            for ext in ["svg", "dxf"] {
                // Each file's name carries its stock after the sheet's name.
                let name = format!("{stem}-{p}.{ext}");
                let file = written
                    .keys()
                    .find(|f| sheet_name(f) == name)
                    .unwrap_or_else(|| panic!("{name}"));
                assert!(file.contains("mm."), "{file} names no stock");
                let listed = report["files"].as_array().unwrap();
                assert!(listed.iter().any(|f| f == file), "{file} not listed");
            }
        }
    }
    linkage_sheets_carry_their_labels_and_fibre_direction(&out);
    // Twelve release outlines over the panels: one linkage per actuator.
    let outlines: usize = (1..=panels)
        .map(|p| {
            let svg =
                String::from_utf8(sheet_files(&out)[&format!("linkage-6-release-{p}.svg")].clone())
                    .unwrap();
            svg.matches("<path").count()
        })
        .sum();
    // Each linkage: one outline path and one hole (a circle path); the pins are circles too.
    assert!(outlines >= 12, "{outlines}");
    // The flexures stay in the insect-scale range and within the film's fatigue strain.
    for f in l["flexures"].as_array().unwrap() {
        let length = f["length_um"].as_f64().unwrap();
        assert!((50.0 - 1e-9..=120.0 + 1e-9).contains(&length), "{length}");
        assert!(f["peak_strain"].as_f64().unwrap() <= f["strain_limit"].as_f64().unwrap());
    }
    // The mass is the layers' masses, each its area times its mass per area.
    let layers = l["layers"].as_array().unwrap();
    let sum: f64 = layers
        .iter()
        .map(|x| x["area_mm2"].as_f64().unwrap() * x["areal_density_mg_per_mm2"].as_f64().unwrap())
        .sum();
    assert!((sum - l["mass_mg"].as_f64().unwrap()).abs() < 1e-9);
    let md = String::from_utf8(written["report.md"].clone()).unwrap();
    assert!(md.contains("### Linkage build checklist") && md.contains("release cut"));
    // `drive` takes the same linkage: its transmission is the drawn mass. This insect-scale drive
    // reaches its stroke within the limits, so `drive` exits zero.
    let o = run(&["drive", &drive, "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let json: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let drawn = json["linkage_laminate"]["mass_mg"].as_f64().unwrap();
    assert!((json["mass"]["transmission_mg"].as_f64().unwrap() - drawn).abs() < 1e-12);
    assert!((drawn - l["mass_mg"].as_f64().unwrap()).abs() < 1e-12);
    assert_eq!(
        json["linkage"]["flexure_stiffness_uNm_per_rad"],
        l["flexure_stiffness_uNm_per_rad"]
    );
}

#[test]
fn a_flexure_that_cannot_be_made_writes_nothing() {
    let text = std::fs::read_to_string(example_path("drive-robobee-jafferis2016-linkage.toml"))
        .unwrap()
        .replace(
            "flexure_length_um = [112.5, 120, 50]",
            "flexure_length_um = [112.5, 400, 50]",
        )
        .replace(
            "design = \"robobee-jafferis2016-derated.toml\"",
            &format!(
                "design = {:?}",
                example("robobee-jafferis2016-derated.toml")
            ),
        );
    let dir = tempfile::tempdir().unwrap();
    let drive = dir.path().join("drive.toml");
    std::fs::write(&drive, text).unwrap();
    let out = dir.path().join("out");
    let o = cut_sheet(
        &example("robobee-jafferis2016-derated.toml"),
        &out,
        &["--drive", drive.to_str().unwrap()],
    );
    let err = refused_in_one_line(&o);
    assert!(
        err.contains("drive.toml: transmission.flexure_length_um[1] = 400: flexure B"),
        "{err}"
    );
    assert!(!out.exists(), "nothing is written");
    // A drive file for another design is refused too.
    let o = cut_sheet(
        &example("thesis-7.toml"),
        &out,
        &[
            "--drive",
            &example("drive-robobee-jafferis2016-linkage.toml"),
        ],
    );
    let err = refused_in_one_line(&o);
    assert!(err.contains(": design = "), "{err}");
    assert!(!out.exists());
}

/// A crank so short that its wing-hinge flexure cannot be made even though it barely strains: the
/// refusal's bounds are never negative (the cut-backs' loose film takes a small bend alone, so the
/// strain asks for no gap), and the shortest length is the film thicknesses' or the kerfs', which the
/// line names.
#[test]
fn a_flexure_refusal_names_no_negative_length() {
    let text = std::fs::read_to_string(example_path("drive-robobee-jafferis2016-linkage.toml"))
        .unwrap()
        .replace("stroke_deg = 20\n", "stroke_deg = 50\n")
        .replace("travel_mm = 0.15\n", "travel_mm = 0.10\n")
        .replace("coupler_ratio = 8\n", "coupler_ratio = 4\n")
        .replace(
            "design = \"robobee-jafferis2016-derated.toml\"",
            &format!(
                "design = {:?}",
                example("robobee-jafferis2016-derated.toml")
            ),
        );
    assert!(text.contains("travel_mm = 0.10\n") && text.contains("stroke_deg = 50\n"));
    let dir = tempfile::tempdir().unwrap();
    let drive = dir.path().join("drive.toml");
    std::fs::write(&drive, text).unwrap();
    let err = refused_in_one_line(&run(&["drive", drive.to_str().unwrap()]));
    assert!(
        err.contains("flexure O (crank on airframe, the wing hinge)")
            && err.contains("at least 0.0 µm for the strain")
            && err.contains("film thicknesses and two kerfs"),
        "{err}"
    );
    // No number in the line is negative: every '-' is a hyphen between words.
    let negative = err
        .match_indices('-')
        .any(|(i, _)| err[i + 1..].starts_with(|c: char| c.is_ascii_digit()));
    assert!(!negative, "{err}");
}

/// robobee-jafferis2016-derated.toml with the `[transmission]` of
/// drive-robobee-jafferis2016-linkage.toml and its stroke, written into `dir` as `design.toml` beside a
/// copy of the drive file that drives it (`drive.toml`).
fn design_with_transmission(dir: &std::path::Path) -> (String, String) {
    let drive =
        std::fs::read_to_string(example_path("drive-robobee-jafferis2016-linkage.toml")).unwrap();
    let table = &drive[drive.find("[transmission]").unwrap()..];
    let design = std::fs::read_to_string(example_path("robobee-jafferis2016-derated.toml"))
        .unwrap()
        + "\n"
        + &table.replace("[transmission]", "[transmission]\nstroke_deg = 20");
    let d = dir.join("design.toml");
    std::fs::write(&d, design).unwrap();
    let dr = dir.join("drive.toml");
    std::fs::write(
        &dr,
        drive.replace(
            "design = \"robobee-jafferis2016-derated.toml\"",
            "design = \"design.toml\"",
        ),
    )
    .unwrap();
    (
        d.to_str().unwrap().to_string(),
        dr.to_str().unwrap().to_string(),
    )
}

#[test]
fn a_transmission_in_the_design_file_cuts_the_same_linkage_as_the_drive_file() {
    let dir = tempfile::tempdir().unwrap();
    let (design, drive) = design_with_transmission(dir.path());
    let own = dir.path().join("own");
    let o = cut_sheet(&design, &own, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let by_drive = dir.path().join("by-drive");
    cut_linkage_example(&by_drive);
    // Every linkage layer file the same, byte for byte; the reports name their own source.
    let linkage = |m: std::collections::BTreeMap<String, Vec<u8>>| {
        m.into_iter()
            .filter(|(n, _)| n.starts_with("linkage-"))
            .collect::<Vec<_>>()
    };
    let (a, b) = (linkage(files(&own)), linkage(files(&by_drive)));
    assert_eq!(a.len(), 12);
    assert_eq!(a, b);
    let r = report_json(&own);
    assert!(r["linkage"]["drive_file"]
        .as_str()
        .unwrap()
        .ends_with("design.toml"));
    assert_eq!(
        r["linkage"]["mass_mg"],
        report_json(&by_drive)["linkage"]["mass_mg"]
    );
    // Both given and the same: accepted, the same files.
    let both = dir.path().join("both");
    let o = cut_sheet(&design, &both, &["--drive", &drive]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(linkage(files(&both)), b);
}

#[test]
fn a_design_transmission_that_disagrees_with_the_drive_or_is_out_of_range_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let (design, drive) = design_with_transmission(dir.path());
    // The drive file asks for ±15°, the design for ±20°.
    let text = std::fs::read_to_string(&drive)
        .unwrap()
        .replace("stroke_deg = 20", "stroke_deg = 15");
    std::fs::write(&drive, text).unwrap();
    let out = dir.path().join("out");
    let err = refused_in_one_line(&cut_sheet(&design, &out, &["--drive", &drive]));
    assert!(
        err.contains("design.toml: transmission = (given): the [transmission] (and stroke_deg) of the drive file"),
        "{err}"
    );
    assert!(err.contains("may not disagree"), "{err}");
    assert!(!out.exists(), "nothing is written");
    // A stroke out of its range, named as written.
    let text = std::fs::read_to_string(&design)
        .unwrap()
        .replace("stroke_deg = 20", "stroke_deg = 200");
    std::fs::write(&design, text).unwrap();
    let err = refused_in_one_line(&cut_sheet(&design, &out, &[]));
    assert!(
        err.contains("design.toml: transmission.stroke_deg = 200"),
        "{err}"
    );
    assert!(!out.exists());
}

/// The worked example of docs/cam.md §7, the Berkeley MFI thorax (Wood, Avadhanula, Sahai, Steltz &
/// Fearing, J. Mech. Des. 130, 2008: flexures 112.5, 112.5 and 50 µm long, 2, 3 and 2 mm wide, in
/// 7.6 µm Kapton): every line the document prints is what `drive` prints, and the published flexures'
/// stiffness k = E w t³ / (12 L) and strain t φ / (2 L) it quotes are the closed forms at E = 2.5 GPa.
#[test]
fn the_mfi_thorax_worked_example_is_what_the_tool_prints() {
    let doc = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/cam.md"),
    )
    .unwrap();
    let at = doc
        .find("$ actuator-cam drive examples/drive-mfi-thorax.toml")
        .unwrap();
    let block = &doc[at..at + doc[at..].find("```").unwrap()];
    let o = run(&["drive", &example("drive-mfi-thorax.toml")]);
    let out = common::stdout(&o);
    let mut lines = 0;
    for line in block
        .lines()
        .skip(1)
        .filter(|l| !l.trim().is_empty() && *l != "...")
    {
        assert!(
            out.contains(line),
            "the tool does not print {line:?}:\n{out}"
        );
        lines += 1;
    }
    assert_eq!(lines, 8);
    // The published flexures (O, B, A) and their turns at ±60° of wing (the prose's 60°, 64.8°, 4.8°).
    let e = 2.5e9;
    let t = 7.6e-6;
    let published: [(f64, f64, f64, f64, f64); 3] = [
        (112.5e-6, 2e-3, 1.626, 60.0, 3.54),
        (112.5e-6, 3e-3, 2.439, 64.8, 3.82),
        (50e-6, 2e-3, 3.658, 4.8, 0.63),
    ];
    for (l, w, k_doc, phi_deg, eps_doc) in published {
        let k = e * w * t * t * t / (12.0 * l) * 1e6;
        assert!((k - k_doc).abs() < 5e-4, "k = {k} vs {k_doc}");
        assert!(doc.contains(&format!("{k_doc:.3}")));
        let eps = t * f64::to_radians(phi_deg) / (2.0 * l) * 100.0;
        // Within the printed precision: ε to 0.005 %, φ to 0.05°.
        let slack = 5e-3 + t * f64::to_radians(0.05) / (2.0 * l) * 100.0;
        assert!((eps - eps_doc).abs() <= slack, "ε = {eps} vs {eps_doc}");
        assert!(doc.contains(&format!("{eps_doc:.2} %")));
    }
}
