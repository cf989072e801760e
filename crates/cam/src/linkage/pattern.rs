//! The flat pattern of one linkage laminate, mm, before kerf: the strip of links as the laser sees it,
//! the airframe tab at `x = 0`, the links along `+x`, the centre line on `y = 0`.
//!
//! ```text
//!  airframe tab | O | crank | B |      coupler      | A | tip tab
//!   (hole)        ^ gap = flexure length, film only; pivot = gap middle
//! ```
//!
//! Every cut-out of a layer (a carbon slot, a film or adhesive window) spans the strip's full width and
//! runs past its sides, so a layer's material inside the release outline is a set of spans along `x`
//! at the strip's local width: the areas, masses and inertias are exact sums over those spans
//! ([`super::mass`]).

use crate::process::linkage::LinkageProcess;
use cam_geometry::Point;

/// Joint names in strip order, as reports and messages print them.
pub const JOINTS: [&str; 3] = [
    "O (crank on airframe, the wing hinge)",
    "B (crank on coupler)",
    "A (coupler on actuator tip)",
];

/// One flexure as drawn, mm.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FlexureSize {
    /// Gap length along the strip.
    pub length_mm: f64,
    /// Width across the strip.
    pub width_mm: f64,
}

/// An axis-aligned rectangle `[x0, x1] × [y0, y1]`, mm.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rect {
    /// Left.
    pub x0: f64,
    /// Bottom.
    pub y0: f64,
    /// Right.
    pub x1: f64,
    /// Top.
    pub y1: f64,
}

impl Rect {
    /// Its ring, counter-clockwise from the lower left.
    pub fn ring(&self) -> Vec<Point> {
        vec![
            [self.x0, self.y0],
            [self.x1, self.y0],
            [self.x1, self.y1],
            [self.x0, self.y1],
        ]
    }

    /// Grown by `d` on every side (shrunk for `d < 0`).
    pub fn grown(&self, d: f64) -> Rect {
        Rect {
            x0: self.x0 - d,
            y0: self.y0 - d,
            x1: self.x1 + d,
            y1: self.y1 + d,
        }
    }

    /// Moved by `by`.
    pub fn moved(&self, by: Point) -> Rect {
        Rect {
            x0: self.x0 + by[0],
            y0: self.y0 + by[1],
            x1: self.x1 + by[0],
            y1: self.y1 + by[1],
        }
    }
}

/// The layers of the laminate, bottom to top, then the release cut through the stack.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Ply {
    /// A carbon layer: the links, slotted at the gaps.
    Carbon,
    /// Sheet adhesive, cut back from the gaps.
    Adhesive,
    /// The flexure film, kept over each gap and its margins.
    Film,
}

/// The stack bottom to top, with file names.
pub const STACK: [(Ply, &str); 5] = [
    (Ply::Carbon, "carbon"),
    (Ply::Adhesive, "adhesive"),
    (Ply::Film, "film"),
    (Ply::Adhesive, "adhesive"),
    (Ply::Carbon, "carbon"),
];

/// The flat pattern of one linkage.
#[derive(Debug, Clone, PartialEq)]
pub struct Pattern {
    /// Pivots O, B, A along the strip (gap middles), mm.
    pub pivots_mm: [f64; 3],
    /// The flexures at O, B, A.
    pub flexures: [FlexureSize; 3],
    /// Width of the links and tabs: the widest flexure, mm.
    pub strip_width_mm: f64,
    /// Strip length, tab end to tab end, mm.
    pub length_mm: f64,
    /// Mounting hole centre in the airframe tab.
    pub hole_centre: Point,
    /// Mounting hole diameter, mm.
    pub hole_diameter_mm: f64,
    /// Film reach past each gap, mm.
    pub film_margin_mm: f64,
    /// Adhesive stop short of each gap, mm.
    pub adhesive_cutback_mm: f64,
    /// Run of cut-outs past the strip's sides and ends, mm.
    pub overrun_mm: f64,
    /// Kerf, mm: cut-outs narrower than two kerfs are not drawn.
    pub kerf_mm: f64,
}

impl Pattern {
    /// Lay the strip out for link lengths `crank`, `coupler` (mm) and the flexures at O, B, A. The
    /// caller has checked that every feature is at least two kerfs ([`Pattern::too_narrow`]).
    pub fn new(
        crank_mm: f64,
        coupler_mm: f64,
        flexures: [FlexureSize; 3],
        process: &LinkageProcess,
    ) -> Pattern {
        let o = process.frame_tab_mm + flexures[0].length_mm / 2.0;
        let b = o + crank_mm;
        let a = b + coupler_mm;
        let length = a + flexures[2].length_mm / 2.0 + process.tip_tab_mm;
        let width = flexures.iter().map(|f| f.width_mm).fold(0.0, f64::max);
        // The hole in the middle of the tab's film-free part, so it cuts carbon and adhesive only.
        let bare = process.frame_tab_mm - process.film_margin_mm;
        Pattern {
            pivots_mm: [o, b, a],
            flexures,
            strip_width_mm: width,
            length_mm: length,
            hole_centre: [bare / 2.0, 0.0],
            hole_diameter_mm: process.hole_diameter_mm,
            film_margin_mm: process.film_margin_mm,
            adhesive_cutback_mm: process.adhesive_cutback_mm,
            overrun_mm: process.slot_overrun_mm,
            kerf_mm: process.kerf_mm,
        }
    }

    /// The gap of joint `i` along the strip, `(x0, x1)`.
    pub fn gap(&self, i: usize) -> (f64, f64) {
        let half = self.flexures[i].length_mm / 2.0;
        (self.pivots_mm[i] - half, self.pivots_mm[i] + half)
    }

    /// The cut-outs' extent across the strip: its width and the overrun on both sides.
    fn across(&self) -> (f64, f64) {
        let half = self.strip_width_mm / 2.0 + self.overrun_mm;
        (-half, half)
    }

    fn band(&self, x0: f64, x1: f64) -> Rect {
        let (y0, y1) = self.across();
        Rect { x0, y0, x1, y1 }
    }

    /// The slots of a carbon layer: the gaps.
    pub fn carbon_slots(&self) -> Vec<Rect> {
        (0..3)
            .map(|i| {
                let (x0, x1) = self.gap(i);
                self.band(x0, x1)
            })
            .collect()
    }

    /// The windows of an adhesive layer: each gap and its cut-back.
    pub fn adhesive_windows(&self) -> Vec<Rect> {
        let c = self.adhesive_cutback_mm;
        (0..3)
            .map(|i| {
                let (x0, x1) = self.gap(i);
                self.band(x0 - c, x1 + c)
            })
            .collect()
    }

    /// The windows of the film layer: everything between the film bridges (each gap and its margins),
    /// over the strip and past its ends; a window under two kerfs is left as film.
    pub fn film_windows(&self) -> Vec<Rect> {
        let m = self.film_margin_mm;
        let mut edges = vec![-self.overrun_mm];
        for i in 0..3 {
            let (x0, x1) = self.gap(i);
            edges.push(x0 - m);
            edges.push(x1 + m);
        }
        edges.push(self.length_mm + self.overrun_mm);
        edges
            .chunks(2)
            .filter(|w| w[1] - w[0] >= 2.0 * self.kerf_mm)
            .map(|w| self.band(w[0], w[1]))
            .collect()
    }

    /// The cut-outs of a ply.
    pub fn cut_outs(&self, ply: Ply) -> Vec<Rect> {
        match ply {
            Ply::Carbon => self.carbon_slots(),
            Ply::Adhesive => self.adhesive_windows(),
            Ply::Film => self.film_windows(),
        }
    }

    /// Local width of the released part at `x` (the gap's width inside a gap, else the strip's).
    pub fn width_at(&self, x: f64) -> f64 {
        (0..3)
            .find(|&i| {
                let (x0, x1) = self.gap(i);
                x > x0 && x < x1
            })
            .map_or(self.strip_width_mm, |i| self.flexures[i].width_mm)
    }

    /// Where the local width changes, with the strip's ends, in order.
    pub fn width_steps(&self) -> Vec<f64> {
        let mut xs = vec![0.0];
        for i in 0..3 {
            let (x0, x1) = self.gap(i);
            xs.extend([x0, x1]);
        }
        xs.push(self.length_mm);
        xs
    }

    /// The release outline, counter-clockwise: the strip, narrowed to each flexure's width at its gap.
    pub fn outline(&self) -> Vec<Point> {
        let xs = self.width_steps();
        let mut lower = Vec::new();
        for w in xs.windows(2) {
            let half = self.width_at(0.5 * (w[0] + w[1])) / 2.0;
            lower.push([w[0], -half]);
            lower.push([w[1], -half]);
        }
        let upper: Vec<Point> = lower.iter().rev().map(|p| [p[0], -p[1]]).collect();
        let mut ring: Vec<Point> = Vec::new();
        for p in lower.into_iter().chain(upper) {
            if ring.last() != Some(&p) {
                ring.push(p);
            }
        }
        if ring.first() == ring.last() {
            ring.pop();
        }
        drop_collinear(ring)
    }

    /// Spans `(x0, x1)` along the strip where `ply` has material inside the release outline.
    pub fn material_spans(&self, ply: Ply) -> Vec<(f64, f64)> {
        let mut spans = vec![(0.0, self.length_mm)];
        for cut in self.cut_outs(ply) {
            spans = spans
                .into_iter()
                .flat_map(|(a, b)| {
                    let mut left = Vec::new();
                    if cut.x0 > a {
                        left.push((a, cut.x0.min(b)));
                    }
                    if cut.x1 < b {
                        left.push((cut.x1.max(a), b));
                    }
                    left
                })
                .filter(|(a, b)| b > a)
                .collect();
        }
        spans
    }

    /// Whether `ply` has material under the whole mounting hole.
    pub fn hole_in(&self, ply: Ply) -> bool {
        let r = self.hole_diameter_mm / 2.0;
        let (h0, h1) = (self.hole_centre[0] - r, self.hole_centre[0] + r);
        self.material_spans(ply)
            .iter()
            .any(|(a, b)| *a <= h0 && h1 <= *b)
    }
}

/// `ring` without points that lie on the line through their neighbours (the outline's straight runs
/// where two spans have the same width).
fn drop_collinear(ring: Vec<Point>) -> Vec<Point> {
    let n = ring.len();
    (0..n)
        .filter(|&i| {
            let (p, q, r) = (ring[(i + n - 1) % n], ring[i], ring[(i + 1) % n]);
            let cross = (q[0] - p[0]) * (r[1] - q[1]) - (q[1] - p[1]) * (r[0] - q[0]);
            cross.abs() > 1e-12
        })
        .map(|i| ring[i])
        .collect()
}
