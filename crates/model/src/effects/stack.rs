//! What an actuator's stack gives the δ/F_b physics once it is solved: the planform-free
//! [`StackSection`] a data set's actuators share, and the [`StackBasis`] of one planform, so that a
//! fit varies the effects without re-solving the laminate.

use crate::error::ModelError;
use crate::performance::{beam_tip_compliance, extension_tip_compliance};
use crate::planform::Planform;

/// What the δ/F_b physics needs of one actuator once the stack is fixed: lets a fit vary η, β, Δ, φ, c_θ
/// and s_k without re-solving the laminate. [`Effects::outputs`](super::Effects::outputs) applies them exactly as
/// [`Effects::predict`](super::Effects::predict) does (a unit test holds the two together).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StackBasis {
    /// Free curvature with the nominal d31 at the drive field, 1/m.
    pub free_curvature: f64,
    /// Tip compliance of the tapered beam with a rigid extension, m/N.
    pub beam_compliance: f64,
    /// Extra tip compliance of an extension made of the bare plies (φ = 1), m/N.
    pub extension_compliance: f64,
    /// Drive field, V/m.
    pub field: f64,
    /// Planform.
    pub planform: Planform,
}

/// The part of a [`StackBasis`] that depends on the stack and its drive alone, not on the planform: the
/// actuators of a data set that share a stack and a drive field share it, so a calibration solves each
/// distinct stack once per evaluation rather than once per actuator. [`StackSection::basis`] gives the
/// same numbers [`Effects::basis`](super::Effects::basis) gives for each planform (it is the same arithmetic).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StackSection {
    /// Free curvature with the nominal d31 at the drive field, 1/m.
    pub free_curvature: f64,
    /// Bending compliance `C44` of the stack, 1/(N·m).
    pub bending_compliance: f64,
    /// Bending compliance `C44` of the plies alone, 1/(N·m); solved only for an actuator with an
    /// extension (None otherwise).
    pub passive_bending_compliance: Option<f64>,
    /// Drive field, V/m.
    pub field: f64,
}

impl StackSection {
    /// The stack basis of a planform: the tapered beam's tip compliance `C44 l_p³ G(w_r, l_r) / (3 w_nom)`
    /// (thesis eqs. 2.29-2.34, docs/physics.md §3) and the bare plies' extension `C44_pass l_ext³ / (3 w_tip)`.
    pub fn basis(&self, pl: &Planform) -> Result<StackBasis, ModelError> {
        self.basis_with(pl, &PlanformTerms::of(pl))
    }

    /// [`StackSection::basis`] with the planform's terms computed already (the same numbers).
    pub fn basis_with(&self, pl: &Planform, t: &PlanformTerms) -> Result<StackBasis, ModelError> {
        let beam = self.bending_compliance * t.beam_per_section;
        let extension = match t.extension_per_section {
            Some(per_section) => {
                let Some(passive) = self.passive_bending_compliance else {
                    return Err(ModelError::Laminate(
                        "the stack was solved for an actuator without an extension".into(),
                    ));
                };
                passive * per_section
            }
            None => 0.0,
        };
        Ok(StackBasis {
            free_curvature: self.free_curvature,
            beam_compliance: beam,
            extension_compliance: extension,
            field: self.field,
            planform: *pl,
        })
    }
}

/// The planform's part of [`StackSection::basis`]: the tip compliances per unit section compliance
/// `C44` of the tapered beam ([`beam_tip_compliance`]) and, with an extension, of the extension
/// ([`extension_tip_compliance`]). The same under every stack, so a fit that solves the stacks again on
/// each evaluation computes them once per planform (the shape factor is an integral).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlanformTerms {
    beam_per_section: f64,
    extension_per_section: Option<f64>,
}

impl PlanformTerms {
    /// The terms of `pl`.
    pub fn of(pl: &Planform) -> PlanformTerms {
        PlanformTerms {
            beam_per_section: beam_tip_compliance(1.0, pl),
            extension_per_section: (pl.extension_ratio > 0.0)
                .then(|| extension_tip_compliance(1.0, pl)),
        }
    }
}

impl StackBasis {
    /// The same stack driven at another (positive) field of the same mode: the CLT free curvature is
    /// linear in the layer fields (`DriveMode::layer_fields`, thesis eq. 2.20's piezoelectric moment
    /// `∝ d31 E`) and the compliances do not depend on the field. Saves a stack solve per voltage.
    pub fn at_field(&self, field: f64) -> StackBasis {
        StackBasis {
            free_curvature: self.free_curvature * field / self.field,
            field,
            ..*self
        }
    }
}
