//! The drawing model: shapes in millimetres (y up), each tagged with the laser operation
//! that will process it.
//!
//! Writers ([`crate::drawing::svg`], [`crate::drawing::dxf`]) turn a [`Drawing`] into files; they emit
//! operations in [`Operation`] order (engrave, score, secondary, cut) so that inner features
//! and score lines come before the outer contours that free a part (docs/cam.md §3).

use super::arc::CircularArc;
use cam_geometry::{Bounds, Point};

/// What the laser does along a shape. The derived order is the processing order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Operation {
    /// A guide that is never run: sheet outlines and other references to place stock by. Grey,
    /// on its own layer, which the DXF marks not to plot (docs/cam.md §3).
    Reference,
    /// Surface marking: labels, fiducials. Black.
    Engrave,
    /// Partial-depth line for snapping ceramic. Blue.
    Score,
    /// A second cut pass: set it up to cut through. Green.
    Secondary,
    /// Cut through. Red.
    Cut,
}

impl Operation {
    /// All operations in processing order.
    pub const ALL: [Operation; 5] = [
        Operation::Reference,
        Operation::Engrave,
        Operation::Score,
        Operation::Secondary,
        Operation::Cut,
    ];

    /// Layer name used in both SVG (`inkscape:label`) and DXF.
    pub fn layer_name(self) -> &'static str {
        match self {
            Operation::Reference => "REFERENCE",
            Operation::Engrave => "ENGRAVE",
            Operation::Score => "SCORE",
            Operation::Secondary => "SECONDARY",
            Operation::Cut => "CUT",
        }
    }

    /// Name of the operation in a process template (`[operations]` keys, `[features]` values).
    pub fn template_key(self) -> &'static str {
        match self {
            Operation::Reference => "reference",
            Operation::Engrave => "engrave",
            Operation::Score => "score",
            Operation::Secondary => "secondary",
            Operation::Cut => "cut",
        }
    }

    /// Stroke colour that laser drivers map to this operation (docs/cam.md §3): pure primaries for the
    /// operations that run, mid grey for the reference, which no driver maps to a cut by default.
    pub fn svg_colour(self) -> &'static str {
        match self {
            Operation::Reference => "#808080",
            Operation::Engrave => "#000000",
            Operation::Score => "#0000FF",
            Operation::Secondary => "#00FF00",
            Operation::Cut => "#FF0000",
        }
    }

    /// AutoCAD Colour Index of the DXF layer: 8 grey, 7 white/black, 5 blue, 3 green, 1 red.
    pub fn aci(self) -> u8 {
        match self {
            Operation::Reference => 8,
            Operation::Engrave => 7,
            Operation::Score => 5,
            Operation::Secondary => 3,
            Operation::Cut => 1,
        }
    }

    /// The operation whose layer is named `name` (exact, upper case), if any.
    pub fn from_layer_name(name: &str) -> Option<Operation> {
        Operation::ALL
            .into_iter()
            .find(|op| op.layer_name() == name)
    }

    /// The operation whose SVG stroke colour is `colour` (case-insensitive `#RRGGBB`), if any.
    pub fn from_svg_colour(colour: &str) -> Option<Operation> {
        Operation::ALL
            .into_iter()
            .find(|op| op.svg_colour().eq_ignore_ascii_case(colour))
    }
}

/// One geometric primitive, in millimetres.
#[derive(Clone, Debug, PartialEq)]
pub enum Shape {
    /// Closed ring; the closing point is implied, not repeated.
    Polygon(Vec<Point>),
    /// Open path (score lines, label strokes).
    Polyline(Vec<Point>),
    /// Full circle.
    Circle { center: Point, radius: f64 },
    /// Arc swept counter-clockwise from `start_deg` to `end_deg` (degrees, 0 = +x axis).
    /// Equal start and end angles mean a full turn.
    Arc {
        center: Point,
        radius: f64,
        start_deg: f64,
        end_deg: f64,
    },
}

impl Shape {
    /// Exact bounding box `(min, max)` of the shape: for circles and arcs the extreme points of the
    /// curve itself (an arc reaches an axis direction only if its sweep passes it,
    /// `CircularArc::bounds`), not of its control points, so the box is what a renderer draws.
    pub fn bounds(&self) -> (Point, Point) {
        let b = self.bounding_box();
        (b.min, b.max)
    }

    /// [`Shape::bounds`] as the geometry crate's box.
    fn bounding_box(&self) -> Bounds {
        match self {
            Shape::Polygon(pts) | Shape::Polyline(pts) => Bounds::of(pts),
            Shape::Circle { center, radius } => Bounds::of(&[
                [center[0] - radius, center[1] - radius],
                [center[0] + radius, center[1] + radius],
            ]),
            Shape::Arc {
                center,
                radius,
                start_deg,
                end_deg,
            } => CircularArc {
                center: *center,
                radius: *radius,
                start_deg: *start_deg,
                end_deg: *end_deg,
            }
            .bounds(),
        }
    }
}

/// The stock a sheet is cut from: what a technician takes off the shelf before the file goes to the
/// laser. The sheet size is the drawing's.
#[derive(Clone, Debug, PartialEq)]
pub struct Stock {
    /// Material as bought (`PTFE, non-porous`, `PZT-5H (PZT sheet (Piezo Systems))`).
    pub material: String,
    /// Thickness of the sheet, mm.
    pub thickness_mm: f64,
    /// Kerf of the cuts on it, mm: a cut path removes half of it either side, so the sheet bought must
    /// reach that far past the outermost path.
    pub kerf_mm: f64,
    /// Prepreg: the sheet has a fibre direction, and every part on it is placed for its 0° fibres to
    /// run along this axis of the sheet. The stock line says so, for the technician who lays the sheet
    /// on the bed. `None` for a material without fibres.
    pub fibre_axis: Option<FibreAxis>,
}

/// The sheet axis a prepreg's 0° fibres must lie along on the laser bed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FibreAxis {
    /// Across the page: the linkage panels, whose links run along x.
    X,
    /// Up the page: the actuators' passive parts and every nested prepreg sheet.
    Y,
}

impl FibreAxis {
    /// How a file states it, after the stock.
    pub fn statement(self) -> &'static str {
        match self {
            FibreAxis::X => "0° fibres along the sheet's x axis (across the page)",
            FibreAxis::Y => "0° fibres along the sheet's y axis (up the page)",
        }
    }

    /// The axis as the SVG metadata's `fibre_axis` gives it.
    pub fn name(self) -> &'static str {
        match self {
            FibreAxis::X => "x",
            FibreAxis::Y => "y",
        }
    }
}

impl Stock {
    /// The stock as a file name carries it: the material in lower-case letters and digits joined by
    /// `-` (at most 32 characters, cut at a word), then the thickness: `ptfe-non-porous-0.05mm`. A
    /// technician picks the sheet by the file's name before opening it; no character in it needs quoting
    /// in a shell or is refused by a file system.
    pub fn slug(&self) -> String {
        let material = slug(&self.material, 32);
        let thickness = format!("{}mm", super::decimal::fmt_mm(self.thickness_mm));
        if material.is_empty() {
            thickness
        } else {
            format!("{material}-{thickness}")
        }
    }
}

/// `text` as a name a file system and a shell take as it is: its words (ASCII letters, digits and
/// inner dots) in lower case joined by `-`, at most `max` characters, cut at a word (one over-long
/// word is cut inside it). Empty when `text` has no such word.
pub fn slug(text: &str, max: usize) -> String {
    let mut words: Vec<String> = Vec::new();
    let mut word = String::new();
    for c in text.chars() {
        if c.is_ascii_alphanumeric() || c == '.' {
            word.push(c.to_ascii_lowercase());
        } else if !word.is_empty() {
            words.push(std::mem::take(&mut word));
        }
    }
    if !word.is_empty() {
        words.push(word);
    }
    let mut out = String::new();
    for w in words {
        let w = w.trim_matches('.');
        if w.is_empty() {
            continue;
        }
        let extra = w.len() + usize::from(!out.is_empty());
        if out.len() + extra > max {
            if out.is_empty() {
                out.push_str(&w[..max]);
            }
            break;
        }
        if !out.is_empty() {
            out.push('-');
        }
        out.push_str(w);
    }
    out
}

/// The file stem of a sheet named `stem` (`mold-4-1`): on a named stock, the stock follows it after
/// `_` (`mold-4-1_ptfe-non-porous-0.05mm`), so the name alone says which sheet goes on the bed.
pub fn file_stem(stem: &str, stock: Option<&Stock>) -> String {
    match stock {
        Some(s) => format!("{stem}_{}", s.slug()),
        None => stem.to_string(),
    }
}

/// `text` with every control character (a newline, a tab) made a space, so it stays one line in a file.
fn one_line(text: &str) -> String {
    text.chars()
        .map(|c| if c.is_control() { ' ' } else { c })
        .collect()
}

/// A sheet of shapes: the content of one laser file.
#[derive(Clone, Debug, PartialEq)]
pub struct Drawing {
    /// Sheet width (mm); the SVG page and viewBox width.
    pub width_mm: f64,
    /// Sheet height (mm); the SVG page and viewBox height.
    pub height_mm: f64,
    /// Human-readable title, written to the SVG `<title>`.
    pub title: String,
    /// The stock the sheet is cut from; `None` for a drawing that is not cut (the preview).
    pub stock: Option<Stock>,
    items: Vec<(Operation, Shape)>,
    guides: Vec<Guide>,
}

/// A closed outline that informs and is never a path: where a PZT plate is bonded on a passive part.
/// A guide drawn as a line would cross the part it describes, and laser software that ignores layer
/// locks and no-plot flags (LightBurn does) would cut along it; so a file carries guides only as data
/// (SVG metadata), never as geometry.
#[derive(Clone, Debug, PartialEq)]
pub struct Guide {
    /// What the outline marks (`bonded-zone`).
    pub kind: &'static str,
    /// The outline, sheet coordinates, mm.
    pub ring: Vec<Point>,
}

impl Drawing {
    /// An empty drawing of the given sheet size, cut from no named stock.
    pub fn new(title: &str, width_mm: f64, height_mm: f64) -> Self {
        Drawing {
            width_mm,
            height_mm,
            title: title.to_string(),
            stock: None,
            items: Vec::new(),
            guides: Vec::new(),
        }
    }

    /// An empty drawing of a sheet of `stock`.
    pub fn on_stock(title: &str, width_mm: f64, height_mm: f64, stock: Stock) -> Self {
        Drawing {
            stock: Some(stock),
            ..Drawing::new(title, width_mm, height_mm)
        }
    }

    /// The stock in words, as every file states it: `PTFE, non-porous, 0.05 mm thick, 100 x 100 mm
    /// sheet`; `None` without a stock. Control characters become spaces, so the text stays one line
    /// in any file.
    pub fn stock_line(&self) -> Option<String> {
        self.stock.as_ref().map(|s| {
            let mut text = format!(
                "{}, {} mm thick, {} x {} mm sheet",
                s.material,
                super::decimal::fmt_mm(s.thickness_mm),
                super::decimal::fmt_mm(self.width_mm),
                super::decimal::fmt_mm(self.height_mm)
            );
            if let Some(axis) = s.fibre_axis {
                text.push_str(", ");
                text.push_str(axis.statement());
            }
            one_line(&text)
        })
    }

    /// The title on one line, as a file comment must hold it.
    pub fn title_line(&self) -> String {
        one_line(&self.title)
    }

    /// Appends a shape processed by `op`.
    pub fn add(&mut self, op: Operation, shape: Shape) {
        self.items.push((op, shape));
    }

    /// Adds a guide: data about the sheet, never drawn as a path.
    pub fn add_guide(&mut self, kind: &'static str, ring: Vec<Point>) {
        self.guides.push(Guide { kind, ring });
    }

    /// The guides in insertion order.
    pub fn guides(&self) -> &[Guide] {
        &self.guides
    }

    /// All items in insertion order.
    pub fn items(&self) -> &[(Operation, Shape)] {
        &self.items
    }

    /// The operations that have at least one item, in processing order.
    pub fn operations(&self) -> Vec<Operation> {
        Operation::ALL
            .into_iter()
            .filter(|op| self.items.iter().any(|(o, _)| o == op))
            .collect()
    }

    /// Bounding box `(min, max)` of everything drawn, `None` for an empty drawing.
    pub fn extents(&self) -> Option<(Point, Point)> {
        self.items
            .iter()
            .map(|(_, s)| s.bounding_box())
            .reduce(Bounds::union)
            .map(|b| (b.min, b.max))
    }

    /// The shapes of one operation, in insertion order.
    pub fn shapes_of(&self, op: Operation) -> impl Iterator<Item = &Shape> + '_ {
        self.items
            .iter()
            .filter(move |(o, _)| *o == op)
            .map(|(_, s)| s)
    }
}

/// A drawing with one shape of every kind and every operation, for the writers' tests:
/// a trapezoid and a circle (cut), a score line, an off-grid triangle (secondary) and a
/// 270° arc (engrave), inserted out of processing order.
#[cfg(test)]
pub(crate) fn sample_drawing() -> Drawing {
    let mut d = Drawing::new("sample <A&B>", 80.0, 50.0);
    d.add(
        Operation::Cut,
        Shape::Polygon(vec![[5.0, 5.0], [45.0, 8.0], [45.0, 22.0], [5.0, 25.0]]),
    );
    d.add(
        Operation::Score,
        Shape::Polyline(vec![[0.0, 30.0], [80.0, 30.0]]),
    );
    d.add(
        Operation::Secondary,
        Shape::Polygon(vec![[60.123456789, 10.0], [70.0, 10.000001], [65.5, 19.25]]),
    );
    d.add(
        Operation::Cut,
        Shape::Circle {
            center: [20.0, 40.0],
            radius: 0.79,
        },
    );
    d.add(
        Operation::Engrave,
        Shape::Arc {
            center: [60.0, 40.0],
            radius: 3.0,
            start_deg: 0.0,
            end_deg: 270.0,
        },
    );
    d
}

#[cfg(test)]
mod tests {

    #[test]
    fn a_stock_slug_is_the_material_in_words_and_the_thickness() {
        let stock = |material: &str, t: f64| Stock {
            material: material.into(),
            thickness_mm: t,
            kerf_mm: 0.0,
            fibre_axis: None,
        };
        assert_eq!(
            stock("PTFE, non-porous", 0.05).slug(),
            "ptfe-non-porous-0.05mm"
        );
        // Cut at a word once 32 characters are reached; one over-long word is cut inside it.
        assert_eq!(
            stock("PZT-5H (PZT sheet (Piezo Systems)), lot 7", 0.267).slug(),
            "pzt-5h-pzt-sheet-piezo-systems-0.267mm"
        );
        assert_eq!(
            stock(&"x".repeat(40), 1.0).slug(),
            format!("{}-1mm", "x".repeat(32))
        );
        // Nothing a shell or file system would trip on survives; no material leaves the thickness.
        assert_eq!(stock("µ/\\:*?\"<>|", 0.1).slug(), "0.1mm");
        assert_eq!(file_stem("mold-4-1", None), "mold-4-1");
        assert_eq!(
            file_stem("mold-4-1", Some(&stock("felt pad", 1.0))),
            "mold-4-1_felt-pad-1mm"
        );
    }
    use super::*;

    #[test]
    fn operations_come_out_in_processing_order() {
        let mut d = Drawing::new("t", 10.0, 10.0);
        d.add(
            Operation::Cut,
            Shape::Polygon(vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]),
        );
        d.add(
            Operation::Score,
            Shape::Polyline(vec![[0.0, 0.0], [1.0, 1.0]]),
        );
        d.add(
            Operation::Cut,
            Shape::Circle {
                center: [5.0, 5.0],
                radius: 1.0,
            },
        );
        assert_eq!(d.operations(), vec![Operation::Score, Operation::Cut]);
        assert_eq!(d.shapes_of(Operation::Cut).count(), 2);
        assert_eq!(d.items().len(), 3);
        assert_eq!(d.items()[1].0, Operation::Score);
    }

    #[test]
    fn extents_follow_the_curves_not_their_centres() {
        // Sample: trapezoid x 5..45, y 5..25; score line x 0..80 at y 30; circle r 0.79 at
        // (20, 40) reaching y 40.79; 270° arc r 3 at (60, 40) from 0° to 270°, which passes
        // 90° (y 43) and 180° (x 57) and ends at 270° (y 37).
        let (lo, hi) = sample_drawing().extents().unwrap();
        assert_eq!(lo, [0.0, 5.0]);
        assert_eq!(hi, [80.0, 43.0]);
        // A 10° arc around 45° reaches no axis: its box is its two end points.
        let arc = Shape::Arc {
            center: [0.0, 0.0],
            radius: 1.0,
            start_deg: 40.0,
            end_deg: 50.0,
        };
        let (lo, hi) = arc.bounds();
        let (s50, c50) = 50f64.to_radians().sin_cos();
        assert!(
            (lo[0] - c50).abs() < 1e-12 && (hi[1] - s50).abs() < 1e-12,
            "{lo:?} {hi:?}"
        );
        assert_eq!(Drawing::new("empty", 1.0, 1.0).extents(), None);
    }

    #[test]
    fn colour_and_layer_names_round_trip() {
        for op in Operation::ALL {
            assert_eq!(Operation::from_layer_name(op.layer_name()), Some(op));
            assert_eq!(Operation::from_svg_colour(op.svg_colour()), Some(op));
        }
        assert_eq!(Operation::from_svg_colour("#ff0000"), Some(Operation::Cut));
        assert_eq!(Operation::from_layer_name("0"), None);
    }
}
