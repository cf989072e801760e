//! The tapered bimorph with the nonlinear ceramic of [`crate::ceramic`] (Jafferis, Smith & Wood 2015;
//! docs/physics.md §18): the section's strain and curvature solved at each station under the plates'
//! actual fields and the local moment, the tip deflection integrated from the curvature along the beam,
//! the blocked force as the load that holds the tip at its rest position.
//!
//! The ceramic's departure from the linear PZT of the laminate enters as an axial stress
//! `Δσ = σ_e(ε) - E ε + s [f31(ξ, ε) - E |d31|] ξ` in every PZT layer (`E`, `d31` the laminate's
//! material, `s = -sign d31`), integrated through the thickness into force and moment resultants; the
//! rest of the laminate (plies, transverse coupling) is classical lamination theory as in the original
//! model. With [`Ceramic::linear`] at the material's own `E` and `E |d31|`, `Δσ` is zero and every
//! output is the original model's.

use crate::ceramic::Ceramic;
use crate::drive::{plate_fields_at, Drive};
use crate::error::ModelError;
use crate::laminate::{Laminate, LayerRole};
use crate::performance::{base_stress, beam_tip_compliance, evaluate, Performance};
use crate::planform::Planform;
use crate::plate::PlatePeak;
use crate::quadrature::GAUSS5;
use crate::section::Section;
use nalgebra::Vector6;
use std::f64::consts::FRAC_PI_2;

/// Panels through each PZT layer: the modulus switches over `1/a` = 125 µm/m of strain, a fraction of
/// the strain across a plate in bending; three panels of five points give thesis design C's outputs
/// to 1e-12 of eight.
const THICKNESS_PANELS: usize = 3;
/// Panels along the active length at least; more where the width shrinks (each panel spans a width
/// ratio of at most [`WIDTH_STEP`]). Thesis designs A, B, C, 7 and 21 give the same outputs to 1e-10
/// with two panels as with eight.
const LENGTH_PANELS: usize = 3;
/// Largest ratio of widths across one panel along the beam.
const WIDTH_STEP: f64 = 1.25;
/// Newton steps allowed per station.
const NEWTON_STEPS: usize = 60;
/// Root-finding steps allowed for the blocked force.
const ROOT_STEPS: usize = 200;

/// A point of the through-thickness quadrature in a PZT layer.
#[derive(Debug, Clone, Copy)]
struct Point {
    z: f64,
    weight: f64,
    field: f64,
}

/// A solved station: axial strain and curvature `[ε0x, κx]`, the correction resultants `[ΔN, ΔM]`
/// and the tangent `∂κ/∂m` of the curvature in the external moment per width.
#[derive(Debug, Clone, Copy)]
struct State {
    strain: f64,
    curvature: f64,
    correction: [f64; 2],
    slope: f64,
}

/// The laminate's section under the nonlinear ceramic at one pair of plate fields.
#[derive(Debug, Clone)]
pub struct NonlinearSection<'a> {
    laminate: &'a Laminate,
    ceramic: Ceramic,
    /// The laminate PZT's modulus and stress coefficient `E`, `E |d31|`.
    reference: (f64, f64),
    /// `-sign d31`: the sign of the internal stress of a field along the poling.
    sign: f64,
    /// The plate fields, bottom then top, V/m, positive along each plate's poling.
    fields: [f64; 2],
    points: Vec<Point>,
    free: Vector6<f64>,
    /// The x rows and columns of the laminate's compliance: `[[C11, C14], [C41, C44]]`.
    compliance: [[f64; 2]; 2],
}

impl<'a> NonlinearSection<'a> {
    /// The section of `laminate` with its PZT replaced along the axis by `ceramic`, at plate fields
    /// `fields` (bottom, top; V/m along each plate's poling).
    pub fn new(laminate: &'a Laminate, ceramic: Ceramic, fields: [f64; 2]) -> Self {
        let layers = laminate.layers();
        let pzt = &layers[laminate.piezo_layer(0)].material;
        let z = laminate.interfaces();
        let mut points = Vec::new();
        for (plate, &field) in fields.iter().enumerate() {
            for k in laminate.piezo_plate(plate) {
                let driven = layers[k].role == LayerRole::Piezo;
                let h = (z[k + 1] - z[k]) / THICKNESS_PANELS as f64;
                for p in 0..THICKNESS_PANELS {
                    let mid = z[k] + (p as f64 + 0.5) * h;
                    for (n, w) in GAUSS5 {
                        points.push(Point {
                            z: mid + 0.5 * h * n,
                            weight: 0.5 * h * w,
                            field: if driven { field } else { 0.0 },
                        });
                    }
                }
            }
        }
        let c = laminate.compliance();
        NonlinearSection {
            laminate,
            ceramic,
            reference: (pzt.e1, pzt.e1 * pzt.d31.abs()),
            sign: -pzt.d31.signum(),
            fields,
            points,
            free: laminate.free_response(&fields),
            compliance: [[c[(0, 0)], c[(0, 3)]], [c[(3, 0)], c[(3, 3)]]],
        }
    }

    /// `Δσ` and `∂Δσ/∂ε` at strain `ε` and field `ξ` (module docs; docs/physics.md eq. 18.4), Pa.
    fn excess_stress(&self, strain: f64, field: f64) -> (f64, f64) {
        let (modulus, coefficient) = self.reference;
        let (elastic, tangent) = self.ceramic.elastic_stress(strain);
        let (internal, slope) = self.ceramic.internal_stress(field, strain);
        (
            elastic - modulus * strain + self.sign * (internal - coefficient * field),
            tangent - modulus + self.sign * slope,
        )
    }

    /// The correction resultants `[ΔN, ΔM] = ∫ Δσ [1, z] dz` over the PZT layers and their Jacobian in
    /// `[ε0, κ]` (docs/physics.md eq. 18.5).
    fn correction(&self, strain: f64, curvature: f64) -> ([f64; 2], [[f64; 2]; 2]) {
        let (mut r, mut j) = ([0.0; 2], [[0.0; 2]; 2]);
        for p in &self.points {
            let (s, t) = self.excess_stress(strain + p.z * curvature, p.field);
            r[0] += p.weight * s;
            r[1] += p.weight * p.z * s;
            j[0][0] += p.weight * t;
            j[0][1] += p.weight * p.z * t;
            j[1][1] += p.weight * p.z * p.z * t;
        }
        j[1][0] = j[0][1];
        (r, j)
    }

    /// Solve the station under an external moment per unit width `m` (N·m/m, positive bending the
    /// beam toward positive curvature) and no axial force: `u = u_free + C ([0, m] - ΔR(u))` by Newton's
    /// method from `start` (docs/physics.md eq. 18.6).
    fn solve(&self, moment: f64, start: Option<State>) -> Result<State, ModelError> {
        let c = self.compliance;
        let mut u = start.map_or(
            [
                self.free[0] + c[0][1] * moment,
                self.free[3] + c[1][1] * moment,
            ],
            |s| [s.strain, s.curvature],
        );
        let scale = 0.5 * self.laminate.thickness();
        for _ in 0..NEWTON_STEPS {
            let (r, j) = self.correction(u[0], u[1]);
            let load = [-r[0], moment - r[1]];
            let g = [
                u[0] - self.free[0] - (c[0][0] * load[0] + c[0][1] * load[1]),
                u[1] - self.free[3] - (c[1][0] * load[0] + c[1][1] * load[1]),
            ];
            // ∂g/∂u = I + C J.
            let a = tangent(&c, &j);
            let det = a[0][0] * a[1][1] - a[0][1] * a[1][0];
            let step = [
                (a[1][1] * g[0] - a[0][1] * g[1]) / det,
                (a[0][0] * g[1] - a[1][0] * g[0]) / det,
            ];
            if !(step[0].is_finite() && step[1].is_finite()) {
                break;
            }
            u = [u[0] - step[0], u[1] - step[1]];
            if step[0].abs() + scale * step[1].abs() <= 1e-15 {
                let (correction, j) = self.correction(u[0], u[1]);
                // ∂u/∂m = (I + C J)⁻¹ C [0, 1]ᵀ.
                let a = tangent(&c, &j);
                let det = a[0][0] * a[1][1] - a[0][1] * a[1][0];
                return Ok(State {
                    strain: u[0],
                    curvature: u[1],
                    correction,
                    slope: (a[0][0] * c[1][1] - a[1][0] * c[0][1]) / det,
                });
            }
        }
        Err(ModelError::NotCovered {
            name: "nonlinear ceramic",
            value: "section",
            allowed: "the section's strain did not converge at this field and load",
        })
    }

    /// Peak |σ_x| and |ε_x| on the PZT layers' surfaces of a solved station under moment `m`.
    fn surface_peak(&self, state: &State, moment: f64) -> (f64, f64) {
        let lam = self.laminate;
        let c = lam.compliance();
        let r = self.free
            + c.column(0) * (-state.correction[0])
            + c.column(3) * (moment - state.correction[1]);
        let z = lam.interfaces();
        let (mut stress, mut strain) = (0.0f64, 0.0f64);
        for (plate, &field) in self.fields.iter().enumerate() {
            for k in lam.piezo_plate(plate) {
                let driven = lam.layers()[k].role == LayerRole::Piezo;
                let xi = if driven { field } else { 0.0 };
                for zz in [z[k], z[k + 1]] {
                    let eps = state.strain + zz * state.curvature;
                    let sigma =
                        lam.stress_at(k, zz, &r, &self.fields)[0] + self.excess_stress(eps, xi).0;
                    stress = stress.max(sigma.abs());
                    strain = strain.max(eps.abs());
                }
            }
        }
        (stress, strain)
    }
}

/// `I + C J`, the Jacobian of the station's equations in `[ε0, κ]`.
fn tangent(c: &[[f64; 2]; 2], j: &[[f64; 2]; 2]) -> [[f64; 2]; 2] {
    [
        [
            1.0 + c[0][0] * j[0][0] + c[0][1] * j[1][0],
            c[0][0] * j[0][1] + c[0][1] * j[1][1],
        ],
        [
            c[1][0] * j[0][0] + c[1][1] * j[1][0],
            1.0 + c[1][0] * j[0][1] + c[1][1] * j[1][1],
        ],
    ]
}

/// A tapered beam of the nonlinear section (docs/physics.md §18.2).
#[derive(Debug, Clone)]
pub struct NonlinearBeam<'a> {
    section: NonlinearSection<'a>,
    planform: Planform,
    /// Stations along the active length and their quadrature weights, m.
    stations: Vec<(f64, f64)>,
}

impl<'a> NonlinearBeam<'a> {
    /// The beam of `planform` over `section`.
    pub fn new(section: NonlinearSection<'a>, planform: Planform) -> Self {
        let stations = stations(&planform);
        NonlinearBeam {
            section,
            planform,
            stations,
        }
    }

    /// Tip deflection under a tip load `F` (N, positive toward positive deflection), m:
    /// `δ = ∫0..l_p κ(x) (L - x) dx` with each station solved under `M(x)/w(x) = F (L - x)/w(x)`
    /// (docs/physics.md eq. 18.7). With `peak`, the surfaces' peak stress and strain at both ends of the
    /// active length are folded into it: `M(x)/w(x)` is monotone along a taper (eq. 6.3), so the peak of
    /// a station's state lies at an end, as `plate::peak` takes it.
    pub fn deflection(&self, force: f64, peak: Option<&mut PlatePeak>) -> Result<f64, ModelError> {
        Ok(self.integrate(force, peak)?.0)
    }

    /// [`NonlinearBeam::deflection`] and its tangent compliance
    /// `dδ/dF = ∫ (∂κ/∂m) (L - x)² / w(x) dx`, m/N.
    fn integrate(
        &self,
        force: f64,
        peak: Option<&mut PlatePeak>,
    ) -> Result<(f64, f64), ModelError> {
        let pl = &self.planform;
        let l = pl.length;
        let moment = |x: f64| crate::plate::moment_per_width(pl, force, x);
        let (mut delta, mut compliance) = (0.0, 0.0);
        if force == 0.0 {
            // No load: every station is in the same state, `δ = κ (L l_p - l_p²/2)`, and (18.7)'s
            // compliance is the linear beam's with the one tangent `∂κ/∂m` as its `C44`.
            let l_p = pl.piezo_length();
            let s = self.section.solve(0.0, None)?;
            delta = s.curvature * (l * l_p - 0.5 * l_p * l_p);
            compliance = beam_tip_compliance(s.slope, pl);
        } else {
            let mut state = None;
            for &(x, w) in &self.stations {
                let s = self.section.solve(moment(x), state)?;
                delta += w * s.curvature * (l - x);
                compliance += w * s.slope * (l - x) * (l - x) / pl.width_at(x);
                state = Some(s);
            }
        }
        if let Some(peak) = peak {
            let l_p = pl.piezo_length();
            for x in [0.0, l_p] {
                let m = moment(x);
                let s = self.section.solve(m, None)?;
                let (stress, strain) = self.section.surface_peak(&s, m);
                let at = x / l_p;
                *peak = peak.max(PlatePeak {
                    stress,
                    stress_at: at,
                    strain,
                    strain_at: at,
                });
            }
        }
        Ok((delta, compliance))
    }

    /// The tip load that holds the tip at `target` (m), N: the root of `δ(F) = target`.
    pub fn force_at(&self, target: f64) -> Result<f64, ModelError> {
        // Newton's method on the tangent compliance, which the section's own Jacobian gives.
        let mut f = 0.0;
        for _ in 0..NEWTON_STEPS {
            let (d, slope) = self.integrate(f, None)?;
            let step = (d - target) / slope;
            if !step.is_finite() {
                break;
            }
            f -= step;
            if step.abs() <= 1e-13 * f.abs() {
                return Ok(f);
            }
        }
        self.bracketed_force_at(target)
    }

    /// [`NonlinearBeam::force_at`] by bracketing, where Newton's method does not settle: bracketed
    /// from the linear laminate's compliance and closed by the Illinois method.
    fn bracketed_force_at(&self, target: f64) -> Result<f64, ModelError> {
        let g = |f: f64| self.deflection(f, None).map(|d| d - target);
        let (mut a, mut ga) = (0.0, g(0.0)?);
        if ga == 0.0 {
            return Ok(0.0);
        }
        let compliance = beam_tip_compliance(self.section.compliance[1][1], &self.planform);
        let mut step = -ga / compliance;
        let (mut b, mut gb) = (step, g(step)?);
        let mut tries = 0;
        while ga.signum() == gb.signum() {
            tries += 1;
            if tries > 40 {
                return Err(not_bracketed());
            }
            step *= 2.0;
            (a, ga) = (b, gb);
            b = step;
            gb = g(b)?;
        }
        let mut side = 0;
        for _ in 0..ROOT_STEPS {
            let c = (a * gb - b * ga) / (gb - ga);
            let gc = g(c)?;
            if gc == 0.0 || (b - a).abs() <= 1e-14 * c.abs() {
                return Ok(c);
            }
            if gc.signum() == gb.signum() {
                (b, gb) = (c, gc);
                if side == -1 {
                    ga *= 0.5;
                }
                side = -1;
            } else {
                (a, ga) = (c, gc);
                if side == 1 {
                    gb *= 0.5;
                }
                side = 1;
            }
        }
        Ok((a * gb - b * ga) / (gb - ga))
    }
}

fn not_bracketed() -> ModelError {
    ModelError::NotCovered {
        name: "nonlinear ceramic",
        value: "blocked force",
        allowed: "a tip load that holds the tip at rest was not found",
    }
}

/// Quadrature stations along the active length: Gauss-Legendre panels whose ends are spaced evenly in
/// `ln w(x)` (uniformly for a rectangle), so that `1/w(x)` is smooth on each.
fn stations(planform: &Planform) -> Vec<(f64, f64)> {
    let l_p = planform.piezo_length();
    let (w0, wt) = (planform.base_width, planform.tip_width());
    let ratio = (wt / w0).ln().abs();
    let n = LENGTH_PANELS.max((ratio / WIDTH_STEP.ln()).ceil() as usize);
    let edge = |k: usize| {
        let t = k as f64 / n as f64;
        if ratio < 1e-9 {
            t * l_p
        } else {
            (w0 * (wt / w0).powf(t) - w0) / (wt - w0) * l_p
        }
    };
    let mut out = Vec::with_capacity(5 * n);
    for k in 0..n {
        let (x0, x1) = (edge(k), edge(k + 1));
        let h = x1 - x0;
        for (node, w) in GAUSS5 {
            out.push((x0 + 0.5 * h * (1.0 + node), 0.5 * h * w));
        }
    }
    out
}

/// True when the stack is its own mirror image about the midplane (the same layers in reverse
/// order), so that its coupling matrix B vanishes and swapping the plates' fields mirrors the response.
fn symmetric(laminate: &Laminate) -> bool {
    let layers = laminate.layers();
    layers.iter().zip(layers.iter().rev()).all(|(a, b)| a == b)
}

/// One half-cycle of a drive: the plates' fields at a phase of the signal.
fn half_cycle<'a>(
    laminate: &'a Laminate,
    ceramic: Ceramic,
    planform: &Planform,
    drive: &Drive,
    phase: f64,
) -> NonlinearBeam<'a> {
    let fields = plate_fields_at(drive, phase);
    NonlinearBeam::new(NonlinearSection::new(laminate, ceramic, fields), *planform)
}

/// The actuator under the nonlinear ceramic at a drive, one-sided amplitudes about the rest position
/// (the unloaded tip at the signal's zero, phase 0): `δ = |δ(π/2) - δ(-π/2)| / 2` and
/// `F_b = |F(π/2) - F(-π/2)| / 2` with `F(θ)` the tip load that holds the tip at rest at phase θ
/// (docs/physics.md eq. 18.8).
#[derive(Debug, Clone)]
pub struct Response {
    /// One-sided free deflection, m.
    pub free_deflection: f64,
    /// One-sided blocked force, N.
    pub blocked_force: f64,
    /// Peak |σ_x| and |ε_x| on the PZT surfaces, free and blocked, both half-cycles.
    pub peak: PlatePeak,
}

/// Solve the actuator of `laminate` and `planform` at `drive` under `ceramic` (docs/physics.md §18).
pub fn response(
    laminate: &Laminate,
    planform: &Planform,
    drive: &Drive,
    ceramic: Ceramic,
) -> Result<Response, ModelError> {
    let rest = half_cycle(laminate, ceramic, planform, drive, 0.0).deflection(0.0, None)?;
    let mut peak = PlatePeak::default();
    let mut ends = [(0.0, 0.0); 2];
    // The two half-cycles swap the plates' fields (`plate_fields_at`); on a stack symmetric about its
    // midplane the second is the first mirrored.
    let phases: &[f64] = if symmetric(laminate) {
        &[FRAC_PI_2]
    } else {
        &[FRAC_PI_2, -FRAC_PI_2]
    };
    for (i, &phase) in phases.iter().enumerate() {
        let beam = half_cycle(laminate, ceramic, planform, drive, phase);
        let free = beam.deflection(0.0, Some(&mut peak))?;
        let force = beam.force_at(rest)?;
        beam.deflection(force, Some(&mut peak))?;
        ends[i] = (free, force);
    }
    if phases.len() == 1 {
        ends[1] = (2.0 * rest - ends[0].0, -ends[0].1);
    }
    Ok(Response {
        free_deflection: 0.5 * (ends[0].0 - ends[1].0).abs(),
        blocked_force: 0.5 * (ends[0].1 - ends[1].1).abs(),
        peak,
    })
}

/// The force-deflection curve of the first half-cycle (the signal's peak, phase π/2): `n + 1` points
/// `(F, δ)` from free (`F = 0`) to blocked (`δ = 0`), each `δ` from the rest position and `F` the
/// magnitude of the tip load holding the tip back, N and m (docs/physics.md §18.3).
pub fn force_deflection(
    laminate: &Laminate,
    planform: &Planform,
    drive: &Drive,
    ceramic: Ceramic,
    n: usize,
) -> Result<Vec<(f64, f64)>, ModelError> {
    let rest = half_cycle(laminate, ceramic, planform, drive, 0.0).deflection(0.0, None)?;
    let beam = half_cycle(laminate, ceramic, planform, drive, FRAC_PI_2);
    let blocked = beam.force_at(rest)?;
    let sign = -blocked.signum();
    (0..=n)
        .map(|i| {
            let f = blocked * i as f64 / n.max(1) as f64;
            Ok((f.abs(), sign * (beam.deflection(f, None)? - rest)))
        })
        .collect()
}

/// The prediction of the nonlinear model: the original's mass and capacitance, the nonlinear
/// free deflection, blocked force, stiffness `F_b/δ`, peak stress and strain (docs/physics.md §18).
pub fn predict(
    laminate: &Laminate,
    planform: &Planform,
    drive: Drive,
    ceramic: Ceramic,
) -> Result<Performance, ModelError> {
    let section = Section::new(laminate, drive)?;
    let original = evaluate(&section, planform);
    let r = response(laminate, planform, &drive, ceramic)?;
    let p = Performance {
        peak_pzt_strain: r.peak.strain,
        peak_pzt_strain_at: r.peak.strain_at,
        peak_pzt_stress: r.peak.stress,
        peak_pzt_stress_at: r.peak.stress_at,
        base_stress: base_stress(r.blocked_force, planform, section.thickness),
        ..original
    };
    Ok(p.with_outputs(r.free_deflection, r.blocked_force, original.mass_breakdown))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::drive::DriveMode;
    use crate::material::Material;

    fn laminate(t_p: f64, layup: &[f64], bond: bool) -> Laminate {
        let pzt = Material::builtin("PZT-5H").unwrap();
        let cf = Material::builtin("CF-thesis").unwrap();
        let pyralux = Material::builtin("Pyralux-LF").unwrap();
        let bond = bond.then_some((&pyralux, 25e-6));
        Laminate::bimorph(&pzt, t_p, &cf, 61.8e-6, layup, bond).unwrap()
    }

    /// The laminate PZT as a linear ceramic: PZT-5H's E = 62 GPa and E |d31| = 19.84 Pa·m/V.
    fn linear() -> Ceramic {
        Ceramic::linear(62e9, 62e9 * 320e-12)
    }

    fn drives() -> Vec<Drive> {
        let mut d: Vec<Drive> = DriveMode::ALL
            .into_iter()
            .map(|m| Drive::new(m, 700e3))
            .collect();
        d.push(Drive {
            mode: DriveMode::Biased,
            field: 500e3,
            bias: 1500e3,
        });
        d
    }

    #[test]
    fn a_linear_ceramic_reduces_to_the_original_model_exactly() {
        // Closed form: with one modulus and a field-independent coefficient equal to the laminate's own,
        // Δσ = 0 and the integral of the curvature is thesis eqs. 2.26 and 2.35 (docs/physics.md §18.4).
        let shapes = [
            Planform::new(42.2e-3, 0.833, 5e-3, 1.667, 0.0).unwrap(),
            Planform::new(50e-3, 0.0, 10e-3, 1.0, 0.0).unwrap(),
            Planform::new(40e-3, 1.2, 7.3e-3, 1.93, 0.0).unwrap(),
            Planform::new(30e-3, 0.5, 6e-3, 0.6, 0.0).unwrap(),
        ];
        for (lam, layup) in [
            (laminate(267e-6, &[0.0, 90.0, 0.0], false), "B/C"),
            (
                laminate(127e-6, &[0.0, 0.0, 90.0, 0.0, 0.0], true),
                "bonded",
            ),
        ] {
            for drive in drives() {
                for pl in &shapes {
                    let want = evaluate(&Section::new(&lam, drive).unwrap(), pl);
                    let got = predict(&lam, pl, drive, linear()).unwrap();
                    for (g, w, what) in [
                        (got.free_deflection, want.free_deflection, "δ"),
                        (got.blocked_force, want.blocked_force, "F_b"),
                        (got.energy, want.energy, "U"),
                        (got.stiffness, want.stiffness, "k"),
                    ] {
                        assert!(
                            (g / w - 1.0).abs() < 1e-9,
                            "{layup} {drive:?} {pl:?} {what}: {g} {w}"
                        );
                    }
                    if drive.mode == DriveMode::Parallel {
                        // Parallel drive's fields are the original's [E, -E]: the peaks match too.
                        assert!((got.peak_pzt_strain / want.peak_pzt_strain - 1.0).abs() < 1e-9);
                        assert!((got.peak_pzt_stress / want.peak_pzt_stress - 1.0).abs() < 1e-9);
                    }
                }
            }
        }
    }

    #[test]
    fn on_a_mirror_image_stack_the_trough_is_the_peak_mirrored() {
        // docs/physics.md §18.4: the half-cycles swap the plates' fields, so on a stack that is its own
        // mirror image the trough (phase -π/2) is the peak (π/2) mirrored about the rest position,
        // `δ(-π/2) = 2 δ_rest - δ(π/2)` and `F(-π/2) = -F(π/2)`, and `response` need not solve it. Both
        // solved here under the nonlinear ceramic, in every drive mode.
        let j = Ceramic::JAFFERIS_2015;
        let pl = Planform::new(42.2e-3, 0.833, 5e-3, 1.667, 0.0).unwrap();
        let ends = |lam: &Laminate, drive: &Drive| {
            let rest = half_cycle(lam, j, &pl, drive, 0.0)
                .deflection(0.0, None)
                .unwrap();
            let end = |phase: f64| {
                let beam = half_cycle(lam, j, &pl, drive, phase);
                let free = beam.deflection(0.0, None).unwrap();
                (free, beam.force_at(rest).unwrap())
            };
            (rest, end(FRAC_PI_2), end(-FRAC_PI_2))
        };
        let mirror = laminate(267e-6, &[0.0, 90.0, 0.0], false);
        assert!(symmetric(&mirror));
        for drive in drives() {
            let [bottom, top] = plate_fields_at(&drive, FRAC_PI_2);
            assert_eq!(plate_fields_at(&drive, -FRAC_PI_2), [top, bottom]);
            let (rest, peak, trough) = ends(&mirror, &drive);
            let what = format!("{drive:?}");
            assert!(
                (trough.0 - (2.0 * rest - peak.0)).abs() < 1e-9 * peak.0.abs(),
                "{what}"
            );
            assert!((trough.1 + peak.1).abs() < 1e-9 * peak.1.abs(), "{what}");
            // `response` reports (18.8) of these ends.
            let r = response(&mirror, &pl, &drive, j).unwrap();
            let delta = 0.5 * (peak.0 - trough.0).abs();
            let force = 0.5 * (peak.1 - trough.1).abs();
            assert!((r.free_deflection / delta - 1.0).abs() < 1e-9, "{what}");
            assert!((r.blocked_force / force - 1.0).abs() < 1e-9, "{what}");
        }
        // Not so on a stack that is not its own mirror image: the shortcut would be wrong there.
        let lopsided = laminate(267e-6, &[0.0, 0.0, 90.0], false);
        assert!(!symmetric(&lopsided));
        let drive = Drive::new(DriveMode::Parallel, 700e3);
        let (rest, peak, trough) = ends(&lopsided, &drive);
        assert!((trough.0 - (2.0 * rest - peak.0)).abs() > 1e-3 * peak.0.abs());
    }

    #[test]
    fn the_response_scales_as_the_original_with_length_and_width() {
        // docs/physics.md §18.2: under F (L - x)/w(x) the station's state depends on F L / w_0 and the
        // shape alone, so δ ∝ l_tot² and F_b ∝ w_0 / l_tot at a fixed (l_r, w_r), as in the original.
        let lam = laminate(267e-6, &[0.0, 90.0, 0.0], false);
        let drive = Drive::new(DriveMode::Parallel, 800e3);
        let j = Ceramic::JAFFERIS_2015;
        let base = predict(
            &lam,
            &Planform::new(40e-3, 0.8, 5e-3, 1.6, 0.0).unwrap(),
            drive,
            j,
        )
        .unwrap();
        let big = predict(
            &lam,
            &Planform::new(60e-3, 0.8, 9e-3, 1.6, 0.0).unwrap(),
            drive,
            j,
        )
        .unwrap();
        assert!((big.free_deflection / base.free_deflection - 2.25).abs() < 1e-9);
        assert!((big.blocked_force / base.blocked_force - 9.0 / 5.0 / 1.5).abs() < 1e-8);
    }

    #[test]
    fn the_force_deflection_curve_runs_from_free_to_blocked_and_is_not_straight() {
        // The curve's ends are the response's δ and F_b; the bimodular modulus stiffens the section as
        // the blocking load puts the driven plate in compression, so the curve bends (docs/physics.md
        // §18.3). With the linear ceramic the midpoint is on the straight line to rounding.
        let lam = laminate(267e-6, &[0.0, 90.0, 0.0], false);
        let pl = Planform::new(42.2e-3, 0.833, 5e-3, 1.667, 0.0).unwrap();
        let drive = Drive::new(DriveMode::Parallel, 800e3);
        for (ceramic, bent) in [(Ceramic::JAFFERIS_2015, true), (linear(), false)] {
            let r = response(&lam, &pl, &drive, ceramic).unwrap();
            let c = force_deflection(&lam, &pl, &drive, ceramic, 4).unwrap();
            assert!((c[0].1 / r.free_deflection - 1.0).abs() < 1e-9);
            assert!((c[4].0 / r.blocked_force - 1.0).abs() < 1e-9);
            assert!(c[4].1.abs() < 1e-12 * r.free_deflection);
            let straight = 0.5 * r.free_deflection;
            let off = (c[2].1 - straight).abs() / r.free_deflection;
            assert_eq!(off > 1e-3, bent, "{off}");
            assert!(c.windows(2).all(|w| w[1].1 < w[0].1), "monotone");
        }
    }

    #[test]
    fn the_nonlinear_ceramic_moves_the_thesis_design_c_as_its_constants_say() {
        // Jafferis et al. 2015: at 800 V/mm the coefficient is near f_max (1 - d ξ) ≈ 27.4 Pa·m/V against
        // the linear 19.84, and the PZT in tension is 38.5 GPa against 62: the free deflection grows by
        // more than the coefficient's ratio, the stiffness falls.
        let lam = laminate(267e-6, &[0.0, 90.0, 0.0], false);
        let pl = Planform::new(42.2e-3, 0.833, 5e-3, 1.667, 0.0).unwrap();
        let drive = Drive::new(DriveMode::Parallel, 800e3);
        let orig = evaluate(&Section::new(&lam, drive).unwrap(), &pl);
        let nl = predict(&lam, &pl, drive, Ceramic::JAFFERIS_2015).unwrap();
        let ratio = Ceramic::JAFFERIS_2015.stress_coefficient(800e3) / 19.84;
        assert!(nl.free_deflection / orig.free_deflection > ratio, "{nl:?}");
        assert!(nl.stiffness < orig.stiffness);
        assert!(nl.mass == orig.mass);
    }
}
