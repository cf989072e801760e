//! Stress and strain along the plate: the moment of a tip load per unit width at each station of the
//! active length, and the largest PZT surface stress and strain it gives there (docs/physics.md §6,
//! "Stress and strain along the plate").

use crate::planform::Planform;
use crate::section::Section;

/// Relative margin by which a station must exceed the peak found so far to take its place, so that a
/// plate on the uniform-strain ridge, flat to rounding, reports its root.
const TIE: f64 = 1e-9;

/// The largest |σ_x| and |ε_x| on the PZT surfaces over the active length, and the station of each.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PlatePeak {
    /// Peak |σ_x|, Pa.
    pub stress: f64,
    /// Its station, `x / l_p`.
    pub stress_at: f64,
    /// Peak |ε_x|.
    pub strain: f64,
    /// Its station, `x / l_p`.
    pub strain_at: f64,
}

impl PlatePeak {
    /// The larger of two peaks, stress and strain each with its own station; `self` keeps a tie.
    pub fn max(self, other: PlatePeak) -> PlatePeak {
        let larger = |a: (f64, f64), b: (f64, f64)| if b.0 > a.0 * (1.0 + TIE) { b } else { a };
        let (stress, stress_at) = larger(
            (self.stress, self.stress_at),
            (other.stress, other.stress_at),
        );
        let (strain, strain_at) = larger(
            (self.strain, self.strain_at),
            (other.strain, other.strain_at),
        );
        PlatePeak {
            stress,
            stress_at,
            strain,
            strain_at,
        }
    }
}

/// Bending moment per unit width at station `x` of the active length under a tip load `F` at the end
/// of the extension, `M(x) / w(x) = F (L - x) / w(x)` with `L = l_tot` (the cantilever under an end
/// load, Timoshenko, *Strength of Materials* I, §31; docs/physics.md eq. 6.1), N·m/m.
pub fn moment_per_width(planform: &Planform, tip_load: f64, x: f64) -> f64 {
    tip_load * (planform.length - x) / planform.width_at(x)
}

/// Peak |σ_x| and |ε_x| over the PZT surfaces at station `x` (m from the clamp line), with the field
/// at `share` of the section's (signed) and a tip load `F` (N) holding the tip back against its free
/// bending: the free response scaled by `share` plus the response to `M(x) / w(x)` (CLT,
/// `ε = ε0 + z κ`, `σ = Q̄ (ε - d E3)`, thesis eqs. 2.17, 3.5; docs/physics.md eq. 6.2).
pub fn at_station(
    section: &Section,
    planform: &Planform,
    share: f64,
    tip_load: f64,
    x: f64,
) -> PlatePeak {
    let (stress, strain) =
        section.peak_pzt_stress_and_strain(share, moment_per_width(planform, tip_load, x));
    let at = x / planform.piezo_length();
    PlatePeak {
        stress,
        stress_at: at,
        strain,
        strain_at: at,
    }
}

/// Peak |σ_x| and |ε_x| along the active length from `start` (the beam's root: 0, or the end of a held
/// length) to `l_p`. `M(x)/w(x)` is monotone in `x` and each surface's stress and strain is linear in it,
/// so the peak lies at one end (docs/physics.md eq. 6.3); both ends are evaluated, the root keeping a tie.
pub fn peak(
    section: &Section,
    planform: &Planform,
    share: f64,
    tip_load: f64,
    start: f64,
) -> PlatePeak {
    let root = at_station(section, planform, share, tip_load, start);
    root.max(at_station(
        section,
        planform,
        share,
        tip_load,
        planform.piezo_length(),
    ))
}

/// Peak along the active length over a static stroke at the section's field, from free deflection (no
/// tip load) to blocked (`F_b`): the stress and strain are linear in the load, so these two ends bound
/// every load between them (docs/physics.md §6).
pub fn over_stroke(
    section: &Section,
    planform: &Planform,
    blocked_force: f64,
    start: f64,
) -> PlatePeak {
    peak(section, planform, 1.0, 0.0, start).max(peak(section, planform, 1.0, blocked_force, start))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::section::thesis_section as section;

    /// Blocked force `F_b = 3 P w_nom (1 + 2 l_r) / (2 C44 l_p G)` (thesis eq. 2.35, docs/physics.md §3).
    fn blocked_force(s: &Section, pl: &Planform) -> f64 {
        3.0 * s.free_curvature * pl.nominal_width() * (1.0 + 2.0 * pl.extension_ratio)
            / (2.0 * s.bending_compliance * pl.piezo_length() * pl.shape_factor())
    }

    /// Stations `x_j = j l_p / n`, `j = 0 … n`.
    fn stations(planform: &Planform, n: usize) -> impl Iterator<Item = f64> + '_ {
        (0..=n).map(move |j| planform.piezo_length() * j as f64 / n as f64)
    }

    #[test]
    fn the_moment_per_width_is_the_tip_load_arm_over_the_local_width() {
        // Source: Timoshenko, Strength of Materials I §31, M(x) = F (L - x) for a cantilever under an end
        // load; the width of docs/physics.md §1, w(x) = w_0 + (w_tip - w_0) x / l_p, written out here.
        for (l_r, w_r) in [(0.0, 1.0), (1.0, 1.75), (0.5, 1.5), (0.3, 0.6)] {
            let pl = Planform::new(50e-3, l_r, 20e-3, w_r, 0.0).unwrap();
            let (w_0, l_p) = (20e-3, 50e-3 / (1.0 + l_r));
            let w_tip = w_0 * (2.0 - w_r) / w_r;
            let force = 0.68;
            let at_root = force * 50e-3 / w_0;
            for x in stations(&pl, 16) {
                let want = force * (50e-3 - x) / (w_0 + (w_tip - w_0) * x / l_p);
                let got = moment_per_width(&pl, force, x);
                assert!(
                    (got - want).abs() < 1e-12 * at_root,
                    "{l_r} {w_r} {x}: {got} {want}"
                );
            }
        }
    }

    #[test]
    fn a_taper_on_the_uniform_strain_ridge_is_flat_along_the_plate() {
        // Source: docs/physics.md §3, the ridge w_r = 2 (1 + l_r)/(1 + 2 l_r) where M/w is uniform under a
        // tip load, and eq. 6.3: every station equal under the blocked force and under any other load.
        let s = section(267e-6, &[0.0, 90.0, 0.0]);
        for l_r in [0.5, 1.0, 2.5] {
            let w_r = 2.0 * (1.0 + l_r) / (1.0 + 2.0 * l_r);
            let pl = Planform::new(42.2e-3, l_r, 5e-3, w_r, 0.0).unwrap();
            let f_b = blocked_force(&s, &pl);
            for load in [f_b, -0.4 * f_b, 2.0 * f_b] {
                let root = at_station(&s, &pl, 1.0, load, 0.0);
                for x in stations(&pl, 64) {
                    let p = at_station(&s, &pl, 1.0, load, x);
                    assert!((p.stress / root.stress - 1.0).abs() < 1e-9, "{l_r} {x}");
                    assert!(
                        (p.strain - root.strain).abs() < 1e-9 * s.peak_pzt_strain,
                        "{l_r} {x}"
                    );
                }
                // A flat plate reports its root (the blocked strain is zero to rounding there, and
                // where it is has no meaning).
                let peak = peak(&s, &pl, 1.0, load, 0.0);
                assert_eq!(peak.stress_at, 0.0);
                if load != f_b {
                    assert_eq!(peak.strain_at, 0.0);
                }
            }
        }
    }

    #[test]
    fn the_peak_is_at_the_outer_end_past_the_ridge_and_at_the_root_for_a_rectangle() {
        // Source: docs/physics.md eq. 6.3: past the ridge (thesis design 7, w_r 1.75 against 4/3 at
        // l_r = 1) M/w grows toward the tip; a rectangle's falls from the root. The peak of the ends
        // is the peak of a 257-station profile.
        let s = section(267e-6, &[0.0, 0.0, 90.0, 0.0, 0.0]);
        for (l_r, w_r, end) in [(1.0, 1.75, 1.0), (1.0, 1.0, 0.0), (0.0, 1.0, 0.0)] {
            let pl = Planform::new(50e-3, l_r, 20e-3, w_r, 0.0).unwrap();
            let f_b = blocked_force(&s, &pl);
            let p = peak(&s, &pl, 1.0, f_b, 0.0);
            assert_eq!(p.stress_at, end, "{l_r} {w_r}");
            let profile = stations(&pl, 256)
                .map(|x| at_station(&s, &pl, 1.0, f_b, x))
                .fold(PlatePeak::default(), PlatePeak::max);
            assert!((p.stress / profile.stress - 1.0).abs() < 1e-12);
            assert!((p.strain / profile.strain - 1.0).abs() < 1e-12);
        }
    }

    #[test]
    fn design_7_blocked_strain_at_the_outer_end_is_the_closed_form() {
        // Source: docs/physics.md eq. 6.2 for a symmetric stack in parallel drive (ε0 = 0): the surface
        // strain is (t/2) κ with κ(x) = P - C44 F_b (L - x) / w(x), F_b of thesis eq. 2.35; at the outer
        // end of design 7, C44 F_b l_ext / (P w_tip) = 3 (1 + 2 l_r) l_r / (2 (2 - w_r) G), G(1.75, 1)
        // = 7.369320 (docs/physics.md §3 table), so |κ| = 1.44305 P.
        let s = section(267e-6, &[0.0, 0.0, 90.0, 0.0, 0.0]);
        let pl = Planform::new(50e-3, 1.0, 20e-3, 1.75, 0.0).unwrap();
        let ratio = 3.0 * 3.0 * 1.0 / (2.0 * 0.25 * 7.369_320);
        let want = 0.5 * s.thickness * s.free_curvature * (ratio - 1.0);
        let p = over_stroke(&s, &pl, blocked_force(&s, &pl), 0.0);
        assert!((p.strain / want - 1.0).abs() < 1e-6, "{} {want}", p.strain);
        assert_eq!(p.strain_at, 1.0);
        // The free strain P t/2 is smaller: the blocked end is the peak.
        assert!(p.strain > 1.4 * s.peak_pzt_strain);
    }
}
