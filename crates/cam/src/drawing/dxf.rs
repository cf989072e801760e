//! DXF writer: R2000 (AC1015), byte-reproducible, with the bytes the `dxf` crate writes.
//!
//! Conventions (docs/cam.md §3): polygons as closed LWPOLYLINE, polylines as open LWPOLYLINE,
//! CIRCLE and ARC as themselves; one layer per operation with its ACI colour; entities on
//! BYLAYER colour; `$INSUNITS = 4` (mm) and `$MEASUREMENT = 1` (metric; Inkscape's importer
//! reads this one). Entities are written in processing order, like the SVG layers.
//!
//! Why our own emitter: a cut sheet of 20 000 actuators writes about 28 000 DXF files, and the
//! crate built, formatted and re-parsed its full 9 kB header for every one of them.
//! The header and tables here are the crate's own R2000 output, kept in `dxf/r2000_head.txt` with
//! the few values that vary per drawing left as slots; the tests hold every file to the crate's
//! bytes (the crate stays: src/parts reads DXF with it). What the crate writes, and what we
//! therefore write:
//! - fixed dates and GUIDs instead of the clock and random ones, so that two runs give the same
//!   bytes: `$TDCREATE` and friends are 2460676.5 (2025-01-01 00:00);
//! - handles in the crate's order: 1-F for the default table records, then each operation's layer
//!   followed by its entities, then the seven TABLE heads;
//! - a handle and owner 0 on every TABLE head, as AutoCAD writes them (the crate itself leaves them
//!   out, which ezdxf's audit has to repair: "invalid table head handle");
//! - numbers with up to 12 decimals, trailing zeros trimmed but one kept after the point;
//! - the sheet as the drawing limits, `$LIMMIN` (0, 0) to `$LIMMAX` (width, height): the sheet's
//!   lower-left corner is the origin (docs/cam.md §3 "One origin").

use std::sync::OnceLock;

use thiserror::Error;

use super::decimal::push_fixed;
use super::model::{Drawing, Operation, Shape};
use super::palette::Palette;
use cam_geometry::Point;

/// Why a DXF could not be written.
#[derive(Debug, Error)]
pub enum DxfError {
    #[error("{op:?} polyline with {count} vertices: a polygon needs at least 3, a polyline 2")]
    TooFewVertices { op: Operation, count: usize },
    #[error("non-finite coordinate in a {0:?} shape")]
    NonFinite(Operation),
}

/// The crate's R2000 file from `SECTION HEADER` to the end of `TABLES`, one line per line with
/// `\n` endings, and a slot line `@NAME@` for each value that depends on the drawing.
const HEAD_TEMPLATE: &str = include_str!("dxf/r2000_head.txt");

/// Line ending of the crate's ASCII writer.
const EOL: &str = "\r\n";

/// First handle after the default table records (1-F).
const FIRST_HANDLE: u64 = 0x10;

/// Number of TABLE heads in the template, each given a handle after all items.
const TABLE_HEADS: u64 = 7;

/// A value of the head that depends on the drawing.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Slot {
    ExtMinX,
    ExtMinY,
    ExtMaxX,
    ExtMaxY,
    LimMaxX,
    LimMaxY,
    HandSeed,
    TableHandle,
    Layers,
}

/// The head as fixed text (with CRLF line endings) between slots.
enum Piece {
    Text(String),
    Slot(Slot),
}

/// [`HEAD_TEMPLATE`] cut at its slots: done once per process, as every file needs it.
fn head() -> &'static [Piece] {
    static HEAD: OnceLock<Vec<Piece>> = OnceLock::new();
    HEAD.get_or_init(|| {
        let mut pieces = Vec::new();
        let mut text = String::new();
        for line in HEAD_TEMPLATE.lines() {
            let slot = match line {
                "@EXTMIN_X@" => Some(Slot::ExtMinX),
                "@EXTMIN_Y@" => Some(Slot::ExtMinY),
                "@EXTMAX_X@" => Some(Slot::ExtMaxX),
                "@EXTMAX_Y@" => Some(Slot::ExtMaxY),
                "@LIMMAX_X@" => Some(Slot::LimMaxX),
                "@LIMMAX_Y@" => Some(Slot::LimMaxY),
                "@HANDSEED@" => Some(Slot::HandSeed),
                "@TABLE@" => Some(Slot::TableHandle),
                "@LAYERS@" => Some(Slot::Layers),
                _ => None,
            };
            match slot {
                Some(slot) => {
                    pieces.push(Piece::Text(std::mem::take(&mut text)));
                    pieces.push(Piece::Slot(slot));
                }
                None => {
                    text.push_str(line);
                    text.push_str(EOL);
                }
            }
        }
        pieces.push(Piece::Text(text));
        pieces
    })
}

/// The file being written: code/value pairs as the crate formats them.
struct Writer {
    out: String,
}

impl Writer {
    /// Group code, right-aligned in three columns.
    fn code(&mut self, code: u16) {
        self.padded(i64::from(code), 3);
    }

    /// `value` right-aligned in `width` columns, as `format!("{value: >width$}")`, and the line end
    /// (by hand: the formatting machinery was a tenth of the writer's time).
    fn padded(&mut self, value: i64, width: usize) {
        let mut line = [b' '; 24];
        let mut at = digits(&mut line, value.unsigned_abs(), 10);
        if value < 0 {
            at -= 1;
            line[at] = b'-';
        }
        let start = at.min(line.len() - width);
        self.out
            .push_str(std::str::from_utf8(&line[start..]).expect("ASCII"));
        self.out.push_str(EOL);
    }

    fn text(&mut self, code: u16, value: &str) {
        self.code(code);
        self.out.push_str(value);
        self.out.push_str(EOL);
    }

    /// A 16-bit integer value, right-aligned in six columns.
    fn short(&mut self, code: u16, value: i16) {
        self.code(code);
        self.padded(i64::from(value), 6);
    }

    /// A 32-bit integer value, right-aligned in nine columns.
    fn int(&mut self, code: u16, value: i32) {
        self.code(code);
        self.padded(i64::from(value), 9);
    }

    fn handle(&mut self, value: u64) {
        self.code(5);
        self.handle_value(value);
    }

    /// A handle: upper-case hexadecimal, as `format!("{value:X}")`.
    fn handle_value(&mut self, value: u64) {
        let mut line = [0u8; 16];
        let at = digits(&mut line, value, 16);
        self.out
            .push_str(std::str::from_utf8(&line[at..]).expect("ASCII"));
        self.out.push_str(EOL);
    }

    fn real(&mut self, code: u16, value: f64) {
        self.code(code);
        self.real_value(value);
    }

    /// Up to 12 decimals, trailing zeros trimmed, at least one digit after the point.
    fn real_value(&mut self, value: f64) {
        let start = self.out.len();
        push_fixed(&mut self.out, value, 12);
        let trimmed = self.out[start..].trim_end_matches('0').len();
        self.out.truncate(start + trimmed);
        if self.out.ends_with('.') {
            self.out.push('0');
        }
        self.out.push_str(EOL);
    }

    fn point(&mut self, p: Point) {
        self.real(10, p[0]);
        self.real(20, p[1]);
        self.real(30, 0.0);
    }

    fn layer(&mut self, op: Operation, handle: u64, aci: u8) {
        self.text(0, "LAYER");
        self.handle(handle);
        self.text(100, "AcDbSymbolTableRecord");
        self.text(100, "AcDbLayerTableRecord");
        self.text(2, op.layer_name());
        self.short(70, 0);
        self.short(62, i16::from(aci));
        self.text(6, "CONTINUOUS");
        // Group 290: a reference layer is shown but never plotted, so it is not sent to a laser.
        self.text(290, if op == Operation::Reference { "0" } else { "1" });
        self.short(370, 0);
        self.text(390, "0");
    }

    fn entity(&mut self, op: Operation, handle: u64, shape: &Shape) {
        let kind = match shape {
            Shape::Polygon(_) | Shape::Polyline(_) => "LWPOLYLINE",
            Shape::Circle { .. } => "CIRCLE",
            Shape::Arc { .. } => "ARC",
        };
        self.text(0, kind);
        self.handle(handle);
        self.text(100, "AcDbEntity");
        self.text(8, op.layer_name());
        self.short(370, 0);
        match shape {
            Shape::Polygon(points) | Shape::Polyline(points) => {
                self.text(100, "AcDbPolyline");
                self.int(90, points.len() as i32);
                self.short(70, i16::from(matches!(shape, Shape::Polygon(_))));
                for p in points {
                    self.real(10, p[0]);
                    self.real(20, p[1]);
                }
            }
            Shape::Circle { center, radius } => {
                self.text(100, "AcDbCircle");
                self.point(*center);
                self.real(40, *radius);
            }
            // DXF arcs also run counter-clockwise from start to end angle, in degrees.
            Shape::Arc {
                center,
                radius,
                start_deg,
                end_deg,
            } => {
                self.text(100, "AcDbCircle");
                self.point(*center);
                self.real(40, *radius);
                self.text(100, "AcDbArc");
                self.real(50, *start_deg);
                self.real(51, *end_deg);
            }
        }
    }
}

/// Writes the digits of `n` in `base` (10 or 16, upper case) at the end of `buf`; returns where they
/// start.
fn digits(buf: &mut [u8], mut n: u64, base: u64) -> usize {
    let mut at = buf.len();
    loop {
        at -= 1;
        buf[at] = b"0123456789ABCDEF"[(n % base) as usize];
        n /= base;
        if n == 0 {
            return at;
        }
    }
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

/// A shape the writer can write: finite, with enough vertices for its kind.
fn check(op: Operation, shape: &Shape) -> Result<(), DxfError> {
    if !is_finite(shape) {
        return Err(DxfError::NonFinite(op));
    }
    let (count, min) = match shape {
        Shape::Polygon(ring) => (ring.len(), 3),
        Shape::Polyline(path) => (path.len(), 2),
        Shape::Circle { .. } | Shape::Arc { .. } => return Ok(()),
    };
    if count < min {
        return Err(DxfError::TooFewVertices { op, count });
    }
    Ok(())
}

/// The origin convention in a comment line (docs/cam.md §3 "One origin"): the sheet's lower-left corner
/// at (0, 0), the sheet as the drawing limits, the same corner as the SVG page's.
fn origin_comment(drawing: &Drawing) -> String {
    format!(
        "origin: (0, 0) is the sheet's lower-left corner, x to the right, y up; the sheet runs to ({}, {}) \
         mm ($LIMMIN, $LIMMAX); the SVG of the same name has its page on the sheet, the same corner \
         lower left",
        super::decimal::fmt_mm(drawing.width_mm),
        super::decimal::fmt_mm(drawing.height_mm)
    )
}

/// Writes `drawing` as an ASCII DXF R2000 file with the default colours (deterministic: same drawing,
/// same bytes).
pub fn to_dxf(drawing: &Drawing) -> Result<Vec<u8>, DxfError> {
    to_dxf_with(drawing, &Palette::default())
}

/// [`to_dxf`] with the layer colours of `palette`.
pub fn to_dxf_with(drawing: &Drawing, palette: &Palette) -> Result<Vec<u8>, DxfError> {
    let ops = drawing.operations();
    // Handles in the crate's order: each layer, then its entities; the table heads after all.
    let mut layer_handles = Vec::with_capacity(ops.len());
    let mut next = FIRST_HANDLE;
    for &op in &ops {
        layer_handles.push(next);
        next += 1;
        for shape in drawing.shapes_of(op) {
            check(op, shape)?;
            next += 1;
        }
    }
    let first_table_handle = next;
    // CAM programs zoom to and place by $EXTMIN/$EXTMAX; an empty drawing keeps the origin.
    let (lo, hi) = drawing.extents().unwrap_or(([0.0; 2], [0.0; 2]));

    let mut w = Writer {
        out: String::with_capacity(HEAD_TEMPLATE.len() + 256 + 160 * drawing.items().len()),
    };
    // The stock and the origin as DXF comments (group 999) before the header: laser software and
    // ezdxf skip them, a person opening the file in a text editor reads them first.
    if let Some(stock) = drawing.stock_line() {
        w.text(999, &format!("actuator-cam: {}", drawing.title_line()));
        w.text(999, &format!("stock: {stock}"));
        w.text(999, &origin_comment(drawing));
        w.text(999, super::svg::CUT_ORDER);
    }
    let mut table = first_table_handle;
    for piece in head() {
        match piece {
            Piece::Text(text) => w.out.push_str(text),
            Piece::Slot(Slot::ExtMinX) => w.real_value(lo[0]),
            Piece::Slot(Slot::ExtMinY) => w.real_value(lo[1]),
            Piece::Slot(Slot::ExtMaxX) => w.real_value(hi[0]),
            Piece::Slot(Slot::ExtMaxY) => w.real_value(hi[1]),
            Piece::Slot(Slot::LimMaxX) => w.real_value(drawing.width_mm),
            Piece::Slot(Slot::LimMaxY) => w.real_value(drawing.height_mm),
            Piece::Slot(Slot::HandSeed) => w.handle_value(first_table_handle + TABLE_HEADS),
            Piece::Slot(Slot::TableHandle) => {
                w.handle_value(table);
                table += 1;
            }
            Piece::Slot(Slot::Layers) => {
                for (&op, &handle) in ops.iter().zip(&layer_handles) {
                    w.layer(op, handle, palette.aci(op));
                }
            }
        }
    }
    w.text(0, "SECTION");
    w.text(2, "ENTITIES");
    for (&op, &layer_handle) in ops.iter().zip(&layer_handles) {
        for (k, shape) in drawing.shapes_of(op).enumerate() {
            w.entity(op, layer_handle + 1 + k as u64, shape);
        }
    }
    w.text(0, "ENDSEC");
    w.text(0, "SECTION");
    w.text(2, "OBJECTS");
    w.text(0, "ENDSEC");
    w.text(0, "EOF");
    Ok(w.out.into_bytes())
}

#[cfg(test)]
mod crate_reference;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::drawing::model::sample_drawing as sample;
    use dxf::entities::{Entity, EntityType};
    use dxf::enums::{DrawingUnits, Units};
    use proptest::prelude::*;

    /// Byte for byte what the `dxf` crate writes for the same drawing (an independent
    /// implementation of the format); on a difference, the first differing line is shown.
    fn assert_same_as_crate(drawing: &Drawing, palette: &Palette) {
        let ours = to_dxf_with(drawing, palette).unwrap();
        let theirs = crate_reference::crate_dxf(drawing, palette);
        if ours != theirs {
            let (a, b) = (
                String::from_utf8_lossy(&ours),
                String::from_utf8_lossy(&theirs),
            );
            let at = a.lines().zip(b.lines()).position(|(x, y)| x != y);
            panic!(
                "differs at line {at:?}: ours {:?}, crate {:?} ({} vs {} bytes)",
                at.and_then(|i| a.lines().nth(i)),
                at.and_then(|i| b.lines().nth(i)),
                ours.len(),
                theirs.len()
            );
        }
    }

    #[test]
    fn same_bytes_as_the_dxf_crate() {
        assert_same_as_crate(&sample(), &Palette::default());
        assert_same_as_crate(&Drawing::new("empty", 10.0, 10.0), &Palette::default());
        // Every operation, the reference layer not plotted, colours from a template's palette.
        let mut d = Drawing::new("all", 300.0, 200.0);
        for (k, op) in Operation::ALL.into_iter().enumerate() {
            let x = 10.0 * k as f64;
            d.add(op, Shape::Polyline(vec![[x, -0.0], [x + 1.0 / 3.0, 1e-13]]));
            d.add(
                op,
                Shape::Polygon(vec![[-x, 0.1], [x + 0.2, 0.3], [x, 2.0f64.sqrt()]]),
            );
        }
        assert_same_as_crate(&d, &Palette::default());
        let mut palette = Palette::default();
        palette.set(Operation::Cut, "#FF0000", 255).unwrap();
        palette.set(Operation::Engrave, "#000000", 250).unwrap();
        assert_same_as_crate(&d, &palette);
    }

    fn coordinate() -> impl Strategy<Value = f64> {
        prop_oneof![
            -2000.0f64..2000.0,
            (-200_000i64..200_000).prop_map(|k| k as f64 / 100.0),
            Just(-0.0),
            Just(1e20),
            Just(-1e-7),
        ]
    }

    fn shape() -> impl Strategy<Value = Shape> {
        let point = || [coordinate(), coordinate()];
        prop_oneof![
            prop::collection::vec(point(), 3..12).prop_map(Shape::Polygon),
            prop::collection::vec(point(), 2..12).prop_map(Shape::Polyline),
            (point(), 0.01f64..50.0).prop_map(|(center, radius)| Shape::Circle { center, radius }),
            (point(), 0.01f64..50.0, -360.0f64..360.0, -360.0f64..360.0).prop_map(
                |(center, radius, start_deg, end_deg)| Shape::Arc {
                    center,
                    radius,
                    start_deg,
                    end_deg,
                }
            ),
        ]
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(128))]

        #[test]
        fn any_drawing_has_the_crates_bytes(
            items in prop::collection::vec((0usize..5, shape()), 0..40),
        ) {
            let mut d = Drawing::new("random", 500.0, 400.0);
            for (op, shape) in items {
                d.add(Operation::ALL[op], shape);
            }
            assert_same_as_crate(&d, &Palette::default());
        }
    }

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
    fn a_laser_file_states_its_origin() {
        // A laser file (one with a stock) says so in its comment, with the sheet's size.
        let mut d = sample();
        d.stock = Some(crate::drawing::model::Stock {
            material: "PZT-5H".into(),
            thickness_mm: 0.127,
            kerf_mm: 0.0,
            fibre_axis: None,
        });
        let text = String::from_utf8(to_dxf(&d).unwrap()).unwrap();
        assert!(
            text.contains("999\r\norigin: (0, 0) is the sheet's lower-left corner")
                && text.contains("the sheet runs to (80, 50) mm"),
            "{}",
            &text[..600]
        );
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
    fn header_extents_are_the_drawn_extents_and_the_limits_the_sheet() {
        // Sample extents, worked out by hand in drawing.rs: x 0..80, y 5..43 (the arc's top).
        let bytes = to_dxf(&sample()).unwrap();
        let doc = dxf::Drawing::load(&mut bytes.as_slice()).unwrap();
        let (lo, hi) = (
            &doc.header.minimum_drawing_extents,
            &doc.header.maximum_drawing_extents,
        );
        assert_eq!((lo.x, lo.y, hi.x, hi.y), (0.0, 5.0, 80.0, 43.0));
        // The drawing limits are the 80 x 50 mm sheet, its corner the origin.
        let (lo, hi) = (
            &doc.header.minimum_drawing_limits,
            &doc.header.maximum_drawing_limits,
        );
        assert_eq!((lo.x, lo.y, hi.x, hi.y), (0.0, 0.0, 80.0, 50.0));
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
