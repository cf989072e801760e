//! `cut-sheet --drive`: the drive's flexure linkage cut with the actuator (docs/cam.md §7). The linkage
//! layers are written beside the actuator's, one set per panel, and listed in the report with their
//! mass; `drive` with flexures takes the drawn linkage's stiffness and mass; a flexure that cannot be
//! made is one line and nothing is written.

mod common;

use common::{
    cut_sheet, example, example_path, files, refused_in_one_line, report_json, run, sheet_files,
    sheet_name, stderr,
};

#[test]
fn the_insect_scale_linkage_is_cut_with_its_actuator() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("bee");
    let drive = example("drive-robobee-linkage.toml");
    let o = cut_sheet(
        &example("robobee-class.toml"),
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
    // does not reach its stroke, so `drive` exits non-zero, after its report.
    let o = run(&["drive", &drive, "--json"]);
    assert!(
        !o.status.success() && stderr(&o).contains("not reached"),
        "{}",
        stderr(&o)
    );
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
    let text = std::fs::read_to_string(example_path("drive-robobee-linkage.toml"))
        .unwrap()
        .replace(
            "flexure_length_um = [112.5, 120, 50]",
            "flexure_length_um = [112.5, 400, 50]",
        )
        .replace(
            "design = \"robobee-class.toml\"",
            &format!("design = {:?}", example("robobee-class.toml")),
        );
    let dir = tempfile::tempdir().unwrap();
    let drive = dir.path().join("drive.toml");
    std::fs::write(&drive, text).unwrap();
    let out = dir.path().join("out");
    let o = cut_sheet(
        &example("robobee-class.toml"),
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
        &["--drive", &example("drive-robobee-linkage.toml")],
    );
    let err = refused_in_one_line(&o);
    assert!(err.contains(": design = "), "{err}");
    assert!(!out.exists());
}
