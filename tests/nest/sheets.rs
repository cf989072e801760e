//! The example batches checked sheet by sheet against geometry rebuilt from the design files (independent of
//! the planner): seeds, random batches, method 1's Pyralux and ply-by-ply prepreg.

use super::*;

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
