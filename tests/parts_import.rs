//! The limits of reading a part drawing: time linear in its vertices, a curve's size checked before it
//! is cut into chords, a nesting depth, and the values a drawing cannot mean (a NaN bulge, an outline
//! narrower than a laser can cut), each refused in one line naming the file and the entity.

use crate::common;
use crate::nest_parts::{circle, dxf_text, lwpolyline, refused, svg};
use common::*;
use std::f64::consts::PI;

/// `n` vertices on a circle of radius 50 mm whose radius wobbles by 1 mm, 7 waves round: a simple
/// ring with every vertex a corner.
fn wavy_ring(n: usize) -> Vec<(f64, f64, f64)> {
    (0..n)
        .map(|i| {
            let a = 2.0 * PI * i as f64 / n as f64;
            let r = 50.0 + (7.0 * a).sin();
            (60.0 + r * a.cos(), 60.0 + r * a.sin(), 0.0)
        })
        .collect()
}

#[test]
fn a_ring_of_20000_vertices_imports_in_well_under_a_few_seconds_from_dxf_and_svg() {
    // Testing every pair of edges for a crossing took 17.6 s for 10,000 vertices and grew as the
    // square; the sweep line takes some tens of milliseconds for 20,000 (docs/benchmarks.md). 4 s
    // leaves room for a loaded machine and still fails a quadratic check many times over.
    let ring = wavy_ring(20_000);
    let d: String = ring
        .iter()
        .enumerate()
        .map(|(i, (x, y, _))| format!("{}{x} {y} ", if i == 0 { "M" } else { "L" }))
        .collect();
    for (name, text) in [
        (
            "ring.dxf",
            dxf_text(Some(4), &[lwpolyline("2F", &ring, true)]),
        ),
        (
            "ring.svg",
            svg(
                "120mm",
                "120mm",
                " viewBox=\"0 0 120 120\"",
                &format!("<path id=\"ring\" d=\"{d}Z\"/>"),
            ),
        ),
    ] {
        let (_dir, path) = write_temp(name, &text);
        let start = std::time::Instant::now();
        let parts = actuator_cam::import_parts(&path).unwrap();
        let seconds = start.elapsed().as_secs_f64();
        assert_eq!(parts.len(), 1);
        assert_eq!(parts[0].outer.len(), 20_000, "{name}");
        assert!(seconds < 4.0, "{name}: {seconds} s");
    }
}

#[test]
fn a_huge_curve_is_refused_by_its_extent_before_it_is_cut_into_chords() {
    // A radius of 1e9 mm gave 100,000 chords and 47 s of checks before the batch found the part too
    // large; its analytic extent refuses it at once, naming the entity and the allowed size.
    let limit = "too large for a drawing, which must lie within 2000 x 2000 mm (the largest sheet)";
    let huge_bulge = [(0.0, 0.0, 0.0), (1.0, 0.0, 1e12), (1.0, 1.0, 0.0)];
    for (name, text, entity) in [
        (
            "circle.dxf",
            dxf_text(Some(4), &[circle("2A", [0.0, 0.0], 1e9)]),
            "CIRCLE handle 2A",
        ),
        (
            "bulge.dxf",
            dxf_text(Some(4), &[lwpolyline("3B", &huge_bulge, true)]),
            "LWPOLYLINE handle 3B",
        ),
        (
            "circle.svg",
            svg(
                "100mm",
                "100mm",
                " viewBox=\"0 0 100 100\"",
                "<circle id=\"c\" cx=\"50\" cy=\"50\" r=\"1e9\"/>",
            ),
            "<circle id=\"c\">",
        ),
        (
            "arc.svg",
            svg(
                "100mm",
                "100mm",
                " viewBox=\"0 0 100 100\"",
                "<path id=\"p\" d=\"M 0 0 A 1e9 1e9 0 1 1 1 0 Z\"/>",
            ),
            "<path id=\"p\">",
        ),
    ] {
        let (_dir, path) = write_temp(name, &text);
        let start = std::time::Instant::now();
        let err = match actuator_cam::import_parts(&path) {
            Ok(parts) => panic!("{name}: imported, {} points", parts[0].outer.len()),
            Err(e) => e.to_string(),
        };
        let seconds = start.elapsed().as_secs_f64();
        assert!(
            err.starts_with(&format!("{}: {entity}: ", path.display())) && err.contains(limit),
            "{err}"
        );
        assert!(seconds < 1.0, "{name}: {seconds} s");
    }
    // A path is refused at its first segment past the limit: the message names the side found so
    // far, 3000 mm, not the height its later segments would have given.
    let text = svg(
        "100mm",
        "100mm",
        " viewBox=\"0 0 100 100\"",
        "<path id=\"q\" d=\"M0 0 H3000 V3000 H0 Z\"/>",
    );
    let (_dir, path) = write_temp("square.svg", &text);
    let err = actuator_cam::import_parts(&path).unwrap_err().to_string();
    assert!(
        err.contains("<path id=\"q\">: 3000 mm or more across: too large for a drawing"),
        "{err}"
    );
    // 2000 mm across is allowed.
    let text = dxf_text(Some(4), &[circle("2A", [0.0, 0.0], 999.0)]);
    let (_dir, path) = write_temp("large.dxf", &text);
    actuator_cam::import_parts(&path).unwrap();
}

#[test]
fn groups_nested_past_the_limit_are_refused_in_one_line() {
    // 20,000 nested groups overflowed the stack (exit 134); the walk stops at 256 levels.
    let nested = |levels: usize| {
        svg(
            "20mm",
            "20mm",
            " viewBox=\"0 0 20 20\"",
            &format!(
                "{}<rect width=\"5\" height=\"5\"/>{}",
                "<g>".repeat(levels),
                "</g>".repeat(levels)
            ),
        )
    };
    let err = refused("deep.svg", &nested(20_000), "");
    assert!(
        err.contains("elements nested more than 256 levels deep"),
        "{err}"
    );
    let (_dir, path) = write_temp("deep.svg", &nested(255));
    assert_eq!(actuator_cam::import_parts(&path).unwrap().len(), 1);
}

#[test]
fn a_bulge_that_is_not_a_number_is_refused_naming_the_vertex_and_the_value() {
    let square = [
        (0.0, 0.0, 0.0),
        (5.0, 0.0, f64::NAN),
        (5.0, 5.0, 0.0),
        (0.0, 5.0, 0.0),
    ];
    let (_dir, path) = write_temp(
        "nan.dxf",
        &dxf_text(Some(4), &[lwpolyline("3C", &square, true)]),
    );
    let err = actuator_cam::import_parts(&path).unwrap_err().to_string();
    assert_eq!(
        err,
        format!(
            "{}: LWPOLYLINE handle 3C: vertex 2: bulge (group code 42) NaN: a bulge must be a finite number, tan(θ/4) of the arc's included angle θ",
            path.display()
        )
    );
}

#[test]
fn a_part_narrower_than_the_narrowest_feature_is_refused() {
    let bar = |width: f64| {
        let corners = [
            (0.0, 0.0, 0.0),
            (10.0, 0.0, 0.0),
            (10.0, width, 0.0),
            (0.0, width, 0.0),
        ];
        dxf_text(Some(4), &[lwpolyline("4D", &corners, true)])
    };
    let err = refused("sliver.dxf", &bar(0.001), "");
    assert!(
        err.contains("LWPOLYLINE handle 4D: 0.001 mm wide at its narrowest: a part must be at least 0.1 mm wide"),
        "{err}"
    );
    let (_dir, path) = write_temp("bar.dxf", &bar(0.1));
    assert_eq!(actuator_cam::import_parts(&path).unwrap().len(), 1);
}

#[test]
fn handles_that_are_not_hexadecimal_do_not_stop_the_import() {
    // A lab tool's export names its entities G1 and -1: the geometry reads as any other drawing,
    // and messages name the entities by the handles as written.
    let square = [
        (0.0, 0.0, 0.0),
        (8.0, 0.0, 0.0),
        (8.0, 8.0, 0.0),
        (0.0, 8.0, 0.0),
    ];
    let text = dxf_text(
        Some(4),
        &[
            lwpolyline("G1", &square, true),
            circle("-1", [4.0, 4.0], 1.0),
        ],
    );
    let (_dir, path) = write_temp("lab.dxf", &text);
    let parts = actuator_cam::import_parts(&path).unwrap();
    assert_eq!(parts.len(), 1);
    assert_eq!(parts[0].entity, "LWPOLYLINE handle G1");
    assert_eq!(parts[0].holes.len(), 1);
    assert!((parts[0].area_mm2() - (64.0 - PI)).abs() < 0.05);
    let text = dxf_text(
        Some(4),
        &[
            lwpolyline("G1", &square, true),
            circle("-1", [8.0, 4.0], 1.0),
        ],
    );
    let (_dir, path) = write_temp("lab.dxf", &text);
    let err = actuator_cam::import_parts(&path).unwrap_err().to_string();
    assert!(
        err.contains("CIRCLE handle -1: crosses or touches LWPOLYLINE handle G1"),
        "{err}"
    );
}
