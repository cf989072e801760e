//! `actuator-cam drive`: both examples reach their stroke at the reported voltage (re-checked by a time
//! integration), a tiny actuator on the hawk-moth wing is out of reach and says what binds, bad input is
//! one line, the output is the same bytes twice, and `-o` goes through the writer.

mod common;

use actuator_cam::drive::spec::DriveSpec;
use common::{
    drive_analysis, example_path, files, refused_in_one_line, run, run_ok, stdout, write_temp,
};

#[test]
fn both_examples_reach_the_stroke_and_the_time_integration_agrees() {
    for name in ["drive-hawkmoth.toml", "drive-robobee.toml"] {
        let path = example_path(name);
        let spec = DriveSpec::load(&path).unwrap();
        let a = drive_analysis(&path);
        let r = &a.report;
        assert!(r.reached, "{name}: {}", r.table());
        let s = a.state.unwrap();
        assert!(
            (s.stroke_amplitude - spec.transmission.stroke).abs() < 1e-6,
            "{name}"
        );
        // The force the report's voltage gives (the design's mode, linear in the field) drives the
        // same system from rest for 80 periods: the stroke within 2 % of the required one.
        let o = r.operating.as_ref().unwrap();
        let force =
            o.field_V_per_mm * 1e3 * r.actuator.blocked_force_per_field_mN_per_V_per_mm * 1e-6;
        assert!(
            (force / s.force - 1.0).abs() < 1e-9,
            "{force} vs {}",
            s.force
        );
        let integrated = a.system.integrate(force, spec.frequency, 80).unwrap();
        let rel = integrated / spec.transmission.stroke - 1.0;
        // The issue asks for 2 %; the balance's three harmonics put both examples within 0.1 %.
        let tolerance = 0.02;
        assert!(
            rel.abs() < tolerance,
            "{name}: time integration {:.2}° vs ±{:.2}°",
            integrated.to_degrees(),
            spec.transmission.stroke.to_degrees()
        );
        // The field is within the limit, and the voltage is the mode's V(E).
        assert!(o.field_V_per_mm <= r.field_limit_V_per_mm);
        assert_eq!(r.modes.len(), 4);
        // The sweep passes through the operating point's neighbourhood: the sweep point nearest the
        // flapping frequency has a stroke within 10 % of the required one.
        let near = r
            .sweep
            .iter()
            .min_by(|p, q| {
                (p.frequency_Hz - r.frequency_Hz)
                    .abs()
                    .total_cmp(&(q.frequency_Hz - r.frequency_Hz).abs())
            })
            .unwrap();
        assert!(
            (near.stroke_deg / r.required_stroke_deg - 1.0).abs() < 0.1,
            "{name}: {near:?}"
        );
    }
}

#[test]
fn a_tiny_actuator_cannot_flap_the_hawk_moth_wing_and_says_why() {
    let dir = tempfile::tempdir().unwrap();
    let design = std::fs::read_to_string(example_path("thesis-C.toml"))
        .unwrap()
        .replace("length_mm = 42.2", "length_mm = 10")
        .replace("base_width_mm = 5", "base_width_mm = 1.5");
    std::fs::write(dir.path().join("tiny.toml"), design).unwrap();
    let drive = std::fs::read_to_string(example_path("drive-hawkmoth.toml"))
        .unwrap()
        .replace("design = \"thesis-7.toml\"", "design = \"tiny.toml\"");
    let path = dir.path().join("drive.toml");
    std::fs::write(&path, drive).unwrap();
    let a = drive_analysis(&path);
    let r = &a.report;
    assert!(!r.reached);
    let u = r.unreachable.as_ref().unwrap();
    assert!(u.best_stroke_deg < r.required_stroke_deg, "{u:?}");
    assert!(u.binding.contains("field limit"), "{u:?}");
    // The best stroke is at the limit field.
    let o = r.operating.as_ref().unwrap();
    assert!(
        (o.field_V_per_mm / r.field_limit_V_per_mm - 1.0).abs() < 1e-6,
        "{o:?}"
    );
    // The command prints the report, then fails with one line naming the file, the stroke and what
    // binds.
    let o = run(&["drive", path.to_str().unwrap()]);
    let out = stdout(&o);
    assert!(
        out.contains("NOT REACHED") && out.contains("binding: the field limit"),
        "{out}"
    );
    let err = refused_in_one_line(&o);
    assert!(
        err.contains("drive.toml: stroke_deg = 60: not reached at 25 Hz")
            && err.contains("binding: the field limit"),
        "{err}"
    );
    // With -o the report is written in full, as the explanation of the failure.
    let folder = dir.path().join("out");
    let o = run(&[
        "drive",
        path.to_str().unwrap(),
        "-o",
        folder.to_str().unwrap(),
    ]);
    assert!(!o.status.success());
    assert!(files(&folder).contains_key("report.md"));
}

#[test]
fn bad_drive_files_are_refused_in_one_line_naming_the_field() {
    let text = std::fs::read_to_string(example_path("drive-hawkmoth.toml")).unwrap();
    for (from, to, field) in [
        ("frequency_Hz = 25", "frequency_Hz = -3", "frequency_Hz"),
        ("stroke_deg = 60", "stroke_deg = 95", "stroke_deg"),
        ("chord_mm = 23", "chord_mm = 1e300", "wing.chord_mm"),
        (
            "drag_coefficient = 1.3",
            "drag_coefficient = 1.3\ncolour = 1",
            "wing.colour",
        ),
        (
            "coupler_ratio = 4",
            "coupler_ratio = 4\ncrank_mm = 1",
            "transmission",
        ),
    ] {
        assert!(text.contains(from), "{from}");
        let (dir, path) = write_temp("drive.toml", &text.replace(from, to));
        std::fs::copy(
            example_path("thesis-7.toml"),
            dir.path().join("thesis-7.toml"),
        )
        .unwrap();
        let err = refused_in_one_line(&run(&["drive", path.to_str().unwrap()]));
        assert!(
            err.contains("drive.toml") && err.contains(field),
            "{field}: {err}"
        );
    }
}

#[test]
fn the_same_bytes_twice_and_minus_o_through_the_writer() {
    let drive = example_path("drive-robobee.toml");
    let d = drive.to_str().unwrap();
    let one = run_ok(&["drive", d, "--json"]).stdout;
    let two = run_ok(&["drive", d, "--json"]).stdout;
    assert_eq!(one, two);
    let json: serde_json::Value = serde_json::from_slice(&one).unwrap();
    assert_eq!(json["reached"], true);
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    run_ok(&["drive", d, "-o", out.to_str().unwrap()]);
    let written = files(&out);
    for name in ["report.md", "report.json", "frequency-response.svg"] {
        assert!(written.contains_key(name), "{name}: {:?}", written.keys());
    }
    // The writer's manifest is there, and a second run replaces its own files.
    assert!(
        written.keys().any(|k| k.contains("manifest")),
        "{:?}",
        written.keys()
    );
    run_ok(&["drive", d, "-o", out.to_str().unwrap()]);
    assert_eq!(files(&out), written);
    // A folder holding someone else's file is refused.
    let other = dir.path().join("other");
    std::fs::create_dir(&other).unwrap();
    std::fs::write(other.join("notes.txt"), "mine").unwrap();
    let o = run(&["drive", d, "-o", other.to_str().unwrap()]);
    assert!(!o.status.success());
    let svg = String::from_utf8(written["frequency-response.svg"].clone()).unwrap();
    assert!(svg.starts_with("<svg") && svg.contains("polyline") && !svg.contains("NaN"));
}
