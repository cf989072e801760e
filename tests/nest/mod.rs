//! `actuator-cam nest` on batch files: the example batch checked sheet by sheet with geometry rebuilt
//! from the design files (independent of the planner), determinism, random batches, and bad input.

mod budget;
mod edge_gap;
mod sheets;
mod stock;

use crate::common;
use common::*;
use geo::{Distance, Euclidean};
use rand::{Rng, SeedableRng};
use std::collections::BTreeMap;
use std::path::Path;

/// Method-2 template values the checks use (templates/method-2.toml).
const PZT_KERF_MM: f64 = 0.03;

const PZT_EDGE_MARGIN_MM: f64 = 0.3;

const PREPREG_KERF_MM: f64 = 0.05;

fn nest(batch: &Path, out: &Path, extra: &[&str]) -> std::process::Output {
    let mut args = vec!["nest", batch.to_str().unwrap(), "-o", out.to_str().unwrap()];
    args.extend_from_slice(extra);
    run(&args)
}

/// Nominal outlines of a design, rebuilt from its file (docs/physics.md §4 planform): l_p = l / (1 + l_r),
/// w_nom = w_0 / w_r, w_tip = (2 - w_r) w_nom; base centred on the origin, axis along +y.
struct Outlines {
    pzt: Vec<[f64; 2]>,
    passive: Vec<[f64; 2]>,
}

fn outlines(design_file: &Path, ground_tab_mm: Option<f64>) -> Outlines {
    let t: toml::Table = std::fs::read_to_string(design_file)
        .unwrap()
        .parse()
        .unwrap();
    let g = t["geometry"].as_table().unwrap();
    let num = |k: &str| {
        g.get(k)
            .map(|v| v.as_float().or(v.as_integer().map(|i| i as f64)).unwrap())
            .unwrap_or(0.0)
    };
    let (l, lr, w0, wr, tab) = (
        num("length_mm"),
        num("extension_ratio"),
        num("base_width_mm"),
        num("width_ratio"),
        // A design without a tab is cut with the process's ground tab, which the report states.
        ground_tab_mm.unwrap_or(num("base_tab_mm")),
    );
    let lp = l / (1.0 + lr);
    let wnom = w0 / wr;
    let (b, t) = (w0 / 2.0, (2.0 - wr) * wnom / 2.0);
    let pzt = vec![[-b, 0.0], [b, 0.0], [t, lp], [-t, lp]];
    // The tab is a rectangle w_0 x l_tab behind the root.
    let mut passive = vec![
        [-b, -tab],
        [b, -tab],
        [b, 0.0],
        [t, lp],
        [t, l],
        [-t, l],
        [-t, lp],
        [-b, 0.0],
    ];
    if tab == 0.0 {
        passive = vec![[-b, 0.0], [b, 0.0], [t, lp], [t, l], [-t, l], [-t, lp]];
    }
    if lr == 0.0 {
        passive.retain(|p| p[1] != l || lp == l);
        passive.dedup();
    }
    Outlines { pzt, passive }
}

/// Check a written nest independently of the planner: every demanded part once, each part inside its
/// sheet with the edge clearance, every pair at least the gap apart, rotations allowed, utilisation
/// equal to the part area over the sheet area. `designs` maps design name to (file, quantity).
fn check_report(
    out: &Path,
    designs: &BTreeMap<String, (std::path::PathBuf, usize)>,
    spacing_mm: f64,
) {
    check_report_with_edge(out, designs, spacing_mm, spacing_mm);
}

/// [`check_report`] with the cut-through sheets' edge gap `edge_gap_mm` (on top of the kerf) apart
/// from the spacing between their parts.
fn check_report_with_edge(
    out: &Path,
    designs: &BTreeMap<String, (std::path::PathBuf, usize)>,
    spacing_mm: f64,
    edge_gap_mm: f64,
) {
    let report: serde_json::Value = nest_report_json(out);
    let ground_tab = |name: &str| {
        report["items"]
            .as_array()
            .unwrap()
            .iter()
            .find(|i| i["design"] == name)
            .and_then(|i| i["ground_tab_mm"].as_f64())
    };
    let shapes: BTreeMap<&String, Outlines> = designs
        .iter()
        .map(|(n, (f, _))| (n, outlines(f, ground_tab(n))))
        .collect();
    let mut seen: BTreeMap<(String, usize, String), usize> = BTreeMap::new();
    for sheet in report["sheets"].as_array().unwrap() {
        let layer = sheet["layer"].as_str().unwrap();
        let (w, h) = (
            sheet["width_mm"].as_f64().unwrap(),
            sheet["height_mm"].as_f64().unwrap(),
        );
        let stem = sheet["file_stem"].as_str().unwrap();
        assert!(out.join(format!("{stem}.svg")).exists(), "{stem}.svg");
        assert!(out.join(format!("{stem}.dxf")).exists(), "{stem}.dxf");
        let (edge, gap, rotations): (f64, f64, &[f64]) = match layer {
            "pzt" => (PZT_EDGE_MARGIN_MM, PZT_KERF_MM, &[0.0, 90.0, 180.0, 270.0]),
            _ => (
                PREPREG_KERF_MM + edge_gap_mm,
                PREPREG_KERF_MM + spacing_mm,
                &[0.0, 180.0],
            ),
        };
        let mut placed = Vec::new();
        let mut part_area = 0.0;
        for p in sheet["parts"].as_array().unwrap() {
            let design = p["design"].as_str().unwrap().to_string();
            let kind = p["part"].as_str().unwrap().to_string();
            let actuator = p["actuator"].as_u64().unwrap() as usize;
            *seen
                .entry((design.clone(), actuator, kind.clone()))
                .or_default() += 1;
            let rot = p["rotation_deg"].as_f64().unwrap();
            assert!(rotations.contains(&rot), "{stem}: rotation {rot}");
            let s = &shapes[&design];
            let nominal = if layer == "pzt" { &s.pzt } else { &s.passive };
            part_area += area(nominal);
            let (x, y) = (p["x_mm"].as_f64().unwrap(), p["y_mm"].as_f64().unwrap());
            let (sin, cos) = match rot as i64 {
                0 => (0.0, 1.0),
                90 => (1.0, 0.0),
                180 => (0.0, -1.0),
                _ => (-1.0, 0.0),
            };
            let ring: Vec<[f64; 2]> = nominal
                .iter()
                .map(|q| [cos * q[0] - sin * q[1] + x, sin * q[0] + cos * q[1] + y])
                .collect();
            for q in &ring {
                assert!(
                    q[0] >= edge - 1e-6
                        && q[1] >= edge - 1e-6
                        && q[0] <= w - edge + 1e-6
                        && q[1] <= h - edge + 1e-6,
                    "{stem}: {design} {kind} #{actuator} vertex {q:?} within {edge} mm of the edge"
                );
            }
            placed.push((format!("{design} {kind} #{actuator}"), polygon(&ring)));
        }
        for i in 0..placed.len() {
            for j in i + 1..placed.len() {
                let d = Euclidean.distance(&placed[i].1, &placed[j].1);
                assert!(
                    d >= gap - 1e-6,
                    "{stem}: {} and {} are {d} mm apart (gap {gap})",
                    placed[i].0,
                    placed[j].0
                );
            }
        }
        let util = sheet["utilization"].as_f64().unwrap();
        assert!(
            (util - part_area / (w * h)).abs() < 1e-9,
            "{stem} utilisation"
        );
    }
    // Every actuator: two plates and one passive part, each once.
    let mut want = BTreeMap::new();
    for (name, (_, q)) in designs {
        for a in 1..=*q {
            for kind in ["pzt-plate-1", "pzt-plate-2", "passive"] {
                want.insert((name.clone(), a, kind.to_string()), 1usize);
            }
        }
    }
    assert_eq!(seen, want, "every part placed exactly once");
    let panels: usize = report["clamp_panels"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["actuators"].as_array().unwrap().len())
        .sum();
    assert_eq!(panels, designs.values().map(|(_, q)| q).sum::<usize>());
    for b in report["baseline"].as_array().unwrap() {
        assert!(b["sheets"].as_u64() <= b["baseline_sheets"].as_u64(), "{b}");
        let f = |k: &str| b[k].as_f64().unwrap();
        assert!(
            f("used_length_utilization") >= f("utilization") - 1e-12,
            "{b}"
        );
        assert!(
            f("baseline_used_length_utilization") >= f("baseline_utilization") - 1e-12,
            "{b}"
        );
    }
}

fn example_designs() -> BTreeMap<String, (std::path::PathBuf, usize)> {
    [
        ("thesis-C", 12),
        ("thesis-B", 4),
        ("thesis-A", 4),
        ("thesis-1", 4),
    ]
    .iter()
    .map(|(n, q)| (n.to_string(), (example_path(&format!("{n}.toml")), *q)))
    .collect()
}

/// A batch in a temp dir with copies of example designs (one line of a design replaceable).
fn scratch_batch(batch: &str, designs: &[(&str, &str)]) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    for (name, text) in designs {
        std::fs::write(dir.path().join(name), text).unwrap();
    }
    std::fs::write(dir.path().join("batch.toml"), batch).unwrap();
    dir
}

fn fails_without_output(dir: &tempfile::TempDir, expect: &[&str]) {
    let out = dir.path().join("out");
    let o = nest(&dir.path().join("batch.toml"), &out, &[]);
    let err = stderr(&o);
    assert!(!o.status.success(), "should fail: {}", stdout(&o));
    for e in expect {
        assert!(err.contains(e), "{e:?} not in {err}");
    }
    assert!(!out.exists(), "no output on error");
    assert!(
        std::fs::read_dir(dir.path()).unwrap().all(|e| !e
            .unwrap()
            .file_name()
            .to_string_lossy()
            .starts_with('.')),
        "no staging directory left"
    );
}

/// The example batch nested with a time budget far longer than the test, interrupted
/// `interrupts` times once its search is under way (SIGINT, as Ctrl-C sends).
fn interrupted_nest(
    interrupts: usize,
) -> (tempfile::TempDir, std::path::PathBuf, std::process::Output) {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    // The run holds two seconds between an interrupted search and its writing, so the second
    // interrupt, half a second after the first, lands before the writing on a loaded machine too.
    let child = bin()
        .args([
            "nest",
            &example("batch.toml"),
            "-o",
            out.to_str().unwrap(),
            "--time",
            "600s",
        ])
        .env("ACTUATOR_CAM_PAUSE_AFTER_SEARCH", "1")
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(std::time::Duration::from_secs(2));
    for _ in 0..interrupts {
        std::process::Command::new("kill")
            .args(["-INT", &child.id().to_string()])
            .status()
            .unwrap();
        std::thread::sleep(std::time::Duration::from_millis(500));
    }
    let o = child.wait_with_output().unwrap();
    (dir, out, o)
}
