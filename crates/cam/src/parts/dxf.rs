//! Part contours from a DXF drawing (through the `dxf` crate): closed LWPOLYLINE / POLYLINE
//! (bulges are arcs), CIRCLE, and open polylines, LINE and ARC entities to be chained into loops.
//! TEXT, MTEXT and POINT are annotations, not cut, and are skipped; any other entity is refused,
//! so nothing in the drawing is silently left uncut. The drawing must be in millimetres:
//! `$INSUNITS = 4`.

use super::contours::{chain, entity_error, Contour, Piece, JOIN_MM};
use super::flatten::{bulge, circular_arc, circumscribed_ellipse, TOLERANCE_MM};
use crate::input::InputError;
use cam_geometry::Point;
use dxf::entities::{Entity, EntityType};
use dxf::enums::Units;
use std::path::Path;

/// The entity as messages name it: its type and handle (`LWPOLYLINE handle 2F`), or its position
/// among the entities when it has no handle.
fn name(entity: &Entity, index: usize) -> String {
    let debug = format!("{:?}", entity.specific);
    let kind = debug
        .split(['(', ' ', '{'])
        .next()
        .unwrap_or("ENTITY")
        .to_ascii_uppercase();
    match entity.common.handle.0 {
        0 => format!("{kind} #{} (no handle)", index + 1),
        h => format!("{kind} handle {h:X}"),
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
/// closes the ring when `closed`.
fn polyline(vertices: &[(f64, f64, f64)], closed: bool) -> Vec<Point> {
    let mut points: Vec<Point> = Vec::new();
    let n = vertices.len();
    if n == 0 {
        return points;
    }
    points.push([vertices[0].0, vertices[0].1]);
    let segments = if closed { n } else { n - 1 };
    for i in 0..segments {
        let (x0, y0, b) = vertices[i];
        let (x1, y1, _) = vertices[(i + 1) % n];
        points.extend(bulge([x0, y0], [x1, y1], b, TOLERANCE_MM));
    }
    if closed {
        points.pop();
    }
    points
}

/// Every contour of the drawing: closed ones as they are, open pieces chained.
pub fn contours(file: &Path) -> Result<Vec<Contour>, InputError> {
    crate::input::record(file);
    let drawing = dxf::Drawing::load_file(file)
        .map_err(|e| InputError::whole_file(file, format!("not a readable DXF file: {e}")))?;
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
    let mut closed = Vec::new();
    let mut pieces = Vec::new();
    for (index, entity) in drawing.entities().enumerate() {
        let entity_name = name(entity, index);
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
                add(polyline(&v, p.is_closed()), p.is_closed());
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
                add(polyline(&v, p.is_closed()), p.is_closed());
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
