//! Clamp-panel layers (mold frames with a cavity per actuator, pads and covers) for jobs that share one
//! laminate height, so one stack of mold layers fits all of them.

use super::jobs::{kerfed, Drawn, Job, Names};
use super::mold::{choose_mold, LaminateBands, MoldBand, MoldChoice};
use super::panel::{
    border_label, fiducials, layout_panels, panel_outline, pin_centres, rect, window_origin,
};
use super::parts::PartGeometry;
use super::BuildError;
use crate::design::Design;
use crate::drawing::label::label_strokes;
use crate::drawing::model::{file_stem, Drawing, Shape, Stock};
use crate::input::{short_number, InputError};
use crate::process::template::{ClampSpec, Template};
use crate::process::Feature;
use cam_geometry::{place_ring, Bounds, Point};
use std::collections::HashMap;

/// Offsets repeat on every panel of a clamp layer (the same windows, outline and cavity slots): each is
/// computed once, keyed by its exact input, so every panel gets bit for bit what it would compute,
/// and a large quantity does not offset the same ring thousands of times.
#[derive(Default)]
struct Offsets {
    done: HashMap<(Vec<[u64; 2]>, u64), Vec<Point>>,
}

impl Offsets {
    /// [`kerfed`], remembered. Errors are not remembered (they end the build).
    fn kerfed(
        &mut self,
        design: &Design,
        ring: &[Point],
        delta: f64,
        feature: &str,
    ) -> Result<Vec<Point>, BuildError> {
        let key = (
            ring.iter()
                .map(|p| [p[0].to_bits(), p[1].to_bits()])
                .collect(),
            delta.to_bits(),
        );
        if let Some(done) = self.done.get(&key) {
            return Ok(done.clone());
        }
        let ring = kerfed(design, ring, delta, feature)?;
        self.done.insert(key, ring.clone());
        Ok(ring)
    }
}

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
    /// The panels in runs of identical sheets, in panel order.
    pub runs: Vec<PanelRun>,
    /// The file stems of each stack level (as `stack`), one per run: what the build book names.
    pub files: Vec<Vec<String>>,
    /// The mold films, bottom to top, and how the mold height meets the laminate height.
    pub mold: MoldChoice,
}

/// Consecutive panels that hold the same actuators at the same places: every layer of them is the same
/// drawing but for the engraved panel number, so one file per layer serves the run, cut `count` times
/// and engraved with the run's numbers. A lab cuts a thousand identical panels from one file, and
/// a large quantity would otherwise write a file per layer and panel, most of the run's time.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PanelRun {
    /// Number of the run's first panel (1-based, across the build).
    pub first: usize,
    /// Panels in the run.
    pub count: usize,
}

impl PanelRun {
    /// The run's panel numbers as engraved and named: `7`, or `1-6`.
    pub fn numbers(&self) -> String {
        if self.count == 1 {
            self.first.to_string()
        } else {
            format!("{}-{}", self.first, self.first + self.count - 1)
        }
    }

    /// The run's part of a file stem: `7`, or `1to6` (a `-` would read as one more name part).
    pub fn stem(&self) -> String {
        if self.count == 1 {
            self.first.to_string()
        } else {
            format!("{}to{}", self.first, self.first + self.count - 1)
        }
    }
}

/// The panels (each a list of (job, actuator, base point)) as runs of identical sheets: the same jobs
/// at bit-identical base points, numbered on from `first_panel`.
fn panel_runs(panels: &[Vec<(usize, usize, Point)>], first_panel: usize) -> Vec<PanelRun> {
    let same = |a: &Vec<(usize, usize, Point)>, b: &Vec<(usize, usize, Point)>| {
        a.len() == b.len()
            && a.iter().zip(b).all(|((ka, _, pa), (kb, _, pb))| {
                ka == kb && pa[0].to_bits() == pb[0].to_bits() && pa[1].to_bits() == pb[1].to_bits()
            })
    };
    let mut runs: Vec<PanelRun> = Vec::new();
    for (p, members) in panels.iter().enumerate() {
        match runs.last_mut() {
            Some(run) if same(&panels[p - 1], members) => run.count += 1,
            _ => runs.push(PanelRun {
                first: first_panel + p,
                count: 1,
            }),
        }
    }
    runs
}

/// The bands of a design's laminate, mm: a plate, and the passive core of plies and bond layers.
pub fn laminate_bands(design: &Design) -> LaminateBands {
    let bond = design.bond.as_ref().map_or(0.0, |(_, t)| *t);
    LaminateBands {
        plate_mm: design.pzt_thickness * 1e3,
        core_mm: (design.ply_thickness * design.layup_deg.len() as f64 + 2.0 * bond) * 1e3,
        bond_mm: bond * 1e3,
    }
}

/// The cavity shape of a mold layer of `band`: the passive outline where it holds the core, the PZT
/// outline where it holds a plate.
fn cavity_outline(g: &PartGeometry, band: MoldBand) -> Vec<Point> {
    match band {
        MoldBand::Core => g.passive_outline(),
        MoldBand::LowerPlate | MoldBand::UpperPlate => g.pzt_outline(),
    }
}

/// Clearance (mm) between a window number's strokes and the cut edge of every window it is seen
/// through, on top of half the widest kerf of the stack: the engraved line has a width of its own
/// (about 0.1 mm on the ProtoLaser), and the window's edge is where the felt and Teflon fray.
const NUMBER_CLEARANCE_MM: f64 = 0.2;

/// Strokes of the number of stack level `level` (1-based), engraved in its own stacking window
/// (position `level - 1`): as tall as 60 % of the window (at most 2 mm), made smaller if it would not
/// fit within the window less `inset_mm` on each side, and centred on the window by the extent of its
/// strokes (not of its glyph cells, which would put a narrow `1` off-centre). Nothing if even a
/// shrunk number cannot fit.
pub fn window_number(c: &ClampSpec, level: usize, inset_mm: f64) -> Vec<Vec<Point>> {
    let text = level.to_string();
    let (w, h) = (
        c.window_width_mm - 2.0 * inset_mm,
        c.window_height_mm - 2.0 * inset_mm,
    );
    if w <= 0.0 || h <= 0.0 {
        return Vec::new();
    }
    let ink = |height: f64| {
        let strokes = label_strokes(&text, [0.0, 0.0], height);
        let (lo, hi) = strokes_extent(&strokes);
        (strokes, lo, hi)
    };
    let mut height = (c.window_height_mm * 0.6).min(2.0).min(h);
    let (_, lo, hi) = ink(height);
    let scale = (w / (hi[0] - lo[0])).min(h / (hi[1] - lo[1])).min(1.0);
    height *= scale;
    let (strokes, lo, hi) = ink(height);
    let o = window_origin(c, level - 1);
    let centre = [
        o[0] + c.window_width_mm / 2.0,
        o[1] + c.window_height_mm / 2.0,
    ];
    let shift = [
        centre[0] - (lo[0] + hi[0]) / 2.0,
        centre[1] - (lo[1] + hi[1]) / 2.0,
    ];
    strokes
        .into_iter()
        .map(|s| {
            s.iter()
                .map(|p| [p[0] + shift[0], p[1] + shift[1]])
                .collect()
        })
        .collect()
}

/// Bounding box `(min, max)` of a set of strokes.
fn strokes_extent(strokes: &[Vec<Point>]) -> (Point, Point) {
    let b = strokes
        .iter()
        .map(|s| Bounds::of(s))
        .fold(Bounds::EMPTY, Bounds::union);
    (b.min, b.max)
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

/// A panel's actuators: (position in the build's jobs, actuator, base point) each.
type PanelMembers = Vec<(usize, usize, Point)>;

/// One layer of a clamp stack: its kind (`mold` or a cover name), its stem prefix (`mold-2`,
/// `felt-1`) and, for a mold layer, its band of the mold choice.
type StackLayer = (String, String, usize);

/// Assign the actuators of `jobs` (which share one laminate: the same plate and core thicknesses) to
/// clamp panels and draw every
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
            runs: Vec::new(),
            files: Vec::new(),
            first_panel: drawn.panels + 1,
            mold: choose_mold(
                LaminateBands {
                    plate_mm: 0.0,
                    core_mm: 0.0,
                    bond_mm: 0.0,
                },
                &template.mold_stock,
            ),
        });
    };
    let c = &template.clamp;
    let first_panel = drawn.panels + 1;
    let panels = assign_panels(jobs, template, names, drawn)?;
    let runs = panel_runs(&panels, first_panel);
    let mold = choose_mold(laminate_bands(first.design), &template.mold_stock);
    if mold.films_mm.is_empty() {
        return Err(no_film_holds_the_plate(template, first.design));
    }
    let stack = expand_stack(&c.stack, mold.bands.len());
    // A number is seen through the windows of every layer above it: keep it clear of the widest kerf.
    let widest_kerf = stack
        .iter()
        .map(|(kind, _, _)| {
            if kind == "mold" {
                template.mold.kerf_mm
            } else {
                template.covers[kind].kerf_mm
            }
        })
        .fold(0.0, f64::max);
    let drawer = ClampDrawer {
        jobs,
        template,
        names,
        mold: &mold,
        outline: panel_outline(c),
        levels: stack.len(),
        number_inset: widest_kerf / 2.0 + NUMBER_CLEARANCE_MM,
    };
    let mut offsets = Offsets::default();
    let mut files = vec![Vec::new(); stack.len()];
    for (k, layer) in stack.iter().enumerate() {
        let (kind, prefix, _) = layer;
        for run in &runs {
            let members = &panels[run.first - first_panel];
            let d = drawer.draw(&mut offsets, k, layer, run, members)?;
            let stem = format!("{prefix}-{}", run.stem());
            files[k].push(file_stem(&stem, d.stock.as_ref()));
            drawn.push_copies(stem, kind, d, run.count);
        }
    }
    Ok(ClampBuild {
        stack: stack.into_iter().map(|(_, stem, _)| stem).collect(),
        panels: panels
            .iter()
            .map(|m| m.iter().map(|(k, a, _)| (jobs[*k].0, *a)).collect())
            .collect(),
        first_panel,
        runs,
        files,
        mold,
    })
}

/// Lay the actuators of `jobs` out on clamp panels (numbered on from `drawn`'s), each at the base
/// point of its own tab, and note each in the placement map.
fn assign_panels(
    jobs: &[(usize, Job<'_>)],
    template: &Template,
    names: &Names,
    drawn: &mut Drawn,
) -> Result<Vec<PanelMembers>, BuildError> {
    let c = &template.clamp;
    let cell = envelope(jobs);
    // Every actuator in job order: (position in `jobs`, actuator).
    let actuators: Vec<(usize, usize)> = jobs
        .iter()
        .enumerate()
        .flat_map(|(k, (_, j))| (0..j.quantity).map(move |a| (k, a)))
        .collect();
    // A panel too small is the template's to change: the refusal names its file and field.
    let layout = layout_panels(c, &cell, actuators.len()).map_err(|e| {
        let (key, value, need) = e.side_to_grow();
        BuildError::Input(InputError::invalid(
            &template.source,
            &format!("clamp.{key}"),
            short_number(value),
            format!("{e}; it needs at least {need:.2} mm"),
        ))
    })?;
    let first_panel = drawn.panels + 1;
    drawn.panels += layout.panels.len();
    let panels: Vec<PanelMembers> = layout
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
    Ok(panels)
}

/// No stocked film fits under `design`'s plate: no mold layer could hold or press any part, so
/// nothing would be pressed at all. That is a process the template cannot run, not a warning.
fn no_film_holds_the_plate(template: &Template, design: &Design) -> BuildError {
    let films: Vec<String> = template
        .mold_stock
        .films_mm
        .iter()
        .map(|t| short_number(*t))
        .collect();
    let plate_mm = short_number(design.pzt_thickness * 1e3);
    InputError::invalid(
        &template.source,
        "layers.mold.stock_thicknesses_mm",
        format!("[{}]", films.join(", ")),
        format!(
            "no stocked film is as thin as the {plate_mm} mm PZT plate of {}, so no mold layer can \
             hold it; stock a film of at most {plate_mm} mm",
            design.source.display()
        ),
    )
    .into()
}

/// The clamp stack as written (`mold` and cover names, bottom to top) expanded: "mold" becomes
/// mold-1..n, one per mold band; other layers are numbered by occurrence.
fn expand_stack(names: &[String], bands: usize) -> Vec<StackLayer> {
    let mut stack: Vec<StackLayer> = Vec::new();
    for name in names {
        if name == "mold" {
            for j in 0..bands {
                stack.push(("mold".into(), format!("mold-{}", j + 1), j));
            }
        } else {
            let occurrence = stack.iter().filter(|(k, _, _)| k == name).count() + 1;
            stack.push((name.clone(), format!("{name}-{occurrence}"), 0));
        }
    }
    stack
}

/// What every clamp layer drawing of one laminate's stack shares.
struct ClampDrawer<'a, 'j> {
    jobs: &'a [(usize, Job<'j>)],
    template: &'a Template,
    names: &'a Names,
    mold: &'a MoldChoice,
    /// The panel's outline, before its kerf.
    outline: Vec<Point>,
    /// Layers in the stack.
    levels: usize,
    /// How far a window number keeps from its window's edge, mm.
    number_inset: f64,
}

impl ClampDrawer<'_, '_> {
    /// The drawing of stack layer `k` (`layer`) for the panels of `run`, which hold `members`.
    fn draw(
        &self,
        offsets: &mut Offsets,
        k: usize,
        (kind, prefix, j): &StackLayer,
        run: &PanelRun,
        members: &PanelMembers,
    ) -> Result<Drawing, BuildError> {
        let (c, template, names, levels) =
            (&self.template.clamp, self.template, self.names, self.levels);
        // Errors about panel features name the first design (the single design of a cut sheet).
        let design = self.jobs[0].1.design;
        let features = &template.features;
        let spec = if kind == "mold" {
            &template.mold
        } else {
            &template.covers[kind]
        };
        let kerf = spec.kerf_mm;
        let numbers = run.numbers();
        let mut d = Drawing::on_stock(
            &format!(
                "{} clamp layer {}/{levels} ({prefix}), {}",
                names.title,
                k + 1,
                if run.count == 1 {
                    format!("panel {numbers}")
                } else {
                    format!("panels {numbers}: cut {} sheets", run.count)
                }
            ),
            c.panel_width_mm,
            c.panel_height_mm,
            Stock {
                material: spec.material.clone(),
                thickness_mm: if kind == "mold" {
                    self.mold.films_mm[*j]
                } else {
                    spec.thickness_mm
                },
                kerf_mm: kerf,
                fibre_axis: None,
            },
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
                Shape::Polygon(offsets.kerfed(design, &w, -kerf / 2.0, "stacking window")?),
            );
        }
        if kind == "mold" {
            for (m, _, base) in members {
                let job = &self.jobs[*m].1;
                let cavity = cavity_outline(&job.geometry, self.mold.bands[*j]);
                let grown = offsets.kerfed(
                    job.design,
                    &cavity,
                    c.cavity_clearance_mm,
                    "mold cavity clearance",
                )?;
                let placed = place_ring(&grown, 0.0, *base);
                d.add(
                    features.op(Feature::MoldCavity),
                    Shape::Polygon(offsets.kerfed(
                        job.design,
                        &placed,
                        -kerf / 2.0,
                        "mold cavity",
                    )?),
                );
            }
        }
        for s in window_number(c, k + 1, self.number_inset) {
            d.add(features.op(Feature::WindowNumber), Shape::Polyline(s));
        }
        let thickness_mm = d.stock.as_ref().map(|s| s.thickness_mm);
        for s in border_label(c, &names.title, prefix, thickness_mm, &numbers) {
            d.add(features.op(Feature::PanelLabel), Shape::Polyline(s));
        }
        for f in fiducials(c) {
            d.add(features.op(Feature::Fiducial), Shape::Polyline(f));
        }
        d.add(
            features.op(Feature::PanelOutline),
            Shape::Polygon(offsets.kerfed(design, &self.outline, kerf / 2.0, "panel outline")?),
        );
        Ok(d)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    #[test]
    fn window_numbers_fit_and_are_centred_for_1_to_20_layers() {
        // Two-digit numbers are the widest a window holds and must stay inside its inset; every
        // number, one digit or two, must sit on the window's centre. The shipped clamp panel: 3 x 2.5
        // mm windows.
        for process in ["method-1", "method-2"] {
            let t = Template::resolve(process, Path::new("d.toml")).unwrap();
            let c = &t.clamp;
            let kerf = t
                .covers
                .values()
                .map(|l| l.kerf_mm)
                .fold(t.mold.kerf_mm, f64::max);
            let inset = kerf / 2.0 + NUMBER_CLEARANCE_MM;
            for level in 1..=20 {
                let strokes = window_number(c, level, inset);
                assert!(!strokes.is_empty(), "{process}: no number {level}");
                let (lo, hi) = strokes_extent(&strokes);
                let o = window_origin(c, level - 1);
                let (x0, x1) = (o[0] + inset, o[0] + c.window_width_mm - inset);
                let (y0, y1) = (o[1] + inset, o[1] + c.window_height_mm - inset);
                assert!(
                    lo[0] >= x0 - 1e-9
                        && hi[0] <= x1 + 1e-9
                        && lo[1] >= y0 - 1e-9
                        && hi[1] <= y1 + 1e-9,
                    "{process} {level}: ink {lo:?}..{hi:?} outside window {x0}..{x1} x {y0}..{y1}"
                );
                let centre = [
                    o[0] + c.window_width_mm / 2.0,
                    o[1] + c.window_height_mm / 2.0,
                ];
                for k in 0..2 {
                    assert!(
                        ((lo[k] + hi[k]) / 2.0 - centre[k]).abs() < 1e-9,
                        "{process} {level}: off-centre on axis {k}"
                    );
                }
            }
        }
    }
}
