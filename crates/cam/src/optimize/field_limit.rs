//! What set the drive field of a laminate the optimizer searches.

use actuator_model::poling::Binding;

/// What set the drive field of a laminate: the requested field (or survival), the supply voltage, or
/// the PZT strain limit. Strain and field are proportional, so each limit is a cap on the field.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FieldLimit {
    /// The field as requested.
    Requested,
    /// `max_voltage_V` at this PZT thickness and drive mode.
    Voltage,
    /// `max_peak_pzt_strain` in free deflection (uniform along the plate; a shape whose stroke strains
    /// its plate more is left out, `Problem::try_shape_rates`).
    Strain,
    /// The mode's limits on the plates' field (optimize for a wing): the failure fit along the poling,
    /// the depolarization field against it, or the biased signal's range (docs/physics.md §2.1).
    Poling(Binding),
}
