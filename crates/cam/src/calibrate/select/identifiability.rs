//! Whether the data can determine an effect's parameter (docs/calibration.md §3, "Intervals and
//! identifiability"): a parameter whose Jacobian column is zero, or lies in the span of a uniform scale
//! and the model's other parameters, changes the predictions only in a way something else explains as
//! well. Its interval would be meaningless (a zero-width one when the fit is exact), so the effect is
//! reported as not identifiable, with the reason, and cannot be selected.

use crate::calibrate::csv::Dataset;
use crate::calibrate::fit::FitResult;
use crate::calibrate::library::EffectId;
use nalgebra::DMatrix;

/// Relative size of the part of a Jacobian column no other column (or a uniform scale) explains below
/// which the parameter is not identified. Forward differences are good to about 1e-7.
const TOLERANCE: f64 = 1e-4;

/// What every actuator of the data set has in common, as a phrase ("one layup, one PZT thickness"), or
/// None when they differ in every respect the effects act through.
pub fn shared_design(data: &Dataset) -> Option<String> {
    let firsts: Vec<_> = data.groups.iter().map(|g| &data.rows[g[0]]).collect();
    let first = firsts.first()?;
    let same = |f: &dyn Fn(&crate::calibrate::csv::Measurement) -> Vec<f64>| {
        firsts.iter().all(|m| {
            f(m).iter()
                .zip(f(first))
                .all(|(a, b)| (a - b).abs() <= 1e-9 * a.abs().max(b.abs()).max(1e-12))
        })
    };
    let planform = same(&|m| {
        let p = &m.planform;
        vec![p.length, p.extension_ratio, p.base_width, p.width_ratio]
    });
    let layup = firsts.iter().all(|m| m.layup == first.layup);
    let thickness = same(&|m| vec![m.pzt_thickness, m.ply_thickness]);
    let mut parts = Vec::new();
    if layup {
        parts.push("one layup");
    }
    if thickness {
        parts.push("one PZT and ply thickness");
    }
    if planform {
        parts.push("one planform");
    }
    (!parts.is_empty()).then(|| parts.join(", "))
}

/// The library effects of a fit the data cannot determine, each with the reason. Every column is tested
/// against a uniform scale too: in the mass stage, which has no scale parameter of its own, a uniform
/// change could as well be a density or thickness off its nominal value.
pub fn not_identifiable(
    effects: &[EffectId],
    fit: &FitResult,
    shared: Option<&str>,
) -> Vec<(EffectId, String)> {
    let j = &fit.jacobian;
    let (n, p) = (j.nrows(), j.ncols());
    let mut out = Vec::new();
    if j.iter().any(|x| !x.is_finite()) {
        return effects
            .iter()
            .map(|id| {
                (
                    id.clone(),
                    format!(
                        "the model cannot be evaluated beside the fit of {} (a parameter at a physical limit)",
                        id.name()
                    ),
                )
            })
            .collect();
    }
    for (k, id) in effects.iter().enumerate() {
        if matches!(id, EffectId::D31Scale | EffectId::StiffnessScale) {
            continue;
        }
        let col = j.column(k);
        let norm = col.norm();
        if norm == 0.0 || !norm.is_finite() {
            out.push((
                id.clone(),
                format!(
                    "{} changes no prediction of this data (nothing it acts on varies or exists)",
                    id.name()
                ),
            ));
            continue;
        }
        // The other columns and a uniform scale.
        let rest_of: Vec<usize> = (0..p).filter(|&m| m != k).collect();
        let others = DMatrix::from_fn(
            n,
            p,
            |i, c| {
                if c == 0 {
                    1.0
                } else {
                    j[(i, rest_of[c - 1])]
                }
            },
        );
        let svd = others.clone().svd(true, true);
        let rest = match svd.solve(&col.clone_owned(), 1e-12) {
            Ok(coef) => (col - &others * coef).norm(),
            Err(_) => norm,
        };
        if rest <= TOLERANCE * norm {
            let why = match shared {
                Some(s) => format!(
                    "all actuators share {s}: {} changes them all by one factor, which a uniform \
                     scale explains as well",
                    id.name()
                ),
                None => format!(
                    "on this data {} acts as a uniform scale or a mix of the model's other effects",
                    id.name()
                ),
            };
            out.push((id.clone(), why));
        } else if fit.rss <= 1e-20 * n as f64 {
            out.push((
                id.clone(),
                format!(
                    "the fit leaves no residual, so the data give no interval for {}",
                    id.name()
                ),
            ));
        }
    }
    out
}
