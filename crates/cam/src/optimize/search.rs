//! The search problem and its exhaustive stage: every point of an `n⁴` grid over
//! `(l_tot, w_0, l_r, w_r)`, for every laminate `(t_p, layup)`, as the thesis' `OptimizedActuator` did.
//!
//! Structure, not shortcuts: for one laminate and one shape `(l_r, w_r)` the model is
//! `U = l_tot w_0 u g(w_0)`, `m = l_tot w_0 μ` ([`super::model`]), so a shape costs one model call, a
//! `(shape, w_0)` row a few multiplications, and each of the `n` lengths in the row two multiplications,
//! a comparison and a select. Every grid point is still evaluated and counted. A calibrated model with a
//! dead length or a clamp compliance is not linear in `l_tot`; its rows evaluate each length through
//! [`SearchModel::energy`] (a few dozen flops, no allocation).

pub use super::field_limit::FieldLimit;
use super::model::{SearchModel, ShapeRates, Stack};
use super::progress::Progress;
use super::row::{first_feasible_in_row, general_row, lightest_in_row};
use super::spec::{SearchRanges, Spec};
use actuator_model::poling::FieldCheck;
use actuator_model::{Drive, Laminate, Material, ModelError, Performance, Planform, Section};
use rayon::prelude::*;
use std::cmp::Ordering;

/// What the search minimises.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Objective {
    /// Lightest actuator with `U >= U_min`.
    MinMass,
    /// Highest `U / m` with `U >= U_min` (then the lightest such).
    MaxEnergyDensity,
}

impl Objective {
    /// Command-line name.
    pub fn name(self) -> &'static str {
        match self {
            Objective::MinMass => "min-mass",
            Objective::MaxEnergyDensity => "max-energy-density",
        }
    }
}

/// One laminate option, solved once at its drive field.
#[derive(Debug, Clone)]
pub struct Candidate {
    /// PZT plate thickness, m.
    pub pzt_thickness: f64,
    /// Passive layup, degrees.
    pub layup: Vec<f64>,
    /// The laminate at its drive level.
    pub section: Section,
    /// What set the field.
    pub field_limit: FieldLimit,
}

/// One design: a laminate (index into [`Problem::candidates`]) and a planform, with the model's energy
/// and mass.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Design {
    /// Index of the laminate.
    pub candidate: usize,
    /// `l_tot`, m.
    pub length: f64,
    /// `w_0`, m.
    pub base_width: f64,
    /// `l_r`.
    pub extension_ratio: f64,
    /// `w_r`.
    pub width_ratio: f64,
    /// `U`, J.
    pub energy: f64,
    /// `m`, kg.
    pub mass: f64,
}

impl Design {
    /// The planform (no base tab).
    pub fn planform(&self) -> Planform {
        Planform {
            length: self.length,
            extension_ratio: self.extension_ratio,
            base_width: self.base_width,
            width_ratio: self.width_ratio,
            base_tab: 0.0,
        }
    }

    /// Tip width `w_0 (2 - w_r) / w_r`, m.
    pub fn tip_width(&self) -> f64 {
        tip_width(self.base_width, self.width_ratio)
    }
}

/// Tip width of a planform, `w_tip = (2 - w_r) w_nom` (docs/physics.md §1).
pub fn tip_width(base_width: f64, width_ratio: f64) -> f64 {
    base_width * (2.0 - width_ratio) / width_ratio
}

/// Relative slack on the tip-width check, so a design built exactly on the limit passes it.
pub(crate) const TIP_SLACK: f64 = 1e-12;

/// Relative slack on the strain check, so a laminate whose field the strain limit capped passes it.
const STRAIN_SLACK: f64 = 1e-12;

/// A fully specified search.
#[derive(Debug, Clone)]
pub struct Problem {
    /// Model.
    pub model: SearchModel,
    /// Objective.
    pub objective: Objective,
    /// Required energy, J.
    pub energy: f64,
    /// Planform bounds.
    pub bounds: SearchRanges,
    /// Smallest tip width, m.
    pub min_tip_width: f64,
    /// Largest peak PZT strain along the plate over the stroke, free to blocked (`None`: unconstrained).
    pub max_strain: Option<f64>,
    /// Grid points per continuous variable.
    pub grid: usize,
    /// Laminates, in spec order (thickness outer, layup inner).
    pub candidates: Vec<Candidate>,
    /// PZT material (a calibrated model rebuilds the stacks from it).
    pub pzt: Material,
    /// Passive ply material.
    pub ply: Material,
    /// Nominal ply thickness, m.
    pub ply_thickness: f64,
}

impl Problem {
    /// Solve every `(t_p, layup)` laminate once at its field: the requested one, capped by the supply
    /// voltage and by the strain limit.
    pub fn from_spec(
        spec: &Spec,
        model: SearchModel,
        objective: Objective,
    ) -> Result<Problem, ModelError> {
        let mut candidates = Vec::new();
        for &t_p in &spec.pzt_thicknesses {
            for layup in &spec.layups {
                let laminate =
                    Laminate::bimorph(&spec.pzt, t_p, &spec.ply, spec.ply_thickness, layup, None)?;
                candidates.push(solve_candidate(spec, &laminate, t_p, layup)?);
            }
        }
        let problem = Problem {
            model,
            objective,
            energy: spec.energy,
            bounds: spec.bounds,
            min_tip_width: spec.min_tip_width,
            max_strain: spec.max_peak_pzt_strain,
            grid: spec.grid,
            candidates,
            pzt: spec.pzt.clone(),
            ply: spec.ply.clone(),
            ply_thickness: spec.ply_thickness,
        };
        // A calibrated stack that cannot be solved fails here, once per laminate, not inside the search
        // (the stack does not depend on the shape).
        for c in 0..problem.candidates.len() {
            problem.try_shape_rates(c, 0.5, 1.0)?;
        }
        Ok(problem)
    }

    /// The stack of laminate `candidate` at its field.
    pub fn stack(&self, candidate: usize) -> Stack<'_> {
        let c = &self.candidates[candidate];
        Stack {
            pzt: &self.pzt,
            pzt_thickness: c.pzt_thickness,
            ply: &self.ply,
            ply_thickness: self.ply_thickness,
            layup_deg: &c.layup,
            // Replaced by the planform being evaluated.
            planform: Planform {
                length: 1.0,
                extension_ratio: 0.0,
                base_width: 1.0,
                width_ratio: 1.0,
                base_tab: 0.0,
            },
            drive: c.section.drive,
        }
    }

    /// The shape's rates, or `None` when its plate strains beyond `max_strain` along it.
    fn try_shape_rates(
        &self,
        candidate: usize,
        extension_ratio: f64,
        width_ratio: f64,
    ) -> Result<Option<ShapeRates>, ModelError> {
        let rates = self.model.shape_rates(
            &self.candidates[candidate].section,
            &self.stack(candidate),
            extension_ratio,
            width_ratio,
        )?;
        let past = match (self.max_strain, rates.peak_strain) {
            (Some(limit), Some(strain)) => strain > limit * (1.0 + STRAIN_SLACK),
            _ => self.strains_past_limit(candidate, extension_ratio, width_ratio)?,
        };
        if past {
            return Ok(None);
        }
        Ok(Some(rates))
    }

    /// True when the shape's plate strains beyond `max_strain` somewhere along it over the stroke
    /// ([`SearchModel::shape_strain`]).
    pub fn strains_past_limit(
        &self,
        candidate: usize,
        extension_ratio: f64,
        width_ratio: f64,
    ) -> Result<bool, ModelError> {
        let Some(limit) = self.max_strain else {
            return Ok(false);
        };
        let (section, stack) = (&self.candidates[candidate].section, self.stack(candidate));
        let strain = self
            .model
            .shape_strain(section, &stack, extension_ratio, width_ratio)?;
        Ok(strain > limit * (1.0 + STRAIN_SLACK))
    }

    /// The model's rates of one shape on one laminate. [`Problem::from_spec`] has solved every stack
    /// once, so this cannot fail; were it to, or were the shape's plate strained beyond the limit, the
    /// shape gets no energy and is never chosen.
    pub fn shape_rates(
        &self,
        candidate: usize,
        extension_ratio: f64,
        width_ratio: f64,
    ) -> ShapeRates {
        self.try_shape_rates(candidate, extension_ratio, width_ratio)
            .ok()
            .flatten()
            .unwrap_or(ShapeRates {
                energy: 0.0,
                mass: f64::INFINITY,
                basis: None,
                peak_strain: None,
            })
    }

    /// Full prediction of a design through the model crate.
    pub fn performance(&self, d: &Design) -> Result<Performance, ModelError> {
        self.model.performance(
            &self.candidates[d.candidate].section,
            &self.stack(d.candidate),
            &d.planform(),
        )
    }

    /// The grid axes: lengths, base widths, extension ratios, width ratios.
    pub fn axes(&self) -> [Vec<f64>; 4] {
        let b = &self.bounds;
        [
            b.length.grid(self.grid),
            b.base_width.grid(self.grid),
            b.extension_ratio.grid(self.grid),
            b.width_ratio.grid(self.grid),
        ]
    }

    /// Number of grid points over all laminates.
    pub fn grid_size(&self) -> u64 {
        self.axes().iter().map(|a| a.len() as u64).product::<u64>() * self.candidates.len() as u64
    }

    /// Objective value of a feasible design (smaller is better).
    pub fn value(&self, energy: f64, mass: f64) -> f64 {
        match self.objective {
            Objective::MinMass => mass,
            Objective::MaxEnergyDensity => -(energy / mass),
        }
    }

    /// Order two feasible designs: objective, then mass, then the shorter, then laminate order.
    pub fn compare(&self, a: &Design, b: &Design) -> Ordering {
        self.value(a.energy, a.mass)
            .total_cmp(&self.value(b.energy, b.mass))
            .then(a.mass.total_cmp(&b.mass))
            .then(a.length.total_cmp(&b.length))
            .then(a.candidate.cmp(&b.candidate))
    }

    /// A design from the separable rates at a length.
    pub(crate) fn design(
        &self,
        candidate: usize,
        rates: ShapeRates,
        length: f64,
        base_width: f64,
        extension_ratio: f64,
        width_ratio: f64,
    ) -> Design {
        let section = &self.candidates[candidate].section;
        Design {
            candidate,
            length,
            base_width,
            extension_ratio,
            width_ratio,
            energy: self.model.energy(section, &rates, length, base_width),
            mass: length * base_width * rates.mass,
        }
    }
}

fn solve_candidate(
    spec: &Spec,
    laminate: &Laminate,
    t_p: f64,
    layup: &[f64],
) -> Result<Candidate, ModelError> {
    let drive = |field: f64| Drive {
        mode: spec.mode,
        field,
        bias: spec.bias,
    };
    let at = |field: f64| Section::new(laminate, drive(field));
    let requested = at(spec.field)?;
    let mut field = spec.field;
    let mut limit = FieldLimit::Requested;
    if let Some(v) = spec.max_voltage {
        let by_voltage = spec.mode.field_from_voltage(v, t_p);
        if by_voltage < field {
            field = by_voltage;
            limit = FieldLimit::Voltage;
        }
    }
    if let Some(max_strain) = spec.max_peak_pzt_strain {
        // Peak strain is linear in the field (CLT, thesis eq. 2.18).
        let by_strain = spec.field * max_strain / requested.peak_pzt_strain;
        if by_strain < field {
            field = by_strain;
            limit = FieldLimit::Strain;
        }
    }
    if let Some(survival) = spec.poling_survival {
        let check = FieldCheck::new(&drive(field), survival, spec.pzt.depolarization_field)?;
        if check.max_signal < field {
            field = check.max_signal;
            limit = FieldLimit::Poling(check.binds);
        }
    }
    let section = if limit == FieldLimit::Requested {
        requested
    } else {
        at(field)?
    };
    Ok(Candidate {
        pzt_thickness: t_p,
        layup: layup.to_vec(),
        section,
        field_limit: limit,
    })
}

/// The best grid cells of one shape `(l_r, w_r)` for one laminate.
#[derive(Debug, Clone, Copy)]
struct ShapeBest {
    /// Lightest (or best) feasible design of the shape and its flat grid index.
    best: Option<(Design, u64)>,
    /// Most energetic design of the shape (at the longest length).
    most_energy: Option<Design>,
}

/// The exhaustive stage's result for one laminate.
#[derive(Debug, Clone)]
pub struct CandidateGrid {
    /// Best feasible grid design.
    pub best: Option<Design>,
    /// Best few shapes' best designs, best first: where the refinement starts.
    pub seeds: Vec<Design>,
    /// The grid design with the most energy (tip width respected).
    pub most_energy: Option<Design>,
}

/// The exhaustive stage's result.
#[derive(Debug, Clone)]
pub struct GridResult {
    /// Grid points evaluated.
    pub evaluated: u64,
    /// Per laminate, in [`Problem::candidates`] order.
    pub per_candidate: Vec<CandidateGrid>,
    /// Best feasible grid design over all laminates.
    pub best: Option<Design>,
}

/// How many shapes per laminate seed the refinement.
pub const SEEDS_PER_CANDIDATE: usize = 3;

/// One laminate's grid from its `(laminate, l_r)` slices: its best design, its seeds for the
/// refinement (the best of each shape, ranked by value, ties by grid index) and the design with the
/// most energy.
fn candidate_grid(problem: &Problem, slices: &[Vec<ShapeBest>]) -> CandidateGrid {
    let shapes = slices.iter().flatten();
    let mut ranked: Vec<(Design, u64)> = shapes.clone().filter_map(|s| s.best).collect();
    ranked.sort_by(|a, b| {
        problem
            .value(a.0.energy, a.0.mass)
            .total_cmp(&problem.value(b.0.energy, b.0.mass))
            .then(a.1.cmp(&b.1))
    });
    let most_energy =
        shapes
            .filter_map(|s| s.most_energy)
            .reduce(|a, b| if b.energy > a.energy { b } else { a });
    CandidateGrid {
        best: ranked.first().map(|r| r.0),
        seeds: ranked
            .iter()
            .take(SEEDS_PER_CANDIDATE)
            .map(|r| r.0)
            .collect(),
        most_energy,
    }
}

/// Run the exhaustive stage, in parallel over `(laminate, l_r)` slices. The result does not depend on the
/// number of threads: each slice reduces in index order, and slices are combined by (value, index).
/// `progress` hears of each slice done.
pub fn exhaustive(problem: &Problem, progress: &dyn Progress) -> GridResult {
    let [lengths, widths, ext_ratios, width_ratios] = problem.axes();
    let n_c = problem.candidates.len();
    let (n_w, n_r, n_q) = (widths.len(), ext_ratios.len(), width_ratios.len());
    let width_factors: Vec<Vec<f64>> = problem
        .candidates
        .iter()
        .map(|c| {
            widths
                .iter()
                .map(|&w| problem.model.width_factor(&c.section, w))
                .collect()
        })
        .collect();
    progress.start((n_c * n_r) as u64);
    let l_hi = *lengths.last().unwrap_or(&problem.bounds.length.hi);
    let tip_min = problem.min_tip_width * (1.0 - TIP_SLACK);
    let separable = problem.model.is_separable();
    let slices: Vec<Vec<ShapeBest>> = (0..n_c * n_r)
        .into_par_iter()
        .map(|task| {
            let (c, i_r) = (task / n_r, task % n_r);
            let section = &problem.candidates[c].section;
            let l_r = ext_ratios[i_r];
            let shapes = (0..n_q)
                .map(|i_q| {
                    let w_r = width_ratios[i_q];
                    let rates = problem.shape_rates(c, l_r, w_r);
                    let shape_index = ((c * n_r + i_r) * n_q + i_q) as u64;
                    let mut best: Option<(f64, usize, usize)> = None;
                    let mut most: Option<(f64, usize)> = None;
                    for i_w in 0..n_w {
                        let w0 = widths[i_w];
                        let e = w0 * rates.energy * width_factors[c][i_w];
                        let mu = w0 * rates.mass;
                        // A row whose tip is too narrow has no feasible point.
                        let tip_ok = tip_width(w0, w_r) >= tip_min;
                        let energy_min = if tip_ok {
                            problem.energy
                        } else {
                            f64::INFINITY
                        };
                        let (value, i_l) = if !separable {
                            let lightest_to_beat = (problem.objective == Objective::MinMass)
                                .then(|| best.map_or(f64::INFINITY, |(v, _, _)| v));
                            general_row(
                                &lengths,
                                |l| l * w0 * rates.mass,
                                energy_min,
                                lightest_to_beat,
                                |l| problem.model.energy(section, &rates, l, w0),
                                |u, m| problem.value(u, m),
                            )
                        } else {
                            match problem.objective {
                                Objective::MinMass => lightest_in_row(&lengths, e, mu, energy_min),
                                Objective::MaxEnergyDensity => {
                                    let i_l = first_feasible_in_row(&lengths, e, energy_min);
                                    (-(e / mu), i_l)
                                }
                            }
                        };
                        if i_l != usize::MAX && best.is_none_or(|(v, _, _)| value < v) {
                            best = Some((value, i_w, i_l));
                        }
                        let top = if separable {
                            e * l_hi
                        } else {
                            problem.model.energy(section, &rates, l_hi, w0)
                        };
                        if tip_ok && most.is_none_or(|(u, _)| top > u) {
                            most = Some((top, i_w));
                        }
                    }
                    ShapeBest {
                        best: best.map(|(_, i_w, i_l)| {
                            let d = problem.design(c, rates, lengths[i_l], widths[i_w], l_r, w_r);
                            (
                                d,
                                (shape_index * n_w as u64 + i_w as u64) * lengths.len() as u64
                                    + i_l as u64,
                            )
                        }),
                        most_energy: most
                            .map(|(_, i_w)| problem.design(c, rates, l_hi, widths[i_w], l_r, w_r)),
                    }
                })
                .collect();
            progress.advance(1);
            shapes
        })
        .collect();
    progress.finish();
    let per_candidate: Vec<CandidateGrid> = (0..n_c)
        .map(|c| candidate_grid(problem, &slices[c * n_r..(c + 1) * n_r]))
        .collect();
    let best = per_candidate.iter().filter_map(|g| g.best).reduce(|a, b| {
        if problem.compare(&b, &a) == Ordering::Less {
            b
        } else {
            a
        }
    });
    GridResult {
        evaluated: problem.grid_size(),
        per_candidate,
        best,
    }
}
