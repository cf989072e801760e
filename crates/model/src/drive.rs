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
    /// Alternating drive with a DC bias: bias V_b on the stack, the middle electrode at
    /// `V_b/2 + V_s sin ωt` with the signal amplitude `V_s ≤ V_b/2`, so the signal stays between 0 and
    /// the bias and both plates always along their poling (docs/physics.md §2.1).
    Biased,
}

impl DriveMode {
    /// All modes, in documentation order.
    pub const ALL: [DriveMode; 5] = [
        DriveMode::Parallel,
        DriveMode::Series,
        DriveMode::Simultaneous,
        DriveMode::Alternating,
        DriveMode::Biased,
    ];

    /// Lower-case name as in design files.
    pub fn name(self) -> &'static str {
        match self {
            DriveMode::Parallel => "parallel",
            DriveMode::Series => "series",
            DriveMode::Simultaneous => "simultaneous",
            DriveMode::Alternating => "alternating",
            DriveMode::Biased => "biased",
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
    /// - alternating: one plate at E, the other idle: `[E, 0]`;
    /// - biased: the signal moves the plates by its own field E about the bias, which bends neither:
    ///   `[E, -E]`.
    pub fn layer_fields(self, field: f64) -> [f64; 2] {
        match self {
            DriveMode::Parallel | DriveMode::Series | DriveMode::Biased => [field, -field],
            DriveMode::Simultaneous => [0.5 * field, -0.5 * field],
            DriveMode::Alternating => [field, 0.0],
        }
    }

    /// Weibull model of the field limit (thesis Table 4.12), read at the highest field a plate carries
    /// along its poling. Modes that drive a plate against its poling (parallel, series) use the parallel
    /// fit; modes that never do (simultaneous, alternating, biased) use the simultaneous fit.
    pub fn field_limit(self) -> Weibull {
        match self {
            DriveMode::Parallel | DriveMode::Series => Weibull::FIELD_PARALLEL,
            DriveMode::Simultaneous | DriveMode::Alternating | DriveMode::Biased => {
                Weibull::FIELD_SIMULTANEOUS
            }
        }
    }
}

/// A drive level: mode, peak plate field of the signal and, for the biased mode, the bias.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Drive {
    /// Drive mode.
    pub mode: DriveMode,
    /// Peak field in a plate, V/m; for the biased mode the signal's amplitude `V_s/t_p`.
    pub field: f64,
    /// The biased mode's bias field `V_b/t_p`, V/m; 0 for every other mode.
    pub bias: f64,
}

impl Drive {
    /// A drive without a bias (every mode but the biased one).
    pub fn new(mode: DriveMode, field: f64) -> Drive {
        Drive {
            mode,
            field,
            bias: 0.0,
        }
    }

    /// Survival share from the mode's Weibull fit (thesis eq. 2.40, Table 4.12) at the highest field a
    /// plate carries along its poling.
    pub fn survival(&self) -> f64 {
        self.mode.field_limit().survival(PlateSwing::of(self).along)
    }
}

/// The field in the bottom and top plate at phase `θ = ω t` of a sinusoidal signal, V/m, positive along
/// the plate's own poling (docs/physics.md §2.1, the table of modes):
/// - parallel and series: `E sin θ` and `-E sin θ`: each plate against its poling for half the cycle;
/// - simultaneous: `E/2 (1 + sin θ)` and `E/2 (1 - sin θ)`: the middle electrode swings the whole bias;
/// - alternating: `E max(sin θ, 0)` and `E max(-sin θ, 0)`: one plate at a time;
/// - biased: `E_b/2 + E sin θ` and `E_b/2 - E sin θ`, with `E_b` the bias field.
pub fn plate_fields_at(drive: &Drive, phase: f64) -> [f64; 2] {
    let (e, s) = (drive.field, phase.sin());
    match drive.mode {
        DriveMode::Parallel | DriveMode::Series => [e * s, -e * s],
        DriveMode::Simultaneous => [0.5 * e * (1.0 + s), 0.5 * e * (1.0 - s)],
        DriveMode::Alternating => [e * s.max(0.0), e * (-s).max(0.0)],
        DriveMode::Biased => [0.5 * drive.bias + e * s, 0.5 * drive.bias - e * s],
    }
}

/// The extremes of [`plate_fields_at`] over a cycle, the same for both plates, V/m.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlateSwing {
    /// Highest field along the poling.
    pub along: f64,
    /// Highest field against the poling (0 when a plate never sees one).
    pub against: f64,
}

impl PlateSwing {
    /// The swing of a drive, in closed form.
    pub fn of(drive: &Drive) -> PlateSwing {
        let e = drive.field;
        match drive.mode {
            DriveMode::Parallel | DriveMode::Series => PlateSwing {
                along: e,
                against: e,
            },
            DriveMode::Simultaneous | DriveMode::Alternating => PlateSwing {
                along: e,
                against: 0.0,
            },
            DriveMode::Biased => PlateSwing {
                along: 0.5 * drive.bias + e,
                against: (e - 0.5 * drive.bias).max(0.0),
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    fn drives() -> Vec<Drive> {
        let mut all: Vec<Drive> = DriveMode::ALL
            .into_iter()
            .map(|m| Drive::new(m, 500e3))
            .collect();
        all.push(Drive {
            mode: DriveMode::Biased,
            field: 400e3,
            bias: 1200e3,
        });
        // A signal past half the bias drives each plate against its poling for part of the cycle.
        all.push(Drive {
            mode: DriveMode::Biased,
            field: 400e3,
            bias: 500e3,
        });
        all
    }

    #[test]
    fn the_swing_is_the_extreme_of_the_fields_over_a_cycle() {
        // The closed form of PlateSwing against a sampled cycle of plate_fields_at.
        for d in drives() {
            let (mut along, mut against) = (f64::MIN, 0.0f64);
            for i in 0..3600 {
                for f in plate_fields_at(&d, 2.0 * PI * i as f64 / 3600.0) {
                    along = along.max(f);
                    against = against.max(-f);
                }
            }
            let s = PlateSwing::of(&d);
            assert!((s.along - along).abs() < 1e-6, "{d:?}");
            assert!((s.against - against).abs() < 1e-6, "{d:?}");
        }
    }

    #[test]
    fn the_bending_part_of_each_mode_is_its_layer_fields() {
        // The difference between the plates at the signal's peak is what bends the stack: the mode's
        // layer fields (thesis §2.3.3), whatever the bias.
        for d in drives() {
            let [b0, t0] = plate_fields_at(&d, 0.0);
            let [b1, t1] = plate_fields_at(&d, 0.5 * PI);
            let [lb, lt] = d.mode.layer_fields(d.field);
            assert!(((b1 - b0) - (t1 - t0) - (lb - lt)).abs() < 1e-6, "{d:?}");
        }
    }

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
        let d = Drive::new(DriveMode::Parallel, 800e3);
        assert!(d.survival() > 0.9);
    }
}
