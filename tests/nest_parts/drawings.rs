//! Reading part drawings: the shipped drawings are their generator's, imported areas match closed forms, and
//! lines and arcs chain into the part a bulged polyline draws.

use super::*;

#[test]
fn example_drawings_match_their_generator() {
    // EXAMPLES_UPDATE=1 writes them; otherwise the shipped files must be what this file makes.
    for (name, text) in [("spar.dxf", spar_dxf()), ("flexure.svg", flexure_svg())] {
        let path = example_path(&format!("parts/{name}"));
        if std::env::var_os("EXAMPLES_UPDATE").is_some() {
            std::fs::write(&path, &text).unwrap();
        }
        assert_eq!(
            std::fs::read_to_string(&path).unwrap(),
            text,
            "{name}: regenerate with EXAMPLES_UPDATE=1"
        );
    }
}

#[test]
fn imported_areas_match_the_closed_forms() {
    let spar = actuator_cam::import_parts(&example_path("parts/spar.dxf")).unwrap();
    assert_eq!(spar.len(), 1);
    assert_eq!(spar[0].holes.len(), 1);
    assert_eq!(spar[0].entity, "LWPOLYLINE handle A1");
    let err = (spar[0].area_mm2() - SPAR_AREA_MM2).abs();
    assert!(err <= SPAR_ARCS_MM * TOLERANCE_MM, "spar area off by {err}");
    let flexure = actuator_cam::import_parts(&example_path("parts/flexure.svg")).unwrap();
    assert_eq!(flexure.len(), 1);
    assert_eq!(flexure[0].holes.len(), 1);
    assert_eq!(flexure[0].entity, "<rect id=\"flexure\">");
    let err = (flexure[0].area_mm2() - FLEXURE_AREA_MM2).abs();
    assert!(
        err <= FLEXURE_ARCS_MM * TOLERANCE_MM,
        "flexure area off by {err}"
    );
    // The group's translate(20 20) in tenths of a mm and the y flip: 2 mm in, 10 - 2 mm down.
    let xs = flexure[0].outer.iter().map(|p| p[0]);
    let ys = flexure[0].outer.iter().map(|p| p[1]);
    assert!((xs.clone().fold(f64::INFINITY, f64::min) - 2.0).abs() < 1e-9);
    assert!((xs.fold(0.0, f64::max) - 18.0).abs() < 1e-9);
    assert!((ys.fold(0.0, f64::max) - 8.0).abs() < 1e-9);
}

#[test]
fn lines_and_arcs_chain_into_the_same_part_as_a_polyline_with_a_bulge() {
    // The spar drawn as LINE + ARC + LINE + LINE in scrambled order and direction.
    let text = dxf_text(
        Some(4),
        &[
            line("B1", [0.0, 2.0], [60.0, 1.0]),
            arc("B2", [60.0, 0.0], 1.0, -90.0, 90.0),
            line("B3", [0.0, -2.0], [0.0, 2.0]),
            line("B4", [60.0, -1.0], [0.0, -2.0]),
            circle("B5", [4.0, 0.0], 0.75),
            text_entity("B6"),
        ],
    );
    let (_dir, path) = write_temp("chained.dxf", &text);
    let parts = actuator_cam::import_parts(&path).unwrap();
    assert_eq!(parts.len(), 1);
    let err = (parts[0].area_mm2() - SPAR_AREA_MM2).abs();
    assert!(err <= SPAR_ARCS_MM * TOLERANCE_MM, "off by {err}");
}
