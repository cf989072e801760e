//! Each plate's field over a drive cycle relative to its poling, and the two limits on it: the failure
//! fit along the poling and the depolarization field against it (docs/physics.md §2.1).

use crate::drive::{Drive, DriveMode, PlateSwing};
use crate::error::ModelError;

/// The limit that sets the highest signal a mode can take.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Binding {
    /// The Weibull failure fit of the mode, along the poling (thesis Table 4.12).
    Failure,
    /// The material's depolarization field, against the poling.
    Depolarization,
    /// The biased mode's signal reaching 0 or the bias.
    Bias,
}

impl Binding {
    /// A word for reports.
    pub fn name(self) -> &'static str {
        match self {
            Binding::Failure => "failure",
            Binding::Depolarization => "depolarization",
            Binding::Bias => "bias",
        }
    }
}

/// A drive held against both limits.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FieldCheck {
    /// The plates' swing at the drive.
    pub swing: PlateSwing,
    /// The failure fit's field at the required survival, along the poling, V/m.
    pub failure_limit: f64,
    /// The material's depolarization field, against the poling, V/m.
    pub depolarization_limit: f64,
    /// The highest signal field (the drive's `field`) within every limit, V/m.
    pub max_signal: f64,
    /// The limit that sets `max_signal`.
    pub binds: Binding,
}

impl FieldCheck {
    /// Hold `drive` to the mode's failure fit at survival share `survival` and to the depolarization
    /// field `depolarization` (V/m) of its plates.
    pub fn new(
        drive: &Drive,
        survival: f64,
        depolarization: f64,
    ) -> Result<FieldCheck, ModelError> {
        let failure_limit = drive.mode.field_limit().threshold(survival)?;
        let (max_signal, binds) = match drive.mode {
            DriveMode::Parallel | DriveMode::Series => {
                if depolarization < failure_limit {
                    (depolarization, Binding::Depolarization)
                } else {
                    (failure_limit, Binding::Failure)
                }
            }
            DriveMode::Simultaneous | DriveMode::Alternating => (failure_limit, Binding::Failure),
            DriveMode::Biased => {
                let by_failure = (failure_limit - 0.5 * drive.bias).max(0.0);
                if 0.5 * drive.bias < by_failure {
                    (0.5 * drive.bias, Binding::Bias)
                } else {
                    (by_failure, Binding::Failure)
                }
            }
        };
        Ok(FieldCheck {
            swing: PlateSwing::of(drive),
            failure_limit,
            depolarization_limit: depolarization,
            max_signal,
            binds,
        })
    }

    /// Margin to the failure fit, V/m (negative past it).
    pub fn failure_margin(&self) -> f64 {
        self.failure_limit - self.swing.along
    }

    /// Margin to the depolarization field, V/m (negative past it).
    pub fn depolarization_margin(&self) -> f64 {
        self.depolarization_limit - self.swing.against
    }

    /// True when the drive is within every limit.
    pub fn within(&self, drive: &Drive) -> bool {
        drive.field <= self.max_signal * (1.0 + 1e-12)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parallel_at_the_coercive_field_is_bound_by_depolarization() {
        // PZT-5H: initial depolarizing field 300 V/mm, coercive 800 V/mm (thesis Table 2.1). Parallel
        // drive at 799 V/mm puts a plate at about the coercive field against its poling each cycle.
        let pzt = crate::Material::builtin("PZT-5H").unwrap();
        let d = Drive::new(DriveMode::Parallel, 799e3);
        let c = FieldCheck::new(&d, 0.9, pzt.depolarization_field).unwrap();
        assert_eq!(c.binds, Binding::Depolarization);
        assert!((c.depolarization_margin() + 499e3).abs() < 1e-6);
        assert!(c.failure_margin() > 0.0 && !c.within(&d));
    }

    #[test]
    fn a_biased_signal_is_held_to_half_the_bias_and_to_the_fit_along_the_poling() {
        // Simultaneous fit at survival 0.9: 654 V/mm (thesis Table 4.12).
        let low = Drive {
            mode: DriveMode::Biased,
            field: 100e3,
            bias: 400e3,
        };
        let c = FieldCheck::new(&low, 0.9, 300e3).unwrap();
        assert_eq!((c.binds, c.max_signal), (Binding::Bias, 200e3));
        let high = Drive { bias: 900e3, ..low };
        let c = FieldCheck::new(&high, 0.9, 300e3).unwrap();
        assert_eq!(c.binds, Binding::Failure);
        assert!((c.max_signal + 450e3 - c.failure_limit).abs() < 1e-6);
        assert!((c.failure_limit - 654e3).abs() < 0.005 * 654e3);
        assert_eq!(c.swing.against, 0.0);
    }
}
