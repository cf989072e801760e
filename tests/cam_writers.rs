//! Writes a sample panel (outline, holes, score lines, label, kerf-compensated part) as SVG and
//! DXF files, the way a layout would, and checks the files on disk.
//!
//! Set `CAM_SAMPLE_DIR=/some/dir` to keep the files there for `tools/check_outputs.py`,
//! Inkscape or LightBurn; otherwise they go to a temporary directory.

use crate::common;
use common::svg_read::{read_svg_polygons, ParseError};
use std::fs;
use std::path::Path;

use actuator_cam::{label_strokes, to_dxf, to_svg, Drawing, Operation, Shape, SvgOptions};
use cam_geometry::offset::offset_ring;
use cam_geometry::signed_area;

fn sample_panel() -> Drawing {
    let mut d = Drawing::new("sample panel #1", 72.4, 40.0);
    let kerf_mm = 0.03;
    // A trapezoid plate with an extension tab, cut out with its outline grown by kerf/2.
    let part = vec![
        [10.0, 5.0],
        [40.0, 12.0],
        [48.0, 12.0],
        [48.0, 18.0],
        [40.0, 18.0],
        [10.0, 25.0],
    ];
    let outline = offset_ring(&part, kerf_mm / 2.0).expect("outline offset");
    // A square via hole, shrunk by kerf/2 (holes take the opposite sign).
    let hole = vec![[20.0, 14.0], [22.0, 14.0], [22.0, 16.0], [20.0, 16.0]];
    let hole = offset_ring(&hole, -kerf_mm / 2.0).expect("hole offset");
    d.add(Operation::Cut, Shape::Polygon(outline));
    d.add(Operation::Cut, Shape::Polygon(hole));
    // Registration pin holes and a fiducial arc.
    for center in [[3.0, 3.0], [69.4, 3.0], [3.0, 37.0], [69.4, 37.0]] {
        d.add(
            Operation::Cut,
            Shape::Circle {
                center,
                radius: 0.79,
            },
        );
    }
    d.add(
        Operation::Secondary,
        Shape::Arc {
            center: [60.0, 30.0],
            radius: 2.0,
            start_deg: 45.0,
            end_deg: 315.0,
        },
    );
    // Score lines run edge to edge with an overrun.
    d.add(
        Operation::Score,
        Shape::Polyline(vec![[-0.5, 30.0], [72.9, 30.0]]),
    );
    for stroke in label_strokes("A1-07 #3", [12.0, 33.0], 2.5) {
        d.add(Operation::Engrave, Shape::Polyline(stroke));
    }
    d
}

fn write_files(dir: &Path, drawing: &Drawing) {
    let svg = to_svg(drawing, &SvgOptions::default());
    fs::write(dir.join("sample_panel.svg"), svg).unwrap();
    fs::write(dir.join("sample_panel.dxf"), to_dxf(drawing).unwrap()).unwrap();
}

#[test]
fn sample_panel_files_are_written_and_read_back() {
    let drawing = sample_panel();
    let tmp = tempfile::tempdir().unwrap();
    write_files(tmp.path(), &drawing);
    if let Ok(keep) = std::env::var("CAM_SAMPLE_DIR") {
        fs::create_dir_all(&keep).unwrap();
        write_files(Path::new(&keep), &drawing);
    }

    let svg = fs::read_to_string(tmp.path().join("sample_panel.svg")).unwrap();
    let polygons = read_svg_polygons(&svg).unwrap();
    assert_eq!(polygons.len(), 2, "outline and via hole");
    let outline_area = signed_area(&polygons[0].1);
    let hole_area = signed_area(&polygons[1].1);
    // 438 mm² part, grown by 0.015 mm along a 103.6 mm perimeter.
    assert!(
        outline_area > 439.4 && outline_area < 439.8,
        "{outline_area}"
    );
    assert!((hole_area - 1.97 * 1.97).abs() < 1e-5, "{hole_area}");

    let dxf_bytes = fs::read(tmp.path().join("sample_panel.dxf")).unwrap();
    assert_eq!(
        dxf_bytes,
        to_dxf(&drawing).unwrap(),
        "same bytes on a second run"
    );
    let doc = dxf::Drawing::load(&mut dxf_bytes.as_slice()).unwrap();
    assert_eq!(doc.entities().count(), drawing.items().len());
}

#[test]
fn every_closed_polygon_comes_back_from_the_svg() {
    let drawing = sample_panel();
    let back = read_svg_polygons(&to_svg(&drawing, &SvgOptions::default())).unwrap();
    let drawn: Vec<(Operation, &Vec<[f64; 2]>)> = drawing
        .items()
        .iter()
        .filter_map(|(op, shape)| match shape {
            Shape::Polygon(ring) => Some((*op, ring)),
            _ => None,
        })
        .collect();
    assert_eq!(back.len(), drawn.len());
    // The page may grow past the sheet by a margin (outlines kerf-offset past its edge), which moves
    // every shape by one offset: the same for all.
    let offset = {
        let (_, first) = &back[0];
        let (_, ring) = drawn.iter().find(|(o, _)| *o == back[0].0).unwrap();
        [first[0][0] - ring[0][0], first[0][1] - ring[0][1]]
    };
    for (op, ring) in &back {
        let close = |r: &Vec<[f64; 2]>| {
            r.len() == ring.len()
                && r.iter().zip(ring).all(|(a, b)| {
                    (a[0] + offset[0] - b[0]).abs() <= 1e-6
                        && (a[1] + offset[1] - b[1]).abs() <= 1e-6
                })
        };
        assert!(
            drawn.iter().any(|(o, r)| o == op && close(r)),
            "{op:?} ring {ring:?} was not drawn"
        );
        assert!(signed_area(ring) > 0.0, "orientation survives the y flip");
    }
}

#[test]
fn the_reader_rejects_relative_commands_and_foreign_colours() {
    let head = "<svg width=\"1mm\" height=\"1mm\" viewBox=\"0 0 1 1\">";
    let rel = format!("{head}<path d=\"m0 0 l1 1 z\" stroke=\"#FF0000\"/></svg>");
    assert!(matches!(
        read_svg_polygons(&rel),
        Err(ParseError::BadPathData(..))
    ));
    let foreign = format!("{head}<path d=\"M0 0 L1 1 Z\" stroke=\"#123456\"/></svg>");
    assert_eq!(
        read_svg_polygons(&foreign),
        Err(ParseError::UnknownColour("#123456".into()))
    );
}
