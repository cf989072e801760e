//! Bad batches, time budgets and interrupts: refused in one line, a budget held and reported, an interrupt
//! that keeps the best layout and a second that leaves nothing.

use super::*;

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
