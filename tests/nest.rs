//! `actuator-cam nest` on batch files: the example batch checked sheet by sheet with geometry rebuilt
//! from the design files (independent of the planner), determinism, random batches, and bad input.

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
        let (edge, gap, rotations): (f64, f64, &[f64]) = if layer == "pzt" {
            (PZT_EDGE_MARGIN_MM, PZT_KERF_MM, &[0.0, 90.0, 180.0, 270.0])
        } else {
            (
                PREPREG_KERF_MM + spacing_mm,
                PREPREG_KERF_MM + spacing_mm,
                &[0.0, 180.0],
            )
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

#[test]
fn example_batch_nests_and_every_sheet_checks_out() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = nest(Path::new(&example("batch.toml")), &out, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o).contains("24 actuators"), "{}", stdout(&o));
    let f = sheet_files(&out);
    for name in [
        "pzt-1.svg",
        "pzt-3.dxf",
        "passive-1.svg",
        "passive-2.dxf",
        "mold-1-1.svg",
        "felt-2-5.dxf",
        "nest-report.json",
        "nest-report.md",
    ] {
        assert!(f.contains_key(name), "{name} missing: {:?}", f.keys());
    }
    check_report(&out, &example_designs(), 0.3);
    let report: serde_json::Value = serde_json::from_slice(&f["nest-report.json"]).unwrap();
    assert_eq!(report["name"], "batch-2026-11");
    assert_eq!(report["seed"], 1);
    // Three PZT thicknesses: three PZT sheets, one per thickness; two layups: two prepreg sheets.
    let layers: Vec<&str> = report["sheets"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["layer"].as_str().unwrap())
        .collect();
    assert_eq!(layers, ["pzt", "pzt", "pzt", "passive", "passive"]);
    let md = String::from_utf8(f["nest-report.md"].clone()).unwrap();
    assert!(md.contains("thesis-C actuator 12 plate 2: PZT sheet 1"));
    assert!(md.contains("thesis-1 actuator 4: clamp panel"));
    assert!(md.contains("bounding-box baseline"));
    // The report says what x_mm/y_mm mean (root centre, y up, the DXF's frame).
    let coordinates = report["coordinates"].as_str().unwrap_or_default();
    for needle in ["centre of the part's base", "y up", "DXF", "y_svg"] {
        assert!(
            coordinates.contains(needle),
            "{needle:?} not in {coordinates:?}"
        );
    }
    assert!(
        md.contains(coordinates),
        "the Markdown report omits the coordinate note"
    );
}

#[test]
fn same_seed_gives_identical_bytes_and_another_seed_still_checks_out() {
    let dir = tempfile::tempdir().unwrap();
    let batch = example("batch.toml");
    let (a, b, c) = (
        dir.path().join("a"),
        dir.path().join("b"),
        dir.path().join("c"),
    );
    for out in [&a, &b] {
        let o = nest(Path::new(&batch), out, &[]);
        assert!(o.status.success(), "{}", stderr(&o));
    }
    assert_eq!(files(&a), files(&b));
    let o = nest(
        Path::new(&batch),
        &c,
        &["--seed", "7", "--iterations", "300"],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    check_report(&c, &example_designs(), 0.3);
}

#[test]
fn random_batches_always_check_out() {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(4);
    let names = THESIS_DESIGNS;
    for case in 0..3 {
        let dir = tempfile::tempdir().unwrap();
        let mut designs = BTreeMap::new();
        let mut text = format!(
            "name = \"random-{case}\"\nseed = {}\niterations = 200\n",
            rng.gen_range(0..1000)
        );
        for name in names {
            if rng.gen_bool(0.5) || designs.is_empty() && name == "thesis-21" {
                let q = rng.gen_range(1..8);
                let file = dir.path().join(format!("{name}.toml"));
                std::fs::copy(example(&format!("{name}.toml")), &file).unwrap();
                text += &format!("[[item]]\ndesign = \"{name}.toml\"\nquantity = {q}\n");
                designs.insert(name.to_string(), (file, q));
            }
        }
        let spacing = rng.gen_range(0.0..1.0);
        text += &format!("[sheets]\nspacing_mm = {spacing}\n");
        let batch = dir.path().join("batch.toml");
        std::fs::write(&batch, &text).unwrap();
        let out = dir.path().join("out");
        let o = nest(&batch, &out, &[]);
        assert!(o.status.success(), "{text}\n{}", stderr(&o));
        check_report(&out, &designs, spacing);
    }
}

#[test]
fn method_1_batch_nests_pyralux_bond_layers_with_vias() {
    let c = std::fs::read_to_string(example("thesis-C.toml")).unwrap();
    let b = std::fs::read_to_string(example("thesis-B.toml")).unwrap();
    let dir = scratch_batch(
        "name = \"m1\"\n[[item]]\ndesign = \"c.toml\"\nquantity = 5\n[[item]]\ndesign = \"b.toml\"\nquantity = 3\n\
         [sheets]\npyralux = { width_mm = 60, height_mm = 60, price_per_sheet = 12.5 }\n",
        &[
            ("c.toml", &c.replace("method-2", "method-1")),
            ("b.toml", &b.replace("method-2", "method-1")),
        ],
    );
    let out = dir.path().join("out");
    let o = nest(&dir.path().join("batch.toml"), &out, &["--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let report: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert_eq!(
        report,
        nest_report_json(&out),
        "--json prints the written report"
    );
    let mut bond_parts = BTreeMap::new();
    for sheet in report["sheets"].as_array().unwrap() {
        if sheet["layer"] == "pyralux" {
            assert_eq!(sheet["width_mm"], 60.0);
            for p in sheet["parts"].as_array().unwrap() {
                *bond_parts
                    .entry(p["design"].as_str().unwrap().to_string())
                    .or_insert(0) += 1;
            }
            let svg = std::fs::read_to_string(
                out.join(format!("{}.svg", sheet["file_stem"].as_str().unwrap())),
            )
            .unwrap();
            // One via (a circle drawn with arcs) per bond part.
            assert_eq!(
                svg.matches(" A").count() / 2,
                sheet["parts"].as_array().unwrap().len(),
                "one via per part"
            );
        }
    }
    assert_eq!(bond_parts["thesis-C"], 10);
    assert_eq!(bond_parts["thesis-B"], 6);
    let pyralux = report["totals"]
        .as_array()
        .unwrap()
        .iter()
        .find(|t| t["layer"] == "pyralux")
        .unwrap();
    assert_eq!(
        pyralux["cost"].as_f64().unwrap(),
        12.5 * pyralux["sheets"].as_f64().unwrap()
    );
    assert_eq!(report["total_cost"], pyralux["cost"]);
}

#[test]
fn ply_by_ply_batch_nests_each_ply_of_each_layup() {
    let template = shipped_template("method-2.toml")
        .replace("passive_cut = \"stack\"", "passive_cut = \"ply-by-ply\"");
    let design = |name: &str| {
        std::fs::read_to_string(example(name))
            .unwrap()
            .replace("process = \"method-2\"", "process = \"pbp.toml\"")
            .replace("base_tab_mm = 0.0", "base_tab_mm = 2.0")
    };
    let dir = scratch_batch(
        "name = \"pbp\"\niterations = 200\n[[item]]\ndesign = \"c.toml\"\nquantity = 4\n\
         [[item]]\ndesign = \"a.toml\"\nquantity = 2\n",
        &[
            ("pbp.toml", &template),
            ("c.toml", &design("thesis-C.toml")),
            ("a.toml", &design("thesis-A.toml")),
        ],
    );
    let out = dir.path().join("out");
    let o = nest(&dir.path().join("batch.toml"), &out, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let report: serde_json::Value = nest_report_json(&out);
    // C is 0/90/0 and A 0/0/90/0/0: one nest per ply of each layup, every ply of every actuator once.
    let mut per_layer: BTreeMap<String, usize> = BTreeMap::new();
    for sheet in report["sheets"].as_array().unwrap() {
        let layer = sheet["layer"].as_str().unwrap();
        if layer.starts_with("passive-ply") {
            *per_layer.entry(layer.to_string()).or_default() +=
                sheet["parts"].as_array().unwrap().len();
            assert!(out
                .join(format!("{}.svg", sheet["file_stem"].as_str().unwrap()))
                .exists());
        }
    }
    let want: BTreeMap<String, usize> = [
        ("passive-ply1-0deg", 6),
        ("passive-ply2-90deg", 4),
        ("passive-ply2-0deg", 2),
        ("passive-ply3-0deg", 4),
        ("passive-ply3-90deg", 2),
        ("passive-ply4-0deg", 2),
        ("passive-ply5-0deg", 2),
    ]
    .iter()
    .map(|(k, v)| (k.to_string(), *v))
    .collect();
    assert_eq!(per_layer, want);
    assert_eq!(report["baseline"].as_array().unwrap().len(), 8);
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

#[test]
fn bad_batches_exit_non_zero_with_a_clear_message_and_no_output() {
    let c = std::fs::read_to_string(example("thesis-C.toml")).unwrap();
    let b = std::fs::read_to_string(example("thesis-B.toml")).unwrap();
    let item = |d: &str, q: i64| format!("[[item]]\ndesign = \"{d}\"\nquantity = {q}\n");

    let dir = scratch_batch(&format!("name = \"x\"\n{}", item("missing.toml", 2)), &[]);
    fails_without_output(
        &dir,
        &[
            "batch.toml",
            "item[1].design",
            "missing.toml",
            "no such design file",
        ],
    );

    let dir = scratch_batch(
        &format!("name = \"x\"\n{}", item("c.toml", 0)),
        &[("c.toml", &c)],
    );
    fails_without_output(
        &dir,
        &["batch.toml", "item[1].quantity", "0", "[1, 100000]"],
    );

    // Two of design C on 20 mm wide prepreg sheets of the given height.
    let prepreg = |height_mm: &str| {
        scratch_batch(
            &format!(
                "name = \"x\"\n{}[sheets]\nprepreg = {{ width_mm = 20, height_mm = {height_mm} }}\n",
                item("c.toml", 2)
            ),
            &[("c.toml", &c)],
        )
    };
    fails_without_output(
        &prepreg("20"),
        &[
            "batch.toml: sheets.prepreg.height_mm = 20: the passive part of thesis-C",
            // 42.2 mm of part, the process's 1.5 mm ground tab and 0.55 mm to each edge, which the
            // nester's working margin (1.01 x the separation and a few micrometres) makes 0.5608 mm.
            "does not fit the sheet; it needs at least 44.83 mm",
        ],
    );
    // The size the refusal names takes the part, and a hundredth less does not.
    let dir = prepreg("44.83");
    let o = nest(&dir.path().join("batch.toml"), &dir.path().join("out"), &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    fails_without_output(
        &prepreg("44.82"),
        &["sheets.prepreg.height_mm = 44.82", "at least 44.83 mm"],
    );

    // 40 actuators of design C need 80 plates: more than one 72.4 mm PZT sheet.
    let dir = scratch_batch(
        &format!(
            "name = \"x\"\n{}[sheets]\npzt = {{ width_mm = 72.4, height_mm = 72.4, stock = 1 }}\n",
            item("c.toml", 40)
        ),
        &[("c.toml", &c)],
    );
    fails_without_output(&dir, &["PZT sheets", "needs 2 sheets", "stock is 1"]);

    let dir = scratch_batch(
        &format!(
            "name = \"x\"\n{}[sheets]\nprepreg = {{ width_mm = 60, height_mm = 60, stock = 1 }}\n",
            item("c.toml", 30)
        ),
        &[("c.toml", &c)],
    );
    fails_without_output(
        &dir,
        &[
            "passive sheets",
            "stock too small",
            "the batch needs",
            "stock is 1",
        ],
    );

    let dir = scratch_batch(
        &format!("name = \"x\"\n{}{}", item("c.toml", 2), item("b1.toml", 2)),
        &[
            ("c.toml", &c),
            ("b1.toml", &b.replace("method-2", "method-1")),
        ],
    );
    fails_without_output(
        &dir,
        &[
            "item[2].design",
            "b1.toml",
            "method-1",
            "method-2",
            "c.toml",
        ],
    );

    let dir = scratch_batch(
        &format!("name = \"x\"\nseeds = 3\n{}", item("c.toml", 2)),
        &[("c.toml", &c)],
    );
    fails_without_output(&dir, &["seeds", "unknown key"]);

    let dir = scratch_batch(
        &format!(
            "name = \"x\"\n{}[sheets]\nspacing_mm = -1\n",
            item("c.toml", 2)
        ),
        &[("c.toml", &c)],
    );
    fails_without_output(&dir, &["sheets.spacing_mm", "-1"]);

    let dir = scratch_batch(
        &format!("name = \"x\"\ntime_s = 0\n{}", item("c.toml", 2)),
        &[("c.toml", &c)],
    );
    fails_without_output(&dir, &["time_s", "0", "86400"]);
}

#[test]
fn a_bad_time_budget_is_refused_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    for bad in ["soon", "-3s", "0", "2d", "90000"] {
        let out = dir.path().join("out");
        let flag = format!("--time={bad}");
        let o = nest(Path::new(&example("batch.toml")), &out, &[&flag]);
        let err = refused_in_one_line(&o);
        assert!(err.contains("--time") && err.contains(bad), "{bad}: {err}");
        assert!(!out.exists(), "{bad}: output written");
    }
}

#[test]
fn a_time_budget_nests_until_it_runs_out_and_the_report_says_how_far_each_layer_got() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = nest(Path::new(&example("batch.toml")), &out, &["--time", "3s"]);
    assert!(o.status.success(), "{}", stderr(&o));
    check_report(&out, &example_designs(), 0.3);
    let report = nest_report_json(&out);
    assert_eq!(report["time_budget_s"], 3.0);
    let layers = report["baseline"].as_array().unwrap();
    assert!(!layers.is_empty());
    for layer in layers {
        let search = &layer["search"];
        let ended = search["ended"].as_str().unwrap();
        assert!(["time", "budget"].contains(&ended), "{search}");
        // A replayable layer got past the base search of 1000 iterations.
        if search["replayable"].as_bool().unwrap() {
            assert!(search["iterations"].as_u64().unwrap() >= 1000, "{search}");
        }
    }
    let md = std::fs::read_to_string(out.join("nest-report.md")).unwrap();
    assert!(md.contains("## Search (time budget 3 s)"), "{md}");
}

/// A budget shorter than placing every part once: the layout is still complete and verified, and
/// the run says on stderr, in the JSON and in the Markdown report that the budget was exceeded and by
/// how long the first layout took. With a budget the first layout fits in, none of it appears.
#[test]
fn a_budget_the_first_layout_overruns_is_said_with_the_time_it_took() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = nest(
        Path::new(&example("batch.toml")),
        &out,
        &["--time", "0.001"],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    check_report(&out, &example_designs(), 0.3);
    let err = stderr(&o);
    assert!(err.contains("the time budget was exceeded"), "{err}");
    let report = nest_report_json(&out);
    let over: Vec<f64> = report["baseline"]
        .as_array()
        .unwrap()
        .iter()
        .filter_map(|l| l["search"]["over_budget_s"].as_f64())
        .collect();
    assert!(
        !over.is_empty() && over.iter().all(|t| *t > 0.001),
        "{report}"
    );
    let md = std::fs::read_to_string(out.join("nest-report.md")).unwrap();
    assert!(md.contains("past the budget"), "{md}");
    let roomy = dir.path().join("roomy");
    let o = nest(Path::new(&example("batch.toml")), &roomy, &["--time", "3s"]);
    assert!(!stderr(&o).contains("exceeded"), "{}", stderr(&o));
    assert!(!std::fs::read_to_string(roomy.join("nest-report.json"))
        .unwrap()
        .contains("over_budget_s"));
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

#[test]
fn a_first_interrupt_ends_the_search_and_writes_the_best_layout_so_far() {
    let (dir, out, o) = interrupted_nest(1);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("interrupted"), "{}", stderr(&o));
    check_report(&out, &example_designs(), 0.3);
    let report = nest_report_json(&out);
    for layer in report["baseline"].as_array().unwrap() {
        assert_eq!(layer["search"]["ended"], "interrupt", "{layer}");
    }
    assert!(staging_left(dir.path()).is_empty() && staging_left(&out).is_empty());
}

#[test]
fn a_second_interrupt_aborts_and_leaves_nothing_behind() {
    let (dir, out, o) = interrupted_nest(2);
    assert_eq!(o.status.code(), Some(130), "{}", stderr(&o));
    assert!(
        !out.exists() || files(&out).is_empty(),
        "half-written output"
    );
    assert!(staging_left(dir.path()).is_empty());
}
