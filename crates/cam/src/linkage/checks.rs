//! The cross-layer checks run on every linkage drawn (docs/cam.md §7), on the drawings alone: the
//! shapes are read back, the kerf taken off, and the laminate rebuilt from them, without the pattern
//! that made them.
//!
//! - the flexure gaps (carbon slots) line up across the carbon layers;
//! - the film covers each gap by its margin;
//! - no adhesive lies over a gap;
//! - the film left unbonded at each joint (the adhesive window over its gap) is the length the model's
//!   flexure has (docs/physics.md §16.6);
//! - every cut-out, every web between two cut-outs, every edge of the release outline and every hole
//!   is at least two kerfs;
//! - the drawn areas times each layer's mass per area give the reported mass (1e-6 relative);
//! - the pin holes are the same on every layer.

use crate::drawing::model::Shape;
use crate::pipeline::SheetDrawing;
use cam_geometry::offset::offset_ring;
use cam_geometry::{signed_area, Bounds, Point};
use std::f64::consts::PI;

/// What the checks need besides the drawings: the kerf, the film margin, each stack layer's mass per
/// area (bottom to top) and the mass reported for one linkage.
#[derive(Debug, Clone, PartialEq)]
pub struct Expected {
    /// Kerf, mm.
    pub kerf_mm: f64,
    /// Film margin, mm.
    pub film_margin_mm: f64,
    /// The model's unbonded film at O, B, A, mm.
    pub unbonded_mm: [f64; 3],
    /// Mass per area of each stack layer, bottom to top, mg/mm².
    pub areal_densities: Vec<f64>,
    /// Reported mass of one linkage, mg.
    pub mass_mg: f64,
}

impl Expected {
    /// What a laminate's report says its drawings must give.
    pub fn of(report: &super::LinkageReport) -> Expected {
        Expected {
            kerf_mm: report.kerf_mm,
            film_margin_mm: report.film_margin_mm,
            unbonded_mm: unbonded_of(report),
            areal_densities: report
                .layers
                .iter()
                .map(|l| l.areal_density_mg_per_mm2)
                .collect(),
            mass_mg: report.mass_mg,
        }
    }
}

/// The unbonded film lengths at O, B, A a report's flexures are modelled with, mm.
fn unbonded_of(report: &super::LinkageReport) -> [f64; 3] {
    [0, 1, 2].map(|i| report.flexures.get(i).map_or(0.0, |f| f.unbonded_um * 1e-3))
}

/// A cut-out read back: `[x0, x1] × [y0, y1]` after the kerf.
type Band = [f64; 4];

fn rect_of(ring: &[Point]) -> Option<Band> {
    let Bounds { min, max } = Bounds::of(ring);
    let b = [min[0], max[0], min[1], max[1]];
    let area = (b[1] - b[0]) * (b[3] - b[2]);
    (ring.len() == 4 && (signed_area(ring).abs() - area).abs() <= 1e-9 * area.max(1.0)).then_some(b)
}

/// A layer drawing read back: its polygons and circles.
struct Read {
    polygons: Vec<Vec<Point>>,
    circles: Vec<(Point, f64)>,
}

fn read(d: &SheetDrawing) -> Read {
    let mut r = Read {
        polygons: Vec::new(),
        circles: Vec::new(),
    };
    for (_, shape) in d.drawing.items() {
        match shape {
            Shape::Polygon(p) => r.polygons.push(p.clone()),
            Shape::Circle { center, radius } => r.circles.push((*center, *radius)),
            _ => {}
        }
    }
    r
}

/// The part of `ring` between `x = a` and `x = b` (Sutherland-Hodgman against two half-planes).
fn clip_band(ring: &[Point], a: f64, b: f64) -> Vec<Point> {
    let clip = |ring: Vec<Point>, keep: &dyn Fn(Point) -> bool, x: f64| -> Vec<Point> {
        let n = ring.len();
        let mut out = Vec::new();
        for i in 0..n {
            let (p, q) = (ring[i], ring[(i + 1) % n]);
            let cross = |p: Point, q: Point| {
                let t = (x - p[0]) / (q[0] - p[0]);
                [x, p[1] + t * (q[1] - p[1])]
            };
            match (keep(p), keep(q)) {
                (true, true) => out.push(q),
                (true, false) => out.push(cross(p, q)),
                (false, true) => {
                    out.push(cross(p, q));
                    out.push(q);
                }
                (false, false) => {}
            }
        }
        out
    };
    let left = clip(ring.to_vec(), &|p: Point| p[0] >= a, a);
    clip(left, &|p: Point| p[0] <= b, b)
}

fn area(ring: &[Point]) -> f64 {
    if ring.len() < 3 {
        0.0
    } else {
        signed_area(ring).abs()
    }
}

fn inside(p: Point, b: &Band) -> bool {
    b[0] <= p[0] && p[0] <= b[1] && b[2] <= p[1] && p[1] <= b[3]
}

/// The problems found in one set of linkage drawings (the stack layers of a panel, bottom to top, then
/// its release cut); empty when every check holds.
pub fn check_linkage_drawings(drawings: &[SheetDrawing], expected: &Expected) -> Vec<String> {
    let mut problems = Vec::new();
    let k = expected.kerf_mm;
    let two = 2.0 * k - 1e-9;
    let Some((release, stack)) = drawings.split_last() else {
        return vec!["no linkage drawings".into()];
    };
    if stack.len() != expected.areal_densities.len() {
        return vec![format!(
            "{} stack layers drawn, {} expected",
            stack.len(),
            expected.areal_densities.len()
        )];
    }
    let layers: Vec<Read> = stack.iter().map(read).collect();
    let released = read(release);
    let cut_outs = read_cut_outs(&layers, stack, k, &mut problems);
    let carbon: Vec<usize> = stack
        .iter()
        .enumerate()
        .filter(|(_, d)| d.layer == "linkage-carbon")
        .map(|(i, _)| i)
        .collect();
    let film = stack.iter().position(|d| d.layer == "linkage-film");
    let adhesive: Vec<usize> = stack
        .iter()
        .enumerate()
        .filter(|(_, d)| d.layer == "linkage-adhesive")
        .map(|(i, _)| i)
        .collect();
    let (Some(film), &[c0, c1], &[a0, a1]) = (film, carbon.as_slice(), adhesive.as_slice()) else {
        return vec!["the stack is not carbon, adhesive, film, adhesive, carbon".into()];
    };
    let layer = |l: usize| Layer {
        stem: &stack[l].stem,
        cut_outs: &cut_outs[l],
    };
    check_gaps(
        [layer(c0), layer(c1)],
        layer(film),
        [layer(a0), layer(a1)],
        expected,
        &mut problems,
    );
    for l in 0..stack.len() {
        check_two_kerfs(layer(l), two, &mut problems);
    }
    // The released linkages, kerf off; their holes (circles inside them).
    let outlines: Vec<Vec<Point>> = released
        .polygons
        .iter()
        .filter_map(|p| offset_ring(p, -k / 2.0).ok())
        .collect();
    let holes = check_holes(&layers, stack, &released, &release.stem, k, &mut problems);
    for ring in &outlines {
        check_release_edges(ring, &release.stem, two, &mut problems);
    }
    // Mass: each layer's material inside each outline, from the drawn shapes.
    for ring in &outlines {
        let mass = drawn_mass(ring, stack, &cut_outs, &holes, expected, &mut problems);
        if (mass - expected.mass_mg).abs() > 1e-6 * expected.mass_mg.max(1e-9) {
            problems.push(format!(
                "{}: the drawn areas give {mass:.9} mg, the report {:.9} mg",
                release.stem, expected.mass_mg
            ));
        }
    }
    problems
}

/// A stack layer's name and its cut-outs read back, for the checks that compare layers.
#[derive(Clone, Copy)]
struct Layer<'a> {
    stem: &'a str,
    cut_outs: &'a [Band],
}

/// Each layer's cut-outs with the kerf taken off (they were shrunk by kerf/2); the panel outline is
/// the polygon that holds every other. A cut-out that is not a rectangle is a problem.
fn read_cut_outs(
    layers: &[Read],
    stack: &[SheetDrawing],
    k: f64,
    problems: &mut Vec<String>,
) -> Vec<Vec<Band>> {
    layers
        .iter()
        .zip(stack)
        .map(|(l, d)| {
            let mut polys = l.polygons.clone();
            polys.sort_by(|a, b| area(b).total_cmp(&area(a)));
            polys
                .iter()
                .skip(1)
                .filter_map(|p| match rect_of(p) {
                    Some(b) => Some([
                        b[0] - k / 2.0,
                        b[1] + k / 2.0,
                        b[2] - k / 2.0,
                        b[3] + k / 2.0,
                    ]),
                    None => {
                        problems.push(format!("{}: a cut-out is not a rectangle", d.stem));
                        None
                    }
                })
                .collect()
        })
        .collect()
}

/// The flexure gaps: the two carbon layers' slots line up, the film covers each gap by
/// `film_margin_mm`, no adhesive lies over one, and the adhesive window over the gap leaves the film
/// unbonded over the model's length for its joint (gaps in order along each row: O, B, A).
fn check_gaps(
    [c0, c1]: [Layer<'_>; 2],
    film: Layer<'_>,
    adhesive: [Layer<'_>; 2],
    expected: &Expected,
    problems: &mut Vec<String>,
) {
    let film_margin_mm = expected.film_margin_mm;
    let gaps = c0.cut_outs;
    let same = gaps.len() == c1.cut_outs.len()
        && gaps
            .iter()
            .zip(c1.cut_outs)
            .all(|(a, b)| a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-9));
    if !same {
        problems.push(format!(
            "{} and {}: the flexure gaps do not line up",
            c0.stem, c1.stem
        ));
    }
    let mut in_rows = gaps.to_vec();
    in_rows.sort_by(|a, b| a[2].total_cmp(&b[2]).then(a[0].total_cmp(&b[0])));
    for (j, g) in in_rows.iter().enumerate() {
        // Film over each gap and its margins: no film window reaches into it.
        let covered = [g[0] - film_margin_mm, g[1] + film_margin_mm];
        if film.cut_outs.iter().any(|w| {
            w[2] < g[3] && w[3] > g[2] && w[0] < covered[1] - 1e-9 && w[1] > covered[0] + 1e-9
        }) {
            problems.push(format!(
                "{}: the film does not cover the gap at x = {:.4} mm by its {} mm margin",
                film.stem, g[0], film_margin_mm
            ));
        }
        // No adhesive over the gap: an adhesive window holds it whole.
        for a in &adhesive {
            let window = a.cut_outs.iter().find(|w| {
                w[0] <= g[0] + 1e-9
                    && w[1] >= g[1] - 1e-9
                    && w[2] <= g[2] + 1e-9
                    && w[3] >= g[3] - 1e-9
            });
            let Some(w) = window else {
                problems.push(format!(
                    "{}: adhesive over the flexure gap at x = {:.4} mm",
                    a.stem, g[0]
                ));
                continue;
            };
            let model = expected.unbonded_mm[j % 3];
            if (w[1] - w[0] - model).abs() > 1e-6 {
                problems.push(format!(
                    "{}: the film is unbonded over {:.4} mm at x = {:.4} mm, the model's flexure {model:.4} mm",
                    a.stem,
                    w[1] - w[0],
                    g[0]
                ));
            }
        }
    }
}

/// Two kerfs (`two`, mm): each cut-out of `layer`, and the web between neighbours in a row.
fn check_two_kerfs(layer: Layer<'_>, two: f64, problems: &mut Vec<String>) {
    let mut sorted = layer.cut_outs.to_vec();
    sorted.sort_by(|a, b| a[2].total_cmp(&b[2]).then(a[0].total_cmp(&b[0])));
    for b in &sorted {
        if b[1] - b[0] < two || b[3] - b[2] < two {
            problems.push(format!(
                "{}: a {:.4} x {:.4} mm cut-out is under two kerfs",
                layer.stem,
                b[1] - b[0],
                b[3] - b[2]
            ));
        }
    }
    for w in sorted.windows(2) {
        if (w[0][2] - w[1][2]).abs() < 1e-9 && w[1][0] - w[0][1] < two {
            problems.push(format!(
                "{}: {:.4} mm of material between two cut-outs, under two kerfs",
                layer.stem,
                w[1][0] - w[0][1]
            ));
        }
    }
}

/// The pin holes, the same on every layer and on the release cut, and the release cut's other
/// holes, each at least two kerfs across; those holes (centre, radius with the kerf off) returned.
fn check_holes(
    layers: &[Read],
    stack: &[SheetDrawing],
    released: &Read,
    release: &str,
    k: f64,
    problems: &mut Vec<String>,
) -> Vec<(Point, f64)> {
    let two = 2.0 * k - 1e-9;
    let pins: Vec<(Point, f64)> = layers[0].circles.clone();
    for (l, layer) in layers.iter().enumerate() {
        let same = layer.circles.len() == pins.len()
            && layer
                .circles
                .iter()
                .zip(&pins)
                .all(|(a, b)| a.0 == b.0 && a.1 == b.1);
        if !same {
            problems.push(format!(
                "{}: the pin holes differ from {}'s",
                stack[l].stem, stack[0].stem
            ));
        }
    }
    let holes: Vec<(Point, f64)> = released
        .circles
        .iter()
        .filter(|c| !pins.contains(c))
        .map(|(c, r)| (*c, r + k / 2.0))
        .collect();
    if released.circles.len() != holes.len() + pins.len() {
        problems.push(format!("{release}: the pin holes differ from the layers'"));
    }
    for (_, r) in &holes {
        if 2.0 * r < two {
            problems.push(format!(
                "{release}: a {:.4} mm hole is under two kerfs",
                2.0 * r
            ));
        }
    }
    holes
}

/// Every edge of a release outline (`ring`, kerf off) is at least two kerfs (`two`, mm) long.
fn check_release_edges(ring: &[Point], release: &str, two: f64, problems: &mut Vec<String>) {
    let n = ring.len();
    for i in 0..n {
        let (p, q) = (ring[i], ring[(i + 1) % n]);
        let len = ((q[0] - p[0]).powi(2) + (q[1] - p[1]).powi(2)).sqrt();
        if len < two {
            problems.push(format!(
                "{release}: a {len:.4} mm edge of the release outline is under two kerfs"
            ));
        }
    }
}

/// The mass of the linkage inside `ring`, mg: each layer's material (outline less its cut-outs and
/// `holes`) times its mass per area. A cut-out that stops inside the linkage is a problem.
fn drawn_mass(
    ring: &[Point],
    stack: &[SheetDrawing],
    cut_outs: &[Vec<Band>],
    holes: &[(Point, f64)],
    expected: &Expected,
    problems: &mut Vec<String>,
) -> f64 {
    let Bounds { min, max } = Bounds::of(ring);
    let ([x_lo, y_lo], [x_hi, y_hi]) = (min, max);
    let mut mass = 0.0;
    for (l, bands) in cut_outs.iter().enumerate() {
        let mut a = area(ring);
        for b in bands
            .iter()
            .filter(|b| b[0] < x_hi && b[1] > x_lo && b[2] < y_hi && b[3] > y_lo)
        {
            if b[2] > y_lo || b[3] < y_hi {
                problems.push(format!(
                    "{}: a cut-out stops inside the linkage instead of crossing it",
                    stack[l].stem
                ));
            }
            a -= area(&clip_band(ring, b[0], b[1]));
        }
        for (c, r) in holes {
            let in_this = c[0] > x_lo && c[0] < x_hi && c[1] > y_lo && c[1] < y_hi;
            if in_this && !bands.iter().any(|b| inside(*c, b)) {
                a -= PI * r * r;
            }
        }
        mass += a * expected.areal_densities[l];
    }
    mass
}

/// The pivots O, B, A of each linkage read back from a carbon layer: the middles of its slots (the kerf
/// shrinks a slot evenly, so it keeps its middle), in order along each row, mm. The tests hold the
/// drawn pivots to the solved linkage with it.
#[cfg(test)]
pub fn pivots_read_back(carbon: &SheetDrawing) -> Vec<[f64; 3]> {
    let r = read(carbon);
    let mut polys = r.polygons;
    polys.sort_by(|a, b| area(b).total_cmp(&area(a)));
    let mut slots: Vec<Band> = polys.iter().skip(1).filter_map(|p| rect_of(p)).collect();
    slots.sort_by(|a, b| a[2].total_cmp(&b[2]).then(a[0].total_cmp(&b[0])));
    slots
        .chunks(3)
        .filter(|c| c.len() == 3)
        .map(|c| [0, 1, 2].map(|i| 0.5 * (c[i][0] + c[i][1])))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linkage::tests::hawkmoth;
    use crate::linkage::LinkageLaminate;
    use crate::pipeline::SheetDrawing;
    use actuator_model::transmission::Linkage;

    fn expected(l: &LinkageLaminate) -> Expected {
        let r = l.report();
        Expected {
            kerf_mm: r.kerf_mm,
            film_margin_mm: r.film_margin_mm,
            unbonded_mm: unbonded_of(&r),
            areal_densities: r
                .layers
                .iter()
                .map(|x| x.areal_density_mg_per_mm2)
                .collect(),
            mass_mg: r.mass_mg,
        }
    }

    fn drawn(l: &LinkageLaminate, count: usize) -> Vec<SheetDrawing> {
        let (_, template) = hawkmoth();
        crate::linkage::drawings::linkage_drawings(l, &template, count, "test").unwrap()
    }

    #[test]
    fn a_drawn_linkage_passes_every_check() {
        let (l, _) = hawkmoth();
        let d = drawn(&l, 7);
        assert_eq!(d.len(), 6);
        assert_eq!(
            check_linkage_drawings(&d, &expected(&l)),
            Vec::<String>::new()
        );
    }

    /// Replace the polygon at `index` (in drawing order) of drawing `layer` by `f` of its ring.
    fn bend(d: &mut [SheetDrawing], layer: usize, index: usize, f: impl Fn(Point) -> Point) {
        let mut fresh = crate::drawing::model::Drawing::new(
            &d[layer].drawing.title,
            d[layer].drawing.width_mm,
            d[layer].drawing.height_mm,
        );
        let mut seen = 0;
        for (op, shape) in d[layer].drawing.items() {
            let shape = match shape {
                Shape::Polygon(p) => {
                    seen += 1;
                    if seen - 1 == index {
                        Shape::Polygon(p.iter().map(|q| f(*q)).collect())
                    } else {
                        shape.clone()
                    }
                }
                other => other.clone(),
            };
            fresh.add(*op, shape);
        }
        d[layer].drawing = fresh;
    }

    #[test]
    fn each_check_catches_the_fault_it_is_for() {
        let (l, _) = hawkmoth();
        let e = expected(&l);
        let fails = |d: &[SheetDrawing], what: &str| {
            let p = check_linkage_drawings(d, &e);
            assert!(p.iter().any(|m| m.contains(what)), "{what}: {p:?}");
        };
        // A slot of the top carbon layer moved by 10 µm: the gaps no longer line up.
        let mut d = drawn(&l, 1);
        bend(&mut d, 4, 1, |p| [p[0] + 0.01, p[1]]);
        fails(&d, "do not line up");
        // A film window grown into the margin of the first gap.
        let mut d = drawn(&l, 1);
        bend(&mut d, 2, 1, |p| {
            [if p[0] > 1.0 { p[0] + 0.2 } else { p[0] }, p[1]]
        });
        fails(&d, "does not cover the gap");
        // An adhesive window narrowed so that adhesive reaches into a gap.
        let mut d = drawn(&l, 1);
        bend(&mut d, 1, 1, |p| {
            [if p[0] > 12.0 { p[0] - 0.15 } else { p[0] }, p[1]]
        });
        fails(&d, "adhesive over the flexure gap");
        // A pin hole moved on the film layer.
        let mut d = drawn(&l, 1);
        let mut fresh =
            crate::drawing::model::Drawing::new("x", d[2].drawing.width_mm, d[2].drawing.height_mm);
        for (op, shape) in d[2].drawing.items() {
            let shape = match shape {
                Shape::Circle { center, radius } => Shape::Circle {
                    center: [center[0] + 0.05, center[1]],
                    radius: *radius,
                },
                other => other.clone(),
            };
            fresh.add(*op, shape);
        }
        d[2].drawing = fresh;
        fails(&d, "pin holes differ");
        // A reported mass 1e-5 off.
        let d = drawn(&l, 1);
        let off = Expected {
            mass_mg: e.mass_mg * (1.0 + 1e-5),
            ..e.clone()
        };
        assert!(check_linkage_drawings(&d, &off)
            .iter()
            .any(|m| m.contains("drawn areas give")));
        // A kerf the features do not hold: two kerfs of 0.2 mm are wider than the film's gap bridges.
        let wide = Expected {
            kerf_mm: 0.2,
            ..e.clone()
        };
        assert!(check_linkage_drawings(&d, &wide)
            .iter()
            .any(|m| m.contains("under two kerfs")));
    }

    #[test]
    fn the_model_flexure_is_the_unbonded_film_drawn() {
        // The hawk-moth linkage (method 2: adhesive cut back 0.1 mm, flexures 2 mm wide on a strip as
        // wide): each adhesive window read back from the drawn file is the report's unbonded length, gap +
        // 2 × 0.1 mm, and k = E w t³ / (12 (L + 2c w/W)) (docs/physics.md §16.6).
        let (l, _) = hawkmoth();
        let r = l.report();
        let d = drawn(&l, 2);
        let adhesive = read(&d[1]);
        let mut polys = adhesive.polygons;
        polys.sort_by(|a, b| area(b).total_cmp(&area(a)));
        let mut windows: Vec<Band> = polys.iter().skip(1).filter_map(|p| rect_of(p)).collect();
        windows.sort_by(|a, b| a[2].total_cmp(&b[2]).then(a[0].total_cmp(&b[0])));
        assert_eq!(windows.len(), 6);
        let k = r.kerf_mm;
        for (j, w) in windows.iter().enumerate() {
            let f = &r.flexures[j % 3];
            let drawn_um = (w[1] - w[0] + k) * 1e3;
            assert!(
                (drawn_um - f.unbonded_um).abs() < 1e-6,
                "{j}: {drawn_um} vs {}",
                f.unbonded_um
            );
            assert!((f.unbonded_um - f.length_um - 200.0).abs() < 1e-9);
            let strip = r.strip_width_mm;
            let le = f.length_um * 1e-6 + 2.0 * 0.1e-3 * f.width_mm / strip;
            let closed = 2.5e9 * f.width_mm * 1e-3 * (f.film_um * 1e-6).powi(3) / (12.0 * le);
            assert!((f.stiffness_uNm_per_rad - closed * 1e6).abs() < 1e-9 * closed * 1e6);
        }
        // A model whose flexure is the carbon gap alone is caught by the check on every drawing.
        let gap_only = Expected {
            unbonded_mm: [0, 1, 2].map(|i| r.flexures[i].length_um * 1e-3),
            ..expected(&l)
        };
        let p = check_linkage_drawings(&d, &gap_only);
        assert_eq!(
            p.iter()
                .filter(|m| m.contains("the film is unbonded over"))
                .count(),
            12,
            "{p:?}"
        );
    }

    #[test]
    fn the_drawn_geometry_gives_back_the_drive_linkage() {
        // θ_w(δ) of eq. 2.5 through the link lengths read off the carbon slots, at five points.
        let (l, _) = hawkmoth();
        let d = drawn(&l, 3);
        let carbon = pivots_read_back(&d[0]);
        assert_eq!(carbon.len(), 3);
        for [o, b, a] in carbon {
            let read = Linkage::new((a - b) * 1e-3, (b - o) * 1e-3, l.linkage.offset).unwrap();
            for x in [-1.0, -0.5, 0.0, 0.5, 1.0] {
                let x = x * 0.75e-3;
                let drawn = read.stroke_angle(x).unwrap();
                let solved = l.linkage.stroke_angle(x).unwrap();
                assert!((drawn - solved).abs() < 1e-6, "{x}: {drawn} vs {solved}");
            }
        }
    }
}
