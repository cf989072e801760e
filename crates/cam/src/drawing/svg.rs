//! SVG writer for laser software (LightBurn, Inkscape, LPKF via import), and a reader for
//! our own output used by tests and verification.
//!
//! Conventions (docs/cam.md §3): `width`/`height` in mm and `viewBox="0 0 W H"` so one user unit
//! is one millimetre; one Inkscape layer per operation in processing order; every shape a
//! `<path>` with absolute `M`/`L`/`A`/`Z` commands, `fill="none"`, a hairline stroke in the
//! operation's pure colour. The drawing model is y-up; SVG is y-down, so `y_svg = H - y`.
//!
//! A laser file's page is its sheet, so the page's corners are the sheet's corners and the page's
//! lower-left corner is the DXF's origin (docs/cam.md §3 "One origin"); what runs past the sheet edge
//! (score overruns, the outer half of a kerf) lies off the page, and the file's `<desc>` says how far.

use std::fmt::Write as _;

use super::arc::{on_circle, CircularArc};
pub use super::decimal::fmt_mm;
use super::decimal::push_mm;
use super::model::{Drawing, Operation, Shape};
use super::palette::Palette;
use cam_geometry::Point;

/// Options of the SVG writer.
#[derive(Clone, Debug, PartialEq)]
pub struct SvgOptions {
    /// Stroke width in mm; laser drivers treat a hairline as a vector line.
    pub stroke_mm: f64,
    /// Stroke colour per operation.
    pub palette: Palette,
}

impl Default for SvgOptions {
    /// 0.0254 mm (0.001 in), the usual vector-cut hairline.
    fn default() -> Self {
        SvgOptions {
            stroke_mm: 0.0254,
            palette: Palette::default(),
        }
    }
}

/// Escapes text for XML content and double-quoted attributes.
pub fn xml_escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            _ => out.push(c),
        }
    }
    out
}

/// Step the page grows in, mm, so grown pages keep round sizes.
const PAGE_STEP_MM: f64 = 0.1;

/// How far (mm) the farthest shape reaches past the sheet edge, 0 when every shape lies on the
/// sheet (edges included). Kerf-offset outlines reach past the sheet they are drawn on (a 100 mm
/// panel cut in a 0.1 mm kerf runs from -0.05 to 100.05 mm), and score lines run past it by the
/// template's overrun.
pub fn overhang_mm(drawing: &Drawing) -> f64 {
    let Some((lo, hi)) = drawing.extents() else {
        return 0.0;
    };
    let overflow = [
        -lo[0],
        -lo[1],
        hi[0] - drawing.width_mm,
        hi[1] - drawing.height_mm,
    ]
    .into_iter()
    .fold(f64::NEG_INFINITY, f64::max);
    // Shapes on the sheet edge (score lines, sheet outlines) are on the sheet.
    if overflow <= 1e-9 {
        0.0
    } else {
        overflow
    }
}

/// Margin (mm) a picture's page grows by on every side so that it holds everything drawn: the
/// [`overhang_mm`] rounded up to [`PAGE_STEP_MM`], which also leaves room for the hairline stroke
/// of an outline just past the sheet, as a renderer clips what lies off the page. Laser files keep
/// the page at the sheet ([`to_svg`]).
pub fn page_margin_mm(drawing: &Drawing) -> f64 {
    let overhang = overhang_mm(drawing);
    if overhang == 0.0 {
        0.0
    } else {
        (overhang / PAGE_STEP_MM - 1e-9).ceil() * PAGE_STEP_MM
    }
}

/// The order a laser file is cut in, as its `<desc>` and its DXF comment state it.
pub const CUT_ORDER: &str = "Cut order: the file's order, layer by layer in processing order \
     (REFERENCE, ENGRAVE, SCORE, SECONDARY, CUT), each layer's paths in turn; whatever lies inside a \
     closed through-cut contour comes before that contour; on a sheet of cut parts the parts \
     follow one another along a short path from its lower-left corner.";

/// The origin convention of a laser file in words, for its `<desc>` (and, in DXF terms, its comment):
/// where the sheet lies and how far shapes run past its edge.
pub fn origin_statement(drawing: &Drawing) -> String {
    let (w, h) = (fmt_mm(drawing.width_mm), fmt_mm(drawing.height_mm));
    let overhang = overhang_mm(drawing);
    let past = if overhang == 0.0 {
        "Every shape lies on the sheet.".to_string()
    } else {
        format!(
            "Shapes reach {} mm past the sheet edge (score overruns, kerf), off the page: a program \
             that imports the paths keeps them, a print driver that clips at the page loses them.",
            fmt_mm(overhang)
        )
    };
    format!(
        "Origin: the page is the {w} x {h} mm sheet. Its lower-left corner is the sheet's lower-left \
         corner and the (0, 0) of the DXF of the same name (x to the right, y up); SVG user units run \
         from its upper-left corner, also a sheet corner. Lay the sheet's corner on the file's. {past} \
         {CUT_ORDER}"
    )
}

/// Builds one path's `d` string in SVG coordinates: shifted by the page margin and y flipped
/// about the page height.
struct PathData<'a> {
    margin_mm: f64,
    page_height_mm: f64,
    d: &'a mut String,
    /// Whether a command has been written: the next one is set off by a space.
    started: bool,
}

impl PathData<'_> {
    fn xy(&mut self, p: Point) {
        push_mm(self.d, p[0] + self.margin_mm);
        self.d.push(' ');
        push_mm(self.d, self.page_height_mm - self.margin_mm - p[1]);
    }

    fn command(&mut self, cmd: char, p: Point) {
        if self.started {
            self.d.push(' ');
        }
        self.started = true;
        self.d.push(cmd);
        self.xy(p);
    }

    /// Counter-clockwise arc (y up) of at most 180° to `to`. Mirroring y turns it clockwise on
    /// screen, which is SVG's sweep-flag 0; large-arc-flag is 0 because the sweep is ≤ 180°.
    fn arc_to(&mut self, radius: f64, to: Point) {
        self.d.push_str(" A");
        push_mm(self.d, radius);
        self.d.push(' ');
        push_mm(self.d, radius);
        self.d.push_str(" 0 0 0 ");
        self.xy(to);
    }

    fn close(&mut self) {
        self.d.push_str(" Z");
    }
}

/// Appends one path's `d` string to `d`, which holds nothing of this path yet.
fn path_data(d: &mut String, shape: &Shape, margin_mm: f64, page_height_mm: f64) {
    let mut path = PathData {
        margin_mm,
        page_height_mm,
        d,
        started: false,
    };
    match shape {
        Shape::Polygon(ring) | Shape::Polyline(ring) => {
            for (i, &p) in ring.iter().enumerate() {
                path.command(if i == 0 { 'M' } else { 'L' }, p);
            }
            if matches!(shape, Shape::Polygon(_)) && !ring.is_empty() {
                path.close();
            }
        }
        Shape::Circle { center, radius } => {
            // Two half-circle arcs: a single SVG arc cannot end where it starts.
            path.command('M', on_circle(*center, *radius, 0.0));
            path.arc_to(*radius, on_circle(*center, *radius, 180.0));
            path.arc_to(*radius, on_circle(*center, *radius, 0.0));
            path.close();
        }
        Shape::Arc {
            center,
            radius,
            start_deg,
            end_deg,
        } => {
            // Sweeps over 180° come in two equal halves so the large-arc flag is never needed.
            let arc = CircularArc {
                center: *center,
                radius: *radius,
                start_deg: *start_deg,
                end_deg: *end_deg,
            };
            path.command('M', arc.start());
            for end in arc.pieces() {
                path.arc_to(*radius, end);
            }
        }
    }
}

/// How one operation's Inkscape layer is written: its label and stroke colour.
#[derive(Clone, Debug, PartialEq)]
pub struct LayerStyle {
    /// `inkscape:label` of the layer (and, lower-cased, its id).
    pub name: String,
    /// Stroke colour, `#RRGGBB`; the fill colour of a filled layer.
    pub colour: String,
    /// Shapes filled and not stroked: a picture that laser software cannot take for a vector path to cut.
    pub filled: bool,
}

/// Writes `drawing` as a laser file's SVG document (deterministic: same drawing, same bytes).
///
/// The page is the drawing's sheet, so the sheet's lower-left corner is the page's, as it is the
/// DXF's origin; shapes past the sheet edge lie off the page, and the `<desc>` says so
/// (`origin_statement`).
pub fn to_svg(drawing: &Drawing, opts: &SvgOptions) -> String {
    document(
        drawing,
        opts.stroke_mm,
        |op| LayerStyle {
            name: op.layer_name().to_string(),
            colour: opts.palette.svg_colour(op).to_string(),
            filled: false,
        },
        0.0,
        Some(&origin_statement(drawing)),
    )
}

/// A picture (the preview), not a laser file: the layer names and colours of `style` instead of the
/// operations' own, so that it does not look like a laser file to laser software, and the page grown
/// by [`page_margin_mm`] on every side so that everything drawn shows; the drawing's origin then sits
/// at `(margin, margin)` from the page's lower left.
pub fn write_svg(
    drawing: &Drawing,
    stroke_mm: f64,
    style: impl Fn(Operation) -> LayerStyle,
) -> String {
    document(drawing, stroke_mm, style, page_margin_mm(drawing), None)
}

/// The SVG document of `drawing`: its page the sheet grown by `margin` mm on every side, `desc` as its
/// `<desc>`.
fn document(
    drawing: &Drawing,
    stroke_mm: f64,
    style: impl Fn(Operation) -> LayerStyle,
    margin: f64,
    desc: Option<&str>,
) -> String {
    let page_height = drawing.height_mm + 2.0 * margin;
    let w = fmt_mm(drawing.width_mm + 2.0 * margin);
    let h = fmt_mm(page_height);
    let stroke = fmt_mm(stroke_mm);
    let mut out = String::with_capacity(512 + 128 * drawing.items().len());
    out.push_str("<?xml version=\"1.0\" encoding=\"UTF-8\" standalone=\"no\"?>\n");
    let _ = writeln!(
        out,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" \
         xmlns:inkscape=\"http://www.inkscape.org/namespaces/inkscape\" \
         xmlns:sodipodi=\"http://sodipodi.sourceforge.net/DTD/sodipodi-0.dtd\" \
         version=\"1.1\" width=\"{w}mm\" height=\"{h}mm\" viewBox=\"0 0 {w} {h}\">"
    );
    match drawing.stock_line() {
        Some(stock) => {
            let _ = writeln!(
                out,
                "  <title>{}; stock: {}</title>",
                xml_escape(&drawing.title),
                xml_escape(&stock)
            );
        }
        None => {
            let _ = writeln!(out, "  <title>{}</title>", xml_escape(&drawing.title));
        }
    }
    if let Some(desc) = desc {
        let _ = writeln!(out, "  <desc>{}</desc>", xml_escape(desc));
    }
    match &drawing.stock {
        Some(s) => {
            // The stock again as data, for tools that read the file rather than show it.
            let _ = write!(
                out,
                "  <metadata><stock xmlns=\"urn:actuator-cam:stock\" material=\"{}\" thickness_mm=\"{}\" \
                 width_mm=\"{}\" height_mm=\"{}\"{}/>",
                xml_escape(&s.material),
                fmt_mm(s.thickness_mm),
                fmt_mm(drawing.width_mm),
                fmt_mm(drawing.height_mm),
                s.fibre_axis
                    .map_or(String::new(), |a| format!(" fibre_axis=\"{}\"", a.name()))
            );
        }
        None => {
            if !drawing.guides().is_empty() {
                out.push_str("  <metadata>");
            }
        }
    }
    // Guides are data, not paths (crate::drawing::model::Guide): in the metadata, in page coordinates.
    for g in drawing.guides() {
        let _ = write!(
            out,
            "<guide xmlns=\"urn:actuator-cam:guide\" kind=\"{}\" d=\"",
            g.kind
        );
        path_data(
            &mut out,
            &Shape::Polygon(g.ring.clone()),
            margin,
            page_height,
        );
        out.push_str("\"/>");
    }
    if drawing.stock.is_some() || !drawing.guides().is_empty() {
        out.push_str("</metadata>\n");
    }
    for op in drawing.operations() {
        let LayerStyle {
            name,
            colour,
            filled,
        } = style(op);
        // The reference layer is locked in Inkscape, so its guides are seen but not picked up.
        let locked = if op == Operation::Reference {
            " sodipodi:insensitive=\"true\""
        } else {
            ""
        };
        let _ = writeln!(
            out,
            "  <g inkscape:groupmode=\"layer\" inkscape:label=\"{}\" id=\"layer-{}\"{locked}>",
            xml_escape(&name),
            xml_escape(&name.to_ascii_lowercase().replace(' ', "-"))
        );
        for shape in drawing.shapes_of(op) {
            out.push_str("    <path d=\"");
            path_data(&mut out, shape, margin, page_height);
            if filled {
                let _ = writeln!(out, "\" fill=\"{colour}\" stroke=\"none\"/>");
            } else {
                let _ = writeln!(
                    out,
                    "\" fill=\"none\" stroke=\"{colour}\" stroke-width=\"{stroke}\"/>"
                );
            }
        }
        out.push_str("  </g>\n");
    }
    out.push_str("</svg>\n");
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::drawing::model::sample_drawing as sample;

    #[test]
    fn numbers_are_six_decimals_trimmed_without_negative_zero() {
        assert_eq!(fmt_mm(1.0), "1");
        assert_eq!(fmt_mm(0.0254), "0.0254");
        assert_eq!(fmt_mm(-0.0000001), "0");
        assert_eq!(fmt_mm(-0.0), "0");
        assert_eq!(fmt_mm(12.3456789), "12.345679");
        assert_eq!(fmt_mm(-2.5), "-2.5");
        assert_eq!(fmt_mm(100.0), "100");
    }

    #[test]
    fn root_declares_mm_page_and_matching_viewbox() {
        let svg = to_svg(&sample(), &SvgOptions::default());
        assert!(svg.contains("width=\"80mm\" height=\"50mm\" viewBox=\"0 0 80 50\""));
        assert!(svg.contains("xmlns:inkscape=\"http://www.inkscape.org/namespaces/inkscape\""));
        assert!(svg.contains("<title>sample &lt;A&amp;B&gt;</title>"));
        assert!(svg.contains("stroke-width=\"0.0254\""));
        assert_eq!(svg.matches("fill=\"none\"").count(), 5);
    }

    #[test]
    fn layers_follow_processing_order_not_insertion_order() {
        let svg = to_svg(&sample(), &SvgOptions::default());
        let at = |label: &str| svg.find(&format!("inkscape:label=\"{label}\"")).unwrap();
        assert!(at("ENGRAVE") < at("SCORE"));
        assert!(at("SCORE") < at("SECONDARY"));
        assert!(at("SECONDARY") < at("CUT"));
        // Inside the CUT layer the polygon (added first) precedes the circle.
        let cut = &svg[at("CUT")..];
        assert!(cut.find("M5 45").unwrap() < cut.find(" A0.79 0.79").unwrap());
    }

    /// A 100 mm panel outline kerf-offset by 0.05 mm: it runs from -0.05 to 100.05 mm.
    fn kerfed_panel() -> Drawing {
        let mut d = Drawing::new("panel", 100.0, 100.0);
        let (a, b) = (-0.05, 100.05);
        d.add(
            Operation::Cut,
            Shape::Polygon(vec![[a, a], [b, a], [b, b], [a, b]]),
        );
        d
    }

    #[test]
    fn a_laser_files_page_is_its_sheet_and_its_desc_says_how_far_shapes_run_past() {
        // The page stays the 100 mm sheet, so the outline's corner lies 0.05 mm off the page's
        // corners, and the page's lower-left corner is the drawing's (0, 0), as in the DXF.
        let svg = to_svg(&kerfed_panel(), &SvgOptions::default());
        assert!(
            svg.contains("width=\"100mm\" height=\"100mm\" viewBox=\"0 0 100 100\""),
            "{svg}"
        );
        assert!(
            svg.contains("d=\"M-0.05 100.05 L100.05 100.05 L100.05 -0.05 L-0.05 -0.05 Z\""),
            "{svg}"
        );
        assert!(
            svg.contains("the page is the 100 x 100 mm sheet")
                && svg.contains("Shapes reach 0.05 mm past the sheet edge"),
            "{svg}"
        );
        // A drawing on its sheet (the sample's score line ends on both edges) says so.
        assert!(to_svg(&sample(), &SvgOptions::default())
            .contains("Every shape lies on the sheet. Cut order: the file's order"));
    }

    #[test]
    fn a_pictures_page_grows_to_hold_outlines_past_the_sheet() {
        // The same outline in a picture: the page grows by one 0.1 mm step per side to 100.2 mm and
        // the outline starts at 0.1 - 0.05.
        let d = kerfed_panel();
        let style = |op: Operation| LayerStyle {
            name: op.layer_name().to_string(),
            colour: "#123456".to_string(),
            filled: true,
        };
        let svg = write_svg(&d, 0.0254, style);
        assert!(
            svg.contains("width=\"100.2mm\" height=\"100.2mm\" viewBox=\"0 0 100.2 100.2\""),
            "{svg}"
        );
        assert!(
            svg.contains("d=\"M0.05 100.15 L100.15 100.15 L100.15 0.05 L0.05 0.05 Z\""),
            "{svg}"
        );
        assert!(!svg.contains("<desc>"), "a picture states no origin: {svg}");
        assert_eq!(page_margin_mm(&sample()), 0.0);
    }

    #[test]
    fn y_axis_is_flipped_about_sheet_height() {
        let mut d = Drawing::new("flip", 10.0, 20.0);
        d.add(
            Operation::Cut,
            Shape::Polyline(vec![[1.0, 2.0], [3.0, 19.5]]),
        );
        let svg = to_svg(&d, &SvgOptions::default());
        assert!(svg.contains("d=\"M1 18 L3 0.5\""), "{svg}");
    }

    #[test]
    fn circle_is_two_arcs_closed_and_arc_is_split_past_180() {
        let svg = to_svg(&sample(), &SvgOptions::default());
        // Circle at (20, 40) r 0.79 on a 50 mm sheet: y_svg = 10.
        assert!(
            svg.contains("d=\"M20.79 10 A0.79 0.79 0 0 0 19.21 10 A0.79 0.79 0 0 0 20.79 10 Z\"")
        );
        // 270° arc from (63, 40) via 135° to 270° = (60, 37) -> y_svg 13.
        let mid = on_circle([60.0, 40.0], 3.0, 135.0);
        let expected = format!(
            "d=\"M63 10 A3 3 0 0 0 {} {} A3 3 0 0 0 60 13\"",
            fmt_mm(mid[0]),
            fmt_mm(50.0 - mid[1])
        );
        assert!(svg.contains(&expected), "{svg}");
    }

    #[test]
    fn output_is_deterministic() {
        let opts = SvgOptions::default();
        assert_eq!(to_svg(&sample(), &opts), to_svg(&sample(), &opts));
    }
}
