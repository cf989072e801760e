//! Every file a run reads is an input, and no output replaces it, under any name or link.

use super::*;

/// A project folder holding copies of the examples (parts, effects, measured data), a template file that
/// a design names, and a calibrated model: every kind of file a run reads.
fn project() -> (tempfile::TempDir, std::path::PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("p");
    fs::create_dir_all(p.join("parts")).unwrap();
    for e in fs::read_dir(example("")).unwrap() {
        let e = e.unwrap();
        if e.file_type().unwrap().is_file() {
            fs::copy(e.path(), p.join(e.file_name())).unwrap();
        }
    }
    for name in ["spar.dxf", "flexure.svg"] {
        fs::copy(
            example(&format!("parts/{name}")),
            p.join("parts").join(name),
        )
        .unwrap();
    }
    fs::copy(
        format!("{}/templates/method-2.toml", env!("CARGO_MANIFEST_DIR")),
        p.join("my-process.toml"),
    )
    .unwrap();
    fs::write(
        p.join("design.toml"),
        design_c_with(&[("process", "process = \"my-process.toml\"")]),
    )
    .unwrap();
    let cal = dir.path().join("cal");
    run_ok(&[
        "calibrate",
        &example("measured-thesis-like.csv"),
        "-o",
        cal.to_str().unwrap(),
    ]);
    fs::copy(cal.join("calibrated-model.toml"), p.join("model.toml")).unwrap();
    (dir, p)
}

/// Run with the writer's list of inputs on stderr; the list, and the run's output.
fn with_inputs(args: &[&str]) -> (Vec<std::path::PathBuf>, std::process::Output) {
    let o = bin()
        .env("ACTUATOR_CAM_LIST_INPUTS", "1")
        .args(args)
        .output()
        .unwrap();
    let list = stderr(&o)
        .lines()
        .filter_map(|l| l.strip_prefix("input: "))
        .map(std::path::PathBuf::from)
        .collect();
    (list, o)
}

fn snapshot(paths: &[std::path::PathBuf]) -> Vec<Vec<u8>> {
    paths.iter().map(|p| fs::read(p).unwrap()).collect()
}

#[test]
fn every_file_a_run_reads_is_an_input_no_output_replaces() {
    let (_dir, p) = project();
    let at = |n: &str| p.join(n).to_str().unwrap().to_string();
    let model = at("model.toml");
    let folder_runs: Vec<Vec<String>> = vec![
        vec![
            "cut-sheet".into(),
            at("design.toml"),
            "--model".into(),
            model.clone(),
        ],
        vec!["nest".into(), at("batch-with-parts.toml")],
        vec![
            "calibrate".into(),
            at("measured-thesis-like.csv"),
            "--effects".into(),
            at("effects-clamp-width.toml"),
        ],
    ];
    for args in &folder_runs {
        let mut args: Vec<&str> = args.iter().map(String::as_str).collect();
        let out = p.to_str().unwrap();
        args.extend(["-o", out, "--force"]);
        let named: Vec<std::path::PathBuf> = args
            .iter()
            .filter(|a| a.ends_with(".toml") || a.ends_with(".csv"))
            .map(std::path::PathBuf::from)
            .collect();
        let named_before = snapshot(&named);
        let (inputs, o) = with_inputs(&args);
        assert!(o.status.success(), "{args:?}: {}", stderr(&o));
        assert_eq!(snapshot(&named), named_before, "{args:?}");
        // The list holds what the command line names and what those files name.
        for named in args
            .iter()
            .filter(|a| a.ends_with(".toml") || a.ends_with(".csv"))
        {
            assert!(
                inputs.iter().any(|i| i.to_str() == Some(named)),
                "{named} not in {inputs:?}"
            );
        }
        if args[0] == "cut-sheet" {
            assert!(
                inputs.iter().any(|i| i.ends_with("my-process.toml")),
                "{inputs:?}"
            );
        }
        if args[0] == "nest" {
            for part in ["spar.dxf", "flexure.svg", "thesis-A.toml"] {
                assert!(
                    inputs.iter().any(|i| i.ends_with(part)),
                    "{part}: {inputs:?}"
                );
            }
        }
    }
    // optimize's files aimed at each input of the same run: an input in the output folder under the
    // name of one of its files is refused, even with --force; an input given as the folder is not one.
    let optimize = |extra: &[&str]| {
        let mut args = vec![
            "optimize".to_string(),
            at("optimize-thesis.toml"),
            "--model".into(),
            model.clone(),
        ];
        args.extend(extra.iter().map(|s| s.to_string()));
        args
    };
    let scratch = at("optimum");
    let (inputs, o) = with_inputs(
        &optimize(&["-o", &scratch])
            .iter()
            .map(String::as_str)
            .collect::<Vec<_>>(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(inputs.len(), 2, "{inputs:?}");
    let before = snapshot(&inputs);
    for input in &inputs {
        let input = input.to_str().unwrap();
        let args = optimize(&["-o", input, "--force"]);
        let o = run(&args.iter().map(String::as_str).collect::<Vec<_>>());
        refused_in_one_line(&o);
    }
    assert_eq!(snapshot(&inputs), before);
    let named = Path::new(&scratch).join("design.toml");
    fs::copy(&model, &named).unwrap();
    let o = run(&[
        "optimize",
        &at("optimize-thesis.toml"),
        "--model",
        named.to_str().unwrap(),
        "-o",
        &scratch,
        "--force",
    ]);
    let err = refused_in_one_line(&o);
    assert!(err.contains("design.toml is an input of this run"), "{err}");
    let factors = at("sweep-table-3-2.toml");
    let (inputs, _) = with_inputs(&["sweep", &factors, "--csv", &at("designs.csv")]);
    assert_eq!(inputs, [std::path::PathBuf::from(&factors)]);
    let o = run(&["sweep", &factors, "--csv", &factors, "--force"]);
    let err = refused_in_one_line(&o);
    assert!(err.contains("is an input of this run"), "{err}");
}

#[test]
fn a_model_file_is_an_input_under_any_output_name() {
    let dir = tempfile::tempdir().unwrap();
    let c = dir.path().join("C");
    run_ok(&[
        "calibrate",
        &example("measured-thesis-like.csv"),
        "-o",
        c.to_str().unwrap(),
    ]);
    let model = c.join("calibrated-model.toml");
    let before = fs::read(&model).unwrap();
    // The model named as one of optimize's files, in its output folder, with --force.
    let d = dir.path().join("D");
    fs::create_dir(&d).unwrap();
    fs::copy(&model, d.join("report.txt")).unwrap();
    let o = run(&[
        "optimize",
        "examples/optimize-thesis.toml",
        "--model",
        d.join("report.txt").to_str().unwrap(),
        "-o",
        d.to_str().unwrap(),
        "--force",
    ]);
    let err = refused_in_one_line(&o);
    assert!(err.contains("report.txt is an input of this run"), "{err}");
    assert_eq!(fs::read(d.join("report.txt")).unwrap(), before);
    // A model file named like an output of cut-sheet, in the output folder, with --force.
    let p = dir.path().join("P");
    fs::create_dir(&p).unwrap();
    fs::copy(&model, p.join("report.md")).unwrap();
    let o = cut_sheet(
        "examples/thesis-C.toml",
        &p,
        &["--model", p.join("report.md").to_str().unwrap(), "--force"],
    );
    let err = refused_in_one_line(&o);
    assert!(err.contains("report.md is an input of this run"), "{err}");
    assert_eq!(fs::read(p.join("report.md")).unwrap(), before);
}

#[test]
fn one_command_does_not_replace_anothers_files_unasked() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path().join("D");
    run_ok(&[
        "calibrate",
        &example("measured-thesis-like.csv"),
        "-o",
        d.to_str().unwrap(),
    ]);
    let report = fs::read(d.join("report.md")).unwrap();
    let o = cut_sheet_into(&d, &[]);
    let err = refused_in_one_line(&o);
    assert!(
        err.contains("was written by `actuator-cam calibrate`") && err.contains("--force"),
        "{err}"
    );
    assert_eq!(fs::read(d.join("report.md")).unwrap(), report);
    let o = cut_sheet_into(&d, &["--force"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_ne!(fs::read(d.join("report.md")).unwrap(), report);
}
