//! The front of mass against delivered energy: for energy levels up to the most the bounds allow, the
//! lightest design that delivers at least that much.
//!
//! One pass over the grid bins every design by energy and keeps the lightest per (laminate, bin); the
//! lightest grid design delivering at least level `k` is then the lightest in bins `>= k`, which seeds a
//! refinement at that level. The refined designs that no other design dominates (lighter and at least as
//! energetic) form the front.

use super::refine::refine;
use super::report::decimal;
use super::search::{tip_width, Design, Objective, Problem, TIP_SLACK};
use crate::plot::{nice_ceiling, ticks, Anchor, Area, Canvas, Label, Marker, DASHED};
use rayon::prelude::*;
use std::cmp::Ordering;

/// Compute the front at `levels` energy levels `U_top k / levels`, `k = 1..=levels`; `most` holds each
/// laminate's most energetic design. Sorted by energy.
pub fn front(problem: &Problem, most: &[Design], levels: usize) -> Vec<Design> {
    let top = most.iter().map(|d| d.energy).fold(0.0, f64::max);
    if top.is_nan() || top <= 0.0 || levels == 0 {
        return Vec::new();
    }
    let bins = grid_bins(problem, top, levels);
    let mut front: Vec<Design> = (1..=levels)
        .into_par_iter()
        .filter_map(|k| {
            let level = top * k as f64 / levels as f64;
            let at_level = Problem {
                energy: level,
                objective: Objective::MinMass,
                ..problem.clone()
            };
            (0..problem.candidates.len())
                .filter_map(|c| {
                    let mut seeds: Vec<Design> = bins[c][k..]
                        .iter()
                        .flatten()
                        .copied()
                        .min_by(by_mass)
                        .into_iter()
                        .collect();
                    if most[c].energy >= level {
                        seeds.push(most[c]);
                    }
                    refine(&at_level, c, &seeds)
                })
                .min_by(|a, b| at_level.compare(a, b))
        })
        .collect();
    front.sort_by(|a, b| a.energy.total_cmp(&b.energy).then(by_mass(a, b)));
    // Keep a design only if no more energetic one is as light.
    let mut kept: Vec<Design> = Vec::new();
    for d in front.into_iter().rev() {
        if kept.last().is_none_or(|k| d.mass < k.mass) {
            kept.push(d);
        }
    }
    kept.reverse();
    kept
}

fn by_mass(a: &Design, b: &Design) -> Ordering {
    a.mass.total_cmp(&b.mass)
}

/// Lightest grid design per laminate and energy bin `floor(U levels / top)` (`0..=levels`).
fn grid_bins(problem: &Problem, top: f64, levels: usize) -> Vec<Vec<Option<Design>>> {
    let [lengths, widths, ext_ratios, width_ratios] = problem.axes();
    let n_r = ext_ratios.len();
    let tip_min = problem.min_tip_width * (1.0 - TIP_SLACK);
    let per_slice: Vec<Vec<Option<Design>>> = (0..problem.candidates.len() * n_r)
        .into_par_iter()
        .map(|task| {
            let (c, i_r) = (task / n_r, task % n_r);
            let l_r = ext_ratios[i_r];
            let mut bins: Vec<Option<Design>> = vec![None; levels + 1];
            for &w_r in &width_ratios {
                let rates = problem.shape_rates(c, l_r, w_r);
                for &w0 in &widths {
                    if tip_width(w0, w_r) < tip_min {
                        continue;
                    }
                    for &l in &lengths {
                        let d = problem.design(c, rates, l, w0, l_r, w_r);
                        if d.energy.is_nan() || d.energy <= 0.0 {
                            continue;
                        }
                        let bin = ((d.energy / top * levels as f64) as usize).min(levels);
                        if bins[bin].is_none_or(|b| d.mass < b.mass) {
                            bins[bin] = Some(d);
                        }
                    }
                }
            }
            bins
        })
        .collect();
    (0..problem.candidates.len())
        .map(|c| {
            (0..=levels)
                .map(|b| {
                    per_slice[c * n_r..(c + 1) * n_r]
                        .iter()
                        .filter_map(|s| s[b])
                        .min_by(by_mass)
                })
                .collect()
        })
        .collect()
}

/// The front as CSV, SI converted to the file units in the header.
pub fn to_csv(problem: &Problem, front: &[Design]) -> Result<String, csv::Error> {
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record([
        "energy_mJ",
        "mass_mg",
        "energy_density_J_per_kg",
        "pzt_thickness_mm",
        "layup_deg",
        "length_mm",
        "extension_ratio",
        "base_width_mm",
        "width_ratio",
    ])?;
    for d in front {
        let c = &problem.candidates[d.candidate];
        w.write_record([
            format!("{:.6}", d.energy * 1e3),
            format!("{:.3}", d.mass * 1e6),
            format!("{:.5}", d.energy / d.mass),
            format!("{:.3}", c.pzt_thickness * 1e3),
            super::report::layup_label(&c.layup),
            format!("{:.4}", d.length * 1e3),
            format!("{:.4}", d.extension_ratio),
            format!("{:.4}", d.base_width * 1e3),
            format!("{:.4}", d.width_ratio),
        ])?;
    }
    let bytes = w
        .into_inner()
        .map_err(|e| csv::Error::from(e.into_error()))?;
    // Every field is a `String`, so the bytes are UTF-8.
    Ok(String::from_utf8_lossy(&bytes).into_owned())
}

/// The front as an SVG plot: mass (mg) against energy (mJ), one marker per design, the required energy
/// marked.
pub fn to_svg(front: &[Design], required: f64, chosen: Option<&Design>) -> String {
    let (width, height) = (640.0, 420.0);
    let area = Area {
        left: 70.0,
        right: width - 20.0,
        top: 20.0,
        bottom: height - 50.0,
    };
    let e_max = front.iter().map(|d| d.energy * 1e3).fold(0.0, f64::max);
    let m_max = front.iter().map(|d| d.mass * 1e6).fold(0.0, f64::max);
    let e_span = nice_ceiling(e_max.max(required * 1e3));
    let m_span = nice_ceiling(m_max);
    let (x, y) = (area.x_scale(0.0, e_span), area.y_scale(0.0, m_span));
    let mut c = Canvas::new(width, height, 12.0, true);
    c.background(width, height, "white");
    c.axes(&area, "black");
    for (e, m) in ticks(e_span, 5).into_iter().zip(ticks(m_span, 5)) {
        let (e_text, m_text) = (decimal(e, 4), decimal(m, 4));
        c.label(&Label::new(
            x.at(e),
            area.bottom + 16.0,
            Anchor::Middle,
            &e_text,
        ));
        c.label(&Label::new(
            area.left - 6.0,
            y.at(m) + 4.0,
            Anchor::End,
            &m_text,
        ));
    }
    c.label(&Label::new(
        area.centre_x(),
        height - 12.0,
        Anchor::Middle,
        "delivered energy U (mJ)",
    ));
    c.vertical_label(16.0, area.centre_y(), "mass (mg)");
    c.vertical_rule(&area, x.at(required * 1e3), "gray", Some(DASHED));
    let points: Vec<(f64, f64)> = front
        .iter()
        .map(|d| (x.at(d.energy * 1e3), y.at(d.mass * 1e6)))
        .collect();
    c.polyline(&points, "steelblue");
    for &p in &points {
        c.marker(p, &Marker::dot(2.5, "steelblue"));
    }
    if let Some(d) = chosen {
        let ring = Marker {
            stroke: Some(("crimson", 2.0)),
            ..Marker::dot(5.0, "none")
        };
        c.marker((x.at(d.energy * 1e3), y.at(d.mass * 1e6)), &ring);
    }
    c.finish()
}
