//! A rigid flapping wing about its stroke axis: inertia and quasi-steady blade-element drag
//! (docs/physics.md §13).

use crate::error::ModelError;
use crate::quadrature::GAUSS5;

/// Density of air at sea level, 15 °C (ISA), kg/m³.
pub const AIR_DENSITY: f64 = 1.225;

/// The wing as the drive sees it, SI.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Wing {
    /// Inertia about the stroke axis, kg·m²: the wing's own and its added mass.
    pub inertia: f64,
    /// The added mass's part of `inertia`, kg·m² (0 for a wing given directly).
    pub added_inertia: f64,
    /// Drag coefficient `K` in the torque `τ = K θ̇ |θ̇|`, N·m·s².
    pub damping: f64,
    /// Mass, kg (for the budget only when given directly; 0 if unknown).
    pub mass: f64,
}

/// Chord distribution along the span.
#[derive(Debug, Clone, PartialEq)]
pub enum Chord {
    /// Constant chord, m.
    Rectangle(f64),
    /// Half-ellipse `c(s) = c_max √(1 - (2s/R - 1)²)` over the span `s ∈ [0, R]`; `c_max` in m.
    Elliptic(f64),
    /// Piecewise linear through `(s, c)` points, `s` from the wing root, both m; `s` increasing from 0
    /// to the span.
    Table(Vec<(f64, f64)>),
}

/// A wing from its planform, SI.
#[derive(Debug, Clone, PartialEq)]
pub struct WingPlanform {
    /// Span from wing root to tip `R`, m.
    pub span: f64,
    /// Distance from the stroke axis to the wing root, m.
    pub root_offset: f64,
    /// Chord distribution.
    pub chord: Chord,
    /// Areal density of the membrane and veins, kg/m².
    pub areal_density: f64,
    /// Drag coefficient at the stroke's mid (wing at high angle of attack).
    pub drag_coefficient: f64,
    /// Air density, kg/m³.
    pub air_density: f64,
    /// Angle of attack at mid-stroke, rad: the wing's incidence to the stroke plane's motion.
    pub incidence: f64,
}

impl Chord {
    /// Chord at `s` from the wing root, m.
    pub fn at(&self, s: f64, span: f64) -> f64 {
        match self {
            Chord::Rectangle(c) => *c,
            Chord::Elliptic(c) => {
                let u = 2.0 * s / span - 1.0;
                c * (1.0 - u * u).max(0.0).sqrt()
            }
            Chord::Table(points) => {
                let i = points
                    .partition_point(|p| p.0 <= s)
                    .clamp(1, points.len() - 1);
                let ((s0, c0), (s1, c1)) = (points[i - 1], points[i]);
                c0 + (c1 - c0) * (s - s0) / (s1 - s0)
            }
        }
    }
}

impl WingPlanform {
    /// Check the planform: lengths, densities and the drag coefficient positive; a table's stations
    /// increasing from 0 to the span with chords >= 0.
    pub fn validate(&self) -> Result<(), ModelError> {
        let bad = |name, value, range| Err(ModelError::OutOfRange { name, value, range });
        for (name, v) in [
            ("span", self.span),
            ("areal_density", self.areal_density),
            ("drag_coefficient", self.drag_coefficient),
            ("air_density", self.air_density),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return bad(name, v, "greater than 0");
            }
        }
        if !(self.root_offset.is_finite() && self.root_offset >= 0.0) {
            return bad("root_offset", self.root_offset, "at least 0 m");
        }
        if !(self.incidence > 0.0 && self.incidence <= std::f64::consts::FRAC_PI_2) {
            return bad("incidence", self.incidence, "(0, π/2] rad");
        }
        match &self.chord {
            Chord::Rectangle(c) | Chord::Elliptic(c) if !(c.is_finite() && *c > 0.0) => {
                bad("chord", *c, "greater than 0 m")
            }
            Chord::Table(p) => {
                let ends = p.len() >= 2
                    && p[0].0 == 0.0
                    && (p[p.len() - 1].0 - self.span).abs() <= 1e-12 * self.span;
                let increasing = p.windows(2).all(|w| w[1].0 > w[0].0);
                let chords = p.iter().all(|q| q.1.is_finite() && q.1 >= 0.0);
                if ends && increasing && chords {
                    Ok(())
                } else {
                    bad(
                        "chord table",
                        p.len() as f64,
                        "stations increasing from 0 to the span, chords >= 0",
                    )
                }
            }
            _ => Ok(()),
        }
    }

    /// `∫ c(s)^m r^n ds` over the span, `r = r0 + s` (`chord_power` m, `power` n): Gauss-Legendre on 256
    /// panels (per table segment for a table, so each piece is a polynomial and the rule is exact; the
    /// half-ellipse's root singularity at its ends converges as panels⁻³ʹ²).
    fn moment_of(&self, chord_power: i32, power: i32) -> f64 {
        let pieces: Vec<(f64, f64)> = match &self.chord {
            Chord::Table(p) => p.windows(2).map(|w| (w[0].0, w[1].0)).collect(),
            _ => (0..256)
                .map(|i| {
                    let f = |k: usize| {
                        self.span * (1.0 - (std::f64::consts::PI * k as f64 / 256.0).cos()) / 2.0
                    };
                    (f(i), f(i + 1))
                })
                .collect(),
        };
        let mut total = 0.0;
        for (a, b) in pieces {
            let half = 0.5 * (b - a);
            for (xi, w) in GAUSS5 {
                let s = a + half * (xi + 1.0);
                total += w
                    * half
                    * self.chord.at(s, self.span).powi(chord_power)
                    * (self.root_offset + s).powi(power);
            }
        }
        total
    }

    /// `∫ c(s) r^n ds` over the span.
    fn moment(&self, power: i32) -> f64 {
        self.moment_of(1, power)
    }

    /// The added-mass inertia about the stroke axis, kg·m²: `(π/4) ρ sin²α ∫ c² r² dr`
    /// (docs/physics.md §13, "Added mass"). A strip of chord `c` accelerating normal to itself carries the
    /// air of a cylinder of diameter `c`, `ρ π c²/4` per unit span (Sane & Dickinson, J. Exp. Biol.
    /// 204:2607, 2001, eq. 7; Ellington, Phil. Trans. R. Soc. B 305:145, 1984, part IV). At incidence `α`
    /// the strip's acceleration `r θ̈` has the normal part `r θ̈ sin α`, and the normal force's part along
    /// the stroke is `sin α` of it again.
    pub fn added_inertia(&self) -> f64 {
        0.25 * std::f64::consts::PI
            * self.air_density
            * self.incidence.sin().powi(2)
            * self.moment_of(2, 2)
    }

    /// The wing's inertia `σ ∫ c r² dr` plus its [`Self::added_inertia`], drag coefficient
    /// `½ ρ C_D ∫ c r³ dr` and mass `σ ∫ c dr` (blade element, docs/physics.md §13).
    pub fn wing(&self) -> Result<Wing, ModelError> {
        self.validate()?;
        let added = self.added_inertia();
        Ok(Wing {
            inertia: self.areal_density * self.moment(2) + added,
            added_inertia: added,
            damping: 0.5 * self.air_density * self.drag_coefficient * self.moment(3),
            mass: self.areal_density * self.moment(0),
        })
    }

    /// Wing area `∫ c dr`, m².
    pub fn area(&self) -> f64 {
        self.moment(0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn planform(chord: Chord) -> WingPlanform {
        WingPlanform {
            span: 50e-3,
            root_offset: 5e-3,
            chord,
            areal_density: 0.02,
            drag_coefficient: 3.0,
            air_density: AIR_DENSITY,
            incidence: 37.5f64.to_radians(),
        }
    }

    #[test]
    fn rectangle_by_hand() {
        // I = σ c (r1³ - r0³)/3, K = ½ ρ C_D c (r1⁴ - r0⁴)/4, m = σ c R.
        let w = planform(Chord::Rectangle(18e-3)).wing().unwrap();
        let (r0, r1, c) = (5e-3f64, 55e-3f64, 18e-3);
        // Added mass: (π/4) ρ sin²α c² (r1³ - r0³)/3 (Sane & Dickinson 2001, eq. 7, over the span).
        let added = std::f64::consts::PI / 4.0
            * AIR_DENSITY
            * 37.5f64.to_radians().sin().powi(2)
            * c
            * c
            * (r1.powi(3) - r0.powi(3))
            / 3.0;
        assert!((w.added_inertia / added - 1.0).abs() < 1e-12);
        let i = 0.02 * c * (r1.powi(3) - r0.powi(3)) / 3.0 + added;
        let k = 0.5 * AIR_DENSITY * 3.0 * c * (r1.powi(4) - r0.powi(4)) / 4.0;
        assert!((w.inertia / i - 1.0).abs() < 1e-12);
        assert!((w.damping / k - 1.0).abs() < 1e-12);
        assert!((w.mass / (0.02 * c * 50e-3) - 1.0).abs() < 1e-12);
        // The same rectangle as a table.
        let t = planform(Chord::Table(vec![(0.0, c), (20e-3, c), (50e-3, c)]))
            .wing()
            .unwrap();
        assert!((t.inertia / i - 1.0).abs() < 1e-12 && (t.damping / k - 1.0).abs() < 1e-12);
    }

    #[test]
    fn half_ellipse_by_hand() {
        // Area π c R / 4; with r0 = 0, ∫ c r² dr = c R³ (5π/64) (moments of the half-ellipse about its
        // end: substitute s = R(1 + u)/2).
        let mut p = planform(Chord::Elliptic(20e-3));
        p.root_offset = 0.0;
        let area = std::f64::consts::PI * 20e-3 * 50e-3 / 4.0;
        assert!(
            (p.area() / area - 1.0).abs() < 1e-6,
            "{} vs {area}",
            p.area()
        );
        let i = 0.02 * 20e-3 * 50e-3f64.powi(3) * 5.0 * std::f64::consts::PI / 64.0;
        let w = p.wing().unwrap();
        assert!(((w.inertia - w.added_inertia) / i - 1.0).abs() < 1e-6);
        // ∫ c² s² ds = c² R³ ∫ (1 - u²) ((1 + u)/2)² du/2 over [-1, 1] = c² R³ / 5; at α = 90° the
        // added inertia is (π/4) ρ c² R³ / 5.
        p.incidence = std::f64::consts::FRAC_PI_2;
        let added =
            std::f64::consts::PI / 4.0 * AIR_DENSITY * 20e-3f64.powi(2) * 50e-3f64.powi(3) / 5.0;
        assert!(
            (p.added_inertia() / added - 1.0).abs() < 1e-6,
            "{}",
            p.added_inertia()
        );
    }

    #[test]
    fn bad_planforms_are_refused() {
        assert!(planform(Chord::Rectangle(-1.0)).wing().is_err());
        assert!(planform(Chord::Table(vec![(0.0, 1e-3), (20e-3, 1e-3)]))
            .wing()
            .is_err());
        let mut p = planform(Chord::Rectangle(1e-3));
        p.drag_coefficient = f64::NAN;
        assert!(p.wing().is_err());
        let mut p = planform(Chord::Rectangle(1e-3));
        p.incidence = 0.0;
        assert!(p.wing().is_err());
    }
}
