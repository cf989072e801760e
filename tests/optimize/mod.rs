//! `actuator-cam optimize` driven as a user would: the built binary on the example specs.

mod optimum;
mod runs;

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
        let drive = Drive::new(DriveMode::Parallel, self.field);
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
    let s = Section::new(&lam, Drive::new(DriveMode::Parallel, 800e3)).unwrap();
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
