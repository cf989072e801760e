//! Clamp-panel layers (mold frames with a cavity per actuator, pads and covers) for jobs that share one
//! laminate height, so one stack of mold layers fits all of them.

use super::jobs::{kerfed, Drawn, Job, Names};
use super::panel::{fiducials, layout_panels, panel_outline, pin_centres, rect, window_origin};
use super::parts::PartGeometry;
use super::BuildError;
use crate::cam::drawing::{Drawing, Shape};
use crate::cam::label::{label_strokes, label_width};
use crate::cutsheet::Feature;
use crate::design::Design;
use crate::process::template::Template;
use cam_geometry::place_ring;
use cam_geometry::Point;

/// What a clamp build made.
#[derive(Debug, Clone, PartialEq)]
pub struct ClampBuild {
    /// Clamp stack, bottom to top, with the mold layers numbered (`mold-2`) and the others numbered by
    /// occurrence (`felt-1`).
    pub stack: Vec<String>,
    /// Per panel (numbered on from the panels built before), the (job, actuator) it holds.
    pub panels: Vec<Vec<(usize, usize)>>,
    /// Number of the first panel (1-based).
    pub first_panel: usize,
}

/// Laminate height of a design, mm: two plates, the passive core and the bond layers.
pub fn laminate_mm(design: &Design) -> f64 {
    (2.0 * design.pzt_thickness
        + design.ply_thickness * design.layup_deg.len() as f64
        + 2.0 * design.bond.as_ref().map(|(_, t)| *t).unwrap_or(0.0))
        * 1e3
}

/// The cavity shape of mold layer `j` (height band `[j t, (j+1) t]` from the bottom of the stack): the
/// passive outline where the band meets the passive core or bond layers, the PZT outline elsewhere.
fn cavity_outline(
    design: &Design,
    g: &PartGeometry,
    mold_thickness_mm: f64,
    j: usize,
) -> Vec<Point> {
    let t_p = design.pzt_thickness * 1e3;
    let t_b = design.bond.as_ref().map(|(_, t)| t * 1e3).unwrap_or(0.0);
    let core = design.ply_thickness * 1e3 * design.layup_deg.len() as f64 + 2.0 * t_b;
    let (lo, hi) = (
        j as f64 * mold_thickness_mm,
        (j + 1) as f64 * mold_thickness_mm,
    );
    if lo < t_p + core && hi > t_p {
        g.passive_outline()
    } else {
        g.pzt_outline()
    }
}

/// The smallest geometry whose panel cell holds every job's actuator (its own geometry for one job).
fn envelope(jobs: &[(usize, Job<'_>)]) -> PartGeometry {
    if let [(_, only)] = jobs {
        return only.geometry;
    }
    let width = jobs
        .iter()
        .map(|(_, j)| j.geometry.base_width_mm.max(j.geometry.tip_width_mm))
        .fold(0.0, f64::max);
    let tab = jobs
        .iter()
        .map(|(_, j)| j.geometry.base_tab_mm)
        .fold(0.0, f64::max);
    let length = jobs
        .iter()
        .map(|(_, j)| j.geometry.passive_length_mm())
        .fold(0.0, f64::max);
    PartGeometry {
        piezo_length_mm: length - tab,
        extension_length_mm: 0.0,
        base_width_mm: width,
        tip_width_mm: width,
        base_tab_mm: tab,
        pzt_margin_mm: 0.0,
    }
}

/// Assign the actuators of `jobs` (which share one laminate height) to clamp panels and draw every
/// clamp layer of every panel.
pub fn clamp_layers(
    jobs: &[(usize, Job<'_>)],
    template: &Template,
    names: &Names,
    drawn: &mut Drawn,
) -> Result<ClampBuild, BuildError> {
    let Some((_, first)) = jobs.first() else {
        return Ok(ClampBuild {
            stack: Vec::new(),
            panels: Vec::new(),
            first_panel: drawn.panels + 1,
        });
    };
    let c = &template.clamp;
    let cell = envelope(jobs);
    // Every actuator in job order: (position in `jobs`, actuator).
    let actuators: Vec<(usize, usize)> = jobs
        .iter()
        .enumerate()
        .flat_map(|(k, (_, j))| (0..j.quantity).map(move |a| (k, a)))
        .collect();
    let layout = layout_panels(c, &cell, actuators.len())
        .map_err(|e| names.error(format!("clamp panel: {e}")))?;
    let first_panel = drawn.panels + 1;
    drawn.panels += layout.panels.len();
    // (position in `jobs`, actuator, base point) per panel.
    let panels: Vec<Vec<(usize, usize, Point)>> = layout
        .panels
        .iter()
        .map(|members| {
            members
                .iter()
                .map(|(i, base)| {
                    let (k, a) = actuators[*i];
                    let own_tab = jobs[k].1.geometry.base_tab_mm;
                    let base = if own_tab == cell.base_tab_mm {
                        *base
                    } else {
                        [base[0], base[1] - cell.base_tab_mm + own_tab]
                    };
                    (k, a, base)
                })
                .collect()
        })
        .collect();
    for (p, members) in panels.iter().enumerate() {
        for (k, a, _) in members {
            drawn.placement_map.push(format!(
                "{}: clamp panel {}",
                names.actuator(jobs[*k].1.design, *a),
                first_panel + p
            ));
        }
    }
    let molds = ((laminate_mm(first.design) / template.mold.thickness_mm) - 1e-9)
        .ceil()
        .max(1.0) as usize;
    // Expand the stack: "mold" becomes mold-1..n; other layers are numbered by occurrence.
    let mut stack: Vec<(String, String, usize)> = Vec::new(); // (layer kind, stem prefix, index)
    for name in &c.stack {
        if name == "mold" {
            for j in 0..molds {
                stack.push(("mold".into(), format!("mold-{}", j + 1), j));
            }
        } else {
            let occurrence = stack.iter().filter(|(k, _, _)| k == name).count() + 1;
            stack.push((name.clone(), format!("{name}-{occurrence}"), 0));
        }
    }
    let outline = panel_outline(c);
    let levels = stack.len();
    // Errors about panel features name the first design (the single design of a cut sheet).
    let design = first.design;
    let features = &template.features;
    for (k, (kind, prefix, j)) in stack.iter().enumerate() {
        let spec = if kind == "mold" {
            &template.mold
        } else {
            &template.covers[kind]
        };
        let kerf = spec.kerf_mm;
        for (p, members) in panels.iter().enumerate() {
            let number = first_panel + p;
            let mut d = Drawing::new(
                &format!(
                    "{} clamp layer {}/{levels} ({prefix}), panel {number}",
                    names.title,
                    k + 1,
                ),
                c.panel_width_mm,
                c.panel_height_mm,
            );
            for centre in pin_centres(c) {
                let r = c.pin_radius_mm - kerf / 2.0;
                if r <= 0.0 {
                    return Err(super::jobs::design_error(
                        design,
                        format!(
                            "clamp: pin hole radius {} mm vanishes in the {kerf} mm kerf",
                            c.pin_radius_mm
                        ),
                    ));
                }
                d.add(
                    features.op(Feature::PinHole),
                    Shape::Circle {
                        center: centre,
                        radius: r,
                    },
                );
            }
            // Windows through this layer onto every layer below it: the stacking order shows from the top.
            for below in 0..k {
                let w = rect(
                    window_origin(c, below),
                    c.window_width_mm,
                    c.window_height_mm,
                );
                d.add(
                    features.op(Feature::StackingWindow),
                    Shape::Polygon(kerfed(design, &w, -kerf / 2.0, "stacking window")?),
                );
            }
            if kind == "mold" {
                for (m, _, base) in members {
                    let job = &jobs[*m].1;
                    let cavity =
                        cavity_outline(job.design, &job.geometry, template.mold.thickness_mm, *j);
                    let grown = kerfed(
                        job.design,
                        &cavity,
                        c.cavity_clearance_mm,
                        "mold cavity clearance",
                    )?;
                    let placed = place_ring(&grown, 0.0, *base);
                    d.add(
                        features.op(Feature::MoldCavity),
                        Shape::Polygon(kerfed(job.design, &placed, -kerf / 2.0, "mold cavity")?),
                    );
                }
            }
            let level = format!("{}", k + 1);
            let h = (c.window_height_mm * 0.6).min(2.0);
            let o = window_origin(c, k);
            for s in label_strokes(
                &level,
                [o[0] + 0.5, o[1] + (c.window_height_mm - h) / 2.0],
                h,
            ) {
                d.add(features.op(Feature::WindowNumber), Shape::Polyline(s));
            }
            let title = format!("{} {prefix} P{number}", names.title);
            let th = (c.border_mm * 0.3).min(2.5);
            if th > 0.0 && label_width(&title, th) < c.panel_width_mm - 6.0 * c.pin_inset_mm {
                for s in label_strokes(
                    &title,
                    [
                        3.0 * c.pin_inset_mm + 2.0,
                        c.panel_height_mm - (c.border_mm + th) / 2.0,
                    ],
                    th,
                ) {
                    d.add(features.op(Feature::PanelLabel), Shape::Polyline(s));
                }
            }
            for f in fiducials(c) {
                d.add(features.op(Feature::Fiducial), Shape::Polyline(f));
            }
            d.add(
                features.op(Feature::PanelOutline),
                Shape::Polygon(kerfed(design, &outline, kerf / 2.0, "panel outline")?),
            );
            drawn.push(format!("{prefix}-{number}"), kind, d);
        }
    }
    Ok(ClampBuild {
        stack: stack.into_iter().map(|(_, stem, _)| stem).collect(),
        panels: panels
            .iter()
            .map(|m| m.iter().map(|(k, a, _)| (jobs[*k].0, *a)).collect())
            .collect(),
        first_panel,
    })
}
