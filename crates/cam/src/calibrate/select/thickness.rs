//! Thickness forms (docs/calibration.md §3, "Thickness forms"): when the PZT thickness varies in the data,
//! a uniform d31 scale can pass the adequacy test on data whose loss is thickness-dependent (a
//! piezoelectrically dead surface layer costs a thin plate more than a thick one; a plate poled less
//! through its thickness costs a thick one more), and then names the wrong physics, which extrapolates
//! wrongly to other thicknesses. So the model the selection chose is compared with itself plus each
//! thickness form, `{η, …, X}`, and with `{η, X}`, X an inactive surface layer of the PZT (`t_s`) or a d31
//! that follows a power of the plate thickness (`a`), fitted by the selection's own fitter as declared
//! effects (compositions of the model crate's `inactive-surface-layer` and `d31-thickness-power`
//! primitives); a thickness form replaces the chosen model only when its AICc is lower by
//! [`DECISIVE_GAIN`], its cross-validated error is lower and the interval of each of its own effects
//! excludes the null value.

use super::candidate::Candidate;
use crate::calibrate::csv::Dataset;
use crate::calibrate::library::{Declared, DeclaredParameter, DeclaredSpec, EffectId};
use actuator_model::primitives::{Link, Map, Primitive};

/// The ΔAICc by which a thickness form must beat the chosen model. The uniform scale is the thickness
/// form at `t_s = 0` (one parameter fewer), so a gain of 10 is a likelihood-ratio statistic of about 12
/// on one degree of freedom: data whose loss does not depend on the thickness give it with probability
/// about 5e-4, and Burnham and Anderson's ΔAICc > 10 leaves the other model "essentially no support".
pub const DECISIVE_GAIN: f64 = 10.0;

/// The dead-layer form's name in the reports and calibrated-model.toml (the primitive's).
pub const NAME: &str = "inactive-surface-layer";

/// The power form's name (the primitive's).
pub const POWER_NAME: &str = "d31-thickness-power";

/// ΔAICc by which the power form must beat the dead layer to be named instead of it. Over plates of a few
/// thicknesses the two forms nearly coincide for a thin dead layer (a 15 µm layer on 127-267 µm plates
/// departs from the best power law by under 1 % of δ), so where the data cannot tell them apart (the
/// selection's rivals within 2) the mechanism with one physical thickness is named; a loss that grows
/// with the plate thickness, which no dead layer gives, is the power form's alone.
pub const POWER_OVER_LAYER: f64 = 2.0;

/// Smallest relative spread of the PZT thickness (max / min - 1) that counts as varying.
const MIN_SPREAD: f64 = 0.01;

/// The thickness forms, when the PZT thickness varies among the actuators with deflection or force
/// data, each unless a declared effect already drives its primitive: the inactive surface layer, its
/// thickness in µm from 0 to the smaller of 100 µm and half the thinnest plate; and the d31 power of
/// the plate thickness, its exponent from -1 to 1 (over the 127-267 µm plates, a d31 changed by up to
/// their ratio of 2.1).
pub(super) fn forms(data: &Dataset, declared: &[Declared]) -> Vec<EffectId> {
    let (lo, hi) = data
        .rows
        .iter()
        .filter(|r| r.voltage > 0.0 && (r.free_deflection.is_some() || r.blocked_force.is_some()))
        .map(|r| r.pzt_thickness)
        .fold((f64::INFINITY, 0.0_f64), |(a, b), t| (a.min(t), b.max(t)));
    if !(lo > 0.0 && hi > lo * (1.0 + MIN_SPREAD)) {
        return Vec::new();
    }
    let already = |primitive| {
        declared.iter().any(|d| {
            d.spec()
                .parameters
                .iter()
                .any(|p| p.primitives.iter().any(|l| l.primitive == primitive))
        })
    };
    let form = |name: &str, parameter: &str, map, (lo, hi), primitive| DeclaredSpec {
        name: name.into(),
        parameters: vec![DeclaredParameter {
            name: parameter.into(),
            null: 0.0,
            lo,
            hi,
            primitives: vec![Link { primitive, map }],
        }],
    };
    [
        form(
            NAME,
            // In µm at the edge, as the reports print it (the primitive takes metres).
            "inactive_thickness_um",
            Map::Micro,
            (0.0, (0.5 * lo).min(100e-6) * 1e6),
            Primitive::InactiveSurfaceLayer,
        ),
        form(
            POWER_NAME,
            "d31_thickness_exponent",
            Map::Identity,
            (-1.0, 1.0),
            Primitive::D31ThicknessPower,
        ),
    ]
    .into_iter()
    .filter(|spec| !already(spec.parameters[0].primitives[0].primitive))
    .filter_map(|spec| {
        Declared::all(spec)
            .into_iter()
            .next()
            .map(EffectId::Declared)
    })
    .collect()
}

/// Whether `id` is the thickness form the selection added (a declared effect the lab did not declare).
pub fn is_form(id: &EffectId, declared: &[Declared]) -> bool {
    matches!(id, EffectId::Declared(d)
        if !declared.contains(d) && [NAME, POWER_NAME].contains(&d.spec().name.as_str()))
}

/// Whether the candidate carries the power form.
fn has_power(c: &Candidate) -> bool {
    c.effects
        .iter()
        .any(|e| matches!(e, EffectId::Declared(d) if d.spec().name == POWER_NAME))
}

/// A thickness form's own effects are identifiable and significant, and its AICc is lower than
/// `chosen`'s by [`DECISIVE_GAIN`] (the tests before the cross-validation).
pub(super) fn qualifies(c: &Candidate, chosen: &Candidate) -> bool {
    c.not_identifiable.is_empty()
        && c.effects
            .iter()
            .enumerate()
            .filter(|(_, e)| **e != EffectId::D31Scale)
            .all(|(k, _)| c.excludes_null(k))
        && c.aicc < chosen.aicc - DECISIVE_GAIN
}

/// The fit of `fits` (thickness forms) that replaces `chosen`, if any: it [`qualifies`] and its
/// cross-validated error is lower; the lowest AICc among those, except that a power form is named over
/// a qualifying dead-layer form only when its AICc is lower by more than [`POWER_OVER_LAYER`].
pub(super) fn preferred(fits: &[Candidate], chosen: &Candidate) -> Option<usize> {
    let ok = |c: &Candidate| qualifies(c, chosen) && c.cv_rmse < chosen.cv_rmse;
    let best = |power: bool| {
        fits.iter()
            .enumerate()
            .filter(|(_, c)| ok(c) && has_power(c) == power)
            .min_by(|a, b| a.1.aicc.total_cmp(&b.1.aicc))
    };
    match (best(false), best(true)) {
        (Some(layer), Some(power)) if power.1.aicc < layer.1.aicc - POWER_OVER_LAYER => {
            Some(power.0)
        }
        (Some(layer), _) => Some(layer.0),
        (None, power) => power.map(|p| p.0),
    }
}
