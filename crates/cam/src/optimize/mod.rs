//! `actuator-cam optimize`: the lightest actuator (or the highest energy density) that delivers a required
//! mechanical energy, as the thesis' `OptimizedActuator` (Lenzen 2013, §4.10), exact and fast.
//!
//! Two stages: an exhaustive grid over `(l_tot, w_0, l_r, w_r)` for every `(t_p, layup)` ([`search`]),
//! then a continuous refinement from the best grid cells of each laminate ([`refine`]). The laminate is
//! solved once per `(t_p, layup, field)`.

mod field_limit;
pub mod flap;
pub mod flap_report;
pub mod model;
pub mod pareto;
pub mod progress;
pub mod refine;
pub mod report;
mod row;
pub mod search;
pub mod spec;

pub use progress::{Progress, Silent};

use crate::input::short_number;
use actuator_model::poling::Binding;
use rayon::prelude::*;
use search::{Design, FieldLimit, GridResult, Problem};

/// Energy levels on the Pareto front.
pub const PARETO_LEVELS: usize = 40;

/// Everything one optimisation found.
#[derive(Debug, Clone)]
pub struct Outcome {
    /// The problem as solved.
    pub problem: Problem,
    /// Exhaustive stage.
    pub grid: GridResult,
    /// Refined best per laminate (`None`: it cannot reach the energy).
    pub refined: Vec<Option<Design>>,
    /// Most energetic design per laminate (`None`: no design meets the tip width).
    pub most_energy: Vec<Option<Design>>,
    /// The optimum.
    pub best: Design,
}

/// Why an optimisation has no answer.
#[derive(Debug, Clone, thiserror::Error)]
pub enum OptimizeError {
    /// No design in the ranges delivers the energy.
    #[error("infeasible: the most energy reachable in the search ranges is {most_energy_mj} mJ ({design}){}; lower the requirement or widen the ranges", capped_text(*.limit))]
    Infeasible {
        /// The most energy any design reaches, mJ.
        most_energy_mj: String,
        /// That design.
        design: String,
        /// What set that design's field: a cap the user wrote is the field to change, not the
        /// requirement.
        limit: FieldLimit,
    },
}

/// The cap on the most energetic design's field, as the user wrote it.
fn capped_text(limit: FieldLimit) -> &'static str {
    match limit {
        FieldLimit::Requested => "",
        FieldLimit::Voltage => {
            ", its field held down by drive.max_voltage_V: raise max_voltage_V or use thinner plates"
        }
        FieldLimit::Strain => {
            ", its field held down by constraints.max_peak_pzt_strain: raise that limit"
        }
        FieldLimit::Poling(Binding::Depolarization) => {
            ", its field held down by the PZT's depolarization field against the poling: a drive mode that keeps the plates along their poling (biased)"
        }
        FieldLimit::Poling(Binding::Failure) => {
            ", its field held down by the drive mode's failure fit at the drive file's survival"
        }
        FieldLimit::Poling(Binding::Bias) => {
            ", its signal held to half the bias: raise drive.bias_V_per_mm"
        }
    }
}

/// Run both stages on a problem, reporting the exhaustive stage's progress to `progress`.
pub fn optimize(problem: Problem, progress: &dyn Progress) -> Result<Outcome, OptimizeError> {
    let grid = search::exhaustive(&problem, progress);
    let per: Vec<(Option<Design>, Option<Design>)> = (0..problem.candidates.len())
        .into_par_iter()
        .map(|c| {
            let g = &grid.per_candidate[c];
            let most = g
                .most_energy
                .map(|seed| refine::most_energy(&problem, c, &seed));
            let mut seeds = g.seeds.clone();
            if let Some(m) = most.filter(|m| m.energy >= problem.energy) {
                if seeds.is_empty() {
                    seeds.push(m);
                }
            }
            (refine::refine(&problem, c, &seeds), most)
        })
        .collect();
    let (refined, most_energy): (Vec<_>, Vec<_>) = per.into_iter().unzip();
    let best = refined.iter().flatten().copied().reduce(|a, b| {
        if problem.compare(&b, &a).is_lt() {
            b
        } else {
            a
        }
    });
    match best {
        Some(best) => Ok(Outcome {
            problem,
            grid,
            refined,
            most_energy,
            best,
        }),
        None => {
            let top = most_energy.iter().flatten().copied().reduce(|a, b| {
                if b.energy > a.energy {
                    b
                } else {
                    a
                }
            });
            // No energy anywhere because the most energetic shape strains its plate past the limit.
            let strained = top.is_some_and(|d| {
                d.energy <= 0.0
                    && problem
                        .strains_past_limit(d.candidate, d.extension_ratio, d.width_ratio)
                        .unwrap_or(false)
            });
            Err(OptimizeError::Infeasible {
                most_energy_mj: top.map_or("0".into(), |d| short_number(d.energy * 1e3)),
                limit: match top {
                    _ if strained => FieldLimit::Strain,
                    Some(d) => problem.candidates[d.candidate].field_limit,
                    None => FieldLimit::Requested,
                },
                design: top.map_or("no design meets the tip width".into(), |d| {
                    if strained {
                        return "every shape in the ranges strains its plate past constraints.max_peak_pzt_strain somewhere along it between free deflection and blocked".into();
                    }
                    let c = &problem.candidates[d.candidate];
                    format!(
                        "t_p {} mm {}, l_tot {:.4} mm, l_r {:.4}, w_0 {:.4} mm, w_r {:.4}",
                        c.pzt_thickness * 1e3,
                        report::layup_label(&c.layup),
                        d.length * 1e3,
                        d.extension_ratio,
                        d.base_width * 1e3,
                        d.width_ratio
                    )
                }),
            })
        }
    }
}
