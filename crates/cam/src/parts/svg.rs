//! Part contours from an SVG drawing (XML through `roxmltree`, attribute syntax through
//! `svgtypes`): `path` (every command, arcs included; each subpath a contour), `polygon`, `rect`
//! (rounded corners too), `circle` and `ellipse`, through the `transform`s of the element and its
//! groups. Contents of `defs`, `clipPath`, `mask`, `symbol`, `marker` and `pattern` are not drawn
//! and are skipped, as are `text` and elements of other namespaces (editor metadata). `line`,
//! `polyline` and unclosed subpaths are open contours; `use` and `image` are refused.
//!
//! Units: the root's `width` and `height` must be lengths in millimetres and a `viewBox` must map
//! user units onto them with the same scale on both axes. Coordinates become mm with y up (the
//! page's bottom-left corner is the origin), as every other drawing here.

use super::contours::Contour;
use super::entity_error;
use super::extent::Extent;
use super::flatten::{circumscribed_ellipse, cubic, elliptical_arc, quadratic, TOLERANCE_MM};
use crate::input::InputError;
use cam_geometry::Point;
use roxmltree::{Document, Node};
use std::path::Path;
use svgtypes::{Length, LengthUnit, PathParser, PathSegment, Transform, ViewBox};

const SVG_NS: &str = "http://www.w3.org/2000/svg";

/// Elements whose contents are not drawn where they stand.
const NOT_RENDERED: [&str; 8] = [
    "defs", "clipPath", "mask", "symbol", "marker", "pattern", "metadata", "text",
];

fn multiply(p: &Transform, c: &Transform) -> Transform {
    Transform::new(
        p.a * c.a + p.c * c.b,
        p.b * c.a + p.d * c.b,
        p.a * c.c + p.c * c.d,
        p.b * c.c + p.d * c.d,
        p.a * c.e + p.c * c.f + p.e,
        p.b * c.e + p.d * c.f + p.f,
    )
}

fn apply(t: &Transform, p: Point) -> Point {
    [t.a * p[0] + t.c * p[1] + t.e, t.b * p[0] + t.d * p[1] + t.f]
}

/// Where the file's user units land: user → mm, y up.
struct Page {
    to_mm: Transform,
}

fn page(file: &Path, root: Node<'_, '_>) -> Result<Page, InputError> {
    let allowed =
        "parts must be drawn in millimetres: give the <svg> width and height in mm (e.g. width=\"100mm\") and a viewBox";
    let length = |key: &str| -> Result<f64, InputError> {
        let field = format!("<svg> {key}");
        let Some(text) = root.attribute(key) else {
            return Err(InputError::invalid(file, &field, "missing", allowed));
        };
        match text.parse::<Length>() {
            Ok(Length {
                number,
                unit: LengthUnit::Mm,
            }) if number.is_finite() && number > 0.0 => Ok(number),
            Ok(Length {
                unit: LengthUnit::Mm,
                ..
            }) => Err(InputError::invalid(
                file,
                &field,
                format!("{text:?}"),
                "must be a positive length in mm",
            )),
            Ok(Length {
                unit: LengthUnit::None,
                ..
            }) => Err(InputError::invalid(
                file,
                &field,
                format!("{text:?} (no unit)"),
                allowed,
            )),
            _ => Err(InputError::invalid(
                file,
                &field,
                format!("{text:?} (not mm)"),
                allowed,
            )),
        }
    };
    let width = length("width")?;
    let height = length("height")?;
    let Some(text) = root.attribute("viewBox") else {
        return Err(InputError::invalid(
            file,
            "<svg> viewBox",
            "missing",
            allowed,
        ));
    };
    let vb: ViewBox = text
        .parse()
        .ok()
        .filter(|v: &ViewBox| v.w > 0.0 && v.h > 0.0)
        .ok_or_else(|| {
            InputError::invalid(
                file,
                "<svg> viewBox",
                format!("{text:?}"),
                "expected four numbers: min-x min-y width height, width and height positive",
            )
        })?;
    let (sx, sy) = (width / vb.w, height / vb.h);
    if ((sx - sy) / sx).abs() > 1e-6 {
        return Err(InputError::invalid(
            file,
            "<svg> viewBox",
            format!("{text:?}"),
            format!(
                "its aspect ratio differs from width x height ({width} x {height} mm): user units would be scaled differently along x and y"
            ),
        ));
    }
    // x_mm = (x - min_x) sx; y_mm (up) = height - (y - min_y) sy.
    Ok(Page {
        to_mm: Transform::new(sx, 0.0, 0.0, -sy, -vb.x * sx, height + vb.y * sy),
    })
}

/// One element's contours in its own user units (closed flag per subpath).
type Subpaths = Vec<(Vec<Point>, bool)>;

fn number(file: &Path, entity: &str, node: Node<'_, '_>, key: &str) -> Result<f64, InputError> {
    match node.attribute(key) {
        None => Ok(0.0),
        Some(text) => match text.parse::<Length>() {
            Ok(Length {
                number,
                unit: LengthUnit::None | LengthUnit::Mm,
            }) if number.is_finite() => Ok(number),
            _ => Err(entity_error(
                file,
                entity,
                format!("{key} = {text:?}: expected a number in user units"),
            )),
        },
    }
}

/// The subpaths of path data `d`. Each subpath's extent in mm (through `t`) is checked after every
/// segment, so a curve far larger than any part is refused after its own chords, not the whole
/// path's.
fn path_subpaths(
    file: &Path,
    entity: &str,
    d: &str,
    t: &Transform,
    tol: f64,
) -> Result<Subpaths, InputError> {
    let mut out: Subpaths = Vec::new();
    let mut current: Vec<Point> = Vec::new();
    let mut pen = Pen::default();
    let flush = |current: &mut Vec<Point>, out: &mut Subpaths, closed: bool| {
        if current.len() > 1 {
            out.push((std::mem::take(current), closed));
        } else {
            current.clear();
        }
    };
    let mut extent = Extent::default();
    for segment in PathParser::from(d) {
        let segment = segment
            .map_err(|e| entity_error(file, entity, format!("path data d is not valid: {e}")))?;
        // Where this segment's points start in `current` (a new subpath starts its own extent).
        let mut before = current.len();
        match pen.step(segment, tol) {
            Step::Draw(points) => current.extend(points),
            Step::Move(to) => {
                flush(&mut current, &mut out, false);
                current.push(to);
                (extent, before) = (Extent::default(), 0);
            }
            Step::Close(to) => {
                flush(&mut current, &mut out, true);
                current.push(to);
                (extent, before) = (Extent::default(), 0);
            }
        }
        current[before..]
            .iter()
            .for_each(|p| extent.add(apply(t, *p)));
        extent.check(file, entity)?;
    }
    flush(&mut current, &mut out, false);
    Ok(out)
}

/// What one path segment does to the outline: draws points (curves as chords), starts a subpath at a
/// point, or closes the subpath and goes back to its start.
enum Step {
    Draw(Vec<Point>),
    Move(Point),
    Close(Point),
}

/// A path's pen: the current point, the start of its subpath, and the last control points, which the
/// smooth commands (S, T) mirror.
#[derive(Default)]
struct Pen {
    pos: Point,
    start: Point,
    last_cubic: Option<Point>,
    last_quad: Option<Point>,
}

impl Pen {
    /// A segment's point in absolute coordinates.
    fn at(&self, abs: bool, x: f64, y: f64) -> Point {
        if abs {
            [x, y]
        } else {
            [self.pos[0] + x, self.pos[1] + y]
        }
    }

    /// The mirror of the last control point about the pen, or the pen if the last segment had none
    /// (SVG 1.1 §8.3.6).
    fn reflected(&self, last: Option<Point>) -> Point {
        last.map_or(self.pos, |c| {
            [2.0 * self.pos[0] - c[0], 2.0 * self.pos[1] - c[1]]
        })
    }

    /// Move the pen along one segment, with curves cut into chords within `tol`.
    fn step(&mut self, segment: PathSegment, tol: f64) -> Step {
        let (mut next_cubic, mut next_quad) = (None, None);
        let step = match segment {
            PathSegment::MoveTo { abs, x, y } => {
                self.pos = self.at(abs, x, y);
                self.start = self.pos;
                Step::Move(self.pos)
            }
            PathSegment::ClosePath { .. } => {
                self.pos = self.start;
                Step::Close(self.pos)
            }
            PathSegment::LineTo { abs, x, y } => {
                self.pos = self.at(abs, x, y);
                Step::Draw(vec![self.pos])
            }
            PathSegment::HorizontalLineTo { abs, x } => {
                self.pos = [if abs { x } else { self.pos[0] + x }, self.pos[1]];
                Step::Draw(vec![self.pos])
            }
            PathSegment::VerticalLineTo { abs, y } => {
                self.pos = [self.pos[0], if abs { y } else { self.pos[1] + y }];
                Step::Draw(vec![self.pos])
            }
            PathSegment::CurveTo {
                abs,
                x1,
                y1,
                x2,
                y2,
                x,
                y,
            } => {
                let (c1, c2) = (self.at(abs, x1, y1), self.at(abs, x2, y2));
                next_cubic = Some(c2);
                self.cubic_to(c1, c2, self.at(abs, x, y), tol)
            }
            PathSegment::SmoothCurveTo { abs, x2, y2, x, y } => {
                let (c1, c2) = (self.reflected(self.last_cubic), self.at(abs, x2, y2));
                next_cubic = Some(c2);
                self.cubic_to(c1, c2, self.at(abs, x, y), tol)
            }
            PathSegment::Quadratic { abs, x1, y1, x, y } => {
                let c = self.at(abs, x1, y1);
                next_quad = Some(c);
                self.quadratic_to(c, self.at(abs, x, y), tol)
            }
            PathSegment::SmoothQuadratic { abs, x, y } => {
                let c = self.reflected(self.last_quad);
                next_quad = Some(c);
                self.quadratic_to(c, self.at(abs, x, y), tol)
            }
            PathSegment::EllipticalArc {
                abs,
                rx,
                ry,
                x_axis_rotation,
                large_arc,
                sweep,
                x,
                y,
            } => {
                let to = self.at(abs, x, y);
                let from = std::mem::replace(&mut self.pos, to);
                let arc = elliptical_arc(from, to, rx, ry, x_axis_rotation, large_arc, sweep, tol);
                Step::Draw(arc)
            }
        };
        (self.last_cubic, self.last_quad) = (next_cubic, next_quad);
        step
    }

    fn cubic_to(&mut self, c1: Point, c2: Point, to: Point, tol: f64) -> Step {
        let from = std::mem::replace(&mut self.pos, to);
        Step::Draw(cubic([from, c1, c2, to], tol))
    }

    fn quadratic_to(&mut self, c: Point, to: Point, tol: f64) -> Step {
        let from = std::mem::replace(&mut self.pos, to);
        Step::Draw(quadratic(from, c, to, tol))
    }
}

/// A rectangle, its corners rounded by `rx`, `ry` (SVG 1.1 §9.2: a missing one takes the other's
/// value, each at most half the side).
fn rect(x: f64, y: f64, w: f64, h: f64, rx: f64, ry: f64, tol: f64) -> Vec<Point> {
    let (rx, ry) = ((rx.min(w / 2.0)).max(0.0), (ry.min(h / 2.0)).max(0.0));
    if rx == 0.0 || ry == 0.0 {
        return vec![[x, y], [x + w, y], [x + w, y + h], [x, y + h]];
    }
    let mut ring = vec![[x + rx, y]];
    let corner = |ring: &mut Vec<Point>, to: Point| {
        let from = *ring.last().expect("started");
        ring.extend(elliptical_arc(from, to, rx, ry, 0.0, false, true, tol));
    };
    ring.push([x + w - rx, y]);
    corner(&mut ring, [x + w, y + ry]);
    ring.push([x + w, y + h - ry]);
    corner(&mut ring, [x + w - rx, y + h]);
    ring.push([x + rx, y + h]);
    corner(&mut ring, [x, y + h - ry]);
    ring.push([x, y + ry]);
    corner(&mut ring, [x + rx, y]);
    ring.pop();
    ring
}

/// The largest factor by which `t` stretches a length (bounded by its Frobenius norm).
fn stretch(t: &Transform) -> f64 {
    (t.a * t.a + t.b * t.b + t.c * t.c + t.d * t.d)
        .sqrt()
        .max(1e-12)
}

/// Deepest nesting of elements the walk follows. Drawings nest groups a few levels (an Inkscape
/// layer, a group per part, a clone's wrapper); 256 is far past any CAD export, and keeps the
/// recursive walk well inside the smallest stack it runs on (2 MiB, a test or worker thread) where
/// 20,000 levels overflowed the main thread's 8 MiB.
pub const MAX_NESTING: usize = 256;

/// The refusal of an element nested past [`MAX_NESTING`], with its line in the file.
fn too_deep(file: &Path, node: Node<'_, '_>) -> InputError {
    InputError::whole_file(
        file,
        format!(
            "elements nested more than {MAX_NESTING} levels deep (line {}): part drawings are read to {MAX_NESTING} levels of groups; ungroup the drawing",
            node.document().text_pos_at(node.range().start).row
        ),
    )
}

/// The extent in mm of the ellipse at `centre` with semi-axes `rx`, `ry` (user units) through `t`:
/// its image is an ellipse whose half-extents along x and y are the lengths of t's rows applied to
/// the semi-axes.
fn ellipse_extent(t: &Transform, centre: Point, rx: f64, ry: f64) -> Extent {
    let c = apply(t, centre);
    let half = [(t.a * rx).hypot(t.c * ry), (t.b * rx).hypot(t.d * ry)];
    let mut extent = Extent::default();
    extent.add_box((
        [c[0] - half[0], c[1] - half[1]],
        [c[0] + half[0], c[1] + half[1]],
    ));
    extent
}

struct Walk<'f> {
    file: &'f Path,
    shapes: usize,
    contours: Vec<Contour>,
}

impl Walk<'_> {
    /// Read `node` (at `depth` below the root) and the elements inside it.
    fn element(
        &mut self,
        node: Node<'_, '_>,
        parent: &Transform,
        depth: usize,
    ) -> Result<(), InputError> {
        if !node.is_element() || node.tag_name().namespace() != Some(SVG_NS) {
            return Ok(());
        }
        if depth > MAX_NESTING {
            return Err(too_deep(self.file, node));
        }
        let tag = node.tag_name().name();
        if NOT_RENDERED.contains(&tag) {
            return Ok(());
        }
        let is_shape = matches!(
            tag,
            "path"
                | "polygon"
                | "polyline"
                | "line"
                | "rect"
                | "circle"
                | "ellipse"
                | "use"
                | "image"
        );
        if is_shape {
            self.shapes += 1;
        }
        let entity = match node.attribute("id") {
            Some(id) => format!("<{tag} id=\"{id}\">"),
            None => format!("<{tag}> #{} (no id)", self.shapes),
        };
        let own = match node.attribute("transform") {
            None => Transform::default(),
            Some(text) => text.parse::<Transform>().map_err(|e| {
                entity_error(
                    self.file,
                    &entity,
                    format!("transform {text:?} is not valid: {e}"),
                )
            })?,
        };
        let t = multiply(parent, &own);
        let tol = TOLERANCE_MM / stretch(&t);
        let file = self.file;
        let num = |key: &str| number(file, &entity, node, key);
        let subpaths: Subpaths = match tag {
            "svg" | "g" | "a" | "switch" => {
                for child in node.children() {
                    self.element(child, &t, depth + 1)?;
                }
                return Ok(());
            }
            "path" => path_subpaths(file, &entity, node.attribute("d").unwrap_or(""), &t, tol)?,
            "polygon" | "polyline" => {
                let points: Vec<Point> = svgtypes::PointsParser::from(
                    node.attribute("points").unwrap_or(""),
                )
                .map(|(x, y)| [x, y])
                .collect();
                vec![(points, tag == "polygon")]
            }
            "line" => vec![(
                vec![[num("x1")?, num("y1")?], [num("x2")?, num("y2")?]],
                false,
            )],
            "rect" => {
                let (w, h) = (num("width")?, num("height")?);
                if !(w > 0.0 && h > 0.0) {
                    return Err(entity_error(file, &entity, "zero area: width and height must be positive"));
                }
                let (rx, ry) = match (node.attribute("rx"), node.attribute("ry")) {
                    (None, None) => (0.0, 0.0),
                    (Some(_), None) => (num("rx")?, num("rx")?),
                    (None, Some(_)) => (num("ry")?, num("ry")?),
                    _ => (num("rx")?, num("ry")?),
                };
                let (x, y) = (num("x")?, num("y")?);
                let mut extent = Extent::default();
                for corner in [[x, y], [x + w, y], [x + w, y + h], [x, y + h]] {
                    extent.add(apply(&t, corner));
                }
                extent.check(file, &entity)?;
                vec![(rect(x, y, w, h, rx, ry, tol), true)]
            }
            "circle" | "ellipse" => {
                let (rx, ry) = if tag == "circle" {
                    (num("r")?, num("r")?)
                } else {
                    (num("rx")?, num("ry")?)
                };
                if !(rx > 0.0 && ry > 0.0) {
                    return Err(entity_error(file, &entity, "zero area: the radius must be positive"));
                }
                let centre = [num("cx")?, num("cy")?];
                ellipse_extent(&t, centre, rx, ry).check(file, &entity)?;
                vec![(circumscribed_ellipse(centre, rx, ry, tol), true)]
            }
            "use" | "image" => {
                return Err(entity_error(
                    file,
                    &entity,
                    "not a supported part element: draw parts as path, polygon, rect, circle or ellipse (unlink clones, trace images)",
                ))
            }
            _ => return Ok(()),
        };
        self.push_contours(&entity, subpaths, &t)
    }

    /// An element's subpaths as contours in mm: each must be closed and have an area.
    fn push_contours(
        &mut self,
        entity: &str,
        subpaths: Subpaths,
        t: &Transform,
    ) -> Result<(), InputError> {
        let file = self.file;
        for (k, (points, closed)) in subpaths.into_iter().enumerate() {
            let name = if k == 0 {
                entity.to_string()
            } else {
                format!("{entity} subpath {}", k + 1)
            };
            let ends_meet = match (points.first(), points.last()) {
                (Some(a), Some(b)) => points.len() > 2 && (a[0] - b[0]).hypot(a[1] - b[1]) <= 1e-9,
                _ => false,
            };
            if !(closed || ends_meet) {
                return Err(entity_error(
                    file,
                    &name,
                    "open contour: an outline (of a part or a drawn sheet) must be closed (end the path with Z, or use polygon instead of polyline/line)",
                ));
            }
            if points.len() < 3 {
                return Err(entity_error(
                    file,
                    &name,
                    "zero area: a closed contour needs at least three points not on one line",
                ));
            }
            self.contours.push(Contour {
                entity: name,
                ring: points.iter().map(|p| apply(t, *p)).collect(),
            });
        }
        Ok(())
    }
}

/// Every closed contour of the drawing, in mm, y up.
pub fn contours(file: &Path) -> Result<Vec<Contour>, InputError> {
    let text = crate::input::read_text(file)?;
    let doc = Document::parse(&text)
        .map_err(|e| InputError::whole_file(file, format!("not a readable SVG file: {e}")))?;
    let root = doc.root_element();
    if root.tag_name().name() != "svg" || root.tag_name().namespace() != Some(SVG_NS) {
        return Err(InputError::whole_file(
            file,
            "not an SVG drawing: the root element is not <svg> in the SVG namespace",
        ));
    }
    let page = page(file, root)?;
    let mut walk = Walk {
        file,
        shapes: 0,
        contours: Vec::new(),
    };
    walk.element(root, &page.to_mm, 0)?;
    Ok(walk.contours)
}
