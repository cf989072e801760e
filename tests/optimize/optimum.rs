//! The optimum against what it must be: an independent grid, a closed form for rectangles, the Pareto front,
//! the energy-density objective, and a calibrated model's optimum.

use super::*;

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

/// Thesis design variables through the calibrated model (PZT-5H on CF-thesis plies, 800 V/mm parallel).
fn calibrated_predict(
    calibrated: &actuator_model::CalibratedModel,
    t_p: f64,
    layup: &[f64],
    pl: Planform,
) -> actuator_model::Performance {
    let pzt = Material::builtin("PZT-5H").unwrap();
    let cf = Material::builtin("CF-thesis").unwrap();
    calibrated
        .predict(&actuator_model::Actuator {
            pzt: &pzt,
            pzt_thickness: t_p,
            ply: &cf,
            ply_thickness: 61.8e-6,
            layup_deg: layup,
            planform: pl,
            drive: Drive::new(DriveMode::Parallel, 800e3),
        })
        .unwrap()
}

/// The lightest design of a 14-per-axis grid over the spec's ranges that gives the energy, kg.
fn lightest_on_grid(calibrated: &actuator_model::CalibratedModel) -> f64 {
    let n = 14;
    let (lengths, widths) = (linspace(40e-3, 60e-3, n), linspace(5e-3, 20e-3, n));
    let (ext, ratios) = (linspace(0.0, 1.5, n), linspace(1.0, 1.95, n));
    let mut tasks: Vec<(f64, &[f64], f64)> = Vec::new();
    for &t in &THICKNESSES {
        for layup in LAYUPS {
            tasks.extend(ext.iter().map(|&r| (t, layup, r)));
        }
    }
    tasks
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
                        let q = calibrated_predict(calibrated, t_p, layup, pl);
                        if q.energy >= ENERGY {
                            best = best.min(q.mass);
                        }
                    }
                }
            }
            best
        })
        .reduce(|| f64::INFINITY, f64::min)
}

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
    let predict =
        |t_p: f64, layup: &[f64], pl: Planform| calibrated_predict(&calibrated, t_p, layup, pl);
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
    let grid_best = lightest_on_grid(&calibrated);
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

// Strain along the plate (docs/physics.md eqs. 6.1-6.3).

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
