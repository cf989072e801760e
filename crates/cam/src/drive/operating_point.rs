//! The operating point at one field: the actuator predicted at that field, the flapping system it
//! makes with the mechanism, and the steady state at the required stroke (or the best within the field
//! limits). This is all a field-dependent model's search repeats (docs/physics.md §18.5); the report is
//! built once, from the point the search ends on.

use super::mechanism::Mechanism;
use super::report::Unreachable;
use super::spec::DriveSpec;
use super::steady_state::steady_state;
use super::DriveError;
use crate::design::Design;
use crate::field_limits as limits;
use crate::prediction::{actuator_modes, force_per_field, performance};
use actuator_model::dynamics::LumpedActuator;
use actuator_model::flapping::{FlappingSystem, SteadyState};
use actuator_model::model::ModelChoice;
use actuator_model::poling::FieldCheck;
use actuator_model::Performance;

/// The actuator and the steady state at the design's field, SI.
#[derive(Debug, Clone)]
pub struct OperatingPoint {
    /// The design, its drive at the field predicted at.
    pub design: Design,
    /// The actuator's prediction at that field.
    pub perf: Performance,
    /// The bare actuator's first resonance, Hz.
    pub modal_frequency: f64,
    /// Actuator + transmission + wing.
    pub system: FlappingSystem,
    /// Blocked force per signal field in the design's mode, N per V/m.
    pub per_field: f64,
    /// The design's mode against the field limits.
    pub limits: FieldCheck,
    /// The required stroke's steady state when the limits allow it, else the best within them.
    pub state: Option<SteadyState>,
    /// Why the required stroke is out of reach, if it is.
    pub unreachable: Option<Unreachable>,
    /// The force amplitude the required stroke takes at any field, N, where it has a steady state.
    pub required: Option<f64>,
}

impl OperatingPoint {
    /// The operating point of `design` at its own field, through `mechanism`.
    pub fn at(
        spec: &DriveSpec,
        design: Design,
        model: &ModelChoice,
        mechanism: &Mechanism,
    ) -> Result<Self, DriveError> {
        let perf = performance(&design, model)?;
        let modal = actuator_modes(&design, model, &perf)?;
        let actuator = LumpedActuator::new(perf.stiffness, &modal, spec.loss_factor(model));
        let system = FlappingSystem {
            actuator,
            linkage: mechanism.kinematics,
            flexure_stiffness: mechanism.flexure_stiffness,
            inertia: mechanism.wing.inertia + mechanism.link_inertia,
            damping: mechanism.wing.damping,
        };
        let per_field = force_per_field(&design, model, design.drive.mode)?;
        let limits = limits::check(&design, &design.drive, spec.survival)?;
        let (state, unreachable, required) =
            steady_state(spec, &system, &design, per_field, &limits);
        Ok(OperatingPoint {
            design,
            perf,
            modal_frequency: modal.frequency,
            system,
            per_field,
            limits,
            state,
            unreachable,
            required,
        })
    }

    /// The signal field the steady state asks for, V/m (`None` without a steady state).
    pub fn asks(&self) -> Option<f64> {
        self.state.map(|s| s.force / self.per_field)
    }
}
