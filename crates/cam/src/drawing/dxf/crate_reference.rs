//! A DXF writer built on the `dxf` crate: the independent implementation the emitter in [`super`] is held
//! to, byte for byte (tests only).

use dxf::entities::{Arc, Circle, Entity, EntityType, LwPolyline};
use dxf::enums::{AcadVersion, DrawingUnits, Units};
use dxf::tables::Layer;
use dxf::{Color, LwPolylineVertex};

use crate::drawing::model::{Drawing, Operation, Shape};
use crate::drawing::palette::Palette;

/// Header values the crate would otherwise take from the clock and the random generator. The
/// crate's date fields are `chrono` local-time values; they are read through the crate's own
/// header parser, whose local-time conversion is the exact inverse of its writer. The reader
/// truncates to whole seconds and adds one second that its writer does not remove, so
/// 2460676.49999 is written back as exactly 2460676.5 = 2025-01-01 00:00.
const FIXED_HEADER: &str = "0\nSECTION\n2\nHEADER\n\
9\n$TDCREATE\n40\n2460676.49999\n\
9\n$TDUCREATE\n40\n2460676.49999\n\
9\n$TDUPDATE\n40\n2460676.49999\n\
9\n$TDUUPDATE\n40\n2460676.49999\n\
9\n$FINGERPRINTGUID\n2\n{A1C7A3E0-5E2B-4C55-9A7E-0D1F2C3B4A51}\n\
9\n$VERSIONGUID\n2\n{B2D8B4F1-6F3C-4D66-8B8F-1E2A3D4C5B62}\n\
0\nENDSEC\n0\nEOF\n";

fn fixed_document() -> dxf::Drawing {
    let fixed = dxf::Drawing::load(&mut FIXED_HEADER.as_bytes())
        .unwrap()
        .header;
    let mut doc = dxf::Drawing::new();
    let header = &mut doc.header;
    header.version = AcadVersion::R2000;
    header.creation_date = fixed.creation_date;
    header.creation_date_universal = fixed.creation_date_universal;
    header.update_date = fixed.update_date;
    header.update_date_universal = fixed.update_date_universal;
    header.fingerprint_guid = fixed.fingerprint_guid;
    header.version_guid = fixed.version_guid;
    header.drawing_units = DrawingUnits::Metric;
    header.default_drawing_units = Units::Millimeters;
    doc
}

fn vertices(points: &[cam_geometry::Point]) -> Vec<LwPolylineVertex> {
    points
        .iter()
        .map(|p| LwPolylineVertex {
            x: p[0],
            y: p[1],
            ..Default::default()
        })
        .collect()
}

fn entity(op: Operation, shape: &Shape) -> Entity {
    let specific = match shape {
        Shape::Polygon(ring) => {
            let mut poly = LwPolyline {
                vertices: vertices(ring),
                ..Default::default()
            };
            poly.set_is_closed(true);
            EntityType::LwPolyline(poly)
        }
        Shape::Polyline(path) => EntityType::LwPolyline(LwPolyline {
            vertices: vertices(path),
            ..Default::default()
        }),
        Shape::Circle { center, radius } => EntityType::Circle(Circle::new(
            dxf::Point::new(center[0], center[1], 0.0),
            *radius,
        )),
        Shape::Arc {
            center,
            radius,
            start_deg,
            end_deg,
        } => EntityType::Arc(Arc::new(
            dxf::Point::new(center[0], center[1], 0.0),
            *radius,
            *start_deg,
            *end_deg,
        )),
    };
    let mut entity = Entity::new(specific);
    entity.common.layer = op.layer_name().to_string();
    entity
}

/// `drawing` written by the crate, with the TABLE head handles added.
pub(super) fn crate_dxf(drawing: &Drawing, palette: &Palette) -> Vec<u8> {
    let mut doc = fixed_document();
    doc.header.maximum_drawing_limits = dxf::Point::new(drawing.width_mm, drawing.height_mm, 0.0);
    if let Some((lo, hi)) = drawing.extents() {
        doc.header.minimum_drawing_extents = dxf::Point::new(lo[0], lo[1], 0.0);
        doc.header.maximum_drawing_extents = dxf::Point::new(hi[0], hi[1], 0.0);
    }
    for op in drawing.operations() {
        doc.add_layer(Layer {
            name: op.layer_name().to_string(),
            color: Color::from_index(palette.aci(op)),
            is_layer_plotted: op != Operation::Reference,
            ..Default::default()
        });
        for shape in drawing.shapes_of(op) {
            doc.add_entity(entity(op, shape));
        }
    }
    let mut bytes = Vec::new();
    doc.save(&mut bytes).unwrap();
    add_table_head_handles(&bytes)
}

/// Inserts `5 <handle>` and `330 0` after the `0 TABLE / 2 <name>` pairs of each table head,
/// taking handles from `$HANDSEED` and advancing it.
fn add_table_head_handles(bytes: &[u8]) -> Vec<u8> {
    const EOL: &str = "\r\n";
    let text = std::str::from_utf8(bytes).unwrap();
    let lines: Vec<&str> = text.split(EOL).collect();
    let pairs: Vec<(&str, &str)> = lines
        .chunks(2)
        .filter(|c| c.len() == 2)
        .map(|c| (c[0], c[1]))
        .collect();
    let is = |pair: (&str, &str), code: i32, value: &str| {
        pair.1 == value && pair.0.trim().parse::<i32>() == Ok(code)
    };
    let seed_at = pairs.iter().position(|&p| is(p, 9, "$HANDSEED")).unwrap() + 1;
    let seed = u64::from_str_radix(pairs[seed_at].1, 16).unwrap();
    let after_table_name =
        |i: usize| i > 0 && pairs[i].0.trim() == "2" && is(pairs[i - 1], 0, "TABLE");
    let heads = (0..pairs.len()).filter(|&i| after_table_name(i)).count() as u64;
    let mut fixed = String::new();
    let mut next_handle = seed;
    for (i, &(code, value)) in pairs.iter().enumerate() {
        fixed.push_str(code);
        fixed.push_str(EOL);
        if i == seed_at {
            fixed.push_str(&format!("{:X}", seed + heads));
        } else {
            fixed.push_str(value);
        }
        fixed.push_str(EOL);
        if after_table_name(i) {
            fixed.push_str(&format!("  5{EOL}{next_handle:X}{EOL}330{EOL}0{EOL}"));
            next_handle += 1;
        }
    }
    fixed.into_bytes()
}
