//! A small SVG plotting vocabulary: a canvas, plot areas, linear scales, ticks, labels, lines and
//! markers. The calibration plots (parity and residual panels) and the optimizer's Pareto front are
//! drawn with it, so axes and marks are written one way.
//!
//! Numbers are written one fixed way (the golden snapshot pins the bytes): positions computed from
//! data with one decimal, page sizes and plot-area edges in paths as given.

use std::fmt::Write as _;

/// An SVG document being written.
#[derive(Debug, Clone)]
pub struct Canvas {
    svg: String,
}

/// The rectangle a plot draws in, in pixels from the top-left corner of the canvas.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Area {
    /// Left edge.
    pub left: f64,
    /// Right edge.
    pub right: f64,
    /// Top edge.
    pub top: f64,
    /// Bottom edge.
    pub bottom: f64,
}

impl Area {
    /// Horizontal centre.
    pub fn centre_x(&self) -> f64 {
        (self.left + self.right) / 2.0
    }

    /// Vertical centre.
    pub fn centre_y(&self) -> f64 {
        (self.top + self.bottom) / 2.0
    }

    /// Scale mapping data `lo..hi` onto the area from left to right.
    pub fn x_scale(&self, lo: f64, hi: f64) -> Scale {
        Scale {
            lo,
            hi,
            from: self.left,
            to: self.right,
        }
    }

    /// Scale mapping data `lo..hi` onto the area from bottom to top.
    pub fn y_scale(&self, lo: f64, hi: f64) -> Scale {
        Scale {
            lo,
            hi,
            from: self.bottom,
            to: self.top,
        }
    }
}

/// A linear map from data values `lo..hi` to pixels `from..to`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Scale {
    /// Data value at `from`.
    pub lo: f64,
    /// Data value at `to`.
    pub hi: f64,
    /// Pixel of `lo`.
    pub from: f64,
    /// Pixel of `hi`.
    pub to: f64,
}

impl Scale {
    /// Pixel of a data value.
    pub fn at(&self, v: f64) -> f64 {
        self.from + (v - self.lo) / (self.hi - self.lo) * (self.to - self.from)
    }
}

/// Where a label's anchor point lies on the text.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Anchor {
    /// Text starts at the point (SVG's default; no attribute written).
    Start,
    /// Text is centred on the point.
    Middle,
    /// Text ends at the point.
    End,
}

/// A text label at a point.
#[derive(Debug, Clone, PartialEq)]
pub struct Label<'a> {
    /// Anchor x, pixels.
    pub x: f64,
    /// Baseline y, pixels.
    pub y: f64,
    /// Horizontal alignment.
    pub anchor: Anchor,
    /// Bold (panel titles).
    pub bold: bool,
    /// The text (written as given).
    pub text: &'a str,
}

impl<'a> Label<'a> {
    /// A plain label.
    pub fn new(x: f64, y: f64, anchor: Anchor, text: &'a str) -> Self {
        Label {
            x,
            y,
            anchor,
            bold: false,
            text,
        }
    }
}

/// A round marker.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Marker<'a> {
    /// Radius, pixels.
    pub r: f64,
    /// Fill colour (`none` for a ring).
    pub fill: &'a str,
    /// Fill opacity, if not opaque.
    pub fill_opacity: Option<f64>,
    /// Outline colour and width, if outlined.
    pub stroke: Option<(&'a str, f64)>,
}

impl<'a> Marker<'a> {
    /// A filled dot.
    pub fn dot(r: f64, fill: &'a str) -> Self {
        Marker {
            r,
            fill,
            fill_opacity: None,
            stroke: None,
        }
    }
}

/// Dash pattern of guide lines (reference lines, bands, the required value).
pub const DASHED: &str = "4 3";

impl Canvas {
    /// Start a `width` × `height` document in sans-serif of `font_size`; `view_box` also writes a
    /// matching viewBox so the plot scales when embedded.
    pub fn new(width: f64, height: f64, font_size: f64, view_box: bool) -> Self {
        let mut svg = format!(
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{width}\" height=\"{height}\""
        );
        if view_box {
            let _ = write!(svg, " viewBox=\"0 0 {width} {height}\"");
        }
        let _ = writeln!(
            svg,
            " font-family=\"sans-serif\" font-size=\"{font_size}\">"
        );
        Canvas { svg }
    }

    /// Fill the whole page (`width` × `height` as given to [`Canvas::new`]).
    pub fn background(&mut self, width: f64, height: f64, fill: &str) {
        let _ = writeln!(
            self.svg,
            "<rect x=\"0\" y=\"0\" width=\"{width}\" height=\"{height}\" fill=\"{fill}\"/>"
        );
    }

    /// A closed frame around the area.
    pub fn frame(&mut self, area: &Area, stroke: &str) {
        let _ = writeln!(
            self.svg,
            "<rect x=\"{:.1}\" y=\"{:.1}\" width=\"{:.1}\" height=\"{:.1}\" fill=\"none\" stroke=\"{stroke}\"/>",
            area.left,
            area.top,
            area.right - area.left,
            area.bottom - area.top
        );
    }

    /// The left and bottom axis lines of the area.
    pub fn axes(&mut self, area: &Area, stroke: &str) {
        let _ = writeln!(
            self.svg,
            "<path d=\"M{} {} V{} H{}\" stroke=\"{stroke}\" fill=\"none\"/>",
            area.left, area.top, area.bottom, area.right
        );
    }

    /// A vertical line across the area at pixel `x` (a required value).
    pub fn vertical_rule(&mut self, area: &Area, x: f64, stroke: &str, dash: Option<&str>) {
        let _ = write!(
            self.svg,
            "<path d=\"M{x:.1} {} V{}\" stroke=\"{stroke}\"",
            area.top, area.bottom
        );
        self.dash_and_close(dash);
    }

    /// A straight line between two pixel points.
    pub fn line(&mut self, from: (f64, f64), to: (f64, f64), stroke: &str, dash: Option<&str>) {
        let _ = write!(
            self.svg,
            "<line x1=\"{:.1}\" y1=\"{:.1}\" x2=\"{:.1}\" y2=\"{:.1}\" stroke=\"{stroke}\"",
            from.0, from.1, to.0, to.1
        );
        self.dash_and_close(dash);
    }

    fn dash_and_close(&mut self, dash: Option<&str>) {
        if let Some(d) = dash {
            let _ = write!(self.svg, " stroke-dasharray=\"{d}\"");
        }
        self.svg.push_str("/>\n");
    }

    /// An open line through pixel points.
    pub fn polyline(&mut self, points: &[(f64, f64)], stroke: &str) {
        let pts: Vec<String> = points
            .iter()
            .map(|(x, y)| format!("{x:.1},{y:.1}"))
            .collect();
        let _ = writeln!(
            self.svg,
            "<polyline points=\"{}\" fill=\"none\" stroke=\"{stroke}\"/>",
            pts.join(" ")
        );
    }

    /// A marker centred on a pixel point.
    pub fn marker(&mut self, at: (f64, f64), m: &Marker) {
        let _ = write!(
            self.svg,
            "<circle cx=\"{:.1}\" cy=\"{:.1}\" r=\"{}\" fill=\"{}\"",
            at.0, at.1, m.r, m.fill
        );
        if let Some(o) = m.fill_opacity {
            let _ = write!(self.svg, " fill-opacity=\"{o}\"");
        }
        if let Some((colour, width)) = m.stroke {
            let _ = write!(self.svg, " stroke=\"{colour}\" stroke-width=\"{width}\"");
        }
        self.svg.push_str("/>\n");
    }

    /// One label on its own line.
    pub fn label(&mut self, label: &Label) {
        self.labels(std::slice::from_ref(label));
    }

    /// Labels that belong together (an axis' two ends) on one line of the file.
    pub fn labels(&mut self, labels: &[Label]) {
        for l in labels {
            let _ = write!(self.svg, "<text x=\"{:.1}\" y=\"{:.1}\"", l.x, l.y);
            self.anchor(l.anchor);
            if l.bold {
                self.svg.push_str(" font-weight=\"bold\"");
            }
            let _ = write!(self.svg, ">{}</text>", l.text);
        }
        self.svg.push('\n');
    }

    /// A title read bottom to top, centred at (`x`, `y`), for a vertical axis.
    pub fn vertical_label(&mut self, x: f64, y: f64, text: &str) {
        let _ = writeln!(
            self.svg,
            "<text x=\"{x}\" y=\"{y:.1}\" text-anchor=\"middle\" transform=\"rotate(-90 {x} {y:.1})\">{text}</text>"
        );
    }

    fn anchor(&mut self, anchor: Anchor) {
        match anchor {
            Anchor::Start => {}
            Anchor::Middle => self.svg.push_str(" text-anchor=\"middle\""),
            Anchor::End => self.svg.push_str(" text-anchor=\"end\""),
        }
    }

    /// Close the document.
    pub fn finish(mut self) -> String {
        self.svg.push_str("</svg>\n");
        self.svg
    }
}

/// Top-left corner of panel `index` in a grid of `cols` columns of `width` × `height` panels.
pub fn grid_cell(index: usize, cols: usize, width: f64, height: f64) -> (f64, f64) {
    (
        (index % cols) as f64 * width,
        (index / cols) as f64 * height,
    )
}

/// `count + 1` evenly spaced tick values from 0 to `span`.
pub fn ticks(span: f64, count: usize) -> Vec<f64> {
    (0..=count)
        .map(|i| span * i as f64 / count as f64)
        .collect()
}

/// Smallest round number (1, 1.2, 1.5, 2, 2.5, 3, 4, 5, 6, 8 x 10^k) at or above `x`: the end of an
/// axis that starts at zero.
pub fn nice_ceiling(x: f64) -> f64 {
    if x.is_nan() || x <= 0.0 {
        return 1.0;
    }
    let p = 10f64.powf(x.log10().floor());
    [1.0, 1.2, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0, 6.0, 8.0, 10.0]
        .into_iter()
        .map(|f| f * p)
        .find(|v| *v >= x * (1.0 - 1e-12))
        .unwrap_or(10.0 * p)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scales_map_ends_to_the_area_edges() {
        let area = Area {
            left: 50.0,
            right: 305.0,
            top: 25.0,
            bottom: 240.0,
        };
        let (x, y) = (area.x_scale(-1.0, 3.0), area.y_scale(0.0, 10.0));
        assert_eq!((x.at(-1.0), x.at(3.0), x.at(1.0)), (50.0, 305.0, 177.5));
        assert_eq!((y.at(0.0), y.at(10.0)), (240.0, 25.0));
    }

    #[test]
    fn writes_elements_in_the_pinned_formats() {
        let area = Area {
            left: 70.0,
            right: 620.0,
            top: 20.0,
            bottom: 370.0,
        };
        let mut c = Canvas::new(640.0, 420.0, 12.0, true);
        c.background(640.0, 420.0, "white");
        c.axes(&area, "black");
        c.frame(&area, "#444");
        c.vertical_rule(&area, 123.456, "gray", Some(DASHED));
        c.line((1.0, 2.0), (3.0, 4.04), "#999", None);
        c.polyline(&[(1.0, 2.0), (3.26, 4.0)], "steelblue");
        c.marker((1.0, 2.0), &Marker::dot(2.5, "steelblue"));
        c.marker(
            (1.0, 2.0),
            &Marker {
                r: 5.0,
                fill: "none",
                fill_opacity: Some(0.7),
                stroke: Some(("crimson", 2.0)),
            },
        );
        c.labels(&[
            Label::new(1.0, 2.0, Anchor::Start, "a"),
            Label {
                bold: true,
                ..Label::new(3.0, 4.0, Anchor::End, "b")
            },
        ]);
        c.vertical_label(16.0, 195.0, "mass (mg)");
        let svg = c.finish();
        let expected = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"640\" height=\"420\" viewBox=\"0 0 640 420\" font-family=\"sans-serif\" font-size=\"12\">\n\
<rect x=\"0\" y=\"0\" width=\"640\" height=\"420\" fill=\"white\"/>\n\
<path d=\"M70 20 V370 H620\" stroke=\"black\" fill=\"none\"/>\n\
<rect x=\"70.0\" y=\"20.0\" width=\"550.0\" height=\"350.0\" fill=\"none\" stroke=\"#444\"/>\n\
<path d=\"M123.5 20 V370\" stroke=\"gray\" stroke-dasharray=\"4 3\"/>\n\
<line x1=\"1.0\" y1=\"2.0\" x2=\"3.0\" y2=\"4.0\" stroke=\"#999\"/>\n\
<polyline points=\"1.0,2.0 3.3,4.0\" fill=\"none\" stroke=\"steelblue\"/>\n\
<circle cx=\"1.0\" cy=\"2.0\" r=\"2.5\" fill=\"steelblue\"/>\n\
<circle cx=\"1.0\" cy=\"2.0\" r=\"5\" fill=\"none\" fill-opacity=\"0.7\" stroke=\"crimson\" stroke-width=\"2\"/>\n\
<text x=\"1.0\" y=\"2.0\">a</text><text x=\"3.0\" y=\"4.0\" text-anchor=\"end\" font-weight=\"bold\">b</text>\n\
<text x=\"16\" y=\"195.0\" text-anchor=\"middle\" transform=\"rotate(-90 16 195.0)\">mass (mg)</text>\n\
</svg>\n";
        assert_eq!(svg, expected);
    }

    #[test]
    fn ticks_and_nice_ceilings() {
        assert_eq!(ticks(10.0, 5), vec![0.0, 2.0, 4.0, 6.0, 8.0, 10.0]);
        assert_eq!(nice_ceiling(0.0), 1.0);
        assert_eq!(nice_ceiling(1.0), 1.0);
        assert_eq!(nice_ceiling(1.1), 1.2);
        assert_eq!(nice_ceiling(7.3), 8.0);
        assert_eq!(nice_ceiling(8.5), 10.0);
        assert!((nice_ceiling(0.031) - 0.04).abs() < 1e-15);
        assert_eq!(grid_cell(6, 5, 320.0, 280.0), (320.0, 280.0));
    }
}
