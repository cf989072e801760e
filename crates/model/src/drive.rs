//! Drive modes as per-layer fields (thesis §2.3.3, docs/physics.md §2).

use crate::weibull::Weibull;
use serde::{Deserialize, Serialize};

/// How the two PZT plates are driven.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum DriveMode {
    /// Both plates at V, one along and one against its poling.
    Parallel,
    /// V across the stack, V/2 per plate, opposite poling.
    Series,
    /// Bias V_b on the stack, drive V_d in 0..V_b; both plates always along their poling.
    Simultaneous,
    /// Each plate 0..V along its poling, one at a time.
    Alternating,
}

impl DriveMode {
    /// All modes, in documentation order.
    pub const ALL: [DriveMode; 4] = [
        DriveMode::Parallel,
        DriveMode::Series,
        DriveMode::Simultaneous,
        DriveMode::Alternating,
    ];

    /// Lower-case name as in design files.
    pub fn name(self) -> &'static str {
        match self {
            DriveMode::Parallel => "parallel",
            DriveMode::Series => "series",
            DriveMode::Simultaneous => "simultaneous",
            DriveMode::Alternating => "alternating",
        }
    }

    /// Parse a design-file name.
    pub fn from_name(name: &str) -> Option<DriveMode> {
        Self::ALL.into_iter().find(|m| m.name() == name)
    }

    /// Peak field in a plate, V/m, for supply voltage V and plate thickness t_p: `V/t_p`, except series
    /// (`V/(2 t_p)`, the supply splits across two plates).
    pub fn field_from_voltage(self, voltage: f64, pzt_thickness: f64) -> f64 {
        match self {
            DriveMode::Series => voltage / (2.0 * pzt_thickness),
            _ => voltage / pzt_thickness,
        }
    }

    /// Supply voltage for a peak plate field (inverse of [`Self::field_from_voltage`]).
    pub fn voltage_from_field(self, field: f64, pzt_thickness: f64) -> f64 {
        match self {
            DriveMode::Series => 2.0 * field * pzt_thickness,
            _ => field * pzt_thickness,
        }
    }

    /// One-sided amplitude of `E3 p` in the bottom and top plate at peak plate field `E` (V/m), sign
    /// relative to the plate's own poling (thesis §2.3.3):
    /// - parallel and series: `[E, -E]` (series at its own E = V/(2 t_p));
    /// - simultaneous: the plates move by `E/2` each about the neutral state `V_d = V_b/2`: `[E/2, -E/2]`;
    /// - alternating: one plate at E, the other idle: `[E, 0]`.
    pub fn layer_fields(self, field: f64) -> [f64; 2] {
        match self {
            DriveMode::Parallel | DriveMode::Series => [field, -field],
            DriveMode::Simultaneous => [0.5 * field, -0.5 * field],
            DriveMode::Alternating => [field, 0.0],
        }
    }

    /// Weibull model of the field limit (thesis Table 4.12). Modes that drive a plate against its poling
    /// (parallel, series) use the parallel fit; modes that never do (simultaneous, alternating) use the
    /// simultaneous fit.
    pub fn field_limit(self) -> Weibull {
        match self {
            DriveMode::Parallel | DriveMode::Series => Weibull::FIELD_PARALLEL,
            DriveMode::Simultaneous | DriveMode::Alternating => Weibull::FIELD_SIMULTANEOUS,
        }
    }
}

/// A drive level: mode and peak plate field.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Drive {
    /// Drive mode.
    pub mode: DriveMode,
    /// Peak field in a plate, V/m.
    pub field: f64,
}

impl Drive {
    /// Survival share at this field from the mode's Weibull fit (thesis eq. 2.40, Table 4.12).
    pub fn survival(&self) -> f64 {
        self.mode.field_limit().survival(self.field)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn voltage_and_field_round_trip() {
        for mode in DriveMode::ALL {
            let e = mode.field_from_voltage(200.0, 191e-6);
            assert!((mode.voltage_from_field(e, 191e-6) - 200.0).abs() < 1e-9);
            assert_eq!(DriveMode::from_name(mode.name()), Some(mode));
        }
        assert_eq!(DriveMode::Series.field_from_voltage(200.0, 1e-4), 1e6);
    }

    #[test]
    fn thesis_design_field_survives_ninety_percent_in_parallel() {
        // Source: thesis §4.10: 800 V/mm "should give a survival rate of over 90%".
        let d = Drive {
            mode: DriveMode::Parallel,
            field: 800e3,
        };
        assert!(d.survival() > 0.9);
    }
}
