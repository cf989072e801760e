//! `actuator-cam optimize` driven as a user would: the built binary on the example specs.

use crate::common;
use actuator_model::performance::energy_and_mass;
use actuator_model::{
    model, Drive, DriveMode, Laminate, Material, ModelKind, Performance, Planform, Section,
};
use common::{bin, example_path as example, layer_file, run, stderr, stdout};
use rayon::prelude::*;
use std::path::Path;

/// The refined optimum's mass in mg, from the report's `refined:` line.
fn refined_mass(report: &str) -> f64 {
    let line = report.lines().find(|l| l.starts_with("refined:")).unwrap();
    let after = line.split("mass ").nth(1).unwrap();
    after.split(' ').next().unwrap().parse().unwrap()
}

/// A design.toml as the optimizer wrote it, read back into SI.
struct Written {
    length: f64,
    extension_ratio: f64,
    base_width: f64,
    width_ratio: f64,
    pzt_thickness: f64,
    layup: Vec<f64>,
    field: f64,
}

impl Written {
    /// The written design's section and its original-model prediction, through the model crate.
    fn predict(&self) -> (Section, Performance, Planform) {
        let (lam, _) = thesis_section(self.pzt_thickness, &self.layup);
        let drive = Drive {
            mode: DriveMode::Parallel,
            field: self.field,
        };
        let pl = Planform::new(
            self.length,
            self.extension_ratio,
            self.base_width,
            self.width_ratio,
            0.0,
        )
        .unwrap();
        let p = model::predict(ModelKind::Original, &lam, &pl, drive).unwrap();
        (Section::new(&lam, drive).unwrap(), p, pl)
    }
}

fn read_design(path: &Path) -> Written {
    let text = std::fs::read_to_string(path).unwrap();
    let v: toml::Value = toml::from_str(&text).unwrap();
    let num = |t: &str, k: &str| {
        let x = &v[t][k];
        x.as_float()
            .or_else(|| x.as_integer().map(|i| i as f64))
            .unwrap_or_else(|| panic!("{t}.{k} in {text}"))
    };
    assert_eq!(v["name"].as_str(), Some("optimized"));
    assert_eq!(v["quantity"].as_integer(), Some(1));
    assert_eq!(v["process"].as_str(), Some("method-2"));
    assert_eq!(v["laminate"]["pzt"].as_str(), Some("PZT-5H"));
    assert_eq!(v["laminate"]["ply"].as_str(), Some("CF-thesis"));
    assert_eq!(v["drive"]["mode"].as_str(), Some("parallel"));
    assert_eq!(num("geometry", "base_tab_mm"), 0.0);
    Written {
        length: num("geometry", "length_mm") * 1e-3,
        extension_ratio: num("geometry", "extension_ratio"),
        base_width: num("geometry", "base_width_mm") * 1e-3,
        width_ratio: num("geometry", "width_ratio"),
        pzt_thickness: num("laminate", "pzt_thickness_mm") * 1e-3,
        layup: v["laminate"]["layup_deg"]
            .as_array()
            .unwrap()
            .iter()
            .map(|a| a.as_float().or(a.as_integer().map(|i| i as f64)).unwrap())
            .collect(),
        field: num("drive", "field_V_per_mm") * 1e3,
    }
}

fn thesis_section(t_p: f64, layup: &[f64]) -> (Laminate, Section) {
    let pzt = Material::builtin("PZT-5H").unwrap();
    let cf = Material::builtin("CF-thesis").unwrap();
    let lam = Laminate::bimorph(&pzt, t_p, &cf, 61.8e-6, layup, None).unwrap();
    let s = Section::new(
        &lam,
        Drive {
            mode: DriveMode::Parallel,
            field: 800e3,
        },
    )
    .unwrap();
    (lam, s)
}

const LAYUPS: [&[f64]; 3] = [
    &[0.0, 90.0, 0.0],
    &[0.0, 0.0, 90.0, 0.0, 0.0],
    &[0.0, 0.0, 0.0, 90.0, 0.0, 0.0, 0.0],
];
const THICKNESSES: [f64; 3] = [127e-6, 191e-6, 267e-6];
const ENERGY: f64 = 0.059e-3;

fn linspace(lo: f64, hi: f64, n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| lo + (hi - lo) * i as f64 / (n - 1) as f64)
        .collect()
}

/// The lightest design of a 100-per-axis grid over the example spec's ranges, evaluated point by point
/// through the model crate (`energy_and_mass`), independent of the optimizer's code.
fn brute_force_lightest(n: usize) -> f64 {
    let lengths = linspace(40e-3, 60e-3, n);
    let widths = linspace(5e-3, 20e-3, n);
    let ext = linspace(0.0, 1.5, n);
    let ratios = linspace(1.0, 1.95, n);
    let mut sections = Vec::new();
    for &t_p in &THICKNESSES {
        for layup in LAYUPS {
            let (_, s) = thesis_section(t_p, layup);
            // The spec's strain and voltage limits do not bind at 800 V/mm for these laminates, so every
            // laminate runs at the requested field.
            assert!(s.peak_pzt_strain <= 0.0009 && s.voltage <= 300.0);
            sections.push(s);
        }
    }
    let tasks: Vec<(usize, usize)> = (0..sections.len())
        .flat_map(|c| (0..n).map(move |i| (c, i)))
        .collect();
    tasks
        .par_iter()
        .map(|&(c, i_r)| {
            let mut best = f64::INFINITY;
            for &w_r in &ratios {
                for &w0 in &widths {
                    if w0 * (2.0 - w_r) / w_r < 0.5e-3 {
                        continue;
                    }
                    for &l in &lengths {
                        let pl = Planform::new(l, ext[i_r], w0, w_r, 0.0).unwrap();
                        let (u, m) = energy_and_mass(&sections[c], &pl);
                        if u >= ENERGY {
                            best = best.min(m);
                            // Mass grows with length at fixed shape and width: the rest of the row is
                            // heavier.
                            break;
                        }
                    }
                }
            }
            best
        })
        .reduce(|| f64::INFINITY, f64::min)
}

#[test]
fn example_optimum_beats_an_independent_100_grid_and_meets_every_bound() {
    let dir = tempfile::tempdir().unwrap();
    let folder = dir.path().join("optimum");
    let o = run(&[
        "optimize",
        example("optimize-thesis.toml").to_str().unwrap(),
        "-o",
        folder.to_str().unwrap(),
    ]);
    let out = folder.join("design.toml");
    assert!(o.status.success(), "{}", stderr(&o));
    let d = read_design(&out);
    assert_eq!(d.field, 800e3);
    assert!(THICKNESSES
        .iter()
        .any(|t| (t / d.pzt_thickness - 1.0).abs() < 1e-12));
    let (_, p, pl) = d.predict();
    // Meets the energy within 1e-6 relative, from above.
    assert!(p.energy >= ENERGY * (1.0 - 1e-12), "U {}", p.energy);
    assert!((p.energy / ENERGY - 1.0) < 1e-6, "U {}", p.energy);
    // Every bound and constraint.
    assert!((40e-3..=60e-3).contains(&d.length));
    assert!((5e-3..=20e-3).contains(&d.base_width));
    assert!((0.0..=1.5).contains(&d.extension_ratio));
    assert!((1.0..=1.95).contains(&d.width_ratio));
    assert!(pl.tip_width() >= 0.5e-3 * (1.0 - 1e-9));
    assert!(p.peak_pzt_strain <= 0.0009);
    // No heavier than the best point of a 100-per-axis grid.
    let brute = brute_force_lightest(100);
    eprintln!(
        "refined optimum {:.3} mg; best of the independent 100-per-axis grid {:.3} mg",
        p.mass * 1e6,
        brute * 1e6
    );
    assert!(
        p.mass <= brute,
        "refined {} mg, 100-grid {} mg",
        p.mass * 1e6,
        brute * 1e6
    );
    // The report names the same design and mass.
    let text = stdout(&o);
    assert!(
        text.contains(&format!("mass {:.3} mg", p.mass * 1e6)),
        "{text}"
    );
    assert!(text.contains("binding constraints"));
}

#[test]
fn rectangular_optimum_matches_its_closed_form_and_the_tapered_one_is_lighter() {
    // Closed form (docs/physics.md §3, §4): a rectangle has U = 3 P² l w / (8 C44) and m = (μ_p + μ_c) l w,
    // so the lightest one with U >= U_min has l w = 8 C44 U_min / (3 P²), if that area is in the box,
    // and mass U_min (μ_p + μ_c) 8 C44 / (3 P²). Ties in (l, w) go to the shortest actuator.
    let o = run(&[
        "optimize",
        example("optimize-rectangular.toml").to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let rect = stdout(&o);
    let mut best: Option<(f64, f64, f64)> = None; // mass, length, width
    for &t_p in &THICKNESSES {
        for layup in LAYUPS {
            let (_, s) = thesis_section(t_p, layup);
            let per_area = 3.0 * s.free_curvature.powi(2) / (8.0 * s.bending_compliance);
            let area = ENERGY / per_area;
            let (l_lo, w_lo, w_hi) = (40e-3, 5e-3, 20e-3);
            let (mass, l, w) = if area <= l_lo * w_lo {
                // The smallest box still delivers more than needed.
                (
                    (s.pzt_areal_mass + s.passive_areal_mass) * l_lo * w_lo,
                    l_lo,
                    w_lo,
                )
            } else {
                let w = (area / l_lo).min(w_hi);
                (
                    (s.pzt_areal_mass + s.passive_areal_mass) * area,
                    area / w,
                    w,
                )
            };
            if best.is_none_or(|b| mass < b.0) {
                best = Some((mass, l, w));
            }
        }
    }
    let (mass, l, w) = best.unwrap();
    let line = rect.lines().find(|l| l.starts_with("refined:")).unwrap();
    assert!(
        line.contains(&format!("mass {:.3} mg", mass * 1e6)),
        "{line}"
    );
    assert!(line.contains(&format!("l_tot {:.4} mm", l * 1e3)), "{line}");
    assert!(line.contains(&format!("w_0 {:.4} mm", w * 1e3)), "{line}");
    assert!(line.contains("l_r 0.0000") && line.contains("w_r 1.0000"));

    let o = run(&[
        "optimize",
        example("optimize-thesis.toml").to_str().unwrap(),
    ]);
    let tapered = stdout(&o);
    // Taper and extension put the PZT where the strain energy is (G_U up to 4/3) and shed mass at the tip.
    assert!(refined_mass(&tapered) < refined_mass(&rect));
}

#[test]
fn output_is_deterministic_across_runs_and_thread_counts() {
    let spec = example("optimize-thesis.toml");
    let one = bin()
        .env("RAYON_NUM_THREADS", "1")
        .args(["optimize", spec.to_str().unwrap()])
        .output()
        .unwrap();
    let two = bin()
        .env("RAYON_NUM_THREADS", "2")
        .args(["optimize", spec.to_str().unwrap()])
        .output()
        .unwrap();
    let again = run(&["optimize", spec.to_str().unwrap()]);
    assert!(one.status.success());
    assert_eq!(one.stdout, two.stdout);
    assert_eq!(one.stdout, again.stdout);
}

#[test]
fn pareto_front_is_sorted_nondominated_and_agrees_with_the_optimum() {
    let dir = tempfile::tempdir().unwrap();
    let folder = dir.path().join("optimum");
    let o = run(&[
        "optimize",
        example("optimize-thesis.toml").to_str().unwrap(),
        "-o",
        folder.to_str().unwrap(),
        "--pareto",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let csv_path = folder.join("pareto.csv");
    let svg = std::fs::read_to_string(folder.join("pareto.svg")).unwrap();
    assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
    let mut r = csv::Reader::from_path(&csv_path).unwrap();
    assert_eq!(&r.headers().unwrap()[0], "energy_mJ");
    let rows: Vec<(f64, f64)> = r
        .records()
        .map(|rec| {
            let rec = rec.unwrap();
            (rec[0].parse().unwrap(), rec[1].parse().unwrap())
        })
        .collect();
    assert!(rows.len() >= 10, "{} front points", rows.len());
    for pair in rows.windows(2) {
        assert!(pair[0].0 < pair[1].0 && pair[0].1 < pair[1].1, "{pair:?}");
    }
    // The optimum is the lightest design with U >= 0.059 mJ: no front point delivering that is lighter.
    let optimum = refined_mass(&stdout(&o));
    for (e, m) in &rows {
        if *e >= 0.059 {
            assert!(
                *m >= optimum - 0.001,
                "front ({e} mJ, {m} mg) under {optimum} mg"
            );
        }
    }
}

#[test]
fn max_energy_density_objective_is_at_least_as_dense() {
    let spec = example("optimize-thesis.toml");
    let density = |objective: &str| -> f64 {
        let o = run(&["optimize", spec.to_str().unwrap(), "--objective", objective]);
        assert!(o.status.success(), "{}", stderr(&o));
        let text = stdout(&o);
        let line = text.lines().find(|l| l.contains("energy density")).unwrap();
        line.split_whitespace().nth(2).unwrap().parse().unwrap()
    };
    assert!(density("max-energy-density") >= density("min-mass") * (1.0 - 1e-9));
}

#[test]
fn thesis_adjusted_model_runs_and_euler_bernoulli_is_refused() {
    let spec = example("optimize-thesis.toml");
    let o = run(&[
        "optimize",
        spec.to_str().unwrap(),
        "--model",
        "thesis-adjusted",
    ]);
    // The adjusted fits cut δ and F_b to about a fifth; 0.059 mJ is still reachable in these ranges.
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o).contains("predicted by the thesis-adjusted model"));
    let o = run(&[
        "optimize",
        spec.to_str().unwrap(),
        "--model",
        "euler-bernoulli",
    ]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("rectangles only"), "{}", stderr(&o));
}

/// Run the optimizer on the example with one line replaced; it must fail cleanly with this message.
fn fails_with(from: &str, to: &str, expect: &[&str]) {
    let text = std::fs::read_to_string(example("optimize-thesis.toml")).unwrap();
    assert!(text.contains(from), "{from}");
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bad.toml");
    std::fs::write(&path, text.replacen(from, to, 1)).unwrap();
    let o = run(&["optimize", path.to_str().unwrap()]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{to}: {err}");
    assert!(!err.contains("panicked"), "{err}");
    assert!(err.contains("bad.toml"), "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "one line: {err}");
    for e in expect {
        assert!(err.contains(e), "{to}: expected {e:?} in {err}");
    }
}

#[test]
fn bad_input_fails_with_a_clear_message() {
    fails_with(
        "length_mm = [40, 60]",
        "length_mm = [60, 40]",
        &["search.length_mm", "[60, 40]", "inverted"],
    );
    fails_with(
        "base_width_mm = [5, 20]",
        "base_width_mm = []",
        &["search.base_width_mm", "empty"],
    );
    fails_with("grid = 70", "grid = 1", &["search.grid = 1", "[2, 500]"]);
    fails_with(
        "ply = \"CF-thesis\"",
        "ply = \"CF-unknown\"",
        &[
            "laminate.ply",
            "CF-unknown",
            "unknown material",
            "CF-thesis",
        ],
    );
    fails_with(
        "energy_mJ = 0.059",
        "energy_mJ = 50",
        &[
            "requirement.energy_mJ = 50",
            "infeasible",
            "most energy reachable",
        ],
    );
    fails_with("[search]", "[serach]", &["serach"]);
    fails_with(
        "pzt_thickness_mm = [0.127, 0.191, 0.267]",
        "pzt_thickness_mm = [0.127, -0.191]",
        &[
            "search.pzt_thickness_mm[1] = -0.191",
            "outside the allowed range [0.05, 2] mm",
        ],
    );
    // serde's own wording ("expected i64", "did not match any variant of untagged enum") never shows:
    // the message names the field, the value as written and what is allowed.
    fails_with(
        "grid = 70",
        "grid = 8.5",
        &["bad.toml: search.grid = 8.5: expected a whole number in [2, 500]"],
    );
    fails_with(
        "base_width_mm = [5, 20]",
        "base_width_mm = \"5-20\"",
        &["bad.toml: search.base_width_mm = \"5-20\": expected a number or [min, max], each in the allowed range [0.5, 1000] mm"],
    );
    // The search ranges are checked against the design file's ranges.
    fails_with(
        "length_mm = [40, 60]",
        "length_mm = [40, 1600]",
        &["search.length_mm[1] = 1600: outside the allowed range [1, 1000] mm"],
    );
    let o = run(&["optimize", "/nonexistent/spec.toml"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("/nonexistent/spec.toml"));
}

#[test]
fn infeasible_message_names_the_most_energy_in_the_ranges() {
    // The most energetic design in the box cannot be beaten by any grid point: check the printed maximum
    // against a coarse independent grid (it must be at least that).
    let text = std::fs::read_to_string(example("optimize-thesis.toml")).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("too-much.toml");
    std::fs::write(
        &path,
        text.replacen("energy_mJ = 0.059", "energy_mJ = 50", 1),
    )
    .unwrap();
    let o = run(&["optimize", path.to_str().unwrap()]);
    let err = stderr(&o);
    let most: f64 = err
        .split("reachable in the search ranges is ")
        .nth(1)
        .unwrap()
        .split(' ')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    let mut coarse: f64 = 0.0;
    for &t_p in &THICKNESSES {
        for layup in LAYUPS {
            let (_, s) = thesis_section(t_p, layup);
            for w0 in linspace(5e-3, 20e-3, 16) {
                for l_r in linspace(0.0, 1.5, 16) {
                    for w_r in linspace(1.0, 1.95, 20) {
                        if w0 * (2.0 - w_r) / w_r < 0.5e-3 {
                            continue;
                        }
                        let pl = Planform::new(60e-3, l_r, w0, w_r, 0.0).unwrap();
                        coarse = coarse.max(energy_and_mass(&s, &pl).0);
                    }
                }
            }
        }
    }
    assert!(
        most >= coarse * 1e3 * (1.0 - 1e-6),
        "{most} < {}",
        coarse * 1e3
    );
    assert!(most < coarse * 1e3 * 1.05, "{most} vs {}", coarse * 1e3);
}

#[test]
fn voltage_and_strain_limits_cap_the_field_and_are_reported() {
    // 150 V caps the field of the 0.191 mm and 0.267 mm plates (800 V/mm needs 153 V and 214 V).
    let text = std::fs::read_to_string(example("optimize-thesis.toml")).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let spec = dir.path().join("capped.toml");
    let folder = dir.path().join("optimum");
    let out = folder.join("design.toml");
    std::fs::write(
        &spec,
        text.replacen("max_voltage_V = 300", "max_voltage_V = 150", 1)
            .replacen(
                "max_peak_pzt_strain = 0.0009",
                "max_peak_pzt_strain = 0.0003",
                1,
            ),
    )
    .unwrap();
    let o = run(&[
        "optimize",
        spec.to_str().unwrap(),
        "-o",
        folder.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let d = read_design(&out);
    let (section, p, _) = d.predict();
    assert!(
        section.voltage <= 150.0 * (1.0 + 1e-12),
        "{} V",
        section.voltage
    );
    assert!(section.peak_pzt_strain <= 0.0003 * (1.0 + 1e-12));
    assert!(d.field <= 800e3);
    assert!(p.energy >= ENERGY * (1.0 - 1e-12));
    let report = stdout(&o);
    if d.field < 800e3 {
        assert!(
            report.contains("field capped at"),
            "a capped optimum must say so: {report}"
        );
    }
    // The per-laminate table shows the capped fields: 150 V / 0.267 mm = 561.8 V/mm.
    assert!(report.contains("561.8"), "{report}");
}

/// A calibrated model with every effect on, including the two (dead length, clamp compliance) that make
/// the energy non-linear in `l_tot`, as `calibrate` writes it.
const CALIBRATED: &str = r#"model = "calibrated"
verdict = "explained"
selected_effects = ["d31-scale", "dead-length", "clamp-compliance", "ply-thickness"]

[effects]
d31_scale = 0.8
d31_field_coefficient_m_per_V = 0.0
dead_length_m = 0.002
bond_thickness_m = 0.0
extension_flexibility = 0.0
clamp_compliance_rad_per_N_m = 0.4
ply_thickness_scale = 1.25
stiffness_scale = 1.0
"#;

#[test]
fn calibrated_model_file_optimum_meets_the_energy_and_beats_an_independent_grid() {
    let dir = tempfile::tempdir().unwrap();
    let model_file = dir.path().join("calibrated-model.toml");
    std::fs::write(&model_file, CALIBRATED).unwrap();
    let folder = dir.path().join("optimum");
    let best = folder.join("design.toml");
    let spec = example("optimize-thesis.toml");
    let o = run(&[
        "optimize",
        spec.to_str().unwrap(),
        "--model",
        model_file.to_str().unwrap(),
        "-o",
        folder.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let report = stdout(&o);
    assert!(report.contains("calibrated"), "{report}");
    let mass_mg = refined_mass(&report);

    // The written design through the model crate's calibrated path (it rebuilds the stack per actuator).
    let calibrated: actuator_model::CalibratedModel = toml::from_str(CALIBRATED).unwrap();
    let pzt = Material::builtin("PZT-5H").unwrap();
    let cf = Material::builtin("CF-thesis").unwrap();
    let predict = |t_p: f64, layup: &[f64], pl: Planform| {
        calibrated
            .predict(&actuator_model::Actuator {
                pzt: &pzt,
                pzt_thickness: t_p,
                ply: &cf,
                ply_thickness: 61.8e-6,
                layup_deg: layup,
                planform: pl,
                drive: Drive {
                    mode: DriveMode::Parallel,
                    field: 800e3,
                },
            })
            .unwrap()
    };
    let w = read_design(&best);
    let pl = Planform::new(
        w.length,
        w.extension_ratio,
        w.base_width,
        w.width_ratio,
        0.0,
    )
    .unwrap();
    let p = predict(w.pzt_thickness, &w.layup, pl);
    assert!(p.energy >= ENERGY * (1.0 - 1e-9), "{} J", p.energy);
    assert!(p.energy <= ENERGY * (1.0 + 1e-6), "{} J", p.energy);
    assert!(
        (p.mass * 1e6 - mass_mg).abs() < 1e-3,
        "{} vs {mass_mg}",
        p.mass * 1e6
    );
    assert!(pl.tip_width() >= 0.5e-3 * (1.0 - 1e-9));
    assert!((40e-3..=60e-3 + 1e-12).contains(&w.length));

    // An independent 14-per-axis grid, every point predicted through the calibrated model.
    let n = 14;
    let (lengths, widths) = (linspace(40e-3, 60e-3, n), linspace(5e-3, 20e-3, n));
    let (ext, ratios) = (linspace(0.0, 1.5, n), linspace(1.0, 1.95, n));
    let mut tasks: Vec<(f64, &[f64], f64)> = Vec::new();
    for &t in &THICKNESSES {
        for layup in LAYUPS {
            tasks.extend(ext.iter().map(|&r| (t, layup, r)));
        }
    }
    let grid_best = tasks
        .par_iter()
        .map(|&(t_p, layup, l_r)| {
            let mut best = f64::INFINITY;
            for &w_r in &ratios {
                for &w0 in &widths {
                    for &l in &lengths {
                        let pl = Planform::new(l, l_r, w0, w_r, 0.0).unwrap();
                        if pl.tip_width() < 0.5e-3 {
                            continue;
                        }
                        let q = predict(t_p, layup, pl);
                        if q.energy >= ENERGY {
                            best = best.min(q.mass);
                        }
                    }
                }
            }
            best
        })
        .reduce(|| f64::INFINITY, f64::min);
    assert!(grid_best.is_finite());
    assert!(
        mass_mg <= grid_best * 1e6 * (1.0 + 1e-9),
        "refined {mass_mg} mg vs grid {} mg",
        grid_best * 1e6
    );
    // The written design goes straight to cut-sheet with the same model, which predicts the same mass.
    let out = dir.path().join("cut");
    let c = run(&[
        "cut-sheet",
        best.to_str().unwrap(),
        "--model",
        model_file.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(c.status.success(), "{}", stderr(&c));
    let r: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("report.json")).unwrap()).unwrap();
    // Less the ground tab cut-sheet adds to a design without a tab, and states with its mass.
    let predicted = r["predicted"]["mass_mg"].as_f64().unwrap()
        - r["ground_tab"]["mass_mg"].as_f64().unwrap_or(0.0);
    assert!(
        (predicted - mass_mg).abs() < 1e-3,
        "{predicted} vs {mass_mg}"
    );
    assert!(layer_file(&out, "pzt-1.svg").exists());
    // The calibrated actuator is weaker than the original one predicts, so the optimum is heavier.
    let original = run(&["optimize", spec.to_str().unwrap()]);
    assert!(mass_mg > refined_mass(&stdout(&original)) * 1.1);
}

/// The example spec narrowed to one laminate, 0.267 mm PZT on [0/90/0], and to tapers past the
/// uniform-strain ridge (l_r 1 to 1.5, w_r 1.7 to 1.95, against a ridge at 4/3 and below), with a strain
/// limit.
fn past_the_ridge(dir: &Path, limit: &str) -> std::path::PathBuf {
    let text = std::fs::read_to_string(example("optimize-thesis.toml"))
        .unwrap()
        .replacen("[0.127, 0.191, 0.267]", "[0.267]", 1)
        .replacen(
            "[[0, 90, 0], [0, 0, 90, 0, 0], [0, 0, 0, 90, 0, 0, 0]]",
            "[[0, 90, 0]]",
            1,
        )
        .replacen(
            "extension_ratio = [0, 1.5]",
            "extension_ratio = [1, 1.5]",
            1,
        )
        .replacen("width_ratio = [1, 1.95]", "width_ratio = [1.7, 1.95]", 1)
        .replacen(
            "max_peak_pzt_strain = 0.0009",
            &format!("max_peak_pzt_strain = {limit}"),
            1,
        );
    let spec = dir.join(format!("past-{limit}.toml"));
    std::fs::write(&spec, text).unwrap();
    spec
}

#[test]
fn the_strain_limit_holds_along_the_plate_from_free_to_blocked() {
    // Source: docs/physics.md eqs. 6.1-6.3: past the ridge the blocked moment per width is largest at the
    // plate's outer end, where this laminate's strain exceeds its free 328 µm/m. Unconstrained, the optimum
    // strains its plate end more than its free deflection; a limit between the two leaves no shape in
    // these ranges, and the refusal names the limit.
    let dir = tempfile::tempdir().unwrap();
    let folder = dir.path().join("optimum");
    let o = run(&[
        "optimize",
        past_the_ridge(dir.path(), "0.01").to_str().unwrap(),
        "-o",
        folder.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let (section, p, _) = read_design(&folder.join("design.toml")).predict();
    assert!(p.peak_pzt_strain > 1.05 * section.peak_pzt_strain);
    assert_eq!(p.peak_pzt_strain_at, 1.0);
    assert!(stdout(&o).contains(&format!(
        "peak PZT strain  {:.6} at x/l_p 1.00",
        p.peak_pzt_strain
    )));
    // A limit above the optimum's own peak keeps it.
    let above = format!("{:.6}", p.peak_pzt_strain + 1e-6);
    let kept = run(&[
        "optimize",
        past_the_ridge(dir.path(), &above).to_str().unwrap(),
    ]);
    assert!(kept.status.success(), "{}", stderr(&kept));
    assert_eq!(refined_mass(&stdout(&kept)), refined_mass(&stdout(&o)));
    // Between the free strain and every shape's plate end: refused in one line naming the limit.
    let refused = run(&[
        "optimize",
        past_the_ridge(dir.path(), "0.00034").to_str().unwrap(),
    ]);
    assert!(!refused.status.success());
    let err = stderr(&refused);
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(
        err.contains("strains its plate past constraints.max_peak_pzt_strain"),
        "{err}"
    );
}
