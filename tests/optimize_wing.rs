//! `actuator-cam optimize` for a wing (`requirement.flap`): the chosen design, driven by `drive` from
//! the files optimize writes, reaches the stroke within the field limit, and a time integration at that
//! voltage agrees; a narrower base width or another crank does not reach it; the output is the same
//! bytes twice; what the optimizer cannot take is refused in one line.

use crate::common;

use common::{drive_analysis, example_path, refused_in_one_line, run, run_ok, stdout};
use std::path::PathBuf;

/// A smaller search than the example's (two laminates, grid 12) so the test is quick; the wing is the
/// hawk moth's of examples/drive-hawkmoth.toml.
const SPEC: &str = r#"
[requirement]
flap = "drive-hawkmoth.toml"
[drive]
mode = "biased"
bias_V_per_mm = 650
field_V_per_mm = 325
[search]
length_mm = [40, 80]
base_width_mm = [2, 40]
extension_ratio = [0, 1.5]
width_ratio = [1, 1.95]
pzt_thickness_mm = [0.191, 0.267]
layups_deg = [[0, 90, 0]]
grid = 12
[laminate]
pzt = "PZT-5H"
ply = "CF-thesis"
[constraints]
min_tip_width_mm = 0.5
max_peak_pzt_strain = 0.0009
"#;

/// A folder with the spec, the drive file and its design.
fn folder(spec: &str) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    for name in ["drive-hawkmoth.toml", "thesis-7.toml"] {
        std::fs::copy(example_path(name), dir.path().join(name)).unwrap();
    }
    let path = dir.path().join("wing.toml");
    std::fs::write(&path, spec).unwrap();
    (dir, path)
}

/// A TOML text with the number of `key = …` (at a line's start) multiplied by `factor`.
fn scaled(text: &str, key: &str, factor: f64) -> String {
    let line = text
        .lines()
        .find(|l| l.starts_with(&format!("{key} =")))
        .unwrap();
    let value: f64 = line.split('=').nth(1).unwrap().trim().parse().unwrap();
    text.replace(line, &format!("{key} = {}", value * factor))
}

#[test]
fn the_chosen_design_flaps_the_wing_at_the_voltage_optimize_reports() {
    let (dir, spec) = folder(SPEC);
    let folder = dir.path().join("optimum");
    let out = stdout(&run_ok(&[
        "optimize",
        spec.to_str().unwrap(),
        "-o",
        folder.to_str().unwrap(),
    ]));
    let best = folder.join("design.toml");
    let drive = folder.join("drive.toml");
    assert!(best.is_file() && drive.is_file(), "{out}");
    // `drive` on the written files: reached, within the limit, the voltage optimize printed.
    let a = drive_analysis(&drive);
    let r = &a.report;
    assert!(r.reached, "{}", r.table());
    let o = r.operating.as_ref().unwrap();
    assert!(o.field_V_per_mm <= r.field_limit_V_per_mm);
    assert!((o.field_V_per_mm / 325.0 - 1.0).abs() < 1e-3, "{o:?}");
    assert!(
        out.contains(&format!("at {:.1} V biased", o.voltage_V)),
        "{out}"
    );
    // The time integration of the same system at that voltage: the stroke within 2 %.
    let force = o.field_V_per_mm * 1e3 * r.actuator.blocked_force_per_field_mN_per_V_per_mm * 1e-6;
    let integrated = a.system.integrate(force, r.frequency_Hz, 80).unwrap();
    assert!(
        (integrated.to_degrees() / r.required_stroke_deg - 1.0).abs() < 0.02,
        "{}",
        integrated.to_degrees()
    );
    // The lightest width: 1 % narrower, the same crank, no longer reaches the stroke.
    let text = std::fs::read_to_string(&best).unwrap();
    std::fs::write(&best, scaled(&text, "base_width_mm", 0.99)).unwrap();
    assert!(!drive_analysis(&drive).report.reached);
    std::fs::write(&best, &text).unwrap();
    // The best crank: a linkage sized for 0.8 or 1.25 times the travel needs more than the limit.
    let drive_text = std::fs::read_to_string(&drive).unwrap();
    for factor in [0.8, 1.25] {
        std::fs::write(&drive, scaled(&drive_text, "travel_mm", factor)).unwrap();
        assert!(!drive_analysis(&drive).report.reached, "travel x{factor}");
    }
}

/// The limits `drive` holds a design to (docs/physics.md §2.1), in every mode: each optimum `optimize`
/// writes is driven from its own files and reached, within the failure fit and the depolarization field,
/// and within the small-deflection range. Parallel and series at 800 V/mm are held down to PZT-5H's
/// 300 V/mm depolarization field (thesis Table 2.1), and the report says so.
#[test]
fn drive_accepts_every_optimum_in_every_mode() {
    for (drive, capped) in [
        (
            "mode = \"parallel\"\nfield_V_per_mm = 800",
            Some("depolarization"),
        ),
        (
            "mode = \"series\"\nfield_V_per_mm = 800",
            Some("depolarization"),
        ),
        ("mode = \"alternating\"\nsurvival = 0.9", None),
        ("mode = \"simultaneous\"\nsurvival = 0.95", None),
        (
            "mode = \"biased\"\nbias_V_per_mm = 650\nfield_V_per_mm = 325",
            None,
        ),
    ] {
        let spec = SPEC.replace(
            "mode = \"biased\"\nbias_V_per_mm = 650\nfield_V_per_mm = 325",
            drive,
        );
        let (dir, path) = folder(&spec);
        let out = stdout(&run_ok(&[
            "optimize",
            path.to_str().unwrap(),
            "-o",
            dir.path().join("optimum").to_str().unwrap(),
        ]));
        let r = drive_analysis(&dir.path().join("optimum/drive.toml")).report;
        assert!(r.reached, "{drive}: {}", r.table());
        let o = r.operating.as_ref().unwrap();
        assert!(o.poling.within_limit, "{drive}: {o:?}");
        assert!(o.poling.failure_margin_V_per_mm >= -1e-6, "{drive}: {o:?}");
        assert!(
            o.poling.depolarization_margin_V_per_mm >= -1e-6,
            "{drive}: {o:?}"
        );
        assert!(r.past_small_deflection.is_none(), "{drive}");
        assert!(o.peak_pzt_strain <= 0.0009, "{drive}: {o:?}");
        if let Some(limit) = capped {
            assert!(
                out.contains(&format!("{limit} binds")) && (o.field_V_per_mm - 300.0).abs() < 0.5,
                "{drive}: {out}"
            );
        }
    }
}

#[test]
fn the_same_bytes_twice_with_the_front() {
    let (dir, spec) = folder(SPEC);
    let s = spec.to_str().unwrap();
    let folder = dir.path().join("optimum");
    let o = folder.to_str().unwrap();
    let csv = folder.join("pareto.csv");
    let one = run_ok(&["optimize", s, "-o", o, "--pareto"]).stdout;
    let front = std::fs::read(&csv).unwrap();
    // The second run replaces the files the first wrote (the folder's manifest says it wrote them).
    let two = run_ok(&["optimize", s, "-o", o, "--pareto"]).stdout;
    assert_eq!(one, two);
    assert_eq!(std::fs::read(&csv).unwrap(), front);
    let text = String::from_utf8(front).unwrap();
    assert!(
        text.starts_with("margin_percent,actuator_mass_mg,"),
        "{text}"
    );
    // Mass does not fall as the margin rises.
    let masses: Vec<f64> = text
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(1).unwrap().parse().unwrap())
        .collect();
    assert!(!masses.is_empty() && masses.windows(2).all(|w| w[1] >= w[0]));
}

/// The front is a trade, not one point: the designs that just meet the energy at their best crank all
/// sit near one margin, and a higher margin is bought with a stiffer crank and more energy, so more mass
/// (docs/physics.md §17.4).
#[test]
fn the_front_trades_mass_for_margin() {
    // Wide enough in w_0 for the stiff cranks of the high margins.
    let (dir, spec) = folder(&SPEC.replace("base_width_mm = [2, 40]", "base_width_mm = [2, 100]"));
    let folder = dir.path().join("optimum");
    run_ok(&[
        "optimize",
        spec.to_str().unwrap(),
        "-o",
        folder.to_str().unwrap(),
        "--pareto",
    ]);
    let csv = folder.join("pareto.csv");
    let text = std::fs::read_to_string(&csv).unwrap();
    let rows: Vec<(f64, f64)> = text
        .lines()
        .skip(1)
        .map(|l| {
            let mut cells = l.split(',');
            let margin = cells.next().unwrap().parse().unwrap();
            (margin, cells.next().unwrap().parse().unwrap())
        })
        .collect();
    assert!(rows.len() >= 5, "{text}");
    assert!(
        rows.windows(2).all(|w| w[1].0 > w[0].0 && w[1].1 >= w[0].1),
        "{text}"
    );
    let (first, last) = (rows[0], rows[rows.len() - 1]);
    assert!(last.0 - first.0 >= 50.0, "margins {first:?} to {last:?}");
    assert!(last.1 > 1.1 * first.1, "masses {first:?} to {last:?}");
}

#[test]
fn what_the_wing_optimizer_cannot_take_is_refused_in_one_line() {
    // Another model, another objective, both requirements, a missing drive file, a linkage of given
    // lengths.
    let (dir, spec) = folder(SPEC);
    let s = spec.to_str().unwrap();
    let err = refused_in_one_line(&run(&["optimize", s, "--model", "thesis-adjusted"]));
    assert!(err.contains("--model original"), "{err}");
    let err = refused_in_one_line(&run(&["optimize", s, "--objective", "max-energy-density"]));
    assert!(
        err.contains("requirement.flap") && err.contains("min-mass"),
        "{err}"
    );
    for (from, to, expect) in [
        (
            "flap = \"drive-hawkmoth.toml\"",
            "flap = \"drive-hawkmoth.toml\"\nenergy_mJ = 1",
            "not both",
        ),
        (
            "flap = \"drive-hawkmoth.toml\"",
            "flap = \"nowhere.toml\"",
            "expected an existing drive file",
        ),
    ] {
        std::fs::write(&spec, SPEC.replace(from, to)).unwrap();
        let err = refused_in_one_line(&run(&["optimize", s]));
        assert!(
            err.contains("wing.toml: requirement.flap") && err.contains(expect),
            "{err}"
        );
    }
    std::fs::write(&spec, SPEC).unwrap();
    let drive = dir.path().join("drive-hawkmoth.toml");
    let text = std::fs::read_to_string(&drive).unwrap();
    std::fs::write(
        &drive,
        text.replace("solve_for_stroke = true", "coupler_mm = 4\ncrank_mm = 1")
            .replace("coupler_ratio = 4\n", "")
            .replace("travel_mm = 0.85\n", ""),
    )
    .unwrap();
    let err = refused_in_one_line(&run(&["optimize", s]));
    assert!(
        err.contains("drive-hawkmoth.toml: transmission") && err.contains("optimize chooses"),
        "{err}"
    );
}

/// An optimum on a bound of the search says so: the hawk-moth wing wants a longer actuator than 50 mm
/// (the widened search's optimum is 80 mm long), so with lengths up to 50 mm the optimum is at 50 mm.
#[test]
fn an_optimum_on_a_search_bound_says_so() {
    let (dir, spec) = folder(&SPEC.replace("length_mm = [40, 80]", "length_mm = [40, 50]"));
    let out = stdout(&run_ok(&[
        "optimize",
        spec.to_str().unwrap(),
        "-o",
        dir.path().join("optimum").to_str().unwrap(),
    ]));
    assert!(
        out.contains("on the search's bounds: total length at its upper bound 50 mm"),
        "{out}"
    );
    let design = std::fs::read_to_string(dir.path().join("optimum/design.toml")).unwrap();
    assert!(design.contains("length_mm = 50"), "{design}");
}
