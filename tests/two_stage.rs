//! A transmission given by a published ratio law, and the two-stage linkage (a slider-crank and an
//! amplifying four-bar, docs/physics.md §12.4, §16.8): the two-stage reaches the published 3333 rad/m with
//! buildable flexures where a one-stage slider-crank cannot, the ratio law drives as its closed form, no
//! linkage drawing is made of either (cut-sheet and nest refuse them in one line), and bad input in their
//! keys is one line.

use crate::common;

use common::{drive_analysis, drive_design, example_path, refused_in_one_line, run, write_temp};
use std::path::{Path, PathBuf};

/// drive-robobee-jafferis2016-two-stage.toml with its `[transmission]` (and what follows) replaced by
/// `transmission`, beside a copy of its design.
fn with_transmission(transmission: &str) -> (tempfile::TempDir, PathBuf) {
    let text =
        std::fs::read_to_string(example_path("drive-robobee-jafferis2016-two-stage.toml")).unwrap();
    let head = &text[..text.find("[transmission]").unwrap()];
    let (dir, path) = write_temp("drive.toml", &format!("{head}{transmission}"));
    std::fs::copy(
        example_path("robobee-jafferis2016-derated.toml"),
        dir.path().join("robobee-jafferis2016-derated.toml"),
    )
    .unwrap();
    (dir, path)
}

const GIVEN: &str = "flexure_stiffness_uNm_per_rad = 17.80\nlink_inertia_mg_mm2 = 0\nmass_mg = 3\n";

#[test]
fn the_two_stage_linkage_reaches_the_published_ratio_that_one_stage_cannot_build() {
    // The example: crank 0.6 mm, four-bar 1 / 2 / 0.5 mm. At rest the ratio is the product of the
    // stages, (1 / 0.6 mm)(1 / 0.5) = 3333 rad/m (docs/physics.md §16.8), the top of the published
    // 2150-3333 rad/m.
    let r = drive_analysis(&example_path("drive-robobee-jafferis2016-two-stage.toml")).report;
    let ratio = r.linkage.ratio_at_rest_deg_per_mm.to_radians() * 1e3;
    assert!((ratio - 1.0 / 0.6e-3 * 2.0).abs() < 1e-6, "{ratio}");
    assert!(r.unbuildable_linkage.is_none(), "{}", r.table());
    let rows = r.linkage.flexures.as_ref().unwrap();
    assert_eq!(rows.len(), 6);
    // Each film's largest bend held to the fatigue strain, each gap within 0.3 of the shorter link it
    // joins (crank 0.6, coupler 2.4, four-bar 1 / 2 / 0.5 mm; O joins the crank and the input).
    let neighbour = [0.6, 0.6, 2.4, 1.0, 0.5, 0.5];
    for (f, link) in rows.iter().zip(neighbour) {
        assert!(f.peak_strain <= f.strain_limit + 1e-12, "{f:?}");
        assert!(f.length_um <= 300.0 * link, "{f:?}");
    }
    // B, C and D are folded a right angle at assembly (the crank upright, both four-bar links square to
    // the coupler at rest); O, A and the wing hinge W are laid flat.
    for (f, fold) in rows.iter().zip([0.0, 90.0, 0.0, 90.0, 90.0, 0.0]) {
        assert!((f.assembly_fold_deg - fold).abs() < 1e-9, "{f:?}");
    }
    // The wing hinge turns by the stroke itself.
    assert!((rows[5].peak_rotation_deg - 55.0).abs() < 1e-9);
    // The published ratio with the four-bar is the whole transmission's: the slider-crank before it is
    // the one of crank (a/c)/T, 0.6 mm, the example's.
    let (_dir, path) = with_transmission(&format!(
        "[transmission]\nratio_rad_per_m = {}\ncoupler_ratio = 4\n{GIVEN}\n[transmission.four_bar]\ninput_mm = 1.0\ncoupler_mm = 2.0\noutput_mm = 0.5\n",
        1.0 / 0.6e-3 * 2.0
    ));
    let by_ratio = drive_analysis(&path).report;
    assert!((by_ratio.linkage.crank_mm - 0.6).abs() < 1e-12);
    assert!((by_ratio.linkage.coupler_mm - 2.4).abs() < 1e-12);
    // The one-stage slider-crank of the same ratio has a 0.3 mm crank, and joint B's folded film needs
    // more than 0.3 of it whatever the coupler.
    for rho in [2, 4, 8] {
        let (_dir, path) = with_transmission(&format!(
            "[transmission]\nratio_rad_per_m = {}\ncoupler_ratio = {rho}\n{GIVEN}",
            1.0 / 0.6e-3 * 2.0
        ));
        let one = drive_analysis(&path).report;
        let why = one.unbuildable_linkage.unwrap_or_default();
        assert!(
            why.starts_with("flexure B (crank on coupler)"),
            "{rho}: {why}"
        );
        assert!(why.contains("of the 0.300 mm link"), "{why}");
    }
}

#[test]
fn a_ratio_law_drives_as_its_closed_form_and_no_drawing_is_made() {
    // docs/physics.md §12.4: T(θ) = T0 / (1 + 3 c θ²), here 3000 rad/m at rest and 2600 at the ±55°
    // stroke; the harmonic balance (in x(θ)) and the time integration (in θ(x) and T) agree on it.
    let (dir, path) = with_transmission(&format!(
        "[transmission]\nratio_rad_per_m = 3000\nratio_at_stroke_deg = 55\nratio_at_stroke_rad_per_m = 2600\n{GIVEN}"
    ));
    let a = drive_analysis(&path);
    let law = a.report.linkage.ratio_law.unwrap();
    assert!((law.at_rest_rad_per_m - 3000.0).abs() < 1e-9 && (law.stroke_deg - 55.0).abs() < 1e-9);
    assert!((law.at_stroke_rad_per_m - 2600.0).abs() < 1e-6, "{law:?}");
    // report.json names each number with its unit.
    let json = serde_json::to_value(&a.report).unwrap();
    let row = &json["linkage"]["ratio_law"];
    assert_eq!(row["at_rest_rad_per_m"], 3000.0, "{row}");
    assert_eq!(row["stroke_deg"], law.stroke_deg, "{row}");
    assert_eq!(row["at_stroke_rad_per_m"], law.at_stroke_rad_per_m, "{row}");
    let k = a.system.linkage;
    let c = (3000.0 / 2600.0 - 1.0) / (3.0 * 55f64.to_radians().powi(2));
    for deg in [-40.0f64, 10.0, 30.0] {
        let t = deg.to_radians();
        let want = 3000.0 / (1.0 + 3.0 * c * t * t);
        assert!((k.ratio_at_angle(t) / want - 1.0).abs() < 1e-12, "{deg}");
    }
    assert!(a.report.table().contains("none drawn (a ratio law)"));
    let s = a.state.unwrap();
    let integrated = a.system.integrate(s.force, 155.0, 80).unwrap();
    assert!(
        (integrated / s.stroke_amplitude - 1.0).abs() < 0.02,
        "{integrated} vs {}",
        s.stroke_amplitude
    );
    // No linkage drawing can be made from a ratio alone: cut-sheet says so in one line and writes nothing.
    let err = cut_sheet_refusal(&dir.path().join("robobee-jafferis2016-derated.toml"), &path);
    assert!(
        err.contains("drive.toml: transmission.ratio_rad_per_m = 3000")
            && err.contains("no linkage drawing can be made from a ratio alone"),
        "{err}"
    );
}

/// `cut-sheet design --drive drive -o OUT`'s one-line refusal, having written nothing.
fn cut_sheet_refusal(design: &Path, drive: &Path) -> String {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let err = refused_in_one_line(&run(&[
        "cut-sheet",
        design.to_str().unwrap(),
        "--drive",
        drive.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]));
    assert!(!out.exists(), "{err}");
    err
}

#[test]
fn cut_sheet_refuses_a_two_stage_drive_in_one_line() {
    let err = cut_sheet_refusal(
        &example_path("robobee-jafferis2016-derated.toml"),
        &example_path("drive-robobee-jafferis2016-two-stage.toml"),
    );
    assert!(
        err.contains("drive-robobee-jafferis2016-two-stage.toml: transmission.four_bar")
            && err.contains("no layer files are drawn"),
        "{err}"
    );
}

/// `nest` of a batch of one item, the design beside `drive` with `drive` for its linkage: its one-line
/// refusal, having written nothing (no output folder, no file beside the batch).
fn nest_refusal(drive: &Path) -> String {
    let dir = drive.parent().unwrap();
    let batch = dir.join("batch.toml");
    std::fs::write(
        &batch,
        format!(
            "name = \"b\"\nseed = 1\n\n[[item]]\ndesign = \"robobee-jafferis2016-derated.toml\"\nquantity = 1\ndrive = {:?}\n\n[sheets]\nprepreg = {{ width_mm = 150, height_mm = 150 }}\nspacing_mm = 0.3\n",
            drive.file_name().unwrap().to_str().unwrap()
        ),
    )
    .unwrap();
    let listing = || {
        let mut names: Vec<_> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        names.sort();
        names
    };
    let before = listing();
    let out = dir.join("out");
    let err = refused_in_one_line(&run(&[
        "nest",
        batch.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]));
    assert!(!out.exists(), "{err}");
    assert_eq!(listing(), before, "{err}");
    err
}

/// docs/drive.md §2: no layer files are drawn of a two-stage linkage or of a ratio alone, so a batch
/// that asks nest to cut either is refused in one line naming the drive file and its field.
#[test]
fn nest_refuses_a_two_stage_or_ratio_only_drive_in_one_line() {
    let text =
        std::fs::read_to_string(example_path("drive-robobee-jafferis2016-two-stage.toml")).unwrap();
    let (_dir, two_stage) = with_transmission(&text[text.find("[transmission]").unwrap()..]);
    let err = nest_refusal(&two_stage);
    assert!(
        err.contains("drive.toml: transmission.four_bar = (given)")
            && err.contains("no layer files are drawn"),
        "{err}"
    );
    let (_dir, ratio) = with_transmission(&format!(
        "[transmission]\nratio_rad_per_m = 3000\nratio_at_stroke_deg = 55\nratio_at_stroke_rad_per_m = 2600\n{GIVEN}"
    ));
    let err = nest_refusal(&ratio);
    assert!(
        err.contains("drive.toml: transmission.ratio_rad_per_m = 3000")
            && err.contains("no linkage drawing can be made from a ratio alone"),
        "{err}"
    );
}

/// The example's `[transmission]` with `from` replaced by `to`, refused in one line naming `field`.
fn refused(from: &str, to: &str, field: &str, allowed: &str) {
    let text =
        std::fs::read_to_string(example_path("drive-robobee-jafferis2016-two-stage.toml")).unwrap();
    let transmission = &text[text.find("[transmission]").unwrap()..];
    assert!(transmission.contains(from), "{from}");
    let (_dir, path) = with_transmission(&transmission.replace(from, to));
    let err = refused_in_one_line(&run(&["drive", path.to_str().unwrap()]));
    let file = Path::new(&path).file_name().unwrap().to_str().unwrap();
    assert!(
        err.contains(file) && err.contains(field) && err.contains(allowed),
        "{field}: {err}"
    );
}

#[test]
fn bad_ratio_and_four_bar_keys_are_refused_in_one_line() {
    let lengths = "coupler_mm = 2.4\ncrank_mm = 0.6";
    // A ratio law's second point needs both keys; with coupler_ratio it is the slider-crank's own.
    refused(
        lengths,
        "ratio_rad_per_m = 3000\nratio_at_stroke_deg = 50",
        "transmission.ratio_at_stroke_rad_per_m",
        "with ratio_at_stroke_deg",
    );
    refused(
        lengths,
        "ratio_rad_per_m = 3000\ncoupler_ratio = 4\nratio_at_stroke_deg = 50\nratio_at_stroke_rad_per_m = 2800",
        "transmission.ratio_at_stroke_deg = (given)",
        "left out with coupler_ratio",
    );
    // A ratio rising to its dead point inside the stroke: 2000 rad/m at rest, 8000 at 30°, c = -0.91,
    // dead at 34.6°; the ±55° stroke needs the ratio at 30° below 2000 / (1 - (30/55)²) = 2847 rad/m.
    refused(
        lengths,
        "ratio_rad_per_m = 2000\nratio_at_stroke_deg = 30\nratio_at_stroke_rad_per_m = 8000",
        "transmission.ratio_at_stroke_rad_per_m = 8000",
        "below 2847.06 rad/m",
    );
    refused(
        lengths,
        "ratio_rad_per_m = 3000\nratio_at_stroke_deg = 95\nratio_at_stroke_rad_per_m = 2800",
        "transmission.ratio_at_stroke_deg = 95",
        "deg",
    );
    // The four-bar after a ratio alone, a gain that toggles it, a flexure it has no drawing for, a bad
    // length and a misspelt key.
    refused(
        lengths,
        "ratio_rad_per_m = 3000",
        "transmission.four_bar = (given)",
        "the ratio is the whole transmission's",
    );
    // A coupler as short as the input lets the rocker lean past 150° from it at +55° (152.4°).
    refused(
        "coupler_mm = 2.0",
        "coupler_mm = 1.0",
        "transmission.four_bar = input 1 mm, coupler 1 mm, output 0.5 mm",
        "transmission angle stays within 30° to 150° over the stroke from -55.0° to 55.0° (this one's runs from 42.0° to 152.4°)",
    );
    refused(
        GIVEN.trim_end(),
        "film_thickness_um = 7.6",
        "transmission.film_thickness_um = (given)",
        "no linkage drawing is made",
    );
    refused(
        "input_mm = 1.0",
        "input_mm = -1",
        "transmission.four_bar.input_mm = -1",
        "mm",
    );
    refused(
        "output_mm = 0.5",
        "ouput_mm = 0.5",
        "transmission.four_bar.ouput_mm",
        "output_mm",
    );
}

#[test]
fn through_the_two_stage_the_published_actuator_is_what_falls_short_of_the_published_stroke() {
    // docs/validation.md §4: the published RoboBee actuator, biased within the tool's limits, through
    // the example's 3333 rad/m two-stage reaches ±18.5° of ±55° at 155 Hz (original) and ±13.7°
    // (nonlinear), both bound by the biased signal's range (half the bias), with every flexure
    // buildable: the gap is the actuator's.
    use actuator_model::model::{ModelChoice, ModelKind};
    let path = example_path("drive-robobee-jafferis2016-two-stage.toml");
    let spec = actuator_cam::DriveSpec::load(&path).unwrap();
    let design = drive_design(&spec);
    for (kind, stroke) in [(ModelKind::Original, 18.53), (ModelKind::Nonlinear, 13.74)] {
        let r = actuator_cam::analyse_drive(&spec, &design, &ModelChoice::Kind(kind))
            .unwrap()
            .report;
        assert!(r.unbuildable_linkage.is_none(), "{kind:?}");
        let u = r.unreachable.as_ref().unwrap();
        assert!(
            (u.best_stroke_deg - stroke).abs() < 0.05,
            "{kind:?}: {}",
            u.best_stroke_deg
        );
        assert!(
            u.binding.starts_with("the bias of biased drive"),
            "{}",
            u.binding
        );
    }
}
