//! DXF writer: R2000 (AC1015) through the `dxf` crate, byte-reproducible.
//!
//! Conventions (docs/cam.md §3): polygons as closed LWPOLYLINE, polylines as open LWPOLYLINE,
//! CIRCLE and ARC as themselves; one layer per operation with its ACI colour; entities on
//! BYLAYER colour; `$INSUNITS = 4` (mm) and `$MEASUREMENT = 1` (metric; Inkscape's importer
//! reads this one). Entities are written in processing order, like the SVG layers.
//!
//! The `dxf` crate stamps the header with the current time and random GUIDs. We replace them
//! with fixed values so two runs give the same bytes. The crate's date fields are `chrono`
//! local-time values; rather than depend on `chrono` (and on the machine's time zone), we read
//! the fixed values through the crate's own header parser, whose local-time conversion is the
//! exact inverse of its writer, so the written numbers are the ones below on any machine.
//!
//! The crate also writes the `TABLE` heads of the TABLES section without a handle, which
//! ezdxf's audit has to repair ("invalid table head handle"); [`add_table_head_handles`]
//! gives each head a handle from `$HANDSEED` and owner 0, as AutoCAD writes them, so the
//! audit finds nothing to fix.

use dxf::entities::{Arc, Circle, Entity, EntityType, LwPolyline};
use dxf::enums::{AcadVersion, DrawingUnits, Units};
use dxf::tables::Layer;
use dxf::{Color, LwPolylineVertex};
use thiserror::Error;

use super::drawing::{Drawing, Operation, Shape};
use super::palette::Palette;
use cam_geometry::Point;

/// Why a DXF could not be written.
#[derive(Debug, Error)]
pub enum DxfError {
    #[error("dxf library error: {0}")]
    Library(#[from] dxf::DxfError),
    #[error("{op:?} polyline with {count} vertices: a polygon needs at least 3, a polyline 2")]
    TooFewVertices { op: Operation, count: usize },
    #[error("non-finite coordinate in a {0:?} shape")]
    NonFinite(Operation),
    #[error("unexpected output from the dxf library: {0}")]
    Malformed(&'static str),
}

/// Header values the crate would otherwise take from the clock and the random generator.
/// Dates are Julian days; the GUIDs are arbitrary constants. The crate's reader truncates to
/// whole seconds and adds one second that its writer does not remove, so 2460676.49999
/// (2025-01-01 00:00 less 0.86 s) is written back as exactly 2460676.5 = 2025-01-01 00:00.
const FIXED_HEADER: &str = "0\nSECTION\n2\nHEADER\n\
9\n$TDCREATE\n40\n2460676.49999\n\
9\n$TDUCREATE\n40\n2460676.49999\n\
9\n$TDUPDATE\n40\n2460676.49999\n\
9\n$TDUUPDATE\n40\n2460676.49999\n\
9\n$FINGERPRINTGUID\n2\n{A1C7A3E0-5E2B-4C55-9A7E-0D1F2C3B4A51}\n\
9\n$VERSIONGUID\n2\n{B2D8B4F1-6F3C-4D66-8B8F-1E2A3D4C5B62}\n\
0\nENDSEC\n0\nEOF\n";

/// The header read from [`FIXED_HEADER`]: read once per process, as every file needs it.
fn fixed_header() -> Result<&'static dxf::Header, DxfError> {
    static FIXED: std::sync::OnceLock<dxf::Header> = std::sync::OnceLock::new();
    if let Some(h) = FIXED.get() {
        return Ok(h);
    }
    let header = dxf::Drawing::load(&mut FIXED_HEADER.as_bytes())?.header;
    Ok(FIXED.get_or_init(|| header))
}

/// A new crate drawing, R2000, millimetres, with the fixed dates and GUIDs.
fn fixed_document() -> Result<dxf::Drawing, DxfError> {
    let fixed = fixed_header()?.clone();
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
    Ok(doc)
}

fn vertices(
    op: Operation,
    points: &[Point],
    min: usize,
) -> Result<Vec<LwPolylineVertex>, DxfError> {
    if points.len() < min {
        return Err(DxfError::TooFewVertices {
            op,
            count: points.len(),
        });
    }
    Ok(points
        .iter()
        .map(|p| LwPolylineVertex {
            x: p[0],
            y: p[1],
            ..Default::default()
        })
        .collect())
}

fn is_finite(shape: &Shape) -> bool {
    match shape {
        Shape::Polygon(pts) | Shape::Polyline(pts) => pts.iter().flatten().all(|v| v.is_finite()),
        Shape::Circle { center, radius } => center.iter().chain([radius]).all(|v| v.is_finite()),
        Shape::Arc {
            center,
            radius,
            start_deg,
            end_deg,
        } => center
            .iter()
            .chain([radius, start_deg, end_deg])
            .all(|v| v.is_finite()),
    }
}

fn entity(op: Operation, shape: &Shape) -> Result<Entity, DxfError> {
    if !is_finite(shape) {
        return Err(DxfError::NonFinite(op));
    }
    let specific = match shape {
        Shape::Polygon(ring) => {
            let mut poly = LwPolyline {
                vertices: vertices(op, ring, 3)?,
                ..Default::default()
            };
            poly.set_is_closed(true);
            EntityType::LwPolyline(poly)
        }
        Shape::Polyline(path) => EntityType::LwPolyline(LwPolyline {
            vertices: vertices(op, path, 2)?,
            ..Default::default()
        }),
        Shape::Circle { center, radius } => EntityType::Circle(Circle::new(
            dxf::Point::new(center[0], center[1], 0.0),
            *radius,
        )),
        // DXF arcs also run counter-clockwise from start to end angle, in degrees.
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
    Ok(entity)
}

/// Writes `drawing` as an ASCII DXF R2000 file with the default colours (deterministic: same drawing,
/// same bytes).
pub fn to_dxf(drawing: &Drawing) -> Result<Vec<u8>, DxfError> {
    to_dxf_with(drawing, &Palette::default())
}

/// [`to_dxf`] with the layer colours of `palette`.
pub fn to_dxf_with(drawing: &Drawing, palette: &Palette) -> Result<Vec<u8>, DxfError> {
    let mut doc = fixed_document()?;
    // CAM programs zoom to and place by $EXTMIN/$EXTMAX; the crate leaves them at the origin.
    if let Some((lo, hi)) = drawing.extents() {
        doc.header.minimum_drawing_extents = dxf::Point::new(lo[0], lo[1], 0.0);
        doc.header.maximum_drawing_extents = dxf::Point::new(hi[0], hi[1], 0.0);
    }
    for op in drawing.operations() {
        doc.add_layer(Layer {
            name: op.layer_name().to_string(),
            color: Color::from_index(palette.aci(op)),
            // Group 290: a reference layer is shown but never plotted, so it is not sent to a laser.
            is_layer_plotted: op != Operation::Reference,
            ..Default::default()
        });
        for shape in drawing.shapes_of(op) {
            doc.add_entity(entity(op, shape)?);
        }
    }
    let mut bytes = Vec::new();
    doc.save(&mut bytes)?;
    add_table_head_handles(&bytes)
}

/// Line ending of the crate's ASCII writer.
const EOL: &str = "\r\n";

/// Inserts `5 <handle>` and `330 0` after the `0 TABLE / 2 <name>` pairs of each table head,
/// taking handles from `$HANDSEED` and advancing it. Every other pair is copied as it is; one pass
/// counts the table heads (for the new `$HANDSEED`), a second writes.
fn add_table_head_handles(bytes: &[u8]) -> Result<Vec<u8>, DxfError> {
    let text = std::str::from_utf8(bytes).map_err(|_| DxfError::Malformed("not ASCII"))?;
    let lines: Vec<&str> = text.split(EOL).collect();
    // Code/value pairs; the split leaves one empty string after the final line ending.
    let pairs: Vec<(&str, &str)> = lines
        .chunks(2)
        .filter(|c| c.len() == 2)
        .map(|c| (c[0], c[1]))
        .collect();
    let is = |pair: (&str, &str), code: i32, value: &str| {
        pair.1 == value && pair.0.trim().parse::<i32>() == Ok(code)
    };
    let seed_at = pairs
        .iter()
        .position(|&p| is(p, 9, "$HANDSEED"))
        .map(|i| i + 1)
        .filter(|&i| i < pairs.len())
        .ok_or(DxfError::Malformed("no $HANDSEED"))?;
    let seed = u64::from_str_radix(pairs[seed_at].1, 16)
        .map_err(|_| DxfError::Malformed("$HANDSEED is not hexadecimal"))?;
    let after_table_name =
        |i: usize| i > 0 && pairs[i].0.trim() == "2" && is(pairs[i - 1], 0, "TABLE");
    let heads = (0..pairs.len()).filter(|&i| after_table_name(i)).count() as u64;

    let mut fixed = String::with_capacity(text.len() + 24 * heads as usize + 16);
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
    Ok(fixed.into_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cam::drawing::sample_drawing as sample;

    fn header_value<'a>(text: &'a str, var: &str) -> Option<&'a str> {
        let mut lines = text.lines().map(str::trim);
        lines.find(|l| *l == var)?;
        lines.nth(1)
    }

    #[test]
    fn output_is_deterministic() {
        let a = to_dxf(&sample()).unwrap();
        let b = to_dxf(&sample()).unwrap();
        assert_eq!(a, b);
        let text = String::from_utf8(a).unwrap();
        assert_eq!(header_value(&text, "$TDCREATE"), Some("2460676.5"));
        assert_eq!(
            header_value(&text, "$FINGERPRINTGUID"),
            Some("a1c7a3e0-5e2b-4c55-9a7e-0d1f2c3b4a51")
        );
    }

    #[test]
    fn header_declares_r2000_millimetres_metric() {
        let text = String::from_utf8(to_dxf(&sample()).unwrap()).unwrap();
        assert_eq!(header_value(&text, "$ACADVER"), Some("AC1015"));
        assert_eq!(header_value(&text, "$INSUNITS"), Some("4"));
        assert_eq!(header_value(&text, "$MEASUREMENT"), Some("1"));
        assert!(!text.contains("\nTEXT\n") && !text.contains("\nSPLINE\n"));
    }

    #[test]
    fn entities_and_layers_parse_back() {
        let bytes = to_dxf(&sample()).unwrap();
        let doc = dxf::Drawing::load(&mut bytes.as_slice()).unwrap();
        assert_eq!(doc.header.default_drawing_units, Units::Millimeters);
        assert_eq!(doc.header.drawing_units, DrawingUnits::Metric);

        for (name, aci) in [("ENGRAVE", 7), ("SCORE", 5), ("SECONDARY", 3), ("CUT", 1)] {
            let layer = doc.layers().find(|l| l.name == name).expect(name);
            assert_eq!(layer.color.index(), Some(aci), "{name}");
        }

        let entities: Vec<&Entity> = doc.entities().collect();
        // Processing order: ENGRAVE arc, SCORE line, SECONDARY triangle, CUT polygon, circle.
        let layers: Vec<&str> = entities.iter().map(|e| e.common.layer.as_str()).collect();
        assert_eq!(layers, ["ENGRAVE", "SCORE", "SECONDARY", "CUT", "CUT"]);
        match &entities[0].specific {
            EntityType::Arc(a) => {
                let c = (a.center.x, a.center.y, a.radius);
                assert_eq!(c, (60.0, 40.0, 3.0));
                assert_eq!((a.start_angle, a.end_angle), (0.0, 270.0));
            }
            other => panic!("expected ARC, got {other:?}"),
        }
        match &entities[1].specific {
            EntityType::LwPolyline(p) => {
                assert!(!p.is_closed());
                assert_eq!(p.vertices.len(), 2);
            }
            other => panic!("expected LWPOLYLINE, got {other:?}"),
        }
        match &entities[2].specific {
            // Full f64 precision survives, unlike the 6-decimal SVG.
            EntityType::LwPolyline(p) => {
                assert!(p.is_closed());
                assert_eq!(p.vertices[0].x, 60.123456789);
            }
            other => panic!("expected LWPOLYLINE, got {other:?}"),
        }
        match &entities[3].specific {
            EntityType::LwPolyline(p) => {
                assert!(p.is_closed());
                let xy: Vec<(f64, f64)> = p.vertices.iter().map(|v| (v.x, v.y)).collect();
                assert_eq!(xy, [(5.0, 5.0), (45.0, 8.0), (45.0, 22.0), (5.0, 25.0)]);
            }
            other => panic!("expected LWPOLYLINE, got {other:?}"),
        }
        match &entities[4].specific {
            EntityType::Circle(c) => {
                assert_eq!((c.center.x, c.center.y, c.radius), (20.0, 40.0, 0.79))
            }
            other => panic!("expected CIRCLE, got {other:?}"),
        }
    }

    #[test]
    fn header_extents_are_the_drawn_extents() {
        // Sample extents, worked out by hand in drawing.rs: x 0..80, y 5..43 (the arc's top).
        let bytes = to_dxf(&sample()).unwrap();
        let doc = dxf::Drawing::load(&mut bytes.as_slice()).unwrap();
        let (lo, hi) = (
            &doc.header.minimum_drawing_extents,
            &doc.header.maximum_drawing_extents,
        );
        assert_eq!((lo.x, lo.y, hi.x, hi.y), (0.0, 5.0, 80.0, 43.0));
    }

    #[test]
    fn reference_layer_is_grey_and_not_plotted() {
        let mut d = Drawing::new("sheet", 10.0, 10.0);
        let square = vec![[0.0, 0.0], [10.0, 0.0], [10.0, 10.0], [0.0, 10.0]];
        d.add(Operation::Reference, Shape::Polygon(square.clone()));
        d.add(Operation::Cut, Shape::Polygon(square));
        let bytes = to_dxf(&d).unwrap();
        let doc = dxf::Drawing::load(&mut bytes.as_slice()).unwrap();
        let reference = doc.layers().find(|l| l.name == "REFERENCE").unwrap();
        assert_eq!(reference.color.index(), Some(8));
        assert!(!reference.is_layer_plotted);
        assert!(
            doc.layers()
                .find(|l| l.name == "CUT")
                .unwrap()
                .is_layer_plotted
        );
    }

    #[test]
    fn only_operations_present_get_a_layer() {
        let mut d = Drawing::new("cut only", 10.0, 10.0);
        let ring = vec![[1.0, 1.0], [2.0, 1.0], [2.0, 2.0]];
        d.add(Operation::Cut, Shape::Polygon(ring));
        let bytes = to_dxf(&d).unwrap();
        let doc = dxf::Drawing::load(&mut bytes.as_slice()).unwrap();
        let mut names: Vec<&str> = doc.layers().map(|l| l.name.as_str()).collect();
        names.sort_unstable();
        assert!(names.contains(&"CUT"));
        for op in [Operation::Engrave, Operation::Score, Operation::Secondary] {
            assert!(!names.contains(&op.layer_name()), "{names:?}");
        }
    }

    #[test]
    fn table_heads_get_fresh_handles() {
        let text = String::from_utf8(to_dxf(&sample()).unwrap()).unwrap();
        let lines: Vec<&str> = text.split(EOL).collect();
        let handles: Vec<&str> = lines
            .windows(8)
            .filter(|w| w[0].trim() == "0" && w[1] == "TABLE")
            .map(|w| {
                assert_eq!((w[4].trim(), w[6].trim(), w[7]), ("5", "330", "0"), "{w:?}");
                w[5]
            })
            .collect();
        assert!(handles.len() >= 7, "{handles:?}");
        // No handle is used twice, and $HANDSEED lies above all of them. The header's own
        // `$HANDSEED` value is a code-5 pair too: look past the header only.
        let header_end = text.find("ENDSEC").unwrap();
        let after_header: Vec<&str> = text[header_end..].split(EOL).skip(1).collect();
        let mut all: Vec<u64> = after_header
            .chunks(2)
            .filter(|c| c.len() == 2 && c[0].trim() == "5")
            .map(|c| u64::from_str_radix(c[1], 16).unwrap())
            .collect();
        let count = all.len();
        all.sort_unstable();
        all.dedup();
        assert_eq!(all.len(), count, "duplicate handles");
        let seed = u64::from_str_radix(header_value(&text, "$HANDSEED").unwrap(), 16).unwrap();
        assert!(all.iter().all(|&h| h < seed));
    }

    #[test]
    fn degenerate_shapes_are_errors_not_silent_output() {
        let mut d = Drawing::new("bad", 10.0, 10.0);
        d.add(Operation::Cut, Shape::Polygon(vec![[0.0, 0.0], [1.0, 0.0]]));
        assert!(matches!(
            to_dxf(&d),
            Err(DxfError::TooFewVertices { count: 2, .. })
        ));
        let mut d = Drawing::new("nan", 10.0, 10.0);
        d.add(
            Operation::Score,
            Shape::Polyline(vec![[0.0, f64::NAN], [1.0, 0.0]]),
        );
        assert!(matches!(
            to_dxf(&d),
            Err(DxfError::NonFinite(Operation::Score))
        ));
    }
}
