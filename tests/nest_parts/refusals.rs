//! Bad drawings refused in one line naming the file and the entity: open, self-intersecting, unitless,
//! too large, unsupported or crossing contours, and parts the nester would refuse.

use super::*;

#[test]
fn an_open_contour_is_refused_naming_its_entity() {
    let open = dxf_text(
        Some(4),
        &[lwpolyline(
            "2F",
            &[(0.0, 0.0, 0.0), (10.0, 0.0, 0.0), (10.0, 5.0, 0.0)],
            false,
        )],
    );
    let err = refused("open.dxf", &open, "");
    assert!(err.contains("LWPOLYLINE handle 2F: open contour"), "{err}");
    let open = svg(
        "20mm",
        "20mm",
        " viewBox=\"0 0 20 20\"",
        "<path id=\"wing\" d=\"M 1 1 L 10 1 L 10 8\"/>",
    );
    let err = refused("open.svg", &open, "");
    assert!(err.contains("<path id=\"wing\">: open contour"), "{err}");
}

#[test]
fn a_self_intersecting_contour_is_refused_naming_its_entity() {
    let bow_tie = dxf_text(
        Some(4),
        &[lwpolyline(
            "3A",
            &[
                (0.0, 0.0, 0.0),
                (10.0, 10.0, 0.0),
                (10.0, 0.0, 0.0),
                (0.0, 6.0, 0.0),
            ],
            true,
        )],
    );
    let err = refused("bow-tie.dxf", &bow_tie, "");
    assert!(
        err.contains("LWPOLYLINE handle 3A: self-intersecting contour"),
        "{err}"
    );
    let bow_tie = svg(
        "20mm",
        "20mm",
        " viewBox=\"0 0 20 20\"",
        "<polygon points=\"0,0 10,10 10,0 0,6\"/>",
    );
    let err = refused("bow-tie.svg", &bow_tie, "");
    assert!(
        err.contains("<polygon> #1 (no id): self-intersecting contour"),
        "{err}"
    );
    // A symmetric bow-tie: its two lobes cancel to a signed area of zero, yet its points do not lie
    // on one line, so it is a crossing, not a degenerate contour.
    let symmetric = svg(
        "20mm",
        "20mm",
        " viewBox=\"0 0 20 20\"",
        "<polygon id=\"tie\" points=\"0,0 10,10 10,0 0,10\"/>",
    );
    let err = refused("symmetric-bow-tie.svg", &symmetric, "");
    assert!(
        err.contains("<polygon id=\"tie\">: self-intersecting contour"),
        "{err}"
    );
    // Points on one line are still a zero-area contour.
    let flat = svg(
        "20mm",
        "20mm",
        " viewBox=\"0 0 20 20\"",
        "<polygon id=\"flat\" points=\"0,0 5,5 10,10\"/>",
    );
    let err = refused("flat.svg", &flat, "");
    assert!(err.contains("<polygon id=\"flat\">: zero area"), "{err}");
}

#[test]
fn missing_units_are_refused() {
    let square = lwpolyline(
        "10",
        &[
            (0.0, 0.0, 0.0),
            (5.0, 0.0, 0.0),
            (5.0, 5.0, 0.0),
            (0.0, 5.0, 0.0),
        ],
        true,
    );
    let err = refused(
        "unitless.dxf",
        &dxf_text(None, std::slice::from_ref(&square)),
        "",
    );
    assert!(
        err.contains("header $INSUNITS = 0 or missing (unitless)"),
        "{err}"
    );
    let err = refused(
        "unitless.svg",
        &svg(
            "20",
            "20mm",
            " viewBox=\"0 0 20 20\"",
            "<rect width=\"5\" height=\"5\"/>",
        ),
        "",
    );
    assert!(err.contains("<svg> width = \"20\" (no unit)"), "{err}");
    let err = refused(
        "no-viewbox.svg",
        &svg("20mm", "20mm", "", "<rect width=\"5\" height=\"5\"/>"),
        "",
    );
    assert!(err.contains("<svg> viewBox = missing"), "{err}");
}

#[test]
fn units_other_than_mm_are_refused() {
    let square = lwpolyline(
        "10",
        &[
            (0.0, 0.0, 0.0),
            (5.0, 0.0, 0.0),
            (5.0, 5.0, 0.0),
            (0.0, 5.0, 0.0),
        ],
        true,
    );
    let err = refused("inches.dxf", &dxf_text(Some(1), &[square]), "");
    assert!(
        err.contains("header $INSUNITS = 1 (Inches): parts must be drawn in millimetres"),
        "{err}"
    );
    let err = refused(
        "inches.svg",
        &svg(
            "2in",
            "2in",
            " viewBox=\"0 0 2 2\"",
            "<rect width=\"1\" height=\"1\"/>",
        ),
        "",
    );
    assert!(err.contains("<svg> width = \"2in\" (not mm)"), "{err}");
}

#[test]
fn a_part_the_nester_would_refuse_is_refused_by_the_batch_reader_naming_its_entity() {
    // 0.35 mm separation (kerf 0.05 + spacing 0.3) on an 80 mm roll: a 79.29 mm part leaves
    // 0.355 mm to each edge, more than the separation, but not the nester's working gap (its
    // model keeps 1 % more plus a margin of a few f32 steps, half that margin again of start
    // clearance, and 5 µm more to each edge for rounding, cam_nest::fits_empty_sheet).
    // The reader applies the nester's own check, so the refusal names the entity before any
    // nesting, rather than the nester refusing it later without the drawing's entity.
    let (dir, batch) = scratch(
        0.05,
        "[[item]]\ndesign = \"thesis-C.toml\"\nquantity = 2\n",
        "[[part]]\nfile = \"parts/bar.dxf\"\nquantity = 1\nlayup_deg = [0, 90, 0]\nfibre_axis_deg = 90\n\n\
         [sheets]\nprepreg = { width_mm = 80, strip = true }\nspacing_mm = 0.3\n",
    );
    let bar = |width: f64| {
        dxf_text(
            Some(4),
            &[lwpolyline(
                "5C",
                &[
                    (0.0, 0.0, 0.0),
                    (width, 0.0, 0.0),
                    (width, 3.0, 0.0),
                    (0.0, 3.0, 0.0),
                ],
                true,
            )],
        )
    };
    let file = dir.path().join("parts/bar.dxf");
    std::fs::write(&file, bar(79.29)).unwrap();
    let err = refusal(&batch);
    assert!(
        err.contains(&file.display().to_string())
            && err.contains("LWPOLYLINE handle 5C: part too large: 79.290 x 3.000 mm"),
        "{err}"
    );
    // 0.03 mm narrower fits the nester's gap too, and nests.
    std::fs::write(&file, bar(79.26)).unwrap();
    nest_ok(&batch, &dir.path().join("out"), "20");
}

#[test]
fn the_readers_size_check_is_the_nesters() {
    // Bars 79.20-79.35 mm long across an 80 mm strip and on 80 x 20 mm sheets, 0.35 mm apart:
    // cam_nest::fits_empty_sheet says yes exactly when the nester takes the bar.
    let settings = cam_nest::NestSettings {
        separation_mm: 0.35,
        seed: 1,
        iterations: 0,
        workers: 1,
    };
    let (mut yes, mut no) = (0, 0);
    for k in 0..=15 {
        let w = 79.20 + 0.01 * k as f64;
        let item = cam_nest::NestItem {
            outline: vec![[0.0, 0.0], [w, 0.0], [w, 3.0], [0.0, 3.0]],
            demand: 1,
            rotations_deg: vec![0.0, 180.0],
        };
        let items = [item.clone()];
        let strip = cam_nest::fits_empty_sheet(
            &item.outline,
            &item.rotations_deg,
            80.0,
            f64::INFINITY,
            0.35,
        );
        let nested = cam_nest::nest_strip(&items, 80.0, &settings, &|_| {});
        assert_eq!(strip.fits, nested.is_ok(), "{w} mm: {nested:?}");
        if let Err(e) = nested {
            assert!(
                matches!(e, cam_nest::NestError::PartLargerThanBin { .. }),
                "{e:?}"
            );
        }
        let sheet =
            cam_nest::fits_empty_sheet(&item.outline, &item.rotations_deg, 80.0, 20.0, 0.35);
        let bin = cam_nest::NestBin {
            width_mm: 80.0,
            height_mm: 20.0,
            stock: 1,
        };
        assert_eq!(
            sheet.fits,
            cam_nest::nest(&items, &bin, &settings).is_ok(),
            "{w} mm"
        );
        if strip.fits {
            yes += 1
        } else {
            no += 1
        }
    }
    assert!(
        yes > 0 && no > 0,
        "the range straddles the limit: {yes} fit, {no} do not"
    );
}

#[test]
fn on_a_long_strip_the_nesters_refusal_names_the_gap_it_needs() {
    // 20 panels of 70 x 700 mm make about 14 m of strip, where the nester's f32 margin is some
    // hundredths of a millimetre: a bar that one part's check lets through is refused, and the
    // edge gap the refusal gives is the one that takes it. (Few long parts rather than many
    // squares: the strip's length sets the margin, the count only the time.)
    let settings = cam_nest::NestSettings {
        separation_mm: 0.35,
        seed: 1,
        iterations: 0,
        workers: 1,
    };
    let panel = cam_nest::NestItem {
        outline: vec![[0.0, 0.0], [70.0, 0.0], [70.0, 700.0], [0.0, 700.0]],
        demand: 20,
        rotations_deg: vec![0.0],
    };
    let bar = |w: f64| cam_nest::NestItem {
        outline: vec![[0.0, 0.0], [w, 0.0], [w, 3.0], [0.0, 3.0]],
        demand: 1,
        rotations_deg: vec![0.0],
    };
    let w = 79.27;
    let alone = cam_nest::fits_empty_sheet(&bar(w).outline, &[0.0], 80.0, f64::INFINITY, 0.35);
    assert!(alone.fits, "{alone:?}");
    let err = cam_nest::nest_strip(&[panel.clone(), bar(w)], 80.0, &settings, &|_| {})
        .expect_err("the margin of 20 m of parts refuses the bar");
    let message = err.to_string();
    assert!(
        message.ends_with("does not fit the 80 mm wide strip"),
        "{message}"
    );
    let cam_nest::NestError::PartLargerThanBin {
        item, edge_gap_mm, ..
    } = err
    else {
        panic!("{err:?}")
    };
    assert_eq!(item, 1);
    assert!(
        edge_gap_mm > alone.edge_gap_mm && w + 2.0 * edge_gap_mm >= 80.0,
        "{edge_gap_mm} against {alone:?}"
    );
    // Narrower by what the refusal says is missing (and a micrometre), or by 0.4 or 0.8 mm more,
    // the bar is taken: its only room is a band at the top of the strip, which the
    // construction's sampled starts can miss.
    for k in 0..3 {
        let narrower = 80.0 - 2.0 * edge_gap_mm - 0.001 - 0.4 * k as f64;
        let items = [panel.clone(), bar(narrower)];
        let strip = cam_nest::nest_strip(&items, 80.0, &settings, &|_| {})
            .unwrap_or_else(|e| panic!("{narrower} mm: {e}"));
        cam_nest::verify(&items, &strip.bin, &settings, &strip.solution, 1e-9)
            .unwrap_or_else(|v| panic!("{narrower} mm: {v:?}"));
    }
}

#[test]
fn a_part_too_large_for_the_sheet_is_refused_naming_its_entity() {
    // The example batch's prepreg sheets are the template's; a 500 mm spar fits none of them.
    let long = dxf_text(
        Some(4),
        &[lwpolyline(
            "4B",
            &[
                (0.0, 0.0, 0.0),
                (500.0, 0.0, 0.0),
                (500.0, 3.0, 0.0),
                (0.0, 3.0, 0.0),
            ],
            true,
        )],
    );
    let err = refused("long.dxf", &long, "");
    assert!(
        err.contains("LWPOLYLINE handle 4B: part too large: 500.000 x 3.000 mm"),
        "{err}"
    );
    let long = svg(
        "600mm",
        "20mm",
        " viewBox=\"0 0 600 20\"",
        "<rect id=\"beam\" width=\"500\" height=\"3\"/>",
    );
    let err = refused("long.svg", &long, "");
    assert!(err.contains("<rect id=\"beam\">: part too large"), "{err}");
}

#[test]
fn a_drawing_without_a_closed_contour_is_refused() {
    let err = refused("empty.dxf", &dxf_text(Some(4), &[text_entity("5C")]), "");
    assert!(err.contains("no closed contour"), "{err}");
    let err = refused(
        "empty.svg",
        &svg(
            "20mm",
            "20mm",
            " viewBox=\"0 0 20 20\"",
            "<text>spar</text>",
        ),
        "",
    );
    assert!(err.contains("no closed contour"), "{err}");
}

#[test]
fn unsupported_entities_and_crossing_contours_are_refused_naming_them() {
    let spline = dxf_text(
        Some(4),
        &[codes(&[
            (0, "SPLINE".into()),
            (5, "6D".into()),
            (100, "AcDbEntity".into()),
            (8, "0".into()),
            (100, "AcDbSpline".into()),
        ])],
    );
    let err = refused("spline.dxf", &spline, "");
    assert!(
        err.contains("SPLINE handle 6D: not a supported part entity"),
        "{err}"
    );
    let crossing = svg(
        "20mm",
        "20mm",
        " viewBox=\"0 0 20 20\"",
        "<rect id=\"a\" width=\"5\" height=\"5\"/><rect id=\"b\" x=\"3\" y=\"3\" width=\"5\" height=\"5\"/>",
    );
    let err = refused("crossing.svg", &crossing, "");
    assert!(
        err.contains("<rect id=\"b\">: crosses or touches <rect id=\"a\">"),
        "{err}"
    );
}

// ---- No panic on any drawing ------------------------------------------------------------------

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(128))]

    /// Path data of random commands and numbers (arcs with any radii and flags, curves, NaN-free
    /// but huge or tiny values): the importer returns parts or one error naming the file.
    #[test]
    fn random_svg_paths_never_panic(
        cmds in proptest::collection::vec(
            (proptest::sample::select(vec!["M", "L", "H", "V", "C", "S", "Q", "T", "A", "Z", "m", "l", "a", "c"]),
             proptest::collection::vec(-1e6f64..1e6, 0..8)),
            0..12),
    ) {
        let d: String = cmds
            .iter()
            .map(|(c, n)| {
                let nums: Vec<String> = n.iter().map(|x| format!("{x}")).collect();
                format!("{c} {} ", nums.join(" "))
            })
            .collect();
        let text = svg("20mm", "20mm", " viewBox=\"0 0 20 20\"", &format!("<path d=\"{d}\"/>"));
        let (_dir, path) = write_temp("random.svg", &text);
        if let Err(e) = actuator_cam::import_parts(&path) {
            let line = e.to_string();
            proptest::prop_assert!(line.starts_with(&path.display().to_string()));
            proptest::prop_assert_eq!(line.lines().count(), 1);
        }
    }

    /// Polylines of random vertices and bulges, open or closed, with circles of any radius.
    #[test]
    fn random_dxf_polylines_never_panic(
        vertices in proptest::collection::vec((-1e4f64..1e4, -1e4f64..1e4, -20f64..20.0), 0..10),
        closed in proptest::bool::ANY,
        r in -5f64..1e5,
    ) {
        let text = dxf_text(Some(4), &[lwpolyline("1", &vertices, closed), circle("2", [0.0, 0.0], r)]);
        let (_dir, path) = write_temp("random.dxf", &text);
        if let Err(e) = actuator_cam::import_parts(&path) {
            let line = e.to_string();
            proptest::prop_assert!(line.starts_with(&path.display().to_string()));
            proptest::prop_assert_eq!(line.lines().count(), 1);
        }
    }
}
