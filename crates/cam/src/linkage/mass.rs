//! Mass and inertia of a linkage from its drawn areas (docs/physics.md §16.5): each layer's material
//! inside the release outline is a set of spans along the strip at the local width (less the mounting
//! hole where the layer runs under it), times the layer's mass per area.
//!
//! The links split at the pivots: the airframe tab and half of gap O stay put; the crank (O to B) turns
//! with the wing about O; the coupler (B to A) and the tip tab move with the actuator tip. Linearised at
//! rest, the coupler and tab reflect to the wing hinge as `m (dδ/dθ)²` (their turn `ψ` is second order
//! at `θ = 0` and small over the stroke), the crank as its own inertia about O.

use super::pattern::{Pattern, Ply, STACK};
use crate::process::linkage::LinkageProcess;
use std::f64::consts::PI;

/// The laminate's mass and what of it moves, mg and mg·mm².
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinkageMass {
    /// All five layers of one released linkage, mg.
    pub total_mg: f64,
    /// The crank's inertia about the wing hinge O, mg·mm².
    pub crank_inertia_mg_mm2: f64,
    /// Coupler and tip tab (moving with the actuator tip), mg.
    pub tip_side_mg: f64,
    /// Each layer's area inside the release outline, bottom to top, mm².
    pub layer_areas_mm2: [f64; 5],
}

/// Mass per area of a ply, mg/mm².
pub fn areal_density(process: &LinkageProcess, ply: Ply) -> f64 {
    match ply {
        Ply::Carbon => process.carbon.areal_density_mg_per_mm2(),
        Ply::Adhesive => process.adhesive.areal_density_mg_per_mm2(),
        Ply::Film => process.film.areal_density_mg_per_mm2(),
    }
}

/// `∫ w(x) (x - x_o)^n dx` of a ply's material over `[a, b]`, with the hole taken out for `n = 0`
/// when it lies inside (the hole sits in the airframe tab, which does not turn).
fn moment(pattern: &Pattern, ply: Ply, a: f64, b: f64, origin: f64, n: i32) -> f64 {
    let mut xs = pattern.width_steps();
    for (s0, s1) in pattern.material_spans(ply) {
        xs.extend([s0, s1]);
    }
    xs.extend([a, b]);
    xs.retain(|x| *x >= a && *x <= b);
    xs.sort_by(f64::total_cmp);
    xs.dedup();
    let spans = pattern.material_spans(ply);
    let mut sum = 0.0;
    for w in xs.windows(2) {
        let mid = 0.5 * (w[0] + w[1]);
        if !spans.iter().any(|(s0, s1)| *s0 <= mid && mid <= *s1) {
            continue;
        }
        let k = f64::from(n + 1);
        sum +=
            pattern.width_at(mid) * ((w[1] - origin).powi(n + 1) - (w[0] - origin).powi(n + 1)) / k;
    }
    let r = pattern.hole_diameter_mm / 2.0;
    let hole = pattern.hole_centre[0];
    if n == 0 && pattern.hole_in(ply) && a <= hole - r && hole + r <= b {
        sum -= PI * r * r;
    }
    sum
}

/// The mass and inertia of one linkage as drawn.
pub fn linkage_mass(pattern: &Pattern, process: &LinkageProcess) -> LinkageMass {
    let [o, b, _] = pattern.pivots_mm;
    let mut total = 0.0;
    let mut crank_inertia = 0.0;
    let mut tip_side = 0.0;
    let mut areas = [0.0; 5];
    for (k, (ply, _)) in STACK.iter().enumerate() {
        let sigma = areal_density(process, *ply);
        let area = moment(pattern, *ply, 0.0, pattern.length_mm, 0.0, 0);
        areas[k] = area;
        total += sigma * area;
        crank_inertia += sigma * moment(pattern, *ply, o, b, o, 2);
        tip_side += sigma * moment(pattern, *ply, b, pattern.length_mm, 0.0, 0);
    }
    LinkageMass {
        total_mg: total,
        crank_inertia_mg_mm2: crank_inertia,
        tip_side_mg: tip_side,
        layer_areas_mm2: areas,
    }
}
