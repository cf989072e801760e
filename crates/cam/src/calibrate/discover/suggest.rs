//! The loop's next step (docs/calibration.md §3, "Discovery"): the leading candidates of a discovery as
//! effects a lab can declare, with their parameter names, null values and physical bounds, ready for
//! `calibrate --effects suggested-effects.toml`. Only primitives outside the library are suggested (the
//! library's effects are fitted on every run); a combination `A + P` is suggested as P, since the
//! selection fits every declared effect beside each library effect.
//!
//! The leading candidate of the deflection and force ranking is declared, and the leading mass form
//! when it gains the selection's margin over the mass model the selection chose with an interval that
//! excludes its null (a mass the masses show), unless the leading candidate was fitted on the masses
//! too and fits them as well; the runners-up are listed for the reader.

use super::catalogue;
use super::Discovery;
use actuator_model::primitives::Primitive;

/// How many candidates of each ranking are listed.
pub const LISTED: usize = 3;

/// One candidate written to the file.
#[derive(Debug, Clone, PartialEq)]
pub struct Suggestion {
    /// Its rank in its own table (1 = leading).
    pub rank: usize,
    /// Which ranking: `deflection and force`, `mass` or `resonance`.
    pub residual: &'static str,
    /// The effect name (the primitive's report name).
    pub name: String,
    /// The library effect it was fitted beside, in a combination.
    pub partner: Option<String>,
    /// The primitive.
    pub primitive: Primitive,
    /// The parameter's name with its unit (SI).
    pub parameter: &'static str,
    /// Null value.
    pub null: f64,
    /// Physical bounds (SI).
    pub bounds: (f64, f64),
    /// The estimate and its 95 % interval from discovery.
    pub estimate: f64,
    /// 95 % interval.
    pub interval: (f64, f64),
    /// AICc gain over the reference of its ranking ({η} for deflection and force, the chosen mass
    /// model for the mass).
    pub gain: f64,
    /// Declared (true) or listed for the reader.
    pub declared: bool,
}

/// The suggestions of a discovery, the residual the verdict names first.
pub fn suggestions(d: &Discovery, mass_first: bool, min_delta_aicc: f64) -> Vec<Suggestion> {
    let mut actuation = Vec::new();
    for c in &d.candidates {
        let Some(p) = c.primitive() else { continue };
        if actuation.iter().any(|s: &Suggestion| s.primitive == p) {
            continue;
        }
        let Some(bounds) = catalogue::bounds(p) else {
            continue;
        };
        actuation.push(Suggestion {
            rank: actuation.len() + 1,
            residual: "deflection and force",
            name: catalogue::name(p),
            partner: c.partner().map(String::from),
            primitive: p,
            parameter: catalogue::parameter(p),
            null: p.null(),
            bounds,
            estimate: c.estimate,
            interval: c.interval,
            gain: c.gain_over_eta,
            declared: false,
        });
        if actuation.len() == LISTED {
            break;
        }
    }
    // A leader fitted on the masses too that fits them as well as the best mass form explains them: a
    // mass form declared beside it would say the same mass twice.
    let leader_explains_masses = d
        .candidates
        .iter()
        .find(|c| c.primitive().is_some())
        .is_some_and(|c| c.explains_masses);
    let mut mass = Vec::new();
    for f in &d.mass_forms {
        let Some(t) = f.primitive else { continue };
        if mass.iter().any(|s: &Suggestion| s.primitive == t.primitive) {
            continue;
        }
        mass.push(Suggestion {
            rank: mass.len() + 1,
            residual: "mass",
            name: catalogue::name(t.primitive),
            partner: None,
            primitive: t.primitive,
            parameter: catalogue::parameter(t.primitive),
            null: t.primitive.null(),
            bounds: (t.lo, t.hi),
            estimate: f.estimate,
            interval: f.interval,
            gain: f.gain_over_chosen,
            declared: mass.is_empty()
                && !leader_explains_masses
                && f.gain_over_chosen > min_delta_aicc
                && f.excludes_null(),
        });
        if mass.len() == LISTED {
            break;
        }
    }
    let mass_declared = mass.first().is_some_and(|s| s.declared);
    let resonance = resonance_suggestions(d, min_delta_aicc);
    let resonance_declared = resonance.iter().any(|s| s.declared);
    // The deflection and force leader is declared unless the mass or the resonance explains the
    // verdict alone: a mass residual named first and a mass form declared, or a resonance form
    // declared, and no real gain on δ and F_b.
    if let Some(first) = actuation.first_mut() {
        first.declared =
            !(mass_first && mass_declared || resonance_declared) || first.gain > min_delta_aicc;
    }
    let mut all = resonance;
    if mass_first {
        all.extend(mass);
        all.extend(actuation);
    } else {
        all.extend(actuation);
        all.extend(mass);
    }
    all
}

/// The forms only the resonance separates (`resonance_forms.rs`), in their order: the leading one
/// declared when the deflections and forces allow it, it gains the selection's margin on the resonance
/// residuals and its interval excludes its null.
fn resonance_suggestions(d: &Discovery, min_delta_aicc: f64) -> Vec<Suggestion> {
    let lead = d
        .resonance_forms
        .iter()
        .position(|f| f.allowed && f.gain > min_delta_aicc && f.interval.0 > 0.0);
    d.resonance_forms
        .iter()
        .enumerate()
        .map(|(k, f)| Suggestion {
            rank: k + 1,
            residual: "resonance",
            name: f.name.to_string(),
            partner: None,
            primitive: f.primitive,
            parameter: f.parameter,
            null: f.primitive.null(),
            bounds: f.bounds,
            estimate: f.estimate,
            interval: f.interval,
            gain: f.gain,
            declared: lead == Some(k),
        })
        .collect()
}
