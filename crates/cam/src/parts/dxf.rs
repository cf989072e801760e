//! Part contours from a DXF drawing (through the `dxf` crate): closed LWPOLYLINE / POLYLINE
//! (bulges are arcs), CIRCLE, and open polylines, LINE and ARC entities to be chained into loops.
//! TEXT, MTEXT and POINT are annotations, not cut, and are skipped; any other entity is refused,
//! so nothing in the drawing is silently left uncut. The drawing must be in millimetres:
//! `$INSUNITS = 4`.

use super::contours::{chain, Contour, Piece, JOIN_MM};
use super::entity_error;
use super::extent::{arc_bounds, Extent};
use super::flatten::{bulge, bulge_arc, circular_arc, circumscribed_ellipse, TOLERANCE_MM};
use crate::input::InputError;
use cam_geometry::Point;
use dxf::entities::{Entity, EntityType};
use dxf::enums::Units;
use std::collections::HashMap;
use std::path::Path;

/// The entity as messages name it: its type and handle as the drawing wrote it (`LWPOLYLINE handle
/// 2F`), or its position among the entities when it has no handle.
fn name(entity: &Entity, index: usize, renamed: &Renamed) -> String {
    let debug = format!("{:?}", entity.specific);
    let kind = debug
        .split(['(', ' ', '{'])
        .next()
        .unwrap_or("ENTITY")
        .to_ascii_uppercase();
    match entity.common.handle.0 {
        0 => format!("{kind} #{} (no handle)", index + 1),
        h => match renamed.get(&h) {
            Some(written) => format!("{kind} handle {written}"),
            None => format!("{kind} handle {h:X}"),
        },
    }
}

fn flat(file: &Path, entity: &str, normal_z: f64) -> Result<(), InputError> {
    if normal_z < 1.0 - 1e-9 {
        return Err(entity_error(
            file,
            entity,
            "drawn in a tilted or mirrored coordinate system (extrusion direction not +Z); flatten the drawing to the XY plane",
        ));
    }
    Ok(())
}

/// Points of a polyline with bulges: `(x, y, bulge)` per vertex; the bulge of the last vertex
/// closes the ring when `closed`. Every bulge must be a finite number, and the polyline, its arcs
/// included, must lie within [`MAX_SIDE_MM`](super::extent::MAX_SIDE_MM): both checked before any
/// arc is cut into chords.
fn polyline(
    file: &Path,
    entity: &str,
    vertices: &[(f64, f64, f64)],
    closed: bool,
) -> Result<Vec<Point>, InputError> {
    let n = vertices.len();
    let segments = if closed { n } else { n - 1 };
    let ends = |i: usize| {
        let (x0, y0, b) = vertices[i];
        let (x1, y1, _) = vertices[(i + 1) % n];
        ([x0, y0], [x1, y1], b)
    };
    let mut extent = Extent::default();
    for (k, &(x, y, b)) in vertices.iter().enumerate() {
        if !b.is_finite() {
            return Err(entity_error(
                file,
                entity,
                format!(
                    "vertex {}: bulge (group code 42) {b}: a bulge must be a finite number, tan(θ/4) of the arc's included angle θ",
                    k + 1
                ),
            ));
        }
        extent.add([x, y]);
    }
    for i in 0..segments {
        let (from, to, b) = ends(i);
        if let Some(arc) = bulge_arc(from, to, b) {
            extent.add_box(arc_bounds(
                arc.centre,
                arc.radius,
                arc.start_rad,
                arc.sweep_rad,
            ));
        }
    }
    extent.check(file, entity)?;
    let mut points: Vec<Point> = vec![[vertices[0].0, vertices[0].1]];
    for i in 0..segments {
        let (from, to, b) = ends(i);
        points.extend(bulge(from, to, b, TOLERANCE_MM));
    }
    if closed {
        points.pop();
    }
    Ok(points)
}

/// Group codes whose values are handles (DXF reference, "Group codes in numerical order"): an
/// entity's own (5, 105), pointers to other objects (320-369, 390-399, 480-481) and extended data's
/// (1005).
fn is_handle_code(code: i32) -> bool {
    matches!(code, 5 | 105 | 320..=369 | 390..=399 | 480 | 481 | 1005)
}

/// Handles the drawing wrote that are not hexadecimal numbers, by the number read in their place.
type Renamed = HashMap<u64, String>;

/// First number given to a handle that is not hexadecimal: far above the handles a CAD program
/// counts up from 1, so it names no other object of the drawing.
const RENAMED_FROM: u64 = 0xFFFF_0000_0000_0000;

/// An ASCII DXF with every handle that is not a hexadecimal number replaced by one of its own
/// (the same for every mention of it), and those numbers with the handles as written. Handles only
/// name objects and link them; no coordinate depends on them, and some CAD and lab tools write their
/// own (`G12`, `-1`), which the `dxf` crate refuses with a bare parse error. Lines come in pairs,
/// group code then value; a binary DXF (no such lines) is returned as it is.
fn readable_handles(bytes: Vec<u8>) -> (Vec<u8>, Renamed) {
    let mut renamed = Renamed::new();
    if bytes.starts_with(b"AutoCAD Binary DXF") || bytes.starts_with(b"AutoCAD DXB") {
        return (bytes, renamed);
    }
    let mut by_text: HashMap<Vec<u8>, u64> = HashMap::new();
    let mut out = Vec::with_capacity(bytes.len());
    let mut handle_next = false;
    for (k, line) in bytes.split_inclusive(|&b| b == b'\n').enumerate() {
        let body = line.trim_ascii();
        if k % 2 == 0 {
            handle_next = std::str::from_utf8(body)
                .ok()
                .and_then(|c| c.parse::<i32>().ok())
                .is_some_and(is_handle_code);
        } else if handle_next && !body.iter().all(u8::is_ascii_hexdigit) {
            let next = RENAMED_FROM + by_text.len() as u64;
            let number = *by_text.entry(body.to_vec()).or_insert(next);
            renamed
                .entry(number)
                .or_insert_with(|| String::from_utf8_lossy(body).into_owned());
            out.extend(format!("{number:X}").bytes());
            out.extend(&line[line.trim_ascii_end().len()..]);
            continue;
        }
        out.extend(line);
    }
    (out, renamed)
}

/// The drawing must be in millimetres: `$INSUNITS = 4`.
fn check_units(file: &Path, drawing: &dxf::Drawing) -> Result<(), InputError> {
    match drawing.header.default_drawing_units {
        Units::Millimeters => {}
        Units::Unitless => {
            return Err(InputError::invalid(
                file,
                "header $INSUNITS",
                "0 or missing (unitless)",
                "parts must be drawn in millimetres: set $INSUNITS = 4",
            ))
        }
        other => {
            return Err(InputError::invalid(
                file,
                "header $INSUNITS",
                format!("{} ({other:?})", other as i32),
                "parts must be drawn in millimetres: set $INSUNITS = 4",
            ))
        }
    }
    Ok(())
}

/// Every contour of the drawing: closed ones as they are, open pieces chained.
pub fn contours(file: &Path) -> Result<Vec<Contour>, InputError> {
    crate::input::record(file);
    let bytes = std::fs::read(file).map_err(|e| InputError::io(file, &e))?;
    let (bytes, renamed) = readable_handles(bytes);
    let drawing = dxf::Drawing::load(&mut bytes.as_slice())
        .map_err(|e| InputError::whole_file(file, format!("not a readable DXF file: {e}")))?;
    check_units(file, &drawing)?;
    let mut closed = Vec::new();
    let mut pieces = Vec::new();
    for (index, entity) in drawing.entities().enumerate() {
        let entity_name = name(entity, index, &renamed);
        let mut add = |ring: Vec<Point>, is_closed: bool| {
            let ends_meet = ring.len() > 2
                && (ring[0][0] - ring[ring.len() - 1][0])
                    .hypot(ring[0][1] - ring[ring.len() - 1][1])
                    <= JOIN_MM;
            if is_closed || ends_meet {
                closed.push(Contour {
                    entity: entity_name.clone(),
                    ring,
                });
            } else {
                pieces.push(Piece {
                    entity: entity_name.clone(),
                    points: ring,
                });
            }
        };
        match &entity.specific {
            EntityType::LwPolyline(p) => {
                flat(file, &entity_name, p.extrusion_direction.z)?;
                let v: Vec<(f64, f64, f64)> =
                    p.vertices.iter().map(|v| (v.x, v.y, v.bulge)).collect();
                if v.len() < 2 {
                    return Err(entity_error(file, &entity_name, "fewer than two vertices"));
                }
                add(polyline(file, &entity_name, &v, p.is_closed())?, p.is_closed());
            }
            EntityType::Polyline(p) => {
                flat(file, &entity_name, p.normal.z)?;
                let v: Vec<(f64, f64, f64)> = p
                    .vertices()
                    .map(|v| (v.location.x, v.location.y, v.bulge))
                    .collect();
                if v.len() < 2 {
                    return Err(entity_error(file, &entity_name, "fewer than two vertices"));
                }
                add(polyline(file, &entity_name, &v, p.is_closed())?, p.is_closed());
            }
            EntityType::Circle(c) => {
                flat(file, &entity_name, c.normal.z)?;
                if !(c.radius.is_finite() && c.radius > 0.0) {
                    return Err(entity_error(
                        file,
                        &entity_name,
                        format!("radius {}: a circle needs a positive radius", c.radius),
                    ));
                }
                let r = c.radius;
                let mut extent = Extent::default();
                extent.add_box(([c.center.x - r, c.center.y - r], [c.center.x + r, c.center.y + r]));
                extent.check(file, &entity_name)?;
                let ring = circumscribed_ellipse(
                    [c.center.x, c.center.y],
                    c.radius,
                    c.radius,
                    TOLERANCE_MM,
                );
                add(ring, true);
            }
            EntityType::Arc(a) => {
                flat(file, &entity_name, a.normal.z)?;
                if !(a.radius.is_finite() && a.radius > 0.0) {
                    return Err(entity_error(
                        file,
                        &entity_name,
                        format!("radius {}: an arc needs a positive radius", a.radius),
                    ));
                }
                // DXF arcs run counter-clockwise from the start to the end angle (degrees).
                let mut sweep = (a.end_angle - a.start_angle).rem_euclid(360.0);
                if sweep == 0.0 {
                    sweep = 360.0;
                }
                let mut extent = Extent::default();
                extent.add_box(arc_bounds(
                    [a.center.x, a.center.y],
                    a.radius,
                    a.start_angle.to_radians(),
                    sweep.to_radians(),
                ));
                extent.check(file, &entity_name)?;
                add(
                    circular_arc(
                        [a.center.x, a.center.y],
                        a.radius,
                        a.start_angle.to_radians(),
                        sweep.to_radians(),
                        TOLERANCE_MM,
                    ),
                    false,
                );
            }
            EntityType::Line(l) => {
                flat(file, &entity_name, l.extrusion_direction.z)?;
                add(vec![[l.p1.x, l.p1.y], [l.p2.x, l.p2.y]], false);
            }
            EntityType::Text(_) | EntityType::MText(_) | EntityType::ModelPoint(_) => {}
            _ => {
                return Err(entity_error(
                    file,
                    &entity_name,
                    "not a supported part entity: use closed LWPOLYLINE/POLYLINE (bulges allowed), CIRCLE, or LINE/ARC loops (explode splines, ellipses and blocks first)",
                ))
            }
        }
    }
    closed.extend(chain(file, pieces)?);
    Ok(closed)
}
