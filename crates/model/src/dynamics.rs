//! The first bending mode of the actuator as built, and the lumped tip model the drive uses
//! (docs/physics.md §11).
//!
//! | part | bending stiffness per width | mass per length |
//! |---|---|---|
//! | active region `[h, l_p]`, tapered | `w(x) s_k / C44` (CLT section, thesis eq. 2.29) | `w(x)` × areal mass of every layer |
//! | extension `[l_p, l_tot]`, plies at `w_tip` | rigid, or `w_tip / (φ C44_pass)` with the compliant-extension effect | `w_tip` × areal mass of the plies |
//! | root | clamped; a rotational spring `c_θ` at `x = 0` with the clamp-compliance effect; `[0, h]` rigid with a rigid root | `[0, h]` rotates with the spring |
//!
//! The beam is cut into Hermite elements. Each element's stiffness is the exact flexibility of its
//! linearly tapered section (so the static tip stiffness equals the statics' `F_b / δ` to rounding), its
//! mass the consistent cubic-Hermite mass. The lumped model `k = F_b / δ`, `m = k / ω1²` reproduces both
//! the static stiffness and the first resonance.

use crate::banded::{dot, Band};
use crate::beam_element::Element;
use crate::effects::{Effects, StackBasis};
use crate::error::ModelError;
use crate::performance::{beam_tip_compliance, extension_tip_compliance, MassBreakdown};
use crate::planform::Planform;
use crate::section::Section;
use nalgebra::{DMatrix, DVector, Matrix4};

/// Quality factor of a built actuator's first resonance when none is given (docs/physics.md §11.4): an
/// assumption, 20, inside the Q of 18.6 and 21.8 measured on the two piezoelectric bending actuators of
/// the Berkeley MFI's 02γ thorax (Fearing lab, MFI 02γ design page), which check it and were not fitted.
/// It is below PZT-5H's own `Q_m = 32` (PSI-5H4E data sheet): the plies and bonds lose energy too.
pub const DEFAULT_QUALITY_FACTOR: f64 = 20.0;

/// Structural loss factor used when none is given, `η = 1/Q` (hysteretic damping `k (1 + iη)` has
/// `Q = 1/η` at resonance) of [`DEFAULT_QUALITY_FACTOR`].
pub const DEFAULT_LOSS_FACTOR: f64 = 1.0 / DEFAULT_QUALITY_FACTOR;

/// Elements over the active region in [`ActuatorBeam::solve`]; the test `first_frequency_converges`
/// shows the frequency settled to better than 1e-9 there.
pub const ACTIVE_ELEMENTS: usize = 32;

/// Elements over a compliant extension in [`ActuatorBeam::solve`].
pub const EXTENSION_ELEMENTS: usize = 12;

/// Elements over the active region and a compliant extension in [`ActuatorBeam::solve_coarse`]: `f1`
/// within 1e-4 of [`ActuatorBeam::solve`] (tests `the_screens_mesh_is_within_1e_4` in the optimizer and
/// `the_coarse_mesh_holds_with_added_masses_and_a_soft_clamp` here), at a tenth of the cost.
pub const COARSE_ELEMENTS: (usize, usize) = (8, 4);

/// The actuator as a beam: what its first mode depends on, SI.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ActuatorBeam {
    /// Planform (the base tab sits in the clamp and does not move).
    pub planform: Planform,
    /// Bending compliance per width `C44` of the active stack, 1/(N·m).
    pub bending_compliance: f64,
    /// Areal mass of the active stack (PZT, plies, bond), kg/m².
    pub areal_mass: f64,
    /// Areal mass of the extension (the plies), kg/m².
    pub extension_areal_mass: f64,
    /// Bending compliance per width of the extension, 1/(N·m); `None` for a rigid extension.
    pub extension_bending_compliance: Option<f64>,
    /// Rotational compliance of the clamp, rad/(N·m); 0 for a rigid clamp.
    pub clamp_compliance: f64,
    /// Root length of the PZT held rigidly in the clamp, m.
    pub rigid_root: f64,
    /// Uniform factor on the active region's bending stiffness (`s_k`, docs/calibration.md §2).
    pub stiffness_scale: f64,
    /// Line mass along the active region from mass on the PZT plates' long edges (adhesive fillets,
    /// the `added-mass-per-length` primitive), kg/m of beam length.
    pub edge_line_mass: f64,
    /// Point mass at the end of the active region `x = l_p` (the fillets on the plates' tip edges), kg.
    pub tip_point_mass: f64,
    /// Point mass at the actuator's tip, the end of the extension (`x = l_p` without one): a mass fitted
    /// there after weighing (the `tip-mass` primitive), kg.
    pub end_mass: f64,
}

/// The first mode and the static tip stiffness of an [`ActuatorBeam`], SI.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Modal {
    /// First natural frequency `f1`, Hz.
    pub frequency: f64,
    /// Static stiffness at the tip of the extension, `F / δ`, N/m.
    pub static_stiffness: f64,
    /// Rayleigh mass of the static tip-load shape, `∫ μ φ² dx` with `φ(tip) = 1`, kg.
    pub rayleigh_mass: f64,
}

impl Modal {
    /// Circular frequency `ω1 = 2π f1`, rad/s.
    pub fn angular_frequency(&self) -> f64 {
        2.0 * std::f64::consts::PI * self.frequency
    }

    /// Lumped tip mass `m = k / ω1²` (docs/physics.md §11.3), kg.
    pub fn modal_mass(&self) -> f64 {
        self.static_stiffness / self.angular_frequency().powi(2)
    }

    /// The mode with its static stiffness replaced by the statics' `k` (`F_b / δ` of the model): a
    /// uniform stiffness factor moves `k` and `ω1²` together and leaves `m = k / ω1²` alone (§11.3),
    /// so `f1 = √(k / m) / 2π`.
    pub fn with_stiffness(&self, stiffness: f64) -> Modal {
        Modal {
            frequency: self.frequency * (stiffness / self.static_stiffness).sqrt(),
            static_stiffness: stiffness,
            rayleigh_mass: self.rayleigh_mass,
        }
    }
}

/// The stiffness, the mass and the unit tip load on the held system's degrees of freedom (the clamped
/// root's dropped, or the clamp's turn `ψ` first).
type HeldSystem = (DMatrix<f64>, DMatrix<f64>, DVector<f64>);

/// A solved beam's mode and static shapes on the held system's degrees of freedom (the clamped
/// root's dropped, or the clamp's turn `ψ` first), for the Rayleigh quotients of `nearby_modes.rs`.
#[derive(Debug, Clone)]
pub(crate) struct Shapes {
    pub(crate) modal: Modal,
    /// The first mode, unit length.
    pub(crate) mode: Vec<f64>,
    /// The static deflection under the unit tip load.
    pub(crate) static_shape: Vec<f64>,
}

/// The actuator as the drive sees it at its tip: a force source behind a spring and a mass (SI).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LumpedActuator {
    /// Tip stiffness `k = F_b / δ`, N/m.
    pub stiffness: f64,
    /// Tip mass `m = k / ω1²`, kg.
    pub mass: f64,
    /// Structural loss factor η (hysteretic damping `k (1 + i η)`).
    pub loss_factor: f64,
}

impl LumpedActuator {
    /// The lumped model of a prediction: its stiffness `F_b / δ` and the beam's `k / ω1²` scaled to it
    /// (a uniform stiffness factor moves `k` and `ω1²` together and leaves `m` alone).
    pub fn new(stiffness: f64, modal: &Modal, loss_factor: f64) -> Self {
        LumpedActuator {
            stiffness,
            mass: modal.modal_mass(),
            loss_factor,
        }
    }

    /// Natural frequency `√(k/m) / 2π`, Hz.
    pub fn frequency(&self) -> f64 {
        (self.stiffness / self.mass).sqrt() / (2.0 * std::f64::consts::PI)
    }
}

impl ActuatorBeam {
    /// The beam of the original model: the section's `C44` and areal masses, rigid extension, rigid
    /// clamp.
    pub fn from_section(section: &Section, planform: &Planform) -> Self {
        ActuatorBeam {
            planform: *planform,
            bending_compliance: section.bending_compliance,
            areal_mass: section.pzt_areal_mass
                + section.passive_areal_mass
                + section.bond_areal_mass,
            extension_areal_mass: section.passive_areal_mass,
            extension_bending_compliance: None,
            clamp_compliance: 0.0,
            rigid_root: 0.0,
            stiffness_scale: 1.0,
            edge_line_mass: 0.0,
            tip_point_mass: 0.0,
            end_mass: 0.0,
        }
    }

    /// The beam of a model with effects: `C44` back from the basis' beam compliance
    /// (`c = C44 l_p³ G / (3 w_nom)`), the extension's from its bare-ply compliance times φ, the
    /// boundary effects as in [`Effects::outputs`], the areal masses from the effects' mass.
    ///
    /// The mass no layer carries is placed where its primitive puts it (docs/physics.md §11.4): the
    /// adhesive under the plates (`added-mass-per-area` μ) on the active region, `2 μ` per unit area; the
    /// fillets along the plates' outlines (`added-mass-per-length` λ) as a line mass `4 λ sec α` per unit
    /// length from the two long edges of both plates (α the half-taper angle) and a point mass `2 λ w_tip`
    /// from their tip edges, the root edges lying on the clamp line; the mass per actuator
    /// (`added-mass`: leads and solder on the base tab) in the clamp, where it does not move; the tip
    /// mass (`tip-mass`) at the tip, [`ActuatorBeam::end_mass`].
    pub fn from_effects(effects: &Effects, basis: &StackBasis, mass: &MassBreakdown) -> Self {
        let pl = basis.planform;
        let l_p = pl.piezo_length();
        // The section compliances the basis' tip compliances were made of (linear in them).
        let c44 = basis.beam_compliance / beam_tip_compliance(1.0, &pl);
        let a_pzt = pl.piezo_area();
        let half_taper = 0.5 * (pl.base_width - pl.tip_width());
        let passive_areal = mass.passive / (a_pzt + pl.extension_area() + pl.tab_area());
        let extension =
            (effects.extension_flexibility > 0.0 && pl.extension_ratio > 0.0).then(|| {
                effects.extension_flexibility * basis.extension_compliance
                    / extension_tip_compliance(1.0, &pl)
            });
        ActuatorBeam {
            planform: pl,
            bending_compliance: c44,
            areal_mass: (mass.pzt + mass.bond) / a_pzt
                + passive_areal
                + 2.0 * effects.added_mass_per_area,
            extension_areal_mass: passive_areal,
            extension_bending_compliance: extension,
            clamp_compliance: effects.clamp_compliance,
            // Clipped as the statics clip it (effects.rs `held_root`).
            rigid_root: effects.rigid_root.min(0.95 * l_p),
            stiffness_scale: effects.stiffness_scale,
            edge_line_mass: 4.0 * effects.added_mass_per_length * l_p.hypot(half_taper) / l_p,
            tip_point_mass: 2.0 * effects.added_mass_per_length * pl.tip_width(),
            end_mass: effects.tip_mass,
        }
    }

    /// Mass of the parts that move (active region from the clamp line and extension), kg.
    pub fn moving_mass(&self) -> f64 {
        let pl = &self.planform;
        self.areal_mass * pl.piezo_area()
            + self.extension_areal_mass * pl.extension_area()
            + self.edge_line_mass * pl.piezo_length()
            + self.tip_point_mass
            + self.end_mass
    }

    /// First mode and static stiffness with the default mesh ([`ACTIVE_ELEMENTS`],
    /// [`EXTENSION_ELEMENTS`]).
    pub fn solve(&self) -> Result<Modal, ModelError> {
        self.solve_with(ACTIVE_ELEMENTS, EXTENSION_ELEMENTS)
    }

    /// First mode and static stiffness on the coarse mesh ([`COARSE_ELEMENTS`]): the optimizer's screen
    /// and the calibration's fit, which solve it many times.
    pub fn solve_coarse(&self) -> Result<Modal, ModelError> {
        self.solve_with(COARSE_ELEMENTS.0, COARSE_ELEMENTS.1)
    }

    /// First mode and static stiffness with `active` elements over the free active length and
    /// `extension` over a compliant extension.
    pub fn solve_with(&self, active: usize, extension: usize) -> Result<Modal, ModelError> {
        self.solve_shapes(active, extension).map(|s| s.modal)
    }

    /// [`ActuatorBeam::solve_with`] with the held system's mode and static shapes.
    pub(crate) fn solve_shapes(
        &self,
        active: usize,
        extension: usize,
    ) -> Result<Shapes, ModelError> {
        self.check()?;
        let (kr, mr, fr) = self.held_system(active, extension);
        first_mode(&kr, &mr, &fr)
    }

    /// The held system with `active` (at least 1) and `extension` elements.
    fn held_system(&self, active: usize, extension: usize) -> HeldSystem {
        let active = active.max(1);
        let (elements, compliant) = self.mesh(active, extension);
        let mut kr = self.held_at_root(&assemble(&elements, Element::stiffness_matrix, |_| true));
        if self.clamp_compliance > 0.0 {
            kr[(0, 0)] += 1.0 / self.clamp_compliance;
        }
        let (mr, fr) = self.held_mass(&elements, active, compliant);
        (kr, mr, fr)
    }

    /// The held mass matrix and unit tip load on `elements` (this beam's [`ActuatorBeam::mesh`], `active`
    /// over the active length): where each mass sits on the beam (docs/physics.md §11.4), linear in the
    /// mass scalars, which `nearby_modes.rs` takes part by part.
    pub(crate) fn held_mass(
        &self,
        elements: &[Element],
        active: usize,
        compliant: bool,
    ) -> (DMatrix<f64>, DVector<f64>) {
        let mut m = assemble(elements, Element::mass_matrix, |_| true);
        // The tip edges' fillets at the end of the active region (node `active`).
        m[(2 * active, 2 * active)] += self.tip_point_mass;
        let load = self.tip_load(&mut m, compliant);
        let mut mr = self.held_at_root(&m);
        let full = load.len();
        let h = self.rigid_root;
        if self.clamp_compliance <= 0.0 {
            return (mr, load.rows(2, full - 2).into_owned());
        }
        let mut fr = DVector::<f64>::zeros(full - 1);
        fr[0] = h * load[0] + load[1];
        fr.rows_mut(1, full - 2).copy_from(&load.rows(2, full - 2));
        // ∫0..h μ(x) x² dx, μ linear in x: Simpson is exact for the cubic.
        let pl = &self.planform;
        let mu = |x: f64| self.areal_mass * pl.width_at(x) + self.edge_line_mass;
        mr[(0, 0)] += h / 6.0 * (4.0 * mu(h / 2.0) * h * h / 4.0 + mu(h) * h * h);
        (mr, fr)
    }

    /// The beam's elements: `active` over the free active length `[h, l_p]`, then `extension` over a
    /// compliant extension; and whether the extension is compliant (else it is rigid, or absent).
    pub(crate) fn mesh(&self, active: usize, extension: usize) -> (Vec<Element>, bool) {
        let pl = &self.planform;
        let l_p = pl.piezo_length();
        let l_ext = pl.extension_length();
        let h = self.rigid_root;
        let w_tip = pl.tip_width();
        let mut elements = Vec::new();
        for i in 0..active {
            let a = h + (l_p - h) * i as f64 / active as f64;
            let b = h + (l_p - h) * (i + 1) as f64 / active as f64;
            let stiff = |x: f64| self.stiffness_scale * pl.width_at(x) / self.bending_compliance;
            let line = |x: f64| self.areal_mass * pl.width_at(x) + self.edge_line_mass;
            elements.push(Element {
                a,
                b,
                stiffness: [stiff(a), stiff(b)],
                line_mass: [line(a), line(b)],
            });
        }
        let compliant = match self.extension_bending_compliance {
            Some(c) if l_ext > 0.0 => Some(w_tip / c),
            _ => None,
        };
        if let Some(ei) = compliant {
            let n = extension.max(1);
            let mu = self.extension_areal_mass * w_tip;
            for i in 0..n {
                elements.push(Element {
                    a: l_p + l_ext * i as f64 / n as f64,
                    b: l_p + l_ext * (i + 1) as f64 / n as f64,
                    stiffness: [ei, ei],
                    line_mass: [mu, mu],
                });
            }
        }
        (elements, compliant.is_some())
    }

    /// The unit tip load on the last node; a rigid extension (not `compliant`) adds its mass to
    /// the last node in `m` and moves the load to its end. The end mass sits where the load acts.
    fn tip_load(&self, m: &mut DMatrix<f64>, compliant: bool) -> DVector<f64> {
        let full = m.nrows();
        let l_ext = self.planform.extension_length();
        let w_tip = self.planform.tip_width();
        let last = full - 2;
        let mut load = DVector::<f64>::zeros(full);
        load[last] = 1.0;
        m[(last, last)] += self.end_mass;
        if !compliant && l_ext > 0.0 {
            // The end mass at `s = l_ext` moves as `v + θ l_ext`.
            let me = self.end_mass;
            m[(last, last + 1)] += me * l_ext;
            m[(last + 1, last)] += me * l_ext;
            m[(last + 1, last + 1)] += me * l_ext * l_ext;
            // The rigid extension: a line mass moving as `v + θ s`, `s` in [0, l_ext]; the tip load acts
            // at `s = l_ext`.
            let m_ext = self.extension_areal_mass * w_tip * l_ext;
            m[(last, last)] += m_ext;
            m[(last, last + 1)] += m_ext * l_ext / 2.0;
            m[(last + 1, last)] += m_ext * l_ext / 2.0;
            m[(last + 1, last + 1)] += m_ext * l_ext * l_ext / 3.0;
            load[last + 1] = l_ext;
        }
        load
    }

    /// A matrix on the system held at its root: clamped (the first node's two degrees of freedom
    /// dropped), or turning with the clamp's spring about x = 0 (a non-positive compliance is a clamp),
    /// the held root `[0, h]` rigid with it: (v, θ) at x = h is (h ψ, ψ), ψ first.
    pub(crate) fn held_at_root(&self, a: &DMatrix<f64>) -> DMatrix<f64> {
        let full = a.nrows();
        let h = self.rigid_root;
        if self.clamp_compliance <= 0.0 {
            return a.view((2, 2), (full - 2, full - 2)).into_owned();
        }
        let n = full - 1;
        let mut r = DMatrix::<f64>::zeros(n, n);
        let row = |j: usize| h * a[(0, j)] + a[(1, j)];
        r[(0, 0)] = h * row(0) + row(1);
        for j in 2..full {
            let v = row(j);
            r[(0, j - 1)] = v;
            r[(j - 1, 0)] = v;
        }
        r.view_mut((1, 1), (full - 2, full - 2))
            .copy_from(&a.view((2, 2), (full - 2, full - 2)));
        r
    }

    pub(crate) fn check(&self) -> Result<(), ModelError> {
        let positive = |name: &'static str, v: f64| {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(ModelError::OutOfRange {
                    name,
                    value: v,
                    range: "greater than 0",
                })
            }
        };
        positive("bending_compliance", self.bending_compliance)?;
        positive("areal_mass", self.areal_mass)?;
        positive("stiffness_scale", self.stiffness_scale)?;
        if let Some(c) = self.extension_bending_compliance {
            positive("extension_bending_compliance", c)?;
        }
        let nonneg = |name: &'static str, v: f64| {
            if v.is_finite() && v >= 0.0 {
                Ok(())
            } else {
                Err(ModelError::OutOfRange {
                    name,
                    value: v,
                    range: "at least 0",
                })
            }
        };
        nonneg("extension_areal_mass", self.extension_areal_mass)?;
        nonneg("clamp_compliance", self.clamp_compliance)?;
        nonneg("rigid_root", self.rigid_root)?;
        nonneg("edge_line_mass", self.edge_line_mass)?;
        nonneg("tip_point_mass", self.tip_point_mass)?;
        nonneg("end_mass", self.end_mass)?;
        if self.rigid_root >= self.planform.piezo_length() {
            return Err(ModelError::OutOfRange {
                name: "rigid_root",
                value: self.rigid_root,
                range: "[0, l_p) m",
            });
        }
        Ok(())
    }
}

/// The global matrix of each element's `matrix`, two degrees of freedom (v, θ) a node, over the
/// elements whose index `part` holds (the nearby modes' stiffness parts assemble one region at a time).
pub(crate) fn assemble(
    elements: &[Element],
    matrix: fn(&Element) -> Matrix4<f64>,
    part: impl Fn(usize) -> bool,
) -> DMatrix<f64> {
    let full = 2 * (elements.len() + 1);
    let mut a = DMatrix::<f64>::zeros(full, full);
    for (e, el) in elements.iter().enumerate().filter(|(e, _)| part(*e)) {
        let me = matrix(el);
        for r in 0..4 {
            for c in 0..4 {
                a[(2 * e + r, 2 * e + c)] += me[(r, c)];
            }
        }
    }
    a
}

/// The static tip compliance under the load `fr`, the Rayleigh mass of the static shape, and the
/// first mode of the held system (stiffness `kr`, mass `mr`), on their band (`banded.rs`: a Hermite
/// beam couples each degree of freedom to the three either side).
fn first_mode(
    kr: &DMatrix<f64>,
    mr: &DMatrix<f64>,
    fr: &DVector<f64>,
) -> Result<Shapes, ModelError> {
    let not_definite =
        || ModelError::Laminate("the actuator's beam stiffness is not positive definite".into());
    let (Some(k), Some(m)) = (Band::from_dense(kr), Band::from_dense(mr)) else {
        return Err(ModelError::Laminate(
            "the actuator's beam matrices are not banded".into(),
        ));
    };
    let chol = k.cholesky().ok_or_else(not_definite)?;
    let n = fr.len();
    let mut static_shape: Vec<f64> = fr.iter().copied().collect();
    chol.solve_in_place(&mut static_shape);
    let compliance = dot(fr.as_slice(), &static_shape);
    let mut x = static_shape.clone();
    let mut mx = vec![0.0; n];
    m.mul(&x, &mut mx);
    let rayleigh_mass = dot(&x, &mx) / (compliance * compliance);
    // Inverse iteration from the static shape: the first mode dominates it, and the ratio of the
    // first two eigenvalues (about 1/40 for a cantilever) makes each step gain more than a digit.
    // `y = K⁻¹ M x`; the quotient `xᵀMx / xᵀMy` takes `xᵀMy = yᵀMx` (M symmetric), so each step
    // costs one product with M and one solve.
    let mut eigenvalue = 1.0 / (compliance * rayleigh_mass);
    let mut y = vec![0.0; n];
    for _ in 0..200 {
        y.copy_from_slice(&mx);
        chol.solve_in_place(&mut y);
        let next = dot(&x, &mx) / dot(&y, &mx);
        let norm = dot(&y, &y).sqrt();
        for (xi, yi) in x.iter_mut().zip(&y) {
            *xi = yi / norm;
        }
        m.mul(&x, &mut mx);
        let done = ((next - eigenvalue) / next).abs() < 1e-15;
        eigenvalue = next;
        if done {
            break;
        }
    }
    // The last quotient, `xᵀMx / xᵀMK⁻¹Mx`: stationary in `x` as the Rayleigh quotient `xᵀKx / xᵀMx`
    // is, and without its rounding (the product with K cancels most where the mesh is fine).
    Ok(Shapes {
        modal: Modal {
            frequency: eigenvalue.sqrt() / (2.0 * std::f64::consts::PI),
            static_stiffness: 1.0 / compliance,
            rayleigh_mass,
        },
        mode: x,
        static_shape,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::performance::{evaluate, tip_compliance};
    use crate::rayleigh_tip_mass::rigid_extension_tip_mass_ratio;
    use crate::section::thesis_section;

    /// A uniform beam: `EI = w / C44`, `μ = w × areal mass`.
    fn uniform(length: f64, extension_ratio: f64) -> ActuatorBeam {
        ActuatorBeam {
            planform: Planform::new(length, extension_ratio, 5e-3, 1.0, 0.0).unwrap(),
            bending_compliance: 2.0e-3,
            areal_mass: 4.0,
            extension_areal_mass: 0.6,
            extension_bending_compliance: None,
            clamp_compliance: 0.0,
            rigid_root: 0.0,
            stiffness_scale: 1.0,
            edge_line_mass: 0.0,
            tip_point_mass: 0.0,
            end_mass: 0.0,
        }
    }

    #[test]
    fn the_default_quality_factor_is_that_of_built_bending_actuators() {
        // Source: the two piezoelectric bending actuators of the Berkeley MFI's 02γ thorax measured
        // Q = 18.6 and 21.8 (Fearing lab, MFI 02γ design page); PZT-5H's own Q_m is 32 (PSI-5H4E data
        // sheet). The default is an assumption inside the measured pair, below the ceramic's, η = 1/Q.
        assert!((18.6..=21.8).contains(&DEFAULT_QUALITY_FACTOR));
        assert_eq!(DEFAULT_LOSS_FACTOR * DEFAULT_QUALITY_FACTOR, 1.0);
    }

    #[test]
    fn uniform_cantilever_frequency_is_the_classical_one() {
        // Source: Euler-Bernoulli cantilever, β1 L = 1.87510407 (e.g. Rao, Vibration of Continuous
        // Systems, Table 11.1): f1 = (β1 L)² / (2π) √(EI / (μ L⁴)).
        let beam = uniform(30e-3, 0.0);
        let ei = 5e-3 / 2.0e-3;
        let mu = 4.0 * 5e-3;
        let l: f64 = 30e-3;
        let want = 1.875_104_068_7f64.powi(2) / (2.0 * std::f64::consts::PI)
            * (ei / (mu * l.powi(4))).sqrt();
        let got = beam.solve().unwrap();
        assert!(
            ((got.frequency - want) / want).abs() < 1e-4,
            "{} vs {want}",
            got.frequency
        );
        // The static tip stiffness of the same beam is 3 EI / L³.
        let k = 3.0 * ei / l.powi(3);
        assert!(
            ((got.static_stiffness - k) / k).abs() < 1e-9,
            "{} vs {k}",
            got.static_stiffness
        );
        // Rayleigh's static-shape mass is 33/140 of the beam (e.g. Blevins, Formulas for Natural
        // Frequency and Mode Shape, Table 6-2); the lumped mass k/ω1² is 3/1.8751⁴ = 0.2427 of it.
        let m_beam = mu * l;
        assert!(((got.rayleigh_mass - 33.0 / 140.0 * m_beam) / m_beam).abs() < 1e-10);
        let lumped = 3.0 / 1.875_104_068_7f64.powi(4) * m_beam;
        assert!(((got.modal_mass() - lumped) / lumped).abs() < 2e-4);
    }

    #[test]
    fn a_tip_mass_gives_the_classical_frequency_equation() {
        // Source: cantilever with a tip mass M, Blevins, Formulas for Natural Frequency and Mode Shape,
        // Table 8-1 case 8 (no rotary inertia): 1 + cos λ cosh λ + (M / m_b) λ (cos λ sinh λ -
        // sin λ cosh λ) = 0, f1 = λ² / (2π) √(EI / (μ L⁴)). The tip edges' fillets are such a mass.
        let bare = uniform(30e-3, 0.0);
        let (ei, mu, l) = (5e-3 / 2.0e-3, 4.0 * 5e-3, 30e-3f64);
        for ratio in [0.1, 0.5, 2.0] {
            let tip = ActuatorBeam {
                tip_point_mass: ratio * mu * l,
                ..bare
            };
            let g = |x: f64| {
                1.0 + x.cos() * x.cosh() + ratio * x * (x.cos() * x.sinh() - x.sin() * x.cosh())
            };
            let (mut lo, mut hi) = (0.5, 1.875_104_068_7);
            for _ in 0..200 {
                let mid = 0.5 * (lo + hi);
                if g(lo) * g(mid) <= 0.0 {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            let lambda = 0.5 * (lo + hi);
            let want =
                lambda * lambda / (2.0 * std::f64::consts::PI) * (ei / (mu * l.powi(4))).sqrt();
            let got = tip.solve().unwrap().frequency;
            assert!(
                ((got - want) / want).abs() < 1e-4,
                "M/m {ratio}: {got} vs {want}"
            );
        }
        // A line mass along the edges adds to μ: f1 falls as √(μ / (μ + μ_e)), the shape unchanged.
        let edged = ActuatorBeam {
            edge_line_mass: 0.25 * mu,
            ..bare
        };
        let ratio = edged.solve().unwrap().frequency / bare.solve().unwrap().frequency;
        assert!((ratio - (1.0f64 / 1.25).sqrt()).abs() < 1e-9, "{ratio}");
    }

    #[test]
    fn an_end_mass_sits_at_the_tip_of_the_extension() {
        // Without an extension the end is x = l_p: the classical tip-mass equation (Blevins, Table 8-1
        // case 8, as above) holds for it as for the fillets' point mass.
        let bare = uniform(30e-3, 0.0);
        let m = 0.5 * 4.0 * 5e-3 * 30e-3;
        let at_end = ActuatorBeam {
            end_mass: m,
            ..bare
        };
        let at_edge = ActuatorBeam {
            tip_point_mass: m,
            ..bare
        };
        let (f_end, f_edge) = (
            at_end.solve().unwrap().frequency,
            at_edge.solve().unwrap().frequency,
        );
        assert!((f_end / f_edge - 1.0).abs() < 1e-12, "{f_end} vs {f_edge}");
        // With an extension, a rigid one carries the mass at its end as a rigid body (`v + θ l_ext`),
        // a compliant one on its last node: as the compliant extension stiffens the two agree (their
        // difference falls as its compliance, 1.5e-6 at 1e-4 of the stack's; the solve rounds below
        // that), and the mass further out lowers f1 more than the same mass at x = l_p.
        let rigid = ActuatorBeam {
            end_mass: m,
            ..uniform(30e-3, 0.5)
        };
        let stiff = ActuatorBeam {
            extension_bending_compliance: Some(1e-4 * rigid.bending_compliance),
            ..rigid
        };
        let (f_rigid, f_stiff) = (
            rigid.solve().unwrap().frequency,
            stiff.solve().unwrap().frequency,
        );
        assert!(
            (f_stiff / f_rigid - 1.0).abs() < 1e-5,
            "{f_stiff} vs {f_rigid}"
        );
        let inboard = ActuatorBeam {
            end_mass: 0.0,
            tip_point_mass: m,
            ..rigid
        };
        assert!(f_rigid < inboard.solve().unwrap().frequency);
        // The moving mass counts it once.
        let moving = rigid.moving_mass() - uniform(30e-3, 0.5).moving_mass();
        assert!((moving / m - 1.0).abs() < 1e-12);
    }

    #[test]
    fn the_coarse_mesh_holds_with_added_masses_and_a_soft_clamp() {
        let bare = ActuatorBeam {
            planform: Planform::new(30e-3, 0.6, 6e-3, 1.5, 0.0).unwrap(),
            ..uniform(30e-3, 0.6)
        };
        let heavy = ActuatorBeam {
            edge_line_mass: 0.3 * bare.areal_mass * 6e-3,
            tip_point_mass: 0.2 * bare.areal_mass * 6e-3 * 18.75e-3,
            clamp_compliance: 5.0,
            extension_bending_compliance: Some(3.0 * bare.bending_compliance),
            ..bare
        };
        for beam in [bare, heavy] {
            let coarse = beam.solve_coarse().unwrap().frequency;
            let fine = beam.solve().unwrap().frequency;
            assert!((coarse / fine - 1.0).abs() < 1e-4, "{coarse} vs {fine}");
        }
    }

    /// A tapered beam with a rigid extension (267 µm PZT on [0/90/0]), where the mesh converges.
    fn converging() -> ActuatorBeam {
        let s = thesis_section(267e-6, &[0.0, 90.0, 0.0]);
        ActuatorBeam::from_section(
            &s,
            &Planform::new(42.2e-3, 0.833, 5e-3, 1.667, 0.0).unwrap(),
        )
    }

    #[test]
    fn first_frequency_converges() {
        // Hermite elements: the error in ω² falls as h⁴ or faster; with a taper and a rigid extension
        // the frequency on the default mesh agrees with a mesh four times finer to 1e-9.
        let beam = converging();
        let f = |n: usize| beam.solve_with(n, 4).unwrap().frequency;
        let fine = f(4 * ACTIVE_ELEMENTS);
        let errors: Vec<f64> = [2, 4, 8, ACTIVE_ELEMENTS]
            .iter()
            .map(|&n| ((f(n) - fine) / fine).abs())
            .collect();
        for pair in errors.windows(2) {
            assert!(pair[1] < pair[0] / 8.0, "{errors:?}");
        }
        assert!(errors[3] < 1e-9, "{errors:?}");
    }

    #[test]
    fn the_eigenvalue_quotient_is_as_close_as_docs_say() {
        // docs/physics.md §11.6: on the beam of `first_frequency_converges`, the inverse iteration's
        // quotient xᵀMx / xᵀMK⁻¹Mx at 128 elements lies 3.5e-10 from the h⁴ extrapolation of the 8- and
        // 32-element frequencies, the Rayleigh quotient xᵀKx / xᵀMx of the same mode 1.4e-9 (its
        // product with K cancels); on the coarse mesh the two agree to 1e-13.
        let beam = converging();
        let f = |n: usize| beam.solve_with(n, 4).unwrap().frequency;
        let product = |n: usize, e: usize| {
            let (k, m, _) = beam.held_system(n, e);
            let x = DVector::from_vec(beam.solve_shapes(n, e).unwrap().mode);
            (x.dot(&(&k * &x)) / x.dot(&(&m * &x))).sqrt() / (2.0 * std::f64::consts::PI)
        };
        let (f8, f32) = (f(8), f(32));
        let extrapolated = f32 + (f32 - f8) / 255.0;
        let off = |f: f64| (f / extrapolated - 1.0).abs();
        let (quotient, rayleigh) = (off(f(128)), off(product(128, 4)));
        assert!(quotient < 3.5e-10, "{quotient:e}");
        // The product's rounding, above the quotient's and below the figure §11.6 states.
        assert!(
            rayleigh < 1.5e-9 && rayleigh > quotient,
            "{rayleigh:e} {quotient:e}"
        );
        let (active, extension) = COARSE_ELEMENTS;
        let coarse = product(active, extension) / beam.solve_coarse().unwrap().frequency - 1.0;
        assert!(coarse.abs() < 1e-13, "{coarse:e}");
    }

    #[test]
    fn static_stiffness_is_the_statics_tip_stiffness() {
        // The beam's F/δ against the closed-form compliance of thesis eqs. 2.29-2.35 (planform.rs).
        for (t_p, layup, l, l_r, w0, w_r) in [
            (
                191e-6,
                &[0.0, 0.0, 90.0, 0.0, 0.0][..],
                50e-3,
                0.0,
                10e-3,
                1.0,
            ),
            (267e-6, &[0.0, 90.0, 0.0][..], 42.2e-3, 0.833, 5e-3, 1.667),
            (
                127e-6,
                &[0.0, 0.0, 90.0, 0.0, 0.0][..],
                50e-3,
                0.5,
                20e-3,
                1.5,
            ),
            (127e-6, &[0.0, 90.0, 0.0][..], 30e-3, 1.2, 6e-3, 0.3),
            (127e-6, &[0.0, 90.0, 0.0][..], 30e-3, 0.4, 6e-3, 1.97),
        ] {
            let s = thesis_section(t_p, layup);
            let pl = Planform::new(l, l_r, w0, w_r, 0.0).unwrap();
            let modal = ActuatorBeam::from_section(&s, &pl).solve().unwrap();
            let p = evaluate(&s, &pl);
            assert!(
                ((modal.static_stiffness - p.stiffness) / p.stiffness).abs() < 1e-9,
                "w_r {w_r}: {} vs {}",
                modal.static_stiffness,
                p.stiffness
            );
            assert!(
                ((1.0 / modal.static_stiffness - tip_compliance(&s, &pl)) * p.stiffness).abs()
                    < 1e-9
            );
        }
    }

    #[test]
    fn boundary_effects_move_the_stiffness_as_the_statics_do() {
        // Clamp compliance, rigid root, compliant extension and the stiffness scale, each alone and all
        // together: F_b/δ from Effects::outputs against the beam's static stiffness.
        let all = Effects {
            clamp_compliance: 0.4,
            rigid_root: 1.5e-3,
            extension_flexibility: 0.8,
            stiffness_scale: 0.9,
            dead_length: 1e-3,
            ..Effects::null()
        };
        let cases = [
            Effects {
                clamp_compliance: 0.4,
                ..Effects::null()
            },
            Effects {
                rigid_root: 1.5e-3,
                ..Effects::null()
            },
            Effects {
                extension_flexibility: 0.8,
                ..Effects::null()
            },
            Effects {
                stiffness_scale: 0.9,
                ..Effects::null()
            },
            all,
        ];
        crate::primitives::tests::with(|a| {
            let base = Effects::null().predict(a).unwrap().stiffness;
            for e in cases {
                let basis = e.basis(a).unwrap();
                let (d, f) = e.outputs(&basis);
                let beam = ActuatorBeam::from_effects(&e, &basis, &e.mass(a));
                let k = beam.solve().unwrap().static_stiffness;
                assert!(((k - f / d) / k).abs() < 1e-9, "{e:?}: {k} vs {}", f / d);
                assert!(
                    (k / base - 1.0).abs() > 1e-3,
                    "the effect moves the stiffness"
                );
            }
        });
    }

    #[test]
    fn rigid_extension_tip_mass_matches_the_closed_form() {
        // docs/physics.md §11.2: the beam's Rayleigh mass of a rectangle with a rigid extension against
        // m_p × rigid_extension_tip_mass_ratio(l_r, m_ext / m_p).
        for l_r in [0.0, 0.25, 0.833, 2.0] {
            let beam = uniform(40e-3, l_r);
            let pl = beam.planform;
            let m_p = beam.areal_mass * pl.piezo_area();
            let m_ext = beam.extension_areal_mass * pl.extension_area();
            let want = m_p * rigid_extension_tip_mass_ratio(l_r, m_ext / m_p);
            let got = beam.solve().unwrap().rayleigh_mass;
            assert!(
                ((got - want) / want).abs() < 1e-10,
                "{l_r}: {got} vs {want}"
            );
        }
        assert!((rigid_extension_tip_mass_ratio(0.0, 0.0) - 33.0 / 140.0).abs() < 1e-15);
    }

    #[test]
    fn rigid_extension_tip_mass_is_the_published_one() {
        // Source: the effective tip mass of a rectangular actuator with a rigid extension, Finio & Wood,
        // "Nonlinear performance limits for high energy density piezoelectric bending actuators", ICRA
        // 2005 (DOI 10.1109/ROBOT.2005.1570673), its Fig. 10, after Wood, Steltz & Fearing, Sens.
        // Actuators A 119 (2005) 476-488: over the whole actuator's mass, with l_r the extension ratio
        // and d_r the extension's mass per length over the active region's,
        // M = (33 + 7 l_r (13 + 9 l_r + 5 d_r (4 + 3 l_r (6 + l_r (11 + 2 l_r (5 + 2 l_r))))))
        //     / (140 (1 + d_r l_r) (1 + 3 l_r (1 + l_r))²).
        for l_r in [0.0f64, 0.25, 0.833, 2.0] {
            for d_r in [0.0, 0.1, 0.3, 1.5] {
                let published = (33.0
                    + 7.0
                        * l_r
                        * (13.0
                            + 9.0 * l_r
                            + 5.0
                                * d_r
                                * (4.0
                                    + 3.0
                                        * l_r
                                        * (6.0 + l_r * (11.0 + 2.0 * l_r * (5.0 + 2.0 * l_r))))))
                    / (140.0 * (1.0 + d_r * l_r) * (1.0 + 3.0 * l_r * (1.0 + l_r)).powi(2));
                let ours = rigid_extension_tip_mass_ratio(l_r, d_r * l_r) / (1.0 + d_r * l_r);
                assert!(
                    (ours / published - 1.0).abs() < 1e-12,
                    "{l_r} {d_r}: {ours} vs {published}"
                );
            }
        }
    }

    #[test]
    fn lumped_mass_sits_above_the_rayleigh_mass() {
        // Rayleigh's quotient bounds ω1² from above, so k/ω1² >= the static-shape mass: by 3 % for a
        // uniform cantilever (0.2427 against 0.2357), by more for a taper that puts its mass at the root,
        // where the static tip-load shape differs most from the mode.
        let s = thesis_section(267e-6, &[0.0, 90.0, 0.0]);
        for (l_r, w_r) in [(0.0, 1.0), (0.833, 1.0), (0.833, 1.667), (0.2, 0.5)] {
            let pl = Planform::new(42.2e-3, l_r, 5e-3, w_r, 0.0).unwrap();
            let modal = ActuatorBeam::from_section(&s, &pl).solve().unwrap();
            let ratio = modal.modal_mass() / modal.rayleigh_mass;
            assert!(ratio > 1.0, "{l_r} {w_r}: {ratio}");
            let lumped = LumpedActuator::new(modal.static_stiffness, &modal, DEFAULT_LOSS_FACTOR);
            assert!((lumped.frequency() / modal.frequency - 1.0).abs() < 1e-12);
        }
    }

    #[test]
    fn a_compliant_clamp_lowers_the_frequency_and_a_held_root_raises_it() {
        let s = thesis_section(191e-6, &[0.0, 90.0, 0.0]);
        let pl = Planform::new(30e-3, 0.0, 6e-3, 1.0, 0.0).unwrap();
        let bare = ActuatorBeam::from_section(&s, &pl);
        let f0 = bare.solve().unwrap().frequency;
        let soft = ActuatorBeam {
            clamp_compliance: 1.0,
            ..bare
        };
        let held = ActuatorBeam {
            rigid_root: 3e-3,
            ..bare
        };
        assert!(soft.solve().unwrap().frequency < f0);
        // A beam held over its first 3 mm is a 27 mm cantilever: f scales as 1/L².
        let f_held = held.solve().unwrap().frequency;
        assert!(((f_held / f0) - (30.0f64 / 27.0).powi(2)).abs() < 1e-9);
        assert!(ActuatorBeam {
            rigid_root: 31e-3,
            ..bare
        }
        .solve()
        .is_err());
    }
}
