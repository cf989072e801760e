//! Thickness forms (docs/calibration.md §3, "Thickness forms"): when the PZT thickness varies in the data,
//! a uniform d31 scale can pass the adequacy test on data whose loss is thickness-dependent (a
//! piezoelectrically dead surface layer costs a thin plate more than a thick one), and then names the wrong
//! physics, which extrapolates wrongly to other thicknesses. So the model the selection chose is compared
//! with itself plus an inactive surface layer of the PZT, `{η, …, t_s}`, and with `{η, t_s}`, fitted by
//! the selection's own fitter as a declared effect (the composition of the model crate's
//! `inactive-surface-layer` primitive); the thickness form replaces the chosen model only when its AICc
//! is lower by [`DECISIVE_GAIN`], its cross-validated error is lower and the interval of each of its own
//! effects excludes the null value.

use super::candidate::Candidate;
use crate::calibrate::csv::Dataset;
use crate::calibrate::library::{Declared, DeclaredParameter, DeclaredSpec, EffectId};
use actuator_model::primitives::{Link, Map, Primitive};

/// The ΔAICc by which a thickness form must beat the chosen model. The uniform scale is the thickness
/// form at `t_s = 0` (one parameter fewer), so a gain of 10 is a likelihood-ratio statistic of about 12
/// on one degree of freedom: data whose loss does not depend on the thickness give it with probability
/// about 5e-4, and Burnham and Anderson's ΔAICc > 10 leaves the other model "essentially no support".
pub const DECISIVE_GAIN: f64 = 10.0;

/// The effect's name in the reports and calibrated-model.toml (the primitive's).
pub const NAME: &str = "inactive-surface-layer";

/// Smallest relative spread of the PZT thickness (max / min - 1) that counts as varying.
const MIN_SPREAD: f64 = 0.01;

/// The thickness form, when the PZT thickness varies among the actuators with deflection or force data
/// and no declared effect already drives the inactive surface layer. Its bounds run from 0 to the
/// smaller of 100 µm and half the thinnest plate.
pub(super) fn form(data: &Dataset, declared: &[Declared]) -> Option<EffectId> {
    let (lo, hi) = data
        .rows
        .iter()
        .filter(|r| r.voltage > 0.0 && (r.free_deflection.is_some() || r.blocked_force.is_some()))
        .map(|r| r.pzt_thickness)
        .fold((f64::INFINITY, 0.0_f64), |(a, b), t| (a.min(t), b.max(t)));
    if !(lo > 0.0 && hi > lo * (1.0 + MIN_SPREAD)) {
        return None;
    }
    let already = declared.iter().any(|d| {
        d.spec().parameters.iter().any(|p| {
            p.primitives
                .iter()
                .any(|l| l.primitive == Primitive::InactiveSurfaceLayer)
        })
    });
    if already {
        return None;
    }
    let spec = DeclaredSpec {
        name: NAME.into(),
        parameters: vec![DeclaredParameter {
            name: "inactive_thickness_m".into(),
            null: 0.0,
            lo: 0.0,
            hi: (0.5 * lo).min(100e-6),
            primitives: vec![Link {
                primitive: Primitive::InactiveSurfaceLayer,
                map: Map::Identity,
            }],
        }],
    };
    Declared::all(spec).first().copied().map(EffectId::Declared)
}

/// Whether `id` is the thickness form the selection added (a declared effect the lab did not declare).
pub fn is_form(id: EffectId, declared: &[Declared]) -> bool {
    matches!(id, EffectId::Declared(d) if !declared.contains(&d) && d.spec().name == NAME)
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
/// cross-validated error is lower; the lowest AICc among those.
pub(super) fn preferred(fits: &[Candidate], chosen: &Candidate) -> Option<usize> {
    fits.iter()
        .enumerate()
        .filter(|(_, c)| qualifies(c, chosen) && c.cv_rmse < chosen.cv_rmse)
        .min_by(|a, b| a.1.aicc.total_cmp(&b.1.aicc))
        .map(|(i, _)| i)
}
