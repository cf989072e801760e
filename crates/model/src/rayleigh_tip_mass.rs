//! The published lumped tip mass of a rectangular actuator with a rigid extension (docs/physics.md §11.2),
//! the closed form the beam's own first mode is checked against (`dynamics.rs` tests).

/// Rayleigh static-shape tip mass of a rectangular actuator with a rigid extension (docs/physics.md
/// §11.2; the published form of Finio & Wood, ICRA 2005, after Wood, Steltz & Fearing 2005, a function of
/// the extension ratio and the mass ratio, test `rigid_extension_tip_mass_is_the_published_one`):
///
/// `m_eff / m_p = [(1+r)²/20 - (1+r)/36 + 1/252 + m_r ((a + b r)³ - a³) / (3 b r)] / D²`,
///
/// `r = l_ext / l_p`, `m_r = m_ext / m_p` (the mass ratio), `a = 1/3 + r/2`, `b = 1/2 + r`,
/// `D = 1/3 + r + r²`; `33/140` at `r = 0`. Returns `m_eff / m_p`.
pub fn rigid_extension_tip_mass_ratio(extension_ratio: f64, mass_ratio: f64) -> f64 {
    let r = extension_ratio;
    let d = 1.0 / 3.0 + r + r * r;
    let piezo = (1.0 + r).powi(2) / 20.0 - (1.0 + r) / 36.0 + 1.0 / 252.0;
    let extension = if r > 0.0 {
        let (a, b) = (1.0 / 3.0 + r / 2.0, 0.5 + r);
        mass_ratio * ((a + b * r).powi(3) - a.powi(3)) / (3.0 * b * r)
    } else {
        0.0
    };
    (piezo + extension) / (d * d)
}
