//! What the layer builders share: a list of jobs (designs with quantities) built together, the names
//! drawings and messages use, and what has been built so far (drawings, per-sheet records, placement map).

use super::parts::PartGeometry;
use super::{BuildError, SheetDrawing};
use crate::design::Design;
use crate::drawing::model::{file_stem, Drawing};
use crate::process::template::Template;
use cam_geometry::offset::offset_ring;
use cam_geometry::Point;
use serde::Serialize;
use std::collections::BTreeMap;

/// One design's share of a build: the design as the process builds it, its plan geometry, how many.
#[derive(Debug, Clone, Copy)]
pub struct Job<'a> {
    /// The design (bond layers of the process included).
    pub design: &'a Design,
    /// Plan dimensions, mm.
    pub geometry: PartGeometry,
    /// Actuators of this design.
    pub quantity: usize,
}

impl<'a> Job<'a> {
    /// A job for `quantity` actuators of `design`, its PZT plates inset by the template's margin.
    pub fn new(design: &'a Design, quantity: usize, template: &Template) -> Self {
        Job {
            design,
            geometry: PartGeometry::of(design).with_pzt_margin(template.pzt_edge_margin_mm),
            quantity,
        }
    }
}

/// How a build names itself in drawing titles, engraved labels, messages and the placement map.
#[derive(Debug, Clone)]
pub struct Names {
    /// Title of drawings and clamp-panel labels (the design name, or the batch name).
    pub title: String,
    /// File errors are reported against.
    pub file: String,
    /// A batch of several designs: actuators are prefixed with their design name in the placement
    /// map, sheets are recorded under their material group (PZT thickness, layup) and messages say
    /// which group they are about. One design has one group and needs none of it.
    pub name_designs: bool,
}

impl Names {
    /// How the placement map names actuator `actuator` (0-based) of `design`.
    pub fn actuator(&self, design: &Design, actuator: usize) -> String {
        if self.name_designs {
            format!("{} actuator {}", design.name, actuator + 1)
        } else {
            format!("actuator {}", actuator + 1)
        }
    }

    /// Prefix an error's message with the group of a batch it happened in (a batch only).
    pub fn in_group(&self, e: BuildError, group: &str) -> BuildError {
        match e {
            BuildError::Geometry { file, what } if self.name_designs => BuildError::Geometry {
                file,
                what: format!("{group}: {what}"),
            },
            other => other,
        }
    }

    /// A geometry or layout problem of the whole build.
    pub fn error(&self, what: String) -> BuildError {
        BuildError::Geometry {
            file: self.file.clone(),
            what,
        }
    }
}

/// One part placed on a sheet, for reports.
#[derive(Debug, Clone, PartialEq)]
pub struct PartRecord {
    /// Index of the job (design) in the build.
    pub job: usize,
    /// Actuator of that job, 0-based.
    pub actuator: usize,
    /// Part kind: `pzt-plate-1`, `passive`, `pyralux-2`, …
    pub part: String,
    /// Rotation of the nominal outline, degrees CCW.
    pub rotation_deg: f64,
    /// Where the outline's origin (the base centre of the part) lands on the sheet, mm.
    pub offset: Point,
    /// Nominal part area, mm².
    pub area_mm2: f64,
}

/// One sheet of a cut material (PZT, passive, Pyralux) as drawn.
#[derive(Debug, Clone, PartialEq)]
pub struct SheetRecord {
    /// Sheet name (`pzt-2`).
    pub stem: String,
    /// File stem: the name and the stock (`pzt-2_pzt-sheet-piezo-systems-0.267mm`).
    pub file_stem: String,
    /// Layer name.
    pub layer: String,
    /// Material as bought.
    pub material: String,
    /// Sheet width, mm.
    pub width_mm: f64,
    /// Sheet height, mm.
    pub height_mm: f64,
    /// Parts on it.
    pub parts: Vec<PartRecord>,
    /// The drawing of the stock it is cut from, when it is a drawn sheet (a remnant, a sheet with a
    /// flaw) rather than a whole one.
    pub stock_file: Option<String>,
    /// What is left of a cut-through sheet once its parts are cut: its outline and, as keep-outs,
    /// its earlier keep-outs and the parts' cut outlines. `None` for PZT and roll stock.
    pub remnant: Option<cam_nest::SheetShape>,
}

impl SheetRecord {
    /// Nominal part area over sheet area.
    pub fn utilization(&self) -> f64 {
        self.parts.iter().map(|p| p.area_mm2).sum::<f64>() / (self.width_mm * self.height_mm)
    }
}

/// The sheet, mm, that holds `drawing`'s page and every through cut (cut and second pass) with half of
/// `kerf_mm` past its path, rounded up to the micrometre (less a nanometre: the drawing's coordinates are written to the
/// micrometre and carry round-off below it).
pub fn sheet_holding_cuts_mm(drawing: &Drawing, kerf_mm: f64) -> [f64; 2] {
    use crate::drawing::model::Operation;
    let half = kerf_mm / 2.0;
    let (mut lo, mut hi) = ([0.0f64, 0.0], [drawing.width_mm, drawing.height_mm]);
    for (op, shape) in drawing.items() {
        if matches!(op, Operation::Cut | Operation::Secondary) {
            let (min, max) = shape.bounds();
            for i in 0..2 {
                lo[i] = lo[i].min(min[i] - half);
                hi[i] = hi[i].max(max[i] + half);
            }
        }
    }
    [0, 1].map(|i| ((hi[i] - lo[i]) * 1e3 - 1e-3).ceil() / 1e3)
}

/// How many sheets of one stock a build cuts: a line of the stock list a technician shops from.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StockCount {
    /// Material as bought.
    pub material: String,
    /// Thickness, mm.
    pub thickness_mm: f64,
    /// Sheet width, mm.
    pub width_mm: f64,
    /// Sheet height (on a roll: the length drawn), mm.
    pub height_mm: f64,
    /// Sheets of it.
    pub sheets: usize,
}

impl StockCount {
    /// Count `copies` sheets of `drawing`'s stock into `rows`: onto its line if the list has one (same
    /// material, thickness and sheet size), else a line of its own at the end. The sheet is the one
    /// that holds every cut as it is run: the drawing's page, grown to the outermost through-cut path
    /// and half the kerf past it (a panel outline cut outside a 100 mm panel with a 0.1 mm kerf needs
    /// 100.2 mm), to the micrometre above.
    pub fn count(rows: &mut Vec<StockCount>, drawing: &Drawing, copies: usize) {
        let Some(s) = &drawing.stock else { return };
        let [width_mm, height_mm] = sheet_holding_cuts_mm(drawing, s.kerf_mm);
        let same = |c: &&mut StockCount| {
            c.material == s.material
                && c.thickness_mm == s.thickness_mm
                && c.width_mm == width_mm
                && c.height_mm == height_mm
        };
        match rows.iter_mut().find(same) {
            Some(c) => c.sheets += copies,
            None => rows.push(StockCount {
                material: s.material.clone(),
                thickness_mm: s.thickness_mm,
                width_mm,
                height_mm,
                sheets: copies,
            }),
        }
    }

    /// The stock list as a Markdown table, one row per stock.
    pub fn markdown(rows: &[StockCount]) -> String {
        let mut s =
            String::from("| material | thickness mm | sheet mm | sheets |\n|---|---|---|---|\n");
        for r in rows {
            s.push_str(&format!(
                "| {} | {} | {} x {} | {} |\n",
                crate::markdown::text(&r.material),
                crate::drawing::decimal::fmt_mm(r.thickness_mm),
                crate::drawing::decimal::fmt_mm(r.width_mm),
                crate::drawing::decimal::fmt_mm(r.height_mm),
                r.sheets
            ));
        }
        s.push_str(
            "\nEach sheet holds the cuts run on it: the file's page, grown where a through cut runs past it \
             (a panel outline cut outside its panel) to the cut's path and half its kerf beyond.\n",
        );
        s
    }
}

/// The report's line under the stock list when part sheets had no room for their drawn stock label:
/// the technician must then go by the file name, which always carries the stock.
pub fn unlabelled_note(sheets: usize) -> Option<String> {
    (sheets > 0).then(|| {
        format!(
            "{sheets} part sheet(s) are filled too far for a drawn stock label; their file names, titles \
             and metadata name the stock: mark each sheet by hand as it comes off the shelf."
        )
    })
}

/// Why a drawing could not be handed on as it was made (rendering or writing it); the sink's own error.
pub type SinkError = Box<dyn std::error::Error + Send + Sync>;

/// Where a streamed build hands each drawing as soon as it is made (file order), instead of keeping it.
pub type DrawingSink<'s> = dyn FnMut(SheetDrawing) -> Result<(), SinkError> + 's;

/// Everything the layer builders make, in file order.
#[derive(Default)]
pub struct Drawn<'s> {
    /// Drawings in file order (empty when a sink takes them).
    pub drawings: Vec<SheetDrawing>,
    /// Cut-material sheets with the parts on them.
    pub sheets: Vec<SheetRecord>,
    /// Clamp panels used.
    pub panels: usize,
    /// Part sheets with no room left for their stock label (`super::sheet_label`).
    pub unlabelled_sheets: usize,
    /// Sheets of each stock drawn, in the order each stock first appears.
    pub stock: Vec<StockCount>,
    /// Which clamp panel holds each actuator, and which PZT sheet holds each plate.
    pub placement_map: Vec<String>,
    /// The snapping-order picture of each PZT sheet, (file name, SVG) (`super::snap_guide`).
    pub snap_guides: Vec<(String, String)>,
    /// The test-score coupon of each PZT stock, (file stem, [width, height] mm) (`super::coupon`).
    pub coupons: Vec<(String, [f64; 2])>,
    /// Next sheet number of each layer (stems are numbered per layer across the whole build).
    numbers: BTreeMap<String, usize>,
    /// Takes each drawing as it is made, so a large build never holds them all.
    sink: Option<&'s mut DrawingSink<'s>>,
    /// The sink's first error: later drawings are dropped, and the build stops at its next stage.
    failed: Option<SinkError>,
}

impl<'s> Drawn<'s> {
    /// Nothing drawn yet; every drawing goes to `sink` if there is one, else is kept in `drawings`.
    pub fn new(sink: Option<&'s mut DrawingSink<'s>>) -> Self {
        Drawn {
            sink,
            ..Drawn::default()
        }
    }

    /// Draw the stock label of part sheet `name` with `op` where none of `parts` is, or count the
    /// sheet as one without room for it.
    pub fn label_sheet(
        &mut self,
        d: &mut Drawing,
        name: &str,
        margin_mm: f64,
        parts: &[super::sheet_label::Box2],
        op: crate::drawing::model::Operation,
    ) {
        match super::sheet_label::sheet_label(d, name, margin_mm, parts) {
            Some(strokes) => {
                for s in strokes {
                    d.add(op, crate::drawing::model::Shape::Polyline(s));
                }
            }
            None => self.unlabelled_sheets += 1,
        }
    }

    /// The next 1-based sheet number of `layer`.
    pub fn next_number(&mut self, layer: &str) -> usize {
        let n = self.numbers.entry(layer.to_string()).or_insert(0);
        *n += 1;
        *n
    }

    /// Add a drawing that is cut from `copies` sheets of its stock: to the sink if there is one (nothing
    /// more after it failed), else to `drawings`. The stock list counts every sheet,
    /// the files hold the drawing once. A drawing of 0 copies is cut from an offcut and adds no line.
    pub fn push_copies(&mut self, stem: String, layer: &str, drawing: Drawing, copies: usize) {
        // A drawn sheet (copies 0) is stock the lab has, not stock to buy.
        if copies > 0 {
            StockCount::count(&mut self.stock, &drawing, copies);
        }
        let drawing = SheetDrawing {
            stem: file_stem(&stem, drawing.stock.as_ref()),
            layer: layer.into(),
            drawing,
        };
        match &mut self.sink {
            None => self.drawings.push(drawing),
            Some(sink) if self.failed.is_none() => {
                if let Err(e) = sink(drawing) {
                    self.failed = Some(e);
                }
            }
            Some(_) => {}
        }
    }

    /// The sink's error, if it failed: the build ends with it.
    pub fn check_sink(&mut self) -> Result<(), BuildError> {
        self.failed
            .take()
            .map_or(Ok(()), |e| Err(BuildError::Sink(e)))
    }
}

/// Process checks every design of a build must pass: the tip must survive the kerf.
pub fn check_geometry(job: &Job<'_>, template: &Template) -> Result<(), BuildError> {
    let widest_kerf = [template.pzt.kerf_mm, template.passive.kerf_mm]
        .into_iter()
        .fold(0.0, f64::max);
    let g = &job.geometry;
    if g.tip_width_mm < 2.0 * widest_kerf {
        return Err(design_error(
            job.design,
            format!(
                "geometry: tip width {:.4} mm is narrower than twice the kerf (2 x {} mm): the tip would be cut away",
                g.tip_width_mm, widest_kerf
            ),
        ));
    }
    if g.pzt_margin_mm > 0.0 && g.plate_tip_width_mm() < 2.0 * widest_kerf {
        return Err(design_error(
            job.design,
            format!(
                "geometry: the PZT plate inset by the template's {} mm edge margin is {:.4} mm wide at its tip, narrower than twice the kerf (2 x {} mm)",
                g.pzt_margin_mm,
                g.plate_tip_width_mm(),
                widest_kerf
            ),
        ));
    }
    Ok(())
}

/// A problem with one design's geometry, reported against its file.
pub fn design_error(design: &Design, what: String) -> BuildError {
    BuildError::Geometry {
        file: design.source.display().to_string(),
        what,
    }
}

/// Offset a ring by `delta` mm (outer contours +kerf/2, holes and cavities -kerf/2), naming the feature
/// when it vanishes.
pub fn kerfed(
    design: &Design,
    ring: &[Point],
    delta: f64,
    feature: &str,
) -> Result<Vec<Point>, BuildError> {
    if delta == 0.0 {
        return Ok(ring.to_vec());
    }
    offset_ring(ring, delta).map_err(|e| design_error(design, format!("{feature}: {e}")))
}

/// At most three violations, joined for a one-line message.
pub fn format_violations<V: std::fmt::Display>(v: &[V]) -> String {
    v.iter()
        .take(3)
        .map(|x| x.to_string())
        .collect::<Vec<_>>()
        .join("; ")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::drawing::model::{Operation, Shape, Stock};

    #[test]
    fn a_stock_line_holds_the_outline_cut_outside_its_panel_with_its_kerf() {
        // A 100 mm felt panel, 0.1 mm kerf: its outline's path runs kerf/2 outside the panel, from -0.05
        // to 100.05 mm, and the kerf takes 0.05 mm more on each side: a 100.2 mm sheet.
        let stock = Stock {
            material: "felt pad".into(),
            thickness_mm: 1.0,
            kerf_mm: 0.1,
            fibre_axis: None,
        };
        let mut d = Drawing::on_stock("panel", 100.0, 100.0, stock);
        // A score line past the page and a hole inside it take no larger sheet.
        d.add(
            Operation::Score,
            Shape::Polyline(vec![[-2.0, 50.0], [103.0, 50.0]]),
        );
        d.add(
            Operation::Cut,
            Shape::Circle {
                center: [3.0, 3.0],
                radius: 0.74,
            },
        );
        let mut rows = Vec::new();
        StockCount::count(&mut rows, &d, 2);
        assert_eq!((rows[0].width_mm, rows[0].height_mm), (100.0, 100.0));
        let (a, b) = (-0.05, 100.05);
        d.add(
            Operation::Cut,
            Shape::Polygon(vec![[a, a], [b, a], [b, b], [a, b]]),
        );
        StockCount::count(&mut rows, &d, 3);
        assert_eq!(rows.len(), 2);
        assert_eq!((rows[1].width_mm, rows[1].height_mm), (100.2, 100.2));
        assert_eq!(rows[1].sheets, 3);
    }
}
