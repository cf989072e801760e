//! Continuous refinement from the best grid cells, so the answer does not depend on the grid spacing.
//!
//! The built-in models are linear in `l_tot` at fixed `(w_0, l_r, w_r)` ([`super::model`]), so the length
//! is not searched (a calibrated model with a length of its own bisects it instead): the lightest feasible one is `l_tot = max(l_min, U_min / (w_0 u g(w_0)))`, infeasible above
//! `l_max`. That leaves `(w_0, l_r, w_r)` (fewer when a range is fixed), searched by Nelder-Mead with
//! restarts in the unit cube. The tip-width limit `w_0 (2 - w_r)/w_r >= w_tip,min` is built into the
//! coordinates (`w_r` runs up to `2 w_0 / (w_0 + w_tip,min)`), so every point of the cube satisfies it;
//! a length above `l_max` is penalised smoothly, and only feasible designs are ever returned.

use super::search::{tip_width, Design, Objective, Problem, TIP_SLACK};
use super::spec::Range;
use std::cmp::Ordering;

/// Relative margin on the closed-form length, so the design's energy is `U_min (1 + 1e-10)` and rounding
/// in a later evaluation cannot put it below `U_min`.
const LENGTH_MARGIN: f64 = 1e-10;

/// Two designs within this relative objective difference are a tie; ties go to the shorter actuator
/// (stiffer, higher resonance).
pub const TIE_TOLERANCE: f64 = 1e-12;

/// One laminate's continuous problem in unit coordinates.
struct Reduced<'a> {
    problem: &'a Problem,
    candidate: usize,
    /// `w_0` range, its lower end raised so that `w_r = w_r,min` meets the tip-width limit.
    base_width: Range,
    /// Which of `(w_0, l_r, w_r)` vary.
    free: [bool; 3],
}

impl<'a> Reduced<'a> {
    fn new(problem: &'a Problem, candidate: usize) -> Option<Self> {
        let b = &problem.bounds;
        let q_lo = b.width_ratio.lo;
        let w_lo = b
            .base_width
            .lo
            .max(problem.min_tip_width * q_lo / (2.0 - q_lo));
        if w_lo > b.base_width.hi {
            return None;
        }
        let base_width = Range {
            lo: w_lo,
            hi: b.base_width.hi,
        };
        Some(Reduced {
            problem,
            candidate,
            base_width,
            free: [
                !base_width.is_fixed(),
                !b.extension_ratio.is_fixed(),
                !b.width_ratio.is_fixed(),
            ],
        })
    }

    fn dims(&self) -> usize {
        self.free.iter().filter(|f| **f).count()
    }

    /// Highest `w_r` with the tip at least `w_tip,min` wide at this base width.
    fn width_ratio_cap(&self, base_width: f64) -> f64 {
        let q = &self.problem.bounds.width_ratio;
        let t = self.problem.min_tip_width;
        q.hi.min(2.0 * base_width / (base_width + t)).max(q.lo)
    }

    /// `(w_0, l_r, w_r)` of a point of the unit cube (only the free coordinates are read).
    fn variables(&self, x: &[f64]) -> (f64, f64, f64) {
        let mut it = x.iter().copied();
        let mut next = |free: bool| if free { it.next().unwrap_or(0.0) } else { 0.0 };
        let (u_w, u_r, u_q) = (next(self.free[0]), next(self.free[1]), next(self.free[2]));
        let w0 = self.base_width.at(u_w);
        let l_r = self.problem.bounds.extension_ratio.at(u_r);
        let q = Range {
            lo: self.problem.bounds.width_ratio.lo,
            hi: self.width_ratio_cap(w0),
        };
        (w0, l_r, q.at(u_q))
    }

    /// Unit coordinates of a design (inverse of [`Self::variables`]).
    fn coordinates(&self, d: &Design) -> Vec<f64> {
        let q = Range {
            lo: self.problem.bounds.width_ratio.lo,
            hi: self.width_ratio_cap(d.base_width),
        };
        let all = [
            self.base_width.fraction(d.base_width),
            self.problem
                .bounds
                .extension_ratio
                .fraction(d.extension_ratio),
            q.fraction(d.width_ratio),
        ];
        all.iter()
            .zip(self.free)
            .filter(|(_, f)| *f)
            .map(|(u, _)| *u)
            .collect()
    }

    /// The lightest design of this shape that meets the energy (feasible or not), and the length it needs.
    fn design(&self, w0: f64, l_r: f64, w_r: f64) -> (Design, f64) {
        let p = self.problem;
        let rates = p.shape_rates(self.candidate, l_r, w_r);
        if !p.model.is_separable() {
            return self.design_by_length_search(rates, w0, l_r, w_r);
        }
        let section = &p.candidates[self.candidate].section;
        let per_length = w0 * rates.energy * p.model.width_factor(section, w0);
        let needed = if per_length > 0.0 {
            p.energy / per_length
        } else {
            f64::INFINITY
        };
        let length = (needed * (1.0 + LENGTH_MARGIN))
            .max(p.bounds.length.lo)
            .min(p.bounds.length.hi);
        (
            p.design(self.candidate, rates, length, w0, l_r, w_r),
            needed,
        )
    }

    /// [`Self::design`] for a model whose energy is not linear in `l_tot` (a calibrated dead length or
    /// clamp compliance). The energy still grows with length (δ with `(l_tot - Δ)²`, the compliance
    /// slower than `δ²`), so the shortest length meeting `U_min` is found by bisection; outside
    /// `[l_min, l_max]` the needed length is extrapolated linearly, as the penalty only needs it to
    /// grow smoothly with the shortfall.
    fn design_by_length_search(
        &self,
        rates: super::model::ShapeRates,
        w0: f64,
        l_r: f64,
        w_r: f64,
    ) -> (Design, f64) {
        let p = self.problem;
        let (lo, hi) = (p.bounds.length.lo, p.bounds.length.hi);
        let at = |l: f64| p.design(self.candidate, rates, l, w0, l_r, w_r);
        let (short, long) = (at(lo), at(hi));
        if long.energy.is_nan() || long.energy <= 0.0 {
            return (long, f64::INFINITY);
        }
        if short.energy >= p.energy {
            return (short, lo * p.energy / short.energy);
        }
        if long.energy < p.energy {
            return (long, hi * p.energy / long.energy);
        }
        let (mut a, mut b) = (lo, hi);
        while b - a > LENGTH_MARGIN * hi {
            let m = 0.5 * (a + b);
            if at(m).energy >= p.energy {
                b = m;
            } else {
                a = m;
            }
        }
        (at(b), b)
    }

    fn feasible(&self, d: &Design, needed: f64) -> bool {
        let p = self.problem;
        needed <= p.bounds.length.hi
            && d.energy >= p.energy
            && tip_width(d.base_width, d.width_ratio) >= p.min_tip_width * (1.0 - TIP_SLACK)
    }

    /// The objective with a smooth penalty for lengths above `l_max` (continuous at `l_max`).
    fn penalised(&self, d: &Design, needed: f64) -> f64 {
        let p = self.problem;
        if !needed.is_finite() {
            return f64::INFINITY;
        }
        let l_hi = p.bounds.length.hi;
        let excess = (needed / l_hi - 1.0).max(0.0);
        match p.objective {
            Objective::MinMass => {
                // The mass if the length could grow to what the energy needs.
                let mass = d.mass * needed.max(p.bounds.length.lo) / d.length;
                mass * (1.0 + 1e3 * excess)
            }
            Objective::MaxEnergyDensity => {
                let density = d.energy / d.mass;
                -density + density * 1e3 * excess
            }
        }
    }
}

/// Minimise `f` over the unit cube by Nelder-Mead (reflection 1, expansion 2, contraction ½, shrink ½),
/// points clamped to the cube. Returns the best point and value.
fn nelder_mead(
    f: &mut impl FnMut(&[f64]) -> f64,
    start: &[f64],
    step: f64,
    max_evals: usize,
) -> (Vec<f64>, f64) {
    let n = start.len();
    let clamp = |v: Vec<f64>| -> Vec<f64> { v.into_iter().map(|x| x.clamp(0.0, 1.0)).collect() };
    let mut simplex: Vec<(Vec<f64>, f64)> = Vec::with_capacity(n + 1);
    let x0 = clamp(start.to_vec());
    let f0 = f(&x0);
    simplex.push((x0.clone(), f0));
    for i in 0..n {
        let mut x = x0.clone();
        x[i] = if x[i] + step <= 1.0 {
            x[i] + step
        } else {
            x[i] - step
        };
        let x = clamp(x);
        let fx = f(&x);
        simplex.push((x, fx));
    }
    let mut evals = n + 1;
    let along = |a: &[f64], b: &[f64], t: f64| -> Vec<f64> {
        clamp(a.iter().zip(b).map(|(a, b)| a + t * (b - a)).collect())
    };
    while evals < max_evals {
        simplex.sort_by(|a, b| a.1.total_cmp(&b.1));
        let (best, worst) = (simplex[0].1, simplex[n].1);
        let size = simplex
            .iter()
            .flat_map(|(x, _)| x.iter().zip(&simplex[0].0).map(|(a, b)| (a - b).abs()))
            .fold(0.0, f64::max);
        if size < 1e-13 || (worst - best).abs() <= 1e-15 * best.abs() && size < 1e-9 {
            break;
        }
        let centroid: Vec<f64> = (0..n)
            .map(|j| simplex[..n].iter().map(|(x, _)| x[j]).sum::<f64>() / n as f64)
            .collect();
        let reflected = along(&centroid, &simplex[n].0, -1.0);
        let fr = f(&reflected);
        evals += 1;
        if fr < simplex[0].1 {
            let expanded = along(&centroid, &simplex[n].0, -2.0);
            let fe = f(&expanded);
            evals += 1;
            simplex[n] = if fe < fr {
                (expanded, fe)
            } else {
                (reflected, fr)
            };
        } else if fr < simplex[n - 1].1 {
            simplex[n] = (reflected, fr);
        } else {
            let (toward, f_toward) = if fr < simplex[n].1 {
                (reflected, fr)
            } else {
                (simplex[n].0.clone(), simplex[n].1)
            };
            let contracted = along(&centroid, &toward, 0.5);
            let fc = f(&contracted);
            evals += 1;
            if fc < f_toward {
                simplex[n] = (contracted, fc);
            } else {
                let x_best = simplex[0].0.clone();
                for v in simplex.iter_mut().skip(1) {
                    v.0 = along(&x_best, &v.0, 0.5);
                    v.1 = f(&v.0);
                }
                evals += n;
            }
        }
    }
    simplex.sort_by(|a, b| a.1.total_cmp(&b.1));
    simplex.swap_remove(0)
}

/// Keeps the best feasible design seen, by [`Problem::compare`].
struct Incumbent<'a> {
    problem: &'a Problem,
    best: Option<Design>,
}

impl Incumbent<'_> {
    fn offer(&mut self, d: Design) {
        if self
            .best
            .is_none_or(|b| self.problem.compare(&d, &b) == Ordering::Less)
        {
            self.best = Some(d);
        }
    }
}

/// Refine one laminate from its seeds. Returns the best feasible design found (never worse than the
/// feasible seeds), or `None` when nothing feasible was met.
pub fn refine(problem: &Problem, candidate: usize, seeds: &[Design]) -> Option<Design> {
    let reduced = Reduced::new(problem, candidate)?;
    let mut incumbent = Incumbent {
        problem,
        best: None,
    };
    let objective = |x: &[f64], inc: &mut Incumbent| {
        let (w0, l_r, w_r) = reduced.variables(x);
        let (d, needed) = reduced.design(w0, l_r, w_r);
        if reduced.feasible(&d, needed) {
            inc.offer(d);
        }
        reduced.penalised(&d, needed)
    };
    let dims = reduced.dims();
    let cell = 1.0 / (problem.grid.max(2) - 1) as f64;
    for seed in seeds {
        let mut x = reduced.coordinates(seed);
        let mut fx = objective(&x, &mut incumbent);
        if dims == 0 {
            continue;
        }
        // Restart with shrinking steps until a restart no longer improves: a collapsed simplex on a bound
        // face is rebuilt at full dimension.
        for step in [
            2.0 * cell,
            cell,
            0.25 * cell,
            0.05 * cell,
            0.01 * cell,
            1e-3 * cell,
        ] {
            let (y, fy) = nelder_mead(
                &mut |x: &[f64]| objective(x, &mut incumbent),
                &x,
                step,
                400 * (dims + 1),
            );
            if fy < fx {
                x = y;
                fx = fy;
            }
        }
    }
    let best = incumbent.best?;
    let best = match problem.objective {
        Objective::MinMass => best,
        Objective::MaxEnergyDensity => lighter_at_same_density(&reduced, best),
    };
    Some(prefer_shorter(&reduced, best))
}

/// With the highest energy density found, the lightest design of the same shape that keeps it: a
/// golden-section search over `w_0` below the optimum's. With the original model the density does not
/// depend on `w_0`, while the mass does once the length sits at `l_min` with energy to spare.
fn lighter_at_same_density(reduced: &Reduced, best: Design) -> Design {
    if !reduced.free[0] {
        return best;
    }
    let p = reduced.problem;
    let target = p.value(best.energy, best.mass);
    let tol = TIE_TOLERANCE * target.abs();
    let (l_r, w_r) = (best.extension_ratio, best.width_ratio);
    let at = |w0: f64| -> Option<Design> {
        let (d, needed) = reduced.design(w0, l_r, w_r);
        (reduced.feasible(&d, needed) && p.value(d.energy, d.mass) <= target + tol).then_some(d)
    };
    let mass = |w0: f64| at(w0).map_or(f64::INFINITY, |d| d.mass);
    // Lowest base width at which this width ratio keeps the tip wide enough.
    let lo = reduced
        .base_width
        .lo
        .max(p.min_tip_width * w_r / (2.0 - w_r));
    let (mut a, mut b) = (lo, best.base_width);
    let ratio = 0.5 * (5f64.sqrt() - 1.0);
    for _ in 0..100 {
        let (c, d) = (b - ratio * (b - a), a + ratio * (b - a));
        // Ties move right: the feasible side, and the shorter actuator.
        if mass(c) < mass(d) {
            b = d;
        } else {
            a = c;
        }
    }
    match at(0.5 * (a + b)) {
        Some(d) if d.mass < best.mass => d,
        _ => best,
    }
}

/// Among designs of the same shape within [`TIE_TOLERANCE`] of the best (objective and mass), take the
/// widest base and so the shortest actuator. With the original model the mass depends on `w_0 l_tot` only,
/// so a whole segment of designs ties; this makes the answer unique.
fn prefer_shorter(reduced: &Reduced, best: Design) -> Design {
    let p = reduced.problem;
    let target = p.value(best.energy, best.mass);
    let tol = TIE_TOLERANCE * target.abs();
    let accept = |w0: f64| -> Option<Design> {
        let (d, needed) = reduced.design(w0, best.extension_ratio, best.width_ratio);
        let ok = reduced.feasible(&d, needed)
            && p.value(d.energy, d.mass) <= target + tol
            && d.mass <= best.mass * (1.0 + TIE_TOLERANCE);
        ok.then_some(d)
    };
    if !reduced.free[0] {
        return best;
    }
    // A move that does not shorten the actuator noticeably is tolerance creep, not a tie: keep the optimum.
    let shorter = |d: Design| (d.length < best.length * (1.0 - SHORTER_BY)).then_some(d);
    if let Some(d) = accept(reduced.base_width.hi) {
        return shorter(d).unwrap_or(best);
    }
    let (mut lo, mut hi) = (best.base_width, reduced.base_width.hi);
    let mut chosen = best;
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        match accept(mid) {
            Some(d) => {
                lo = mid;
                chosen = d;
            }
            None => hi = mid,
        }
    }
    shorter(chosen).unwrap_or(best)
}

/// Relative shortening below which [`prefer_shorter`] keeps the optimum as found.
const SHORTER_BY: f64 = 1e-6;

/// The most energy one laminate can deliver in the bounds (tip width respected), at `l_tot = l_max`,
/// refined from the grid's most energetic design.
pub fn most_energy(problem: &Problem, candidate: usize, seed: &Design) -> Design {
    let Some(reduced) = Reduced::new(problem, candidate) else {
        return *seed;
    };
    let l_hi = problem.bounds.length.hi;
    let mut best = *seed;
    let mut f = |x: &[f64]| {
        let (w0, l_r, w_r) = reduced.variables(x);
        let rates = problem.shape_rates(candidate, l_r, w_r);
        let d = problem.design(candidate, rates, l_hi, w0, l_r, w_r);
        if d.energy > best.energy {
            best = d;
        }
        -d.energy
    };
    if reduced.dims() > 0 {
        let cell = 1.0 / (problem.grid.max(2) - 1) as f64;
        let mut x = reduced.coordinates(seed);
        for step in [2.0 * cell, 0.25 * cell, 0.01 * cell] {
            x = nelder_mead(&mut f, &x, step, 400 * (reduced.dims() + 1)).0;
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optimize::model::SearchModel;
    use crate::optimize::search::{exhaustive, Candidate, FieldLimit};
    use crate::optimize::spec::SearchRanges;
    use actuator_model::planform::energy_shape_factor;
    use actuator_model::{Drive, DriveMode, Laminate, Material, Section};

    /// One laminate (t_p 267 µm, [0/90/0], 800 V/mm parallel) whose passive plies weigh nothing, so the
    /// extension costs no mass: then `m = μ_p l_p w_nom` and `U = k l_p w_nom G_U` with
    /// `k = 3 P² / (8 C44)` (docs/physics.md §3), and the lightest design maximises `G_U`, whose maximum 4/3 lies
    /// on the ridge `w_r = 2 (1 + l_r) / (1 + 2 l_r)`. Closed-form mass: `U_min μ_p / (k 4/3)`.
    fn massless_extension_problem(extension_ratio: Range) -> (Problem, f64) {
        let pzt = Material::builtin("PZT-5H").unwrap();
        let cf = Material::builtin("CF-thesis").unwrap();
        let lam = Laminate::bimorph(&pzt, 267e-6, &cf, 61.8e-6, &[0.0, 90.0, 0.0], None).unwrap();
        let mut section = Section::new(&lam, Drive::new(DriveMode::Parallel, 800e3)).unwrap();
        section.passive_areal_mass = 0.0;
        let k = 3.0 * section.free_curvature.powi(2) / (8.0 * section.bending_compliance);
        // Piezo area l_p w_nom = 200 mm² on the ridge: inside the box for every l_r in [0, 1.5].
        let energy = k * 200e-6 * 4.0 / 3.0;
        let problem = Problem {
            model: SearchModel::Original,
            objective: Objective::MinMass,
            energy,
            bounds: SearchRanges {
                length: Range {
                    lo: 40e-3,
                    hi: 60e-3,
                },
                base_width: Range {
                    lo: 5e-3,
                    hi: 20e-3,
                },
                extension_ratio,
                width_ratio: Range { lo: 1.0, hi: 1.95 },
            },
            min_tip_width: 0.0,
            max_strain: None,
            grid: 15,
            candidates: vec![Candidate {
                pzt_thickness: 267e-6,
                layup: vec![0.0, 90.0, 0.0],
                section,
                field_limit: FieldLimit::Requested,
            }],
            pzt,
            ply: cf,
            ply_thickness: 61.8e-6,
        };
        let mass = energy * section.pzt_areal_mass / (k * 4.0 / 3.0);
        (problem, mass)
    }

    fn solve(problem: &Problem) -> Design {
        let grid = exhaustive(problem, &crate::optimize::Silent);
        refine(problem, 0, &grid.per_candidate[0].seeds).unwrap()
    }

    #[test]
    fn lands_on_the_uniform_strain_ridge_when_the_extension_is_massless() {
        let (problem, mass) = massless_extension_problem(Range { lo: 0.0, hi: 1.5 });
        let d = solve(&problem);
        let g_u = energy_shape_factor(d.width_ratio, d.extension_ratio);
        assert!((g_u * 0.75 - 1.0).abs() < 1e-9, "G_U {g_u} at {d:?}");
        assert!((d.mass / mass - 1.0).abs() < 1e-8, "{} vs {mass}", d.mass);
        assert!(
            d.energy >= problem.energy && d.energy <= problem.energy * (1.0 + 1e-9),
            "{d:?} {}",
            problem.energy
        );
    }

    #[test]
    fn with_the_extension_fixed_the_width_ratio_is_the_ridge_value() {
        // l_r = 0.5: the ridge is at w_r = 2 (1.5) / 2 = 1.5 exactly, off every grid point of a 15-grid.
        let (problem, mass) = massless_extension_problem(Range::fixed(0.5));
        let d = solve(&problem);
        assert_eq!(d.extension_ratio, 0.5);
        assert!((d.width_ratio - 1.5).abs() < 1e-5, "w_r {}", d.width_ratio);
        assert!((d.mass / mass - 1.0).abs() < 1e-9, "{d:?} {mass}");
    }

    #[test]
    fn nelder_mead_finds_an_interior_and_a_boundary_minimum() {
        let mut bowl = |x: &[f64]| (x[0] - 0.3).powi(2) + 2.0 * (x[1] - 0.7).powi(2);
        let (x, f) = nelder_mead(&mut bowl, &[0.9, 0.1], 0.1, 2000);
        assert!((x[0] - 0.3).abs() < 1e-6 && (x[1] - 0.7).abs() < 1e-6 && f < 1e-12);
        // Minimum outside the cube: the clamped search ends on the face x0 = 1.
        let mut slope = |x: &[f64]| -x[0] + (x[1] - 0.5).powi(2);
        let (x, _) = nelder_mead(&mut slope, &[0.2, 0.2], 0.1, 2000);
        assert!(
            (x[0] - 1.0).abs() < 1e-9 && (x[1] - 0.5).abs() < 1e-4,
            "{x:?}"
        );
    }
}
