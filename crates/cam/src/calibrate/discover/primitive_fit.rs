//! Fit one primitive as a one-parameter effect, with the d31 scale η beside it as every library
//! candidate has it: `{η, P}` on the deflections and forces, by the same bounded least squares as the
//! library ([`least_squares`]), scored by the same AICc. With a [`Partner`], a library effect A is fitted
//! beside it, `{η, P, A}`: the residual of data where a library effect and an effect outside the library
//! are both present.
//!
//! Speed: the stack is solved ([`EffectModel::basis`]) once per actuator and value of the primitive, and
//! η, the partner and the primitive's boundary part act on it ([`EffectModel::outputs`], held to
//! [`EffectModel::predict`] by the model crate's tests); η scales δ and F_b by itself, and δ
//! and F_b are proportional to the field at a field-independent d31 (CLT curvature is linear in the
//! piezoelectric strain `d31 E`), so the other voltages of an actuator follow by ratio (a unit test
//! holds this to the model).

use super::catalogue::Tried;
use crate::calibrate::csv::Dataset;
use crate::calibrate::fit::{least_squares, FitResult, ParameterRange};
use crate::calibrate::library::EffectId;
use crate::calibrate::select::fitter::intervals;
use crate::calibrate::select::observations::ActuationData;
use crate::calibrate::stats;
use actuator_model::effects::StackBasis;
use actuator_model::primitives::{Applied, Primitive};
use actuator_model::EffectModel;
use std::cell::RefCell;

/// A library effect fitted beside the primitive: its id, the bounds of its parameter (report units)
/// and the start (its estimate in its own `{η, A}` fit).
#[derive(Debug, Clone, PartialEq)]
pub struct Partner {
    /// The library effect.
    pub id: EffectId,
    /// Lower bound.
    pub lo: f64,
    /// Upper bound.
    pub hi: f64,
    /// Starting value.
    pub start: f64,
}

/// A fitted `{η, P}` or `{η, P, A}`.
#[derive(Debug, Clone)]
pub struct PrimitiveFit {
    /// The primitive.
    pub primitive: Primitive,
    /// The library effect fitted beside it, if any.
    pub partner: Option<EffectId>,
    /// η, the primitive's value (SI) and, with a partner, the partner's value (report units).
    pub theta: Vec<f64>,
    /// 95% intervals, in the order of `theta`.
    pub intervals: Vec<(f64, f64)>,
    /// Residual sum of squares.
    pub rss: f64,
    /// Residuals.
    pub n: usize,
    /// AICc (2 or 3 parameters).
    pub aicc: f64,
}

/// Whether δ and F_b stay proportional to the field (true for everything but a field-dependent d31).
fn field_linear(p: Primitive, partner: Option<&EffectId>) -> bool {
    !matches!(p, Primitive::FieldDependentD31) && partner != Some(&EffectId::FieldDependentD31)
}

/// The model at the primitive's value `p` and the partner's value `a`, on top of `base` (η apart).
fn model_at(
    base: &EffectModel,
    primitive: Primitive,
    partner: Option<&EffectId>,
    p: f64,
    a: f64,
) -> EffectModel {
    let mut m = base.clone();
    if let Some(id) = partner {
        id.apply(&mut m, a);
    }
    // On top of the frozen mass model's declared primitives, if any.
    m.primitives.push(Applied {
        primitive,
        value: p,
    });
    m
}

/// ln δ and ln F_b at each evaluation point.
type LogOutputs = Vec<(f64, f64)>;

/// Fit `{η, P}`, or `{η, P, A}` with a partner, on top of `base` (the frozen mass-stage effects).
pub(crate) fn fit(
    data: &Dataset,
    act: &ActuationData,
    base: &EffectModel,
    tried: &Tried,
    partner: Option<&Partner>,
) -> Option<PrimitiveFit> {
    let partner_id = partner.map(|x| &x.id);
    let linear = field_linear(tried.primitive, partner_id);
    // Evaluation points (rows: an actuator's first, or every row) and, per observation, (point, ln
    // field ratio).
    let mut points: Vec<usize> = Vec::new();
    let mut first_of_group: Vec<Option<usize>> = vec![None; act.groups];
    let mut map: Vec<(usize, f64)> = Vec::with_capacity(act.obs.len());
    for o in &act.obs {
        let k = match (linear, first_of_group[o.group]) {
            (true, Some(k)) => k,
            _ => {
                points.push(o.row);
                first_of_group[o.group] = Some(points.len() - 1);
                points.len() - 1
            }
        };
        let ratio = (o.basis.field / data.rows[points[k]].field).ln();
        map.push((k, ratio));
    }
    // The stack depends on the primitive's value alone (η and the library partners act on a solved
    // stack: field, boundary and compliance effects), so the stack bases of the last few values are
    // kept (one for a primitive that leaves the stack alone); each (p, a) then costs one `outputs` per
    // point.
    let bases: RefCell<Vec<(f64, Vec<Option<StackBasis>>)>> = RefCell::new(Vec::new());
    let basis_at = |p: f64| -> Vec<Option<StackBasis>> {
        // A boundary or field primitive leaves the stack as it is (`EffectModel::basis` applies the stack
        // primitives only): one basis, at its null value, serves every value.
        let p = if tried.primitive.changes_stack() {
            p
        } else {
            tried.primitive.null()
        };
        if let Some((_, b)) = bases.borrow().iter().find(|(x, _)| *x == p) {
            return b.clone();
        }
        let model = model_at(base, tried.primitive, None, p, 0.0);
        // Each distinct stack solved once.
        let mut stacks = act.stacks.solver(act.data, &model);
        let b: Vec<Option<StackBasis>> = points.iter().map(|&row| stacks.basis(row)).collect();
        let mut c = bases.borrow_mut();
        if c.len() >= 4 {
            c.remove(0);
        }
        c.push((p, b.clone()));
        b
    };
    let solve = |p: f64, a: f64| -> LogOutputs {
        let model = model_at(base, tried.primitive, partner_id, p, a);
        basis_at(p)
            .iter()
            .map(|b| match b.as_ref().map(|b| model.outputs(b)) {
                Some((d, f)) if d > 0.0 && f > 0.0 => (d.ln(), f.ln()),
                // A value the model refuses (a layer thinned to nothing): no fit there.
                _ => (f64::NAN, f64::NAN),
            })
            .collect()
    };
    let residuals = |theta: &[f64], out: &mut Vec<f64>| {
        out.clear();
        let ln_eta = theta[0].ln();
        let s = solve(theta[1], theta.get(2).copied().unwrap_or(0.0));
        for (o, &(k, ratio)) in act.obs.iter().zip(&map) {
            let (ld, lf) = s[k];
            let bad = |x: f64| if x.is_finite() { x } else { 1e3 };
            if let Some(d) = o.ln_delta {
                out.push(bad(d - ln_eta - ld - ratio));
            }
            if let Some(f) = o.ln_force {
                out.push(bad(f - ln_eta - lf - ratio));
            }
        }
    };
    let eta = EffectId::D31Scale.param();
    let mut bounds = vec![
        ParameterRange {
            lo: eta.lo,
            hi: eta.hi,
        },
        ParameterRange {
            lo: tried.lo,
            hi: tried.hi,
        },
    ];
    if let Some(x) = partner {
        bounds.push(ParameterRange { lo: x.lo, hi: x.hi });
    }
    let starts: Vec<Vec<f64>> = tried
        .starts
        .iter()
        .map(|&v| {
            let mut s = vec![1.0, v];
            s.extend(partner.map(|x| x.start.clamp(x.lo, x.hi)));
            s
        })
        .collect();
    let fit: FitResult = least_squares(&residuals, &bounds, &starts);
    // A fit stuck where the model refuses every value has nothing to say.
    if !fit.rss.is_finite() || fit.residuals.iter().any(|r| r.abs() >= 1e3) {
        return None;
    }
    let cov = fit.covariance();
    let (_, iv) = intervals(&fit, &cov);
    let k = fit.theta.len();
    Some(PrimitiveFit {
        primitive: tried.primitive,
        partner: partner_id.cloned(),
        intervals: iv,
        rss: fit.rss,
        n: fit.n,
        aicc: stats::aicc(fit.n, k, fit.rss),
        theta: fit.theta,
    })
}

impl PrimitiveFit {
    /// The fitted model's prediction of an actuator: the primitive (and partner) at its value on top of
    /// `base` with η.
    pub fn predict(
        &self,
        base: &EffectModel,
        a: &actuator_model::effects::Actuator,
    ) -> Result<actuator_model::Performance, actuator_model::ModelError> {
        let mut m = model_at(
            base,
            self.primitive,
            self.partner.as_ref(),
            self.theta[1],
            self.theta.get(2).copied().unwrap_or(0.0),
        );
        m.effects.d31_scale *= self.theta[0];
        m.predict(a)
    }
}

#[cfg(test)]
mod tests {
    use actuator_model::effects::{drive_at_voltage, Actuator};
    use actuator_model::primitives::{compose, Applied, Primitive, Property, Target};
    use actuator_model::{DriveMode, Effects, Material, Planform};

    #[test]
    fn deflection_and_force_are_proportional_to_field_and_to_eta() {
        // The shortcut of this module: δ, F_b ∝ E at a field-independent d31, and ∝ η.
        let pzt = Material::builtin("PZT-5H").unwrap();
        let cf = Material::builtin("CF-thesis").unwrap();
        let layup = [0.0, 90.0, 0.0, 0.0];
        let at = |volts: f64, eta: f64| {
            let a = Actuator {
                pzt: &pzt,
                pzt_thickness: 127e-6,
                ply: &cf,
                ply_thickness: 61.8e-6,
                layup_deg: &layup,
                planform: Planform::new(30e-3, 0.5, 6e-3, 0.7, 0.0).unwrap(),
                drive: drive_at_voltage(DriveMode::Parallel, volts, 127e-6),
            };
            let base = Effects {
                d31_scale: eta,
                bond_thickness: 10e-6,
                ..Effects::default()
            };
            compose(
                &[Applied {
                    primitive: Primitive::Scale {
                        target: Target::Passive,
                        property: Property::E1,
                    },
                    value: 0.6,
                }],
                &base,
                &a,
            )
            .unwrap()
        };
        let (a, b, c) = (at(50.0, 1.0), at(100.0, 1.0), at(50.0, 0.7));
        assert!((b.free_deflection / a.free_deflection - 2.0).abs() < 1e-12);
        assert!((b.blocked_force / a.blocked_force - 2.0).abs() < 1e-12);
        assert!((c.free_deflection / a.free_deflection - 0.7).abs() < 1e-12);
        assert!((c.blocked_force / a.blocked_force - 0.7).abs() < 1e-12);
    }
}
