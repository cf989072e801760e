//! The design variables a residual is tested against and plotted over, per actuator.

use super::csv::Measurement;

/// Design variables per actuator: name and value (report units).
pub fn design_variables(m: &Measurement) -> [(&'static str, f64); 9] {
    let pl = &m.planform;
    let t = 2.0 * m.pzt_thickness + m.layup_deg.len() as f64 * m.ply_thickness;
    [
        ("l_tot_mm", pl.length * 1e3),
        ("l_p_mm", pl.piezo_length() * 1e3),
        ("l_r", pl.extension_ratio),
        ("w0_mm", pl.base_width * 1e3),
        ("w_r", pl.width_ratio),
        ("t_p_mm", m.pzt_thickness * 1e3),
        ("plies", m.layup_deg.len() as f64),
        ("w0*t_p_mm2", pl.base_width * m.pzt_thickness * 1e6),
        (
            "w*t^3/L_mm3",
            pl.nominal_width() * t.powi(3) / pl.length * 1e9,
        ),
    ]
}
