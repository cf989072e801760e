//! The limits on the plates' field in each drive mode, as `drive` holds and reports them
//! (docs/physics.md §2.1): the failure fit along the poling, the PZT's depolarization field against it,
//! and the biased signal's range between 0 and the bias.

use crate::design::Design;
use crate::input::fixed;
use actuator_model::poling::FieldCheck;
use actuator_model::{Drive, DriveMode, ModelError};
use serde::Serialize;
use std::fmt::Write;

/// The drive of `design` in `mode` at signal field `field` (V/m). The design's own mode keeps its
/// bias; the biased mode of a design driven otherwise takes the bias that allows the largest signal at
/// survival share `survival`: the failure fit's field, so that half of it is the signal and half the
/// bias's own share along the poling.
pub fn drive_in(
    design: &Design,
    mode: DriveMode,
    field: f64,
    survival: f64,
) -> Result<Drive, ModelError> {
    let bias = match mode {
        DriveMode::Biased if design.drive.mode == DriveMode::Biased => design.drive.bias,
        DriveMode::Biased => mode.field_limit().threshold(survival)?,
        _ => 0.0,
    };
    Ok(Drive { mode, field, bias })
}

/// `drive` held to the limits at survival share `survival`, for `design`'s PZT.
pub fn check(design: &Design, drive: &Drive, survival: f64) -> Result<FieldCheck, ModelError> {
    FieldCheck::new(drive, survival, design.pzt.depolarization_field)
}

/// A drive against the limits, in lab units.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[allow(non_snake_case)]
pub struct PolingRow {
    /// The biased mode's bias, V (0 for the other modes).
    pub bias_V: f64,
    /// Highest field a plate carries along its poling over a cycle.
    pub along_V_per_mm: f64,
    /// Highest field a plate carries against its poling over a cycle.
    pub against_V_per_mm: f64,
    /// The failure fit's field at the survival share (along the poling).
    pub failure_limit_V_per_mm: f64,
    /// The PZT's depolarization field (against the poling).
    pub depolarization_limit_V_per_mm: f64,
    /// `failure_limit - along`, negative past the limit.
    pub failure_margin_V_per_mm: f64,
    /// `depolarization_limit - against`, negative past the limit.
    pub depolarization_margin_V_per_mm: f64,
    /// The limit that sets the highest signal in this mode: failure, depolarization or bias.
    pub binds: String,
    /// True when the drive is within every limit.
    pub within_limit: bool,
}

impl PolingRow {
    /// The row of `drive` under `check`.
    pub fn new(design: &Design, drive: &Drive, check: &FieldCheck) -> PolingRow {
        PolingRow {
            bias_V: drive.bias * design.pzt_thickness,
            along_V_per_mm: check.swing.along * 1e-3,
            against_V_per_mm: check.swing.against * 1e-3,
            failure_limit_V_per_mm: check.failure_limit * 1e-3,
            depolarization_limit_V_per_mm: check.depolarization_limit * 1e-3,
            failure_margin_V_per_mm: check.failure_margin() * 1e-3,
            depolarization_margin_V_per_mm: check.depolarization_margin() * 1e-3,
            binds: check.binds.name().to_string(),
            within_limit: check.within(drive),
        }
    }

    /// The numbers of the row, named for the finiteness check.
    pub fn numbers(&self) -> [(&'static str, f64); 5] {
        [
            ("bias_V", self.bias_V),
            ("along_V_per_mm", self.along_V_per_mm),
            ("against_V_per_mm", self.against_V_per_mm),
            ("failure_margin_V_per_mm", self.failure_margin_V_per_mm),
            (
                "depolarization_margin_V_per_mm",
                self.depolarization_margin_V_per_mm,
            ),
        ]
    }
}

/// The same stroke in one drive mode.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[allow(non_snake_case)]
pub struct ModeRow {
    pub mode: String,
    /// The signal's peak plate field (the bending part).
    pub field_V_per_mm: f64,
    /// The signal's supply voltage amplitude.
    pub voltage_V: f64,
    /// Survival of the failure fit at the field along the poling.
    pub survival: f64,
    /// The highest signal within every limit.
    pub limit_V_per_mm: f64,
    #[serde(flatten)]
    pub poling: PolingRow,
}

/// The row of the same blocked-force amplitude in `mode`, whose blocked force per unit field is
/// `per_field` (N/(V/m)).
pub fn mode_row(
    design: &Design,
    mode: DriveMode,
    force: f64,
    per_field: f64,
    survival: f64,
) -> Result<ModeRow, ModelError> {
    let field = force / per_field;
    let drive = drive_in(design, mode, field, survival)?;
    let check = check(design, &drive, survival)?;
    Ok(ModeRow {
        mode: mode.name().to_string(),
        field_V_per_mm: field * 1e-3,
        voltage_V: mode.voltage_from_field(field, design.pzt_thickness),
        survival: drive.survival(),
        limit_V_per_mm: check.max_signal * 1e-3,
        poling: PolingRow::new(design, &drive, &check),
    })
}

/// The table of the same `what` (stroke, deflection) in every mode.
pub fn modes_table(modes: &[ModeRow], what: &str, out: &mut String) {
    if modes.is_empty() {
        return;
    }
    let _ = writeln!(
        out,
        "\nthe same {what} by drive mode (a plate's field along / against its poling; margins to the failure fit and to depolarization):\n  mode          field V/mm   voltage V   bias V   along / against V/mm   survival   failure margin   depol. margin   binds            limit V/mm   within"
    );
    for m in modes {
        let p = &m.poling;
        let _ = writeln!(
            out,
            "  {:<12}  {:>10}  {:>10}  {:>7}  {:>21}  {:>9}  {:>15}  {:>14}   {:<15}  {:>10}   {}",
            m.mode,
            fixed(m.field_V_per_mm, 1),
            fixed(m.voltage_V, 1),
            fixed(p.bias_V, 1),
            format!(
                "{} / {}",
                fixed(p.along_V_per_mm, 1),
                fixed(p.against_V_per_mm, 1)
            ),
            fixed(m.survival, 4),
            fixed(p.failure_margin_V_per_mm, 1),
            fixed(p.depolarization_margin_V_per_mm, 1),
            p.binds,
            fixed(m.limit_V_per_mm, 1),
            if p.within_limit { "yes" } else { "no" }
        );
    }
}
