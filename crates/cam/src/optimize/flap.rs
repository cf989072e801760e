//! `optimize` for a wing: the lightest actuator that flaps a drive file's wing to its stroke at its
//! frequency, with the field within the spec's limit and the linkage's crank chosen with it
//! (docs/physics.md §17).
//!
//! With the crank chosen, a design flaps the wing when `U = ½ F_b δ ≥ U_req(f1)`, the requirement
//! depending on the actuator's first resonance `f1` alone ([`actuator_model::drive_energy`]). Three
//! stages:
//! 1. **Modes per shape.** For the original model `f1` does not depend on `w_0` (stiffness and mass per
//!    length both scale with the width) and scales as `1/l_tot²` at a fixed `(l_r, w_r)` (a beam
//!    stretched along its length): one modal solve per laminate and shape `(l_r, w_r)` gives every length.
//! 2. **Screen.** `U_req(f1)` on a log-spaced table over the grid's range of `f1`, interpolated in
//!    `log f1`. For every laminate, shape and length of the grid, the smallest base width with
//!    `U ≥ U_req` (the energy is linear in `w_0`), raised to the width bounds and the tip width; its mass.
//! 3. **Exact.** The lightest screened designs are re-solved as their process builds them (with the bond
//!    layer, as `drive` sees them): the exact `f1`, the exact requirement, and the base width raised (to
//!    the next µm) until the energy meets it. The lightest wins; its crank comes from the requirement.

use super::model::unit_planform;
use super::report::design_toml;
use super::search::{tip_width, Design, Problem};
use super::spec::Spec;
use crate::cutsheet::design_for_process;
use crate::design::Design as DesignFile;
use crate::drive::spec::{DriveSpec, LinkageSpec};
use crate::input::{parse_toml, InputError};
use crate::prediction::{actuator_modes, performance};
use crate::process::template::Template;
use actuator_model::drive_energy::{Requirement, WingLoad};
use actuator_model::dynamics::ActuatorBeam;
use actuator_model::{ModelChoice, ModelKind, Performance};
use rayon::prelude::*;
use std::path::Path;

/// Points of the requirement table over the grid's range of `f1`.
const TABLE: usize = 16;

// The screen's modal solves use the coarse mesh (`ActuatorBeam::solve_coarse`, `f1` within 1e-4 of the
// converged mesh: test `the_screens_mesh_is_within_1e_4`); the exact stage uses the full mesh.

/// Screened designs re-solved exactly.
const EXACT: usize = 4;

/// Margin levels of the front of mass against frequency margin.
pub const FRONT_LEVELS: usize = 40;

/// Step between the front's margin levels (5 %).
const LEVEL_STEP: f64 = 0.05;

/// The drive file's wing, flexures, linkage shape, frequency and stroke as the optimizer needs them, with
/// the loss factor the drive takes under `model` ([`DriveSpec::loss_factor`]).
pub fn wing_load(drive: &DriveSpec, model: &ModelChoice) -> Result<WingLoad, InputError> {
    let LinkageSpec::Solve {
        angle_minus,
        angle_plus,
        coupler_ratio,
        // The travel is what the optimizer chooses; the drive file it writes replaces it.
        ..
    } = drive.transmission.linkage
    else {
        let given = match drive.transmission.linkage {
            LinkageSpec::Ratio(_) => "ratio_rad_per_m",
            _ => "coupler_mm and crank_mm",
        };
        return Err(InputError::invalid(
            &drive.source,
            "transmission",
            given,
            "optimize chooses the linkage's size: give solve_for_stroke = true or end_angles_deg, with coupler_ratio",
        ));
    };
    if drive.transmission.four_bar.is_some() {
        return Err(InputError::invalid(
            &drive.source,
            "transmission.four_bar",
            "(given)",
            "left out: optimize sizes a one-stage slider-crank (drive checks a two-stage linkage)",
        ));
    }
    let wing = drive.wing.wing();
    Ok(WingLoad {
        end_angles: (angle_minus, angle_plus),
        coupler_ratio,
        flexure_stiffness: drive.transmission.flexure_stiffness,
        inertia: wing.inertia + drive.transmission.link_inertia,
        damping: wing.damping,
        frequency: drive.frequency,
        stroke: drive.transmission.stroke,
        loss_factor: drive.loss_factor(model),
    })
}

/// A screened design with its system resonance's margin over the flapping frequency.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Screened {
    /// The design (energy and mass from the search model).
    pub design: Design,
    /// `f_res / f - 1` of the system at the best crank.
    pub margin: f64,
}

/// The exact winner: the design file as its process builds it, its prediction and requirement.
#[derive(Debug, Clone)]
pub struct Chosen {
    /// The search's design, with the base width the exact stage settled on.
    pub design: Design,
    /// The design file's text (`design_toml`).
    pub design_toml: String,
    /// The design as `drive` sees it.
    pub built: DesignFile,
    /// Its prediction.
    pub performance: Performance,
    /// The bare actuator's first resonance, Hz.
    pub actuator_frequency: f64,
    /// What the wing asks of it.
    pub requirement: Requirement,
    /// One-sided actuator travel of the chosen linkage, m.
    pub travel: f64,
}

/// What the search found.
#[derive(Debug, Clone)]
pub struct FlapOutcome {
    /// The winner.
    pub chosen: Chosen,
    /// Laminate-shape-length points screened.
    pub screened: u64,
    /// The lightest screened design at each margin level (margin increasing, mass not decreasing).
    pub front: Vec<Screened>,
}

/// Why the search has no answer.
#[derive(Debug, Clone, thiserror::Error)]
pub enum FlapError {
    /// Only the original model has the scaling the screen relies on.
    #[error("optimize for a wing takes --model original (its first mode scales as 1/l_tot² and does not depend on w_0); evaluate other models with drive")]
    Model,
    /// No design in the ranges flaps the wing.
    #[error("no design in the search ranges flaps the wing to ±{stroke_deg:.1}° at {frequency} Hz within the field limit ({why}); widen base_width_mm or length_mm, or raise the field")]
    Infeasible {
        /// Required stroke, degrees.
        stroke_deg: f64,
        /// Flapping frequency, Hz.
        frequency: f64,
        /// What fell short.
        why: String,
    },
    /// A design could not be built or predicted.
    #[error("{0}")]
    Build(String),
}

/// `U_req` and the system resonance interpolated in `log f1` from a table (infinite outside it or
/// where a point holds no stroke), and for each margin level of the front the energy that puts the
/// system resonance at least that far above the flapping frequency ([`WingLoad::energy_at_resonance`]).
struct Table {
    points: Vec<(f64, f64, f64)>,
    /// Per point, `ln U` for each margin level (infinite where no crank reaches it).
    levels: Vec<Vec<f64>>,
}

impl Table {
    fn new(load: &WingLoad, lo: f64, hi: f64) -> Table {
        let n = if hi > lo { TABLE } else { 1 };
        let (points, levels) = (0..n)
            .into_par_iter()
            .map(|i| {
                let f = if n == 1 {
                    lo
                } else {
                    lo * (hi / lo).powf(i as f64 / (n - 1) as f64)
                };
                match load.requirement(f) {
                    Ok(r) => {
                        let mut levels = vec![f64::INFINITY; FRONT_LEVELS];
                        for (k, slot) in levels.iter_mut().enumerate() {
                            let target = load.frequency * (1.0 + LEVEL_STEP * k as f64);
                            // A higher level needs a stiffer crank still: past the first out of
                            // reach, all are.
                            match load.energy_at_resonance(&r, target) {
                                Some(u) => *slot = u.ln(),
                                None => break,
                            }
                        }
                        ((f.ln(), r.energy.ln(), r.resonance), levels)
                    }
                    Err(_) => (
                        (f.ln(), f64::INFINITY, 0.0),
                        vec![f64::INFINITY; FRONT_LEVELS],
                    ),
                }
            })
            .unzip();
        Table { points, levels }
    }

    /// Where `f1` falls between two points: their indices and the weight of the second.
    fn bracket(&self, f1: f64) -> (usize, usize, f64) {
        let x = f1.ln();
        let p = &self.points;
        if p.len() == 1 {
            return (0, 0, 0.0);
        }
        let i = p.partition_point(|q| q.0 <= x).clamp(1, p.len() - 1);
        let (a, b) = (p[i - 1], p[i]);
        (i - 1, i, ((x - a.0) / (b.0 - a.0)).clamp(0.0, 1.0))
    }

    /// The energy that gives margin level `k` at `f1`, J (infinite where out of reach).
    fn at_level(&self, f1: f64, k: usize) -> f64 {
        let (a, b, t) = self.bracket(f1);
        let (ua, ub) = (self.levels[a][k], self.levels[b][k]);
        if ua.is_infinite() || ub.is_infinite() {
            return f64::INFINITY;
        }
        (ua + t * (ub - ua)).exp()
    }

    fn at(&self, f1: f64) -> (f64, f64) {
        let (a, b, t) = self.bracket(f1);
        let (a, b) = (self.points[a], self.points[b]);
        ((a.1 + t * (b.1 - a.1)).exp(), a.2 + t * (b.2 - a.2))
    }
}

/// Stages 1 and 2: the lightest screened design of every shape, lightest first, and the front.
fn screen(
    problem: &Problem,
    load: &WingLoad,
) -> Result<(Vec<Screened>, Vec<Screened>, u64), FlapError> {
    let [lengths, _, extension_ratios, width_ratios] = problem.axes();
    let mut shapes: Vec<(usize, f64, f64)> = Vec::new();
    for c in 0..problem.candidates.len() {
        for &l_r in &extension_ratios {
            for &w_r in &width_ratios {
                shapes.push((c, l_r, w_r));
            }
        }
    }
    let modes: Vec<f64> = shapes
        .par_iter()
        .map(|&(c, l_r, w_r)| {
            ActuatorBeam::from_section(&problem.candidates[c].section, &unit_planform(l_r, w_r))
                .solve_coarse()
                .map_or(f64::NAN, |m| m.frequency)
        })
        .collect();
    let table = resonance_table(problem, load, &modes)?;
    let per: Vec<(Option<Screened>, Vec<Option<Screened>>)> = shapes
        .par_iter()
        .zip(modes.par_iter())
        .map(|(&shape, &f_unit)| {
            screen_shape(problem, &table, &lengths, load.frequency, shape, f_unit)
        })
        .collect();
    let mut bests: Vec<Screened> = per.iter().filter_map(|p| p.0).collect();
    bests.sort_by(|a, b| {
        a.design
            .mass
            .total_cmp(&b.design.mass)
            .then(a.design.length.total_cmp(&b.design.length))
            .then(a.design.candidate.cmp(&b.design.candidate))
    });
    let front = front(&per);
    let points = shapes.len() as u64 * lengths.len() as u64;
    Ok((bests, front, points))
}

/// The table of the wing's load over the first modes the shapes can reach: each shape's unit-length
/// mode (`modes`, NaN where it could not be solved) scaled by 1/length² across the length bounds.
fn resonance_table(problem: &Problem, load: &WingLoad, modes: &[f64]) -> Result<Table, FlapError> {
    let (l_min, l_max) = (problem.bounds.length.lo, problem.bounds.length.hi);
    let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
    for f in modes.iter().filter(|f| f.is_finite()) {
        lo = lo.min(f / (l_max * l_max));
        hi = hi.max(f / (l_min * l_min));
    }
    if !(lo.is_finite() && hi > 0.0) {
        return Err(FlapError::Build(
            "no shape's first mode could be solved".into(),
        ));
    }
    Ok(Table::new(load, lo, hi))
}

/// The front level of a margin of resonance above the flapping frequency: levels 0, 0.05, …
fn margin_level(margin: f64) -> Option<usize> {
    (margin >= 0.0).then(|| ((margin / LEVEL_STEP).floor() as usize).min(FRONT_LEVELS - 1))
}

/// One shape (candidate, extension ratio, width ratio) with unit-length first mode `f_unit`, at
/// every length: its lightest design that holds the wing at `f`, and its lightest at each front
/// level.
fn screen_shape(
    problem: &Problem,
    table: &Table,
    lengths: &[f64],
    f: f64,
    (c, l_r, w_r): (usize, f64, f64),
    f_unit: f64,
) -> (Option<Screened>, Vec<Option<Screened>>) {
    let bounds = problem.bounds;
    let mut levels = vec![None::<Screened>; FRONT_LEVELS];
    let mut best: Option<Screened> = None;
    if !f_unit.is_finite() {
        return (best, levels);
    }
    let rates = problem.shape_rates(c, l_r, w_r);
    let narrowest = bounds
        .base_width
        .lo
        .max(problem.min_tip_width * w_r / (2.0 - w_r));
    for &length in lengths {
        let (energy, resonance) = table.at(f_unit / (length * length));
        // U = l_tot w_0 u for the original model.
        let width = (energy / (length * rates.energy)).max(narrowest);
        if width.is_nan()
            || width > bounds.base_width.hi * (1.0 + 1e-12)
            || tip_width(width, w_r) < problem.min_tip_width * (1.0 - 1e-12)
        {
            continue;
        }
        let design = problem.design(c, rates, length, width, l_r, w_r);
        let s = Screened {
            design,
            margin: resonance / f - 1.0,
        };
        if best.is_none_or(|b| design.mass < b.design.mass) {
            best = Some(s);
        }
        if let Some(k) = margin_level(s.margin) {
            if levels[k].is_none_or(|b| design.mass < b.design.mass) {
                levels[k] = Some(s);
            }
        }
        // Above its own margin, the same shape and length widened to the energy a stiffer
        // crank needs for each higher level (the front's other points).
        let f1 = f_unit / (length * length);
        for (k, slot) in levels.iter_mut().enumerate() {
            let needed = LEVEL_STEP * k as f64;
            if needed <= s.margin {
                continue;
            }
            let energy = table.at_level(f1, k);
            let width = (energy / (length * rates.energy)).max(narrowest);
            if !width.is_finite()
                || width > bounds.base_width.hi * (1.0 + 1e-12)
                || tip_width(width, w_r) < problem.min_tip_width * (1.0 - 1e-12)
            {
                continue;
            }
            let design = problem.design(c, rates, length, width, l_r, w_r);
            if slot.is_none_or(|b| design.mass < b.design.mass) {
                *slot = Some(Screened {
                    design,
                    margin: needed,
                });
            }
        }
    }
    (best, levels)
}

/// The front: at each level the lightest design with at least that margin, from each shape's
/// lightest at each level.
fn front(per: &[(Option<Screened>, Vec<Option<Screened>>)]) -> Vec<Screened> {
    let mut by_level = vec![None::<Screened>; FRONT_LEVELS];
    for (_, levels) in per {
        for (k, s) in levels.iter().enumerate() {
            if let Some(s) = s {
                if by_level[k].is_none_or(|b| s.design.mass < b.design.mass) {
                    by_level[k] = Some(*s);
                }
            }
        }
    }
    let mut front = Vec::new();
    let mut lightest: Option<Screened> = None;
    for s in by_level.iter().rev() {
        if let Some(s) = s {
            if lightest.is_none_or(|b| s.design.mass < b.design.mass) {
                lightest = Some(*s);
            }
        }
        if let Some(l) = lightest {
            front.push(l);
        }
    }
    front.reverse();
    front.dedup();
    front
}

/// The design file of a search design as its process builds it, and its prediction.
fn build(
    spec: &Spec,
    problem: &Problem,
    d: &Design,
    model: &ModelChoice,
) -> Result<(String, DesignFile, Performance, f64), FlapError> {
    let err = |e: &dyn std::fmt::Display| FlapError::Build(format!("the optimized design: {e}"));
    let text = design_toml(spec, problem, d);
    let path = Path::new("optimized.toml");
    let table = parse_toml(path, &text).map_err(|e| err(&e))?;
    let file = DesignFile::from_table(path, &table).map_err(|e| err(&e))?;
    let template = Template::resolve(&file.process, path).map_err(|e| err(&e))?;
    let built = design_for_process(&file, &template).map_err(|e| err(&e))?;
    let perf = performance(&built, model).map_err(|e| err(&e))?;
    let modal = actuator_modes(&built, model, &perf).map_err(|e| err(&e))?;
    Ok((text, built, perf, modal.frequency))
}

/// Stage 3 on one screened design: widen it to the next µm until its exact energy meets its exact
/// requirement (`None` when that leaves the width bounds or the wing cannot be flapped at all).
fn exact(
    spec: &Spec,
    problem: &Problem,
    load: &WingLoad,
    screened: &Design,
    model: &ModelChoice,
) -> Result<Option<Chosen>, FlapError> {
    let micron = |w: f64| (w * 1e6).ceil() / 1e6;
    let mut d = *screened;
    d.base_width = micron(d.base_width);
    for _ in 0..8 {
        if d.base_width > problem.bounds.base_width.hi * (1.0 + 1e-12) {
            return Ok(None);
        }
        let (text, built, perf, f1) = build(spec, problem, &d, model)?;
        let Ok(requirement) = load.requirement(f1) else {
            return Ok(None);
        };
        if perf.energy >= requirement.energy {
            let travel = load
                .travel_for(perf.stiffness, requirement.reflected_stiffness)
                .map_err(|e| FlapError::Build(e.to_string()))?;
            d.mass = perf.mass;
            d.energy = perf.energy;
            return Ok(Some(Chosen {
                design: d,
                design_toml: text,
                built,
                performance: perf,
                actuator_frequency: f1,
                requirement,
                travel,
            }));
        }
        // The energy is linear in w_0 at a fixed shape (and f1 does not move with it).
        d.base_width = micron(d.base_width * requirement.energy / perf.energy * (1.0 + 1e-9));
    }
    Ok(None)
}

/// Run the three stages.
pub fn optimize_flap(
    spec: &Spec,
    problem: &Problem,
    load: &WingLoad,
    model: &ModelChoice,
) -> Result<FlapOutcome, FlapError> {
    if !matches!(model, ModelChoice::Kind(ModelKind::Original)) {
        return Err(FlapError::Model);
    }
    let (bests, front, screened) = screen(problem, load)?;
    let infeasible = |why: String| FlapError::Infeasible {
        stroke_deg: load.stroke.to_degrees(),
        frequency: load.frequency,
        why,
    };
    if bests.is_empty() {
        return Err(infeasible(
            "every design would need a base width above the search range".into(),
        ));
    }
    let mut chosen: Option<Chosen> = None;
    for s in bests.iter().take(EXACT) {
        if let Some(c) = exact(spec, problem, load, &s.design, model)? {
            if chosen
                .as_ref()
                .is_none_or(|b| c.performance.mass < b.performance.mass)
            {
                chosen = Some(c);
            }
        }
    }
    let chosen = chosen.ok_or_else(|| {
        infeasible(
            "the lightest screened designs fall short once built with their bond layer".into(),
        )
    })?;
    Ok(FlapOutcome {
        chosen,
        screened,
        front,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use actuator_model::{Drive, DriveMode, Laminate, Material, Section};

    #[test]
    fn the_screens_mesh_is_within_1e_4() {
        let pzt = Material::builtin("PZT-5H").unwrap();
        let ply = Material::builtin("CF-thesis").unwrap();
        for (t_p, layup) in [(0.127e-3, vec![0.0, 90.0, 0.0]), (0.267e-3, vec![0.0; 7])] {
            let laminate = Laminate::bimorph(&pzt, t_p, &ply, 61.8e-6, &layup, None).unwrap();
            let drive = Drive::new(DriveMode::Parallel, 800e3);
            let section = Section::new(&laminate, drive).unwrap();
            for l_r in [0.0, 0.5, 1.5] {
                for w_r in [1.0, 1.5, 1.95] {
                    let beam = ActuatorBeam::from_section(&section, &unit_planform(l_r, w_r));
                    let coarse = beam.solve_coarse().unwrap();
                    let fine = beam.solve().unwrap();
                    let rel = coarse.frequency / fine.frequency - 1.0;
                    assert!(rel.abs() < 1e-4, "l_r {l_r} w_r {w_r}: {rel}");
                }
            }
        }
    }
}
