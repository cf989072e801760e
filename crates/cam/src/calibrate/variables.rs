//! The design variables a residual is tested against and plotted over, per actuator: every design
//! variable (`l_tot`, `l_r`, `w_0`, `w_r`, `t_p`, the layup, the drive field) and the ratios the effects act
//! through (PZT/passive thickness, aspect, extension fraction), plus the thesis' fit variables.

use super::csv::Measurement;

/// Number of design variables.
pub const COUNT: usize = 14;

/// Design variables of one actuator, name and value (report units).
pub type DesignVariables = [(&'static str, f64); COUNT];

/// Design variables of the actuator of row `m` (report units). The field is that of the row: between
/// actuators it matters only when each is driven at its own field (within a sweep the adequacy test has
/// its own field trend).
pub fn design_variables(m: &Measurement) -> DesignVariables {
    let pl = &m.planform;
    let plies = m.layup_deg.len() as f64;
    let passive = plies * m.ply_thickness;
    let t = 2.0 * m.pzt_thickness + passive;
    let zero_plies = m.layup_deg.iter().filter(|a| a.abs() < 1e-9).count() as f64;
    [
        ("l_tot_mm", pl.length * 1e3),
        ("l_p_mm", pl.piezo_length() * 1e3),
        ("l_r", pl.extension_ratio),
        ("w0_mm", pl.base_width * 1e3),
        ("w_r", pl.width_ratio),
        ("t_p_mm", m.pzt_thickness * 1e3),
        ("plies", plies),
        ("w0*t_p_mm2", pl.base_width * m.pzt_thickness * 1e6),
        (
            "w*t^3/L_mm3",
            pl.nominal_width() * t.powi(3) / pl.length * 1e9,
        ),
        ("field_V_per_um", m.field * 1e-6),
        ("t_p/t_passive", m.pzt_thickness / passive),
        ("w0/l_p", pl.base_width / pl.piezo_length()),
        ("l_ext/l_tot", pl.extension_length() / pl.length),
        ("zero_ply_share", zero_plies / plies),
    ]
}
