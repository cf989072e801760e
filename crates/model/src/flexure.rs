//! A flexure hinge of the smart-composite-microstructure (SCM) process: a strip of polymer film left bare
//! in a gap between two rigid carbon-fibre links (Wood, Avadhanula, Sahai, Steltz & Fearing, J. Mech.
//! Des. 130, 2008). It bends as a short beam, a small-length flexural pivot (Howell, *Compliant
//! Mechanisms*, 2001, §5.1): the rigid links turn about the middle of the gap, and the film's bending
//! stiffness makes a torsional spring (docs/physics.md §16).

/// One flexure, SI.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Flexure {
    /// Gap length `L` along the links (the bare film between the links), m.
    pub length: f64,
    /// Width `w` across the links (along the hinge axis), m.
    pub width: f64,
    /// Film thickness `t`, m.
    pub thickness: f64,
    /// Film Young's modulus `E`, Pa.
    pub modulus: f64,
}

impl Flexure {
    /// Rotational stiffness of the bent film, `k = E I / L = E w t³ / (12 L)`, N·m/rad: a beam of length
    /// `L` bent into a circular arc by an end moment turns its ends by `φ = M L / (E I)` (Wood et al.
    /// 2008; Howell 2001, small-length flexural pivot; docs/physics.md §16.1).
    pub fn stiffness(&self) -> f64 {
        self.modulus * self.width * self.thickness.powi(3) / (12.0 * self.length)
    }

    /// Peak bending strain at the film surfaces when the flexure turns by `φ` (rad): the arc's curvature is
    /// `φ / L`, and the surfaces lie `t/2` from the neutral plane, so `ε = t φ / (2 L)` (docs/physics.md
    /// §16.2).
    pub fn strain(&self, rotation: f64) -> f64 {
        self.thickness * rotation.abs() / (2.0 * self.length)
    }

    /// The shortest gap that keeps the strain at `φ` within `strain_limit`: `L = t φ / (2 ε)`, m (the
    /// strain formula solved for the length).
    pub fn shortest_length_for(&self, rotation: f64, strain_limit: f64) -> f64 {
        self.thickness * rotation.abs() / (2.0 * strain_limit)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A cantilever of length L under an end moment M: the end slope is M L / (E I) (Gere & Timoshenko,
    /// *Mechanics of Materials*, table of cantilever deflections), I = w t³ / 12.
    #[test]
    fn stiffness_is_the_end_moment_over_the_end_slope_of_a_cantilever() {
        let f = Flexure {
            length: 100e-6,
            width: 2e-3,
            thickness: 7.6e-6,
            modulus: 2.5e9,
        };
        let inertia = f.width * f.thickness.powi(3) / 12.0;
        let moment = 1e-6;
        let slope = moment * f.length / (f.modulus * inertia);
        assert!((f.stiffness() - moment / slope).abs() < 1e-12 * f.stiffness());
        // A worked number: E w t³ / (12 L) = 2.5e9 · 2e-3 · 4.38976e-16 / 1.2e-3 = 1.82907e-6 N·m/rad.
        assert!(
            (f.stiffness() - 1.82907e-6).abs() < 1e-11,
            "{}",
            f.stiffness()
        );
        // Twice as long, half as stiff; twice as thick, eight times.
        let long = Flexure {
            length: 2.0 * f.length,
            ..f
        };
        let thick = Flexure {
            thickness: 2.0 * f.thickness,
            ..f
        };
        assert!((long.stiffness() * 2.0 / f.stiffness() - 1.0).abs() < 1e-12);
        assert!((thick.stiffness() / 8.0 / f.stiffness() - 1.0).abs() < 1e-12);
    }

    /// The arc's surface strain from geometry: a film of thickness t bent to radius R = L/φ stretches its
    /// outer surface to (R + t/2) φ against the neutral plane's R φ = L.
    #[test]
    fn strain_is_the_surface_stretch_of_the_bent_arc() {
        let f = Flexure {
            length: 50e-6,
            width: 3e-3,
            thickness: 7.6e-6,
            modulus: 2.5e9,
        };
        for phi in [0.1f64, 0.5, 1.0, std::f64::consts::FRAC_PI_3] {
            let radius = f.length / phi;
            let outer = (radius + f.thickness / 2.0) * phi;
            let stretch = (outer - f.length) / f.length;
            assert!((f.strain(phi) - stretch).abs() < 1e-15, "{phi}");
            assert_eq!(f.strain(-phi), f.strain(phi));
            let shortest = f.shortest_length_for(phi, 0.03);
            let at = Flexure {
                length: shortest,
                ..f
            };
            assert!((at.strain(phi) - 0.03).abs() < 1e-15);
        }
        // ±60° through a 50 µm gap of 7.6 µm film: 7.6 · 1.0472 / 100 = 7.96 %.
        assert!((f.strain(std::f64::consts::FRAC_PI_3) - 0.079587).abs() < 1e-6);
    }
}
