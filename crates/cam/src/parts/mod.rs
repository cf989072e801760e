//! Extra parts a batch cuts beside its actuators (wing spars, flexures, spacers), imported from
//! DXF or SVG drawings in millimetres.
//!
//! What is read: closed polylines (DXF LWPOLYLINE / POLYLINE with the closed flag or a repeated
//! first point, bulges included), circles, and loops of LINE and ARC entities joined end to end
//! ([`dxf`]); SVG `path`, `polygon`, `rect` (rounded corners included), `circle` and `ellipse`,
//! through their `transform`s ([`svg`]). Arcs and curves are flattened into chords within
//! [`flatten::TOLERANCE_MM`] (10 µm). Each contour that lies inside no other is a part; contours
//! directly inside it are its cut-outs (a flexure's slot), cut before the outline. The nester
//! places the outline, and puts other parts into a cut-out itself (`crate::pipeline`, parts in holes).
//!
//! Refused, in one line naming the file and the entity (DXF handle, SVG element id or index):
//! open contours, self-intersecting or zero-area contours, contours that cross, a part inside a
//! cut-out, entities that are not geometry we can cut exactly (SPLINE, ELLIPSE, INSERT, …),
//! drawings whose units are missing or not millimetres (DXF `$INSUNITS`, SVG `width`/`height`
//! in mm with a `viewBox`), and files without a closed contour ([`contours`]); contours larger than
//! any sheet, measured before curves are flattened, and outlines narrower than a laser can cut
//! ([`extent`]); DXF bulges that are not finite numbers, and SVG elements nested past
//! [`svg::MAX_NESTING`] levels. Crossings are found by a sweep line ([`crossing`]), so a traced
//! outline of 50,000 vertices imports in a fraction of a second (docs/benchmarks.md). Whether a part
//! fits its sheet is checked by the batch, which knows the sheet; docs/limits.md §5c gives the
//! reasons for each limit.

pub mod contours;
pub mod crossing;
pub mod dxf;
pub mod extent;
pub mod flatten;
pub mod svg;

use crate::input::InputError;
use cam_geometry::{place_ring, signed_area, Point};
use std::path::{Path, PathBuf};

/// One part read from a drawing: its outline and cut-outs, in mm, y up.
#[derive(Debug, Clone, PartialEq)]
pub struct ImportedPart {
    /// The drawing.
    pub file: PathBuf,
    /// The entity of the outline (`LWPOLYLINE handle 2F`, `path id="flexure"`).
    pub entity: String,
    /// Outline, counter-clockwise, no closing repeat.
    pub outer: Vec<Point>,
    /// Cut-outs, counter-clockwise.
    pub holes: Vec<Vec<Point>>,
}

impl ImportedPart {
    /// The part moved so that its base point, the centre of its outline's bounding box, is the origin.
    /// Where a drawing puts its origin is arbitrary (a part drawn at (40, -2) in its file); the reports
    /// give where this point lands on the sheet, as they give the centre of an actuator's clamped base,
    /// so a part's reported position is on the part whatever the drawing's origin.
    pub fn at_base_point(self) -> ImportedPart {
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for p in &self.outer {
            for k in 0..2 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        let c = [(lo[0] + hi[0]) / 2.0, (lo[1] + hi[1]) / 2.0];
        let shift = |ring: Vec<Point>| -> Vec<Point> {
            ring.into_iter()
                .map(|[x, y]| [x - c[0], y - c[1]])
                .collect()
        };
        ImportedPart {
            outer: shift(self.outer),
            holes: self.holes.into_iter().map(shift).collect(),
            ..self
        }
    }

    /// The part turned by `deg` counter-clockwise about the drawing's origin.
    pub fn turned(self, deg: f64) -> ImportedPart {
        if deg == 0.0 {
            return self;
        }
        ImportedPart {
            outer: place_ring(&self.outer, deg, [0.0, 0.0]),
            holes: self
                .holes
                .iter()
                .map(|h| place_ring(h, deg, [0.0, 0.0]))
                .collect(),
            ..self
        }
    }

    /// Area of the material: outline less cut-outs, mm².
    pub fn area_mm2(&self) -> f64 {
        signed_area(&self.outer) - self.holes.iter().map(|h| signed_area(h)).sum::<f64>()
    }
}

/// Read every part of a DXF or SVG drawing (by its extension).
pub fn import(path: &Path) -> Result<Vec<ImportedPart>, InputError> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    let contours = match ext.as_deref() {
        Some("dxf") => dxf::contours(path)?,
        Some("svg") => svg::contours(path)?,
        _ => {
            return Err(InputError::whole_file(
                path,
                "not a part drawing: extra parts are read from .dxf or .svg files",
            ))
        }
    };
    contours::assemble(path, contours)
}

/// Which sheets an extra part is cut from.
#[derive(Debug, Clone, PartialEq)]
pub enum PartSheet {
    /// The prepreg (passive) sheets of the batch's designs with this layup: the same sheets as the
    /// passive parts of design `like` (an index into the batch's items).
    Prepreg {
        /// Layup, degrees.
        layup_deg: Vec<f64>,
        /// A design of the batch laid up this way.
        like: usize,
        /// The direction of the part's 0° fibres in its drawing, degrees counter-clockwise from the
        /// drawing's x axis. The part is turned so that this direction lies along the sheet's
        /// fibres, the y axis, as the actuators' passive parts lie ([`ImportedPart::turned`]).
        fibre_axis_deg: f64,
    },
    /// The Pyralux bond-layer sheets (method 1).
    Pyralux,
    /// Sheets of their own: a linkage's film or adhesive, or its carbon when no design of the batch
    /// has its layup (docs/cam.md §7).
    Own(Box<OwnSheet>),
}

/// A cut layer of its own for parts no actuator shares a sheet with.
#[derive(Debug, Clone, PartialEq)]
pub struct OwnSheet {
    /// Layer name and file-stem prefix (`linkage-film`).
    pub layer: String,
    /// Material as bought.
    pub material: String,
    /// Thickness, mm.
    pub thickness_mm: f64,
    /// Density, kg/m³.
    pub density_kg_per_m3: f64,
    /// The sheet: size, kerf and spacing.
    pub spec: crate::process::template::SheetSpec,
    /// Carbon fibre: its 0° fibres lie along the sheet's y axis, as on the prepreg sheets.
    pub prepreg: bool,
}

/// An extra part of a batch: what, how many, where, at which rotations.
#[derive(Debug, Clone, PartialEq)]
pub struct PartOrder {
    /// Name in reports and drawings (the file stem, numbered when the file holds several parts).
    pub name: String,
    /// The part.
    pub part: ImportedPart,
    /// Copies to cut.
    pub quantity: usize,
    /// Rotations the part may be cut at, degrees counter-clockwise.
    pub rotations_deg: Vec<f64>,
    /// Its sheets.
    pub sheet: PartSheet,
    /// Round holes (centre, radius; mm, part coordinates) cut as registration holes: a linkage
    /// coupon's pins. A drawing's circles are cut-outs instead (circumscribed polygons).
    pub pin_holes: Vec<(Point, f64)>,
    /// Where a face of the part is bonded in its stack (part coordinates; a linkage coupon's release
    /// outline): its sheet marks it so, and nothing is engraved there. A drawing's parts are not
    /// known to be bonded anywhere.
    pub bonded_zone: Option<Vec<Point>>,
    /// The engraving of each copy, strokes in part coordinates, off the bonded zone (a linkage
    /// coupon's name and number in its border); empty for none.
    pub labels: Vec<Vec<Vec<Point>>>,
}

/// One line naming the file and the entity: the refusal of every drawing reader.
pub fn entity_error(file: &Path, entity: &str, what: impl Into<String>) -> InputError {
    InputError::invalid(file, entity, "", what)
}
