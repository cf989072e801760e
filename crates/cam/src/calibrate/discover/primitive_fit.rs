//! Fit one primitive as a one-parameter effect, with the d31 scale η beside it as every library
//! candidate has it: `{η, P}` on the deflections and forces, by the same bounded least squares as the
//! library ([`least_squares_grouped`]), scored by the same AICc. With a [`Partner`], a library effect A is fitted
//! beside it, `{η, P, A}`: the residual of data where a library effect and an effect outside the library
//! are both present.
//!
//! Speed: the residuals are the selection's own, per actuator and drive mode
//! ([`DriveGroups`](crate::calibrate::select::drive_groups::DriveGroups)), searched in their grouped form
//! where the fitted model is linear in the field. The stack depends on the primitive's value alone (η and
//! the library partners act on a solved stack: field, boundary and compliance effects), so the stacks
//! solved at the last few values are kept (none for a primitive that leaves the stack alone), and a
//! Jacobian column of η or the partner solves none.

use super::catalogue::Tried;
use super::joint::Masses;
use crate::calibrate::fit::{least_squares_grouped, FitResult, ParameterRange};
use crate::calibrate::library::EffectId;
use crate::calibrate::select::drive_groups::{Form, GroupBasis};
use crate::calibrate::select::fitter::intervals;
use crate::calibrate::select::observations::ActuationData;
use crate::calibrate::stats;
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
    /// Residual sum of squares of the deflections and forces.
    pub rss: f64,
    /// Deflection and force residuals.
    pub n: usize,
    /// AICc of the deflections and forces (2 or 3 parameters).
    pub aicc: f64,
    /// The sum of squares of the log mass residuals, when the masses were fitted with it (a primitive
    /// that changes the mass, [`super::joint`]).
    pub rss_mass: Option<f64>,
    /// The model it sits on (the mass model it was fitted on top of).
    pub base: EffectModel,
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

/// Stacks solved at the last few values of a stack primitive.
const KEPT_STACKS: usize = 4;

/// Fit `{η, P}`, or `{η, P, A}` with a partner, on top of `base` (a mass model), on the deflections and
/// forces and, with `masses`, on the weighed masses too, each log mass residual weighted by
/// [`Masses::weight`] (a primitive that changes the mass is fitted on both).
pub(crate) fn fit(
    act: &ActuationData,
    base: &EffectModel,
    tried: &Tried,
    partner: Option<&Partner>,
    masses: Option<&Masses>,
) -> Option<PrimitiveFit> {
    let partner_id = partner.map(|x| &x.id);
    let groups = &act.drive_groups;
    // Each group's stack at a value of the primitive, the last few values kept.
    let stacks: RefCell<Vec<(f64, Vec<Option<GroupBasis>>)>> = RefCell::new(Vec::new());
    let solved_at = |p: f64| {
        if stacks.borrow().iter().any(|(x, _)| *x == p) {
            return;
        }
        let model = model_at(base, tried.primitive, None, p, 0.0);
        let mut solver = act.stacks.solver(act.data, &model);
        let bases = (0..groups.len())
            .map(|g| {
                solver
                    .basis(act.obs[groups.first(g)].row)
                    .map(GroupBasis::of)
            })
            .collect();
        let mut kept = stacks.borrow_mut();
        if kept.len() >= KEPT_STACKS {
            kept.remove(0);
        }
        kept.push((p, bases));
    };
    // The residuals at θ = (η, p, a) in `form`, each one the model cannot evaluate (a layer thinned to
    // nothing) held at 1e3: no fit there.
    let evaluate = |theta: &[f64], form: Form, out: &mut Vec<f64>| {
        out.clear();
        let p = theta[1];
        let mut model = model_at(
            base,
            tried.primitive,
            partner_id,
            p,
            theta.get(2).copied().unwrap_or(0.0),
        );
        model.effects.d31_scale *= theta[0];
        let left_out = if tried.primitive.changes_stack() {
            solved_at(p);
            let kept = stacks.borrow();
            let bases = &kept.iter().find(|(x, _)| *x == p).expect("just solved").1;
            let mut solve = |g: usize, _: bool| bases[g];
            groups.evaluate(&act.obs, &model, None, Some(&mut solve), form, out)
        } else {
            groups.evaluate(&act.obs, &model, None, None, form, out)
        };
        if let Some(m) = masses {
            m.push_residuals(act.data, &model, m.weight, out);
        }
        for r in out.iter_mut().filter(|r| !r.is_finite()) {
            *r = 1e3;
        }
        left_out
    };
    let residuals = |theta: &[f64], out: &mut Vec<f64>| {
        evaluate(theta, Form::Rows, out);
    };
    let linear =
        tried.primitive.linear_in_field() && partner_id.is_none_or(EffectId::linear_in_field);
    let search = |theta: &[f64], out: &mut Vec<f64>| {
        if linear {
            Some(evaluate(theta, Form::Groups, out))
        } else {
            residuals(theta, out);
            None
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
    let fit: FitResult = least_squares_grouped(&search, &residuals, &bounds, &starts);
    // A fit stuck where the model refuses every value has nothing to say.
    if !fit.rss.is_finite() || fit.residuals.iter().any(|r| r.abs() >= 1e3) {
        return None;
    }
    let cov = fit.covariance();
    let (_, iv) = intervals(&fit, &cov);
    let k = fit.theta.len();
    let (n, rss, rss_mass) = split(&fit.residuals, masses);
    Some(PrimitiveFit {
        primitive: tried.primitive,
        partner: partner_id.cloned(),
        intervals: iv,
        rss,
        n,
        aicc: stats::aicc(n, k, rss),
        rss_mass,
        base: base.clone(),
        theta: fit.theta,
    })
}

/// The count and sum of squares of the deflection and force residuals, which come first, and the sum of
/// squares of the log mass residuals after them (their weight taken out).
fn split(residuals: &[f64], masses: Option<&Masses>) -> (usize, f64, Option<f64>) {
    let n = residuals.len() - masses.map_or(0, |m| m.weighed.len());
    let squares = |r: &[f64]| r.iter().map(|x| x * x).sum::<f64>();
    let rss_mass = masses.map(|m| squares(&residuals[n..]) / (m.weight * m.weight));
    (n, squares(&residuals[..n]), rss_mass)
}

impl PrimitiveFit {
    /// The fitted model's prediction of an actuator: the primitive (and partner) at its value on top of
    /// its base with η.
    pub fn predict(
        &self,
        a: &actuator_model::effects::Actuator,
    ) -> Result<actuator_model::Performance, actuator_model::ModelError> {
        self.model().predict(a)
    }

    /// The fitted model: the primitive (and partner) at its value on top of its base with η.
    pub fn model(&self) -> EffectModel {
        let mut m = model_at(
            &self.base,
            self.primitive,
            self.partner.as_ref(),
            self.theta[1],
            self.theta.get(2).copied().unwrap_or(0.0),
        );
        m.effects.d31_scale *= self.theta[0];
        m
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
