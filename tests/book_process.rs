//! The build book as a process a lab can run on numbers: a test coupon scored before any
//! production PZT sheet, the laser settings per stock and operation, the clamp's dowels, measuring
//! step and force as data, and a functional check that closes every book, each checked against the
//! report's own figures and the files written.

use crate::build_book::{first, steps};
use crate::common;
use common::*;
use serde_json::Value;

/// `cut-sheet` of `design` into a fresh folder: the report and the folder.
fn cut(design: &str) -> (tempfile::TempDir, std::path::PathBuf, Value) {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = cut_sheet(design, &out, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let r = report_json(&out);
    (dir, out, r)
}

/// A copy of the method-2 template with `edit` applied, and thesis-C's design using it.
fn with_template(edit: impl Fn(String) -> String) -> (tempfile::TempDir, std::path::PathBuf) {
    let (dir, design) = write_temp("c.toml", &design_c_with(&[]));
    let template = edit(shipped_template("method-2.toml"));
    std::fs::write(dir.path().join("tpl.toml"), template).unwrap();
    let text = design_c_with(&[("process", "process = \"tpl.toml\"")]);
    std::fs::write(&design, text).unwrap();
    (dir, design)
}

#[test]
fn the_coupon_is_scored_before_any_production_pzt_sheet() {
    let (_dir, out, r) = cut("examples/thesis-C.toml");
    let s = steps(&r["build_book"]);
    let coupon = first(&s, "score the test coupon");
    let score = first(&s, "score it along the blue lines");
    assert!(
        coupon < score,
        "the coupon comes after the production sheet"
    );
    assert!(s[score].1.contains("the setting the coupon passed"));
    // The coupon file is written in both formats, named in its step, and is the PZT stock's.
    let stem = "pzt-coupon-1_pzt-5h-pzt-sheet-piezo-systems-0.267mm";
    assert!(
        s[coupon].1.contains(&format!("`{stem}`")),
        "{}",
        s[coupon].1
    );
    for ext in ["svg", "dxf"] {
        assert!(out.join(format!("{stem}.{ext}")).is_file(), "{stem}.{ext}");
    }
    // 20 x 15 mm: four 5 mm bands of 0.267 mm PZT, its score lines on the score layer; the top strip
    // is the narrowest a production sheet leaves, 5 thicknesses and half the 0.03 mm kerf.
    let svg = std::fs::read_to_string(out.join(format!("{stem}.svg"))).unwrap();
    assert!(
        svg.contains("width=\"20mm\"") && svg.contains("height=\"15mm\""),
        "{}",
        &svg[..300]
    );
    assert!(s[coupon].1.contains("at least 20 x 15 mm"));
    assert_eq!(
        svg.matches("stroke=\"#0000FF\"").count(),
        4,
        "four score lines"
    );
    // SVG y runs down from the top edge: the top line 1.35 mm below it, run 0.5 mm past both sides.
    assert!((5.0f64 * 0.267 + 0.015 - 1.35).abs() < 1e-12);
    assert!(svg.contains("M-0.5 1.35 L20.5 1.35"), "{svg}");
    // The coupon is an offcut: the stock list buys no coupon-sized sheet.
    for row in r["stock_list"].as_array().unwrap() {
        assert!(row["width_mm"].as_f64().unwrap() >= 72.4, "{row}");
    }
}

#[test]
fn a_batch_scores_one_coupon_per_pzt_stock() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("nest");
    let o = bin()
        .args(["nest", "examples/batch.toml", "-o"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let r = nest_report_json(&out);
    let s = steps(&r["build_book"]);
    let coupon = &s[first(&s, "score the test coupon")].1;
    for t in ["0.267mm", "0.191mm", "0.127mm"] {
        let stem = files(&out)
            .into_keys()
            .find(|f| f.starts_with("pzt-coupon-") && f.ends_with(&format!("{t}.svg")))
            .unwrap_or_else(|| panic!("no coupon of the {t} stock"));
        assert!(coupon.contains(stem.trim_end_matches(".svg")), "{coupon}");
    }
}

#[test]
fn laser_settings_come_from_the_template_and_the_rest_are_starting_points() {
    let (dir, design) = with_template(|t| {
        format!(
            "{t}\n[laser.pzt]\nscore = {{ power_percent = 20, speed_mm_per_s = 100, passes = 4, focus_mm = 0.1 }}\n\
             [laser.mold]\ncut = {{ power_percent = 35.5, speed_mm_per_s = 40, passes = 1, focus_mm = 0 }}\n"
        )
    });
    let out = dir.path().join("out");
    let o = cut_sheet(design.to_str().unwrap(), &out, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let s = steps(&report_json(&out)["build_book"]);
    let set = &s[first(&s, "Set the laser up")].1;
    assert!(
        set.contains(
            "pzt score: 20 % power, 100 mm/s, 4 passes, focus 0.1 mm below the top surface"
        ),
        "{set}"
    );
    assert!(
        set.contains("mold cut: 35.5 % power, 40 mm/s, 1 pass, focus on the top surface"),
        "{set}"
    );
    // What the template leaves out is a starting point, never a given setting: the other layers' cuts
    // and every engraving; the PZT's score and the mold's cut are not among them.
    let (_, missing) = set
        .split_once("Not in the template")
        .expect("starting points");
    assert!(
        missing
            .contains("cut on passive, felt, teflon-cover, porous-teflon, bleeder (starting point"),
        "{missing}"
    );
    assert!(!missing.contains("score on pzt"), "{missing}");

    // The shipped templates give no settings: every operation is a starting point.
    let (_d, _o, r) = cut("examples/thesis-C.toml");
    let s = steps(&r["build_book"]);
    let set = &s[first(&s, "Set the laser up")].1;
    assert!(!set.contains("From the template") && set.contains("score on pzt (starting point"));

    // A layer the template does not have is refused, naming it and the nearest one.
    let (dir, design) = with_template(|t| format!("{t}\n[laser.pztt]\n"));
    let o = cut_sheet(design.to_str().unwrap(), &dir.path().join("out"), &[]);
    let e = refused_in_one_line(&o);
    assert!(e.contains("laser.pztt") && e.contains("`pzt`"), "{e}");
}

#[test]
fn the_dowels_stand_through_the_molds_and_below_the_top_layer() {
    let (_dir, _out, r) = cut("examples/thesis-C.toml");
    let s = steps(&r["build_book"]);
    let dowels = &s[first(&s, "Stand the registration dowels")].1;
    // The method-2 stack, from the template's thicknesses and the report's mold films: felt 1,
    // Teflon cover 0.05, the molds, porous Teflon 0.05, bleeder 0.3, Teflon cover 0.05, felt 1.
    let films: f64 = r["mold"]["films_mm"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f.as_f64().unwrap())
        .sum();
    let reach = 1.0 + 0.05 + films;
    let stack = reach + 0.05 + 0.3 + 0.05 + 1.0;
    let below = stack - 1.0;
    let text = format!("standing {reach:.3} to {below:.3} mm above the plate");
    assert!(dowels.contains(&text), "{text} in {dowels}");
    assert!(
        dowels.contains(&format!("the stack is {stack:.3} mm")),
        "{dowels}"
    );
    assert!(dowels.contains("Ø1.5 mm") && dowels.contains("80 µm of clearance"));
    // A dowel larger than its hole is refused.
    let (dir, design) =
        with_template(|t| t.replace("dowel_diameter_mm = 1.5", "dowel_diameter_mm = 1.6"));
    let e = refused_in_one_line(&cut_sheet(
        design.to_str().unwrap(),
        &dir.path().join("o"),
        &[],
    ));
    assert!(
        e.contains("clamp.dowel_diameter_mm = 1.6: larger than the pin holes"),
        "{e}"
    );
}

#[test]
fn the_measuring_step_and_the_clamp_force_are_the_press_fits_numbers() {
    let (_dir, _out, r) = cut("examples/thesis-C.toml");
    let s = steps(&r["build_book"]);
    let measure = first(&s, "measure with a micrometer");
    assert!(measure < first(&s, "Cut the mold sheets"));
    let proud = r["mold"]["press_fit"][0]["proud_um"].as_f64().unwrap();
    let tolerance = r["mold"]["tolerance_um"].as_f64().unwrap();
    let text = format!(
        "stands {proud:.1} µm proud of its mold: each plate may measure up to {:.1} µm under or {:.1} µm over",
        proud / 2.0,
        (tolerance - proud) / 2.0
    );
    assert!(s[measure].1.contains(&text), "{text} in {}", s[measure].1);
    // The force is the template's 100 kPa over the passive parts of the panel: 6 actuators on one
    // panel, each passive part's area from the layer row (kPa x mm² = mN).
    let passive = r["layers"]
        .as_array()
        .unwrap()
        .iter()
        .find(|l| l["layer"] == "passive")
        .unwrap();
    let area = passive["part_area_mm2"].as_f64().unwrap() * r["quantity"].as_f64().unwrap();
    let close = &s[first(&s, "Close the clamp")].1;
    let text = format!("100 kPa on the parts (the template's `cure.pressure_kPa`), for the fullest panel {:.1} N over {area:.1} mm²", 0.1 * area);
    assert!(close.contains(&text), "{text} in {close}");
}

#[test]
fn every_book_ends_with_the_functional_check() {
    for example in ["examples/thesis-C.toml", "examples/thesis-C-method-1.toml"] {
        let (_dir, _out, r) = cut(example);
        let sections = r["build_book"]["sections"].as_array().unwrap();
        assert_eq!(sections.last().unwrap()["title"], "Functional check");
        let s = steps(&r["build_book"]);
        let p = &r["predicted"];
        assert_eq!(p["model"], "original");
        // Capacitance: ε0 K33 A / t_p of the drawn plate, written out (K33 = 3800, PZT-5H, docs/physics.md §8).
        let area = r["layers"][0]["part_area_mm2"].as_f64().unwrap();
        let c_nf = 8.854_187_812_8e-12 * 3800.0 * area * 1e-6 / 0.267e-3 * 1e9;
        assert!((c_nf - p["capacitance_nF"].as_f64().unwrap()).abs() < 1e-9);
        let cap = &s[first(&s, "LCR meter")].1;
        assert!(
            cap.contains(&format!(
                "Expected {c_nf:.2} nF per plate, {:.2} to {:.2} nF",
                0.8 * c_nf,
                1.2 * c_nf
            )),
            "{cap}"
        );
        // Mass: from the model's to the model's plus the thesis' resin, ζ = 0.94 of the carbon (eq. 4.3).
        let m = p["mass_mg"].as_f64().unwrap();
        let cf = p["mass_breakdown_mg"]["passive"].as_f64().unwrap();
        let weigh = first(&s, "weigh each actuator");
        assert!(weigh < first(&s, "wires on with silver epoxy"));
        assert!(
            s[weigh]
                .1
                .contains(&format!("{m:.2} mg to {:.2} mg", m + 0.94 * cf)),
            "{}",
            s[weigh].1
        );
        // Bend: at 100 V/mm, the model's free deflection scaled by the field, the lower bound the
        // thesis' eq. 4.4 factor of it.
        let bend = &s[first(&s, "polarity, bend and poling")].1;
        let field = p["field_V_per_mm"].as_f64().unwrap();
        let delta = p["free_deflection_mm"].as_f64().unwrap() * 100.0 / field;
        let l_r = r["design"]["extension_ratio"].as_f64().unwrap();
        let f = -0.490 * l_r * l_r + 0.204 * l_r + 0.645;
        assert!(
            bend.contains(&format!("at {:.1} V (100 V/mm", 100.0 * 0.267))
                && bend.contains(&format!("{:.4} to {delta:.4} mm", f * delta))
                && bend.contains("toward the dotted face"),
            "{bend}"
        );
    }
}

#[test]
fn a_stack_clamp_names_every_panel_it_holds() {
    // thesis-7 x 8: three panels in one clamp stack, the first two one run of identical sheets.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = cut_sheet("examples/thesis-7.toml", &out, &["--quantity", "8"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let r = report_json(&out);
    assert_eq!(r["clamp_panels"], 3);
    let s = steps(&r["build_book"]);
    let (title, lay) = &s[first(&s, "Lay mold-1:")];
    assert_eq!(title, "Stack clamp 1 (panels 1-3)");
    assert!(
        lay.contains("mold-1-1to2_") && lay.contains("mold-1-3_"),
        "{lay}"
    );
}

#[test]
fn the_linkage_cures_on_the_templates_cycle() {
    // The shipped [linkage.cure]: the prepreg's 2 h at 350 F (thesis §3.2.2), at the Pyralux LF
    // datasheet's 2070 kPa, in the steps and in the report.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    cut_linkage_example(&out);
    let r = report_json(&out);
    let steps: Vec<&str> = r["linkage"]["build_steps"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s.as_str().unwrap())
        .collect();
    let cure = steps
        .iter()
        .find(|s| s.starts_with("Cure the stack"))
        .unwrap();
    assert!(
        cure.contains("2 h at 177 °C (350 F)")
            && cure.contains("(2070 kPa on the parts)")
            && cure.contains("`[linkage.cure]`"),
        "{cure}"
    );
    assert!(r["linkage"]["cure"].is_string());
    // The stock list buys the linkage's sheets: each layer file one sheet of its stock (two carbon,
    // two adhesive, one film per panel); the release cut runs through the laminate, no stock of its own.
    let files: Vec<String> = files(&out).into_keys().collect();
    for (stock, layers) in [
        ("CF-thesis (3 plies)", 2),
        ("Pyralux LF", 2),
        ("Kapton HN", 1),
    ] {
        let row = r["stock_list"]
            .as_array()
            .unwrap()
            .iter()
            .find(|row| row["material"].as_str().unwrap().starts_with(stock))
            .unwrap_or_else(|| panic!("no {stock} on the stock list: {}", r["stock_list"]));
        let panels = r["linkage"]["panels"].as_u64().unwrap();
        assert_eq!(row["sheets"].as_u64(), Some(layers * panels), "{row}");
    }
    // The release cut runs with the stack on its dowels: its four pin holes are grey guides, never
    // run, and only the mounting holes are cut.
    let release = files
        .iter()
        .find(|f| f.starts_with("linkage-6-release-1") && f.ends_with(".svg"))
        .unwrap();
    let svg = std::fs::read_to_string(out.join(release)).unwrap();
    let circles = |colour: &str| {
        svg.lines()
            .filter(|l| l.contains(" A") && l.contains(&format!("stroke=\"{colour}\"")))
            .count()
    };
    assert_eq!(circles("#808080"), 4, "{svg}");
    assert_eq!(
        circles("#FF0000") as u64,
        r["quantity"].as_u64().unwrap(),
        "{svg}"
    );
    assert!(!r["stock_list"]
        .to_string()
        .contains("laminated linkage stack"));
    // Joint B folded at assembly and turning on the fold: ε = t β / (2 L) over B's unbonded film at its
    // largest bend β from flat (docs/physics.md §16.7; B is as wide as the strip, so L is the gap and both
    // cut-backs), within the film's limit, and the assembly step states it.
    let b = &r["linkage"]["flexures"][1];
    let f = |k: &str| b[k].as_f64().unwrap();
    let strain = f("film_um") * f("peak_bend_deg").to_radians() / (2.0 * f("unbonded_um"));
    assert!((strain - f("peak_strain")).abs() < 1e-12, "{strain}");
    assert!(strain <= f("strain_limit"), "{strain}");
    // The turn adds to the fold (β - β(θ0) = φ_B, docs/physics.md §16.7): the film's largest bend past
    // its fold is the joint's largest turn toward the fold, so more than nothing and at most its largest
    // turn either way.
    let past_fold = f("peak_bend_deg") - f("assembly_fold_deg");
    assert!(
        past_fold > 0.0 && past_fold <= f("peak_rotation_deg") + 1e-9,
        "{b}"
    );
    let step = steps
        .iter()
        .find(|s| s.starts_with("Fold the crank"))
        .unwrap();
    assert!(
        step.contains(&format!(
            "Joint B folds {:.1}° here and turns on that fold in flight: its film bends up to {:.1}° from flat, {:.2} % strain over its {:.1} µm of unbonded film (t β / (2 L)), within the film's 3.00 %",
            f("assembly_fold_deg"),
            f("peak_bend_deg"),
            strain * 100.0,
            f("unbonded_um")
        )),
        "{step}"
    );
    // The pin holes as cut (the drawn radius and half the kerf) take the template's Ø1.5 mm dowels
    // with the clearance the stacking step states: a clearance fit, never an interference.
    let carbon = files
        .iter()
        .find(|f| f.starts_with("linkage-1-carbon-1") && f.ends_with(".svg"))
        .unwrap();
    let svg = std::fs::read_to_string(out.join(carbon)).unwrap();
    let kerf = r["linkage"]["kerf_mm"].as_f64().unwrap();
    let radii: Vec<f64> = svg
        .lines()
        .filter_map(|l| l.split(" A").nth(1))
        .map(|arc| arc.split(' ').next().unwrap().parse::<f64>().unwrap())
        .collect();
    assert_eq!(radii.len(), 4, "{svg}");
    let dowel = 1.5;
    for r in radii {
        let hole = 2.0 * (r + kerf / 2.0);
        assert!(hole > dowel, "Ø{hole} mm hole on a Ø{dowel} mm dowel");
        let stack = steps.iter().find(|s| s.starts_with("Stack on")).unwrap();
        let fit = format!(
            "dowels of Ø1.5 mm (the template's `clamp.dowel_diameter_mm`) in the Ø{hole:.2} mm pin holes, {:.0} µm of clearance",
            (hole - dowel) * 1e3
        );
        assert!(stack.contains(&fit), "{fit}\n{stack}");
    }
}
