//! The first mode of many nearby beams from few solves (docs/physics.md §11.6): a fit moves the
//! beam's stiffness and mass a little at a time, and the frequency and static stiffness of a beam
//! close to a solved one follow from the solved beam's mode and static shapes by Rayleigh quotients,
//! whose error is second order in the change of shape, less their second-order terms
//! (`nearby_curvature.rs`), which leave it third order.
//!
//! On a fixed mesh the held system's stiffness and mass are sums of fixed parts, each times one of the
//! beam's scalars: `K = a_w K_w + a_e K_e + a_c e₀e₀ᵀ` (active region per `s_k / C44`, compliant
//! extension per `w_tip / C_ext`, clamp spring per `1/c_θ`) and `M = b_a M_a + b_l M_l + b_e M_e + b_t
//! e_t e_tᵀ + b_n e_n e_nᵀ` (areal mass, edge line mass, extension areal mass, tip point mass, end mass). A uniform factor on
//! every `a` (or every `b`) leaves the shapes as they are, so the shapes depend on the ratios
//! `a_e/a_w, a_c/a_w, b_l/b_a, b_e/b_a, b_t/b_a, b_n/b_a` alone. Each ratio falls in a cell 0.8 % to 1.6 % wide
//! (its leading binary digits); the beam at the middle of its cells (the cell's beam) is solved once,
//! and every beam in its cell gets
//!
//! `ω² = (Σ a_i φᵀK_iφ) / (Σ b_j φᵀM_jφ) - (a_w / b_a) dᵀGd` and `1/k = (fᵀu)² / Σ a_i uᵀK_iu + eᵀHe / a_w`,
//!
//! `φ` the cell beam's mode and `u` its static shape under the tip load `f`, `d` the change of the six
//! ratios from the cell beam's and `e` that of the two stiffness ratios: exact at the cell's ratios
//! (and any uniform scaling of them), and within [`TOLERANCE`] across the cell (tests
//! `nearby_modes_are_within_the_tolerance_of_a_solve`,
//! `with_their_second_order_terms_the_quotients_err_at_third_order`). The value is a function of the
//! beam alone, whatever was asked before, so results do not depend on the order of evaluation. The
//! solved cells are kept in a [`ModeCache`] the caller owns and shares among its users.

use crate::banded::dot;
use crate::dynamics::{ActuatorBeam, COARSE_ELEMENTS};
use crate::error::ModelError;
use crate::nearby_curvature::{mass_parts, unit_elements, Curvature, Ratios};
use nalgebra::DMatrix;
use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, OnceLock};

/// Mantissa bits of a ratio that name its cell: cells `2⁻⁶` of the ratio wide (from 0.8 % to 1.6 %),
/// read off the floating-point bits without a logarithm.
const RATIO_BITS: u32 = 6;
const SHIFT: u32 = f64::MANTISSA_DIGITS - 1 - RATIO_BITS;

/// Largest relative difference of the frequency and the static stiffness from those of
/// [`ActuatorBeam::solve_coarse`] of the same beam: a hundredth of the coarse mesh's own error (1e-4).
pub const TOLERANCE: f64 = 1e-6;

/// Parts of the stiffness: active region, compliant extension, clamp spring.
type StiffnessParts = [f64; 3];
/// Parts of the mass: active areal, edge line, extension areal, tip point, end point.
type MassParts = [f64; 5];

/// A cell: the beam's outline and held root (bits), and its ratios' leading bits (0 for a part the
/// beam lacks).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
struct Cell {
    frame: [u64; 5],
    ratios: [u64; 6],
}

/// The quadratic forms of a cell beam's shapes with each part, per unit scalar.
#[derive(Debug, Clone, Copy)]
struct Forms {
    mode_stiffness: StiffnessParts,
    mode_mass: MassParts,
    static_stiffness: StiffnessParts,
    /// `fᵀu`, the cell beam's static tip deflection per unit load at unit `a_w`.
    load_work: f64,
    /// The quotients' second-order terms in the change of the ratios.
    curvature: Curvature,
}

/// A beam's first frequency and static tip stiffness, SI (the two of [`crate::dynamics::Modal`] the Rayleigh quotients
/// give to second order).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FirstMode {
    /// `f1`, Hz.
    pub frequency: f64,
    /// `F / δ` at the tip, N/m.
    pub static_stiffness: f64,
}

impl FirstMode {
    /// `f1` with the static stiffness replaced by `stiffness` ([`crate::dynamics::Modal::with_stiffness`]).
    pub fn frequency_at(&self, stiffness: f64) -> f64 {
        self.frequency * (stiffness / self.static_stiffness).sqrt()
    }
}

/// The cells asked for by one user (the fits of one actuator's resonance), latest first, in front
/// of the cells its owner's [`ModeCache`] holds.
#[derive(Debug, Default)]
pub struct NearbyModes {
    recent: Vec<(Cell, Forms)>,
    /// Cells asked for that were not among the recent ones.
    looked_up: usize,
}

/// The cells solved for the users that share it (a calibration's resonances, and the fits on them): a
/// cell's forms are a function of the cell alone (its beam has fixed scalars), so any user, on any
/// data, may share them, and a value does not depend on which user solved it or when. Owned by the
/// caller and passed to [`NearbyModes::modal`]; safe to share between threads. Emptied past
/// `MOST_CELLS` (about 35 MB); a cell emptied is solved again to the same bits.
#[derive(Debug, Default)]
pub struct ModeCache {
    cells: Mutex<HashMap<Cell, Arc<Solving>, BuildHasherDefault<WordHasher>>>,
    /// How many cells were solved.
    solves: AtomicUsize,
}

/// A cell's forms, solved by the first user to ask; a user that asks while it is being solved waits
/// for it rather than solving it again: the fits that run at once on the same data ask for the same
/// cells at the same time.
type Solving = OnceLock<Result<Forms, ModelError>>;

/// Most cells kept in one [`ModeCache`].
const MOST_CELLS: usize = 50_000;

impl ModeCache {
    /// The forms of `cell` (whose ratios `beam` has), solved if no user of the cache has yet.
    fn solved(&self, cell: &Cell, beam: &ActuatorBeam) -> Result<Forms, ModelError> {
        let solving = {
            let mut cells = self
                .cells
                .lock()
                .unwrap_or_else(|poisoned| poisoned.into_inner());
            if !cells.contains_key(cell) && cells.len() >= MOST_CELLS {
                cells.clear();
            }
            Arc::clone(cells.entry(*cell).or_default())
        };
        // Solved outside the map's lock, once: other cells are looked up meanwhile.
        solving
            .get_or_init(|| {
                self.solves.fetch_add(1, Ordering::Relaxed);
                Forms::of(&cell.beam(beam))
            })
            .clone()
    }

    /// How many cells its users have had solved.
    pub fn solves(&self) -> usize {
        self.solves.load(Ordering::Relaxed)
    }
}

/// Cells compared before the map is looked in.
const RECENT: usize = 4;

/// A multiplicative hash of whole words (the cells' keys are bits, evenly spread in their low bits).
#[derive(Debug, Default)]
struct WordHasher(u64);

impl Hasher for WordHasher {
    fn finish(&self) -> u64 {
        self.0
    }
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.write_u64(b as u64);
        }
    }
    fn write_u64(&mut self, word: u64) {
        self.0 = (self.0.rotate_left(5) ^ word).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
    }
}

impl ActuatorBeam {
    /// The scalars the held system is linear in: stiffness `[s_k / C44, w_tip / C_ext, 1 / c_θ]` and
    /// mass `[areal, edge line, extension areal, tip point, end point]` (0 for a part the beam lacks).
    fn parts(&self) -> (StiffnessParts, MassParts) {
        let w_tip = self.planform.tip_width();
        let extension = match self.extension_bending_compliance {
            Some(c) if self.planform.extension_length() > 0.0 => w_tip / c,
            _ => 0.0,
        };
        let clamp = if self.clamp_compliance > 0.0 {
            1.0 / self.clamp_compliance
        } else {
            0.0
        };
        (
            [
                self.stiffness_scale / self.bending_compliance,
                extension,
                clamp,
            ],
            [
                self.areal_mass,
                self.edge_line_mass,
                self.extension_areal_mass,
                self.tip_point_mass,
                self.end_mass,
            ],
        )
    }
}

/// The ratios the shapes depend on: `[a_e, a_c] / a_w` and `[b_l, b_e, b_t, b_n] / b_a`.
fn ratios(a: &StiffnessParts, b: &MassParts) -> Ratios {
    [
        a[1] / a[0],
        a[2] / a[0],
        b[1] / b[0],
        b[2] / b[0],
        b[3] / b[0],
        b[4] / b[0],
    ]
}

/// The cell of the ratio `part / whole` (both finite, `whole > 0`): its leading bits, 0 for an absent
/// part.
fn rounded(part: f64, whole: f64) -> u64 {
    if part > 0.0 {
        (part / whole).to_bits() >> SHIFT
    } else {
        0
    }
}

/// The ratio in the middle of a cell, 0 for an absent part.
fn unrounded(cell: u64) -> f64 {
    if cell == 0 {
        0.0
    } else {
        f64::from_bits((cell << SHIFT) | (1 << (SHIFT - 1)))
    }
}

impl Cell {
    fn of(beam: &ActuatorBeam) -> Cell {
        let (a, b) = beam.parts();
        let p = &beam.planform;
        Cell {
            frame: [
                p.length.to_bits(),
                p.extension_ratio.to_bits(),
                p.base_width.to_bits(),
                p.width_ratio.to_bits(),
                beam.rigid_root.to_bits(),
            ],
            ratios: [
                rounded(a[1], a[0]),
                rounded(a[2], a[0]),
                rounded(b[1], b[0]),
                rounded(b[2], b[0]),
                rounded(b[3], b[0]),
                rounded(b[4], b[0]),
            ],
        }
    }

    /// The cell's beam: `beam`'s outline and held root at the cell's ratios, with `a_w = b_a = 1`.
    fn beam(&self, beam: &ActuatorBeam) -> ActuatorBeam {
        let [extension, clamp, edge, extension_mass, tip, end] = self.ratios.map(unrounded);
        ActuatorBeam {
            bending_compliance: 1.0,
            stiffness_scale: 1.0,
            extension_bending_compliance: (extension > 0.0)
                .then(|| beam.planform.tip_width() / extension),
            clamp_compliance: if clamp > 0.0 { 1.0 / clamp } else { 0.0 },
            areal_mass: 1.0,
            edge_line_mass: edge,
            extension_areal_mass: extension_mass,
            tip_point_mass: tip,
            end_mass: end,
            ..*beam
        }
    }
}

impl NearbyModes {
    /// The first frequency and the static stiffness of `beam` on the coarse mesh
    /// ([`ActuatorBeam::solve_coarse`]), each within [`TOLERANCE`]; the Rayleigh mass of the static
    /// shape, which is not stationary in the shape, is not given. A cell not among the recent ones is
    /// taken from `cells`, or solved and kept there.
    pub fn modal(
        &mut self,
        cells: &ModeCache,
        beam: &ActuatorBeam,
    ) -> Result<FirstMode, ModelError> {
        beam.check()?;
        let cell = Cell::of(beam);
        let forms = match self.recent.iter().position(|(c, _)| *c == cell) {
            Some(0) => self.recent[0].1,
            Some(at) => {
                self.recent[..=at].rotate_right(1);
                self.recent[0].1
            }
            None => {
                self.looked_up += 1;
                let forms = cells.solved(&cell, beam)?;
                self.recent.truncate(RECENT - 1);
                self.recent.insert(0, (cell, forms));
                forms
            }
        };
        Ok(forms.first_mode(beam))
    }

    /// How many times a beam fell outside the recent cells.
    pub fn looked_up(&self) -> usize {
        self.looked_up
    }
}

impl Forms {
    /// The quotients on these forms at `beam`, with their second-order terms (docs/physics.md §11.6).
    fn first_mode(&self, beam: &ActuatorBeam) -> FirstMode {
        let (a, b) = beam.parts();
        let (mode_term, static_term) = self.curvature.terms(&ratios(&a, &b));
        let omega2 =
            dot(&a, &self.mode_stiffness) / dot(&b, &self.mode_mass) - a[0] / b[0] * mode_term;
        let compliance =
            self.load_work.powi(2) / dot(&a, &self.static_stiffness) + static_term / a[0];
        FirstMode {
            frequency: omega2.sqrt() / (2.0 * std::f64::consts::PI),
            static_stiffness: 1.0 / compliance,
        }
    }

    fn of(beam: &ActuatorBeam) -> Result<Forms, ModelError> {
        let (active, extension) = COARSE_ELEMENTS;
        let shapes = beam.solve_shapes(active, extension)?;
        let (a, b) = beam.parts();
        let masses = mass_parts(beam);
        Ok(Forms {
            mode_stiffness: stiffness_forms(beam, &shapes.mode),
            mode_mass: mass_forms(&masses, &shapes.mode),
            static_stiffness: stiffness_forms(beam, &shapes.static_shape),
            load_work: 1.0 / shapes.modal.static_stiffness,
            curvature: Curvature::of(beam, &masses, ratios(&a, &b), &shapes),
        })
    }
}

/// `xᵀK_i x` of each stiffness part at unit scalar, `x` on the held system's degrees of freedom of
/// `beam` on the coarse mesh ([`ActuatorBeam::solve_shapes`]). The elements' forms are taken from their
/// deformation, end `b` against the rigid motion of end `a`: the nodal form `xᵀKx` would cancel most
/// of itself on a stiff extension.
fn stiffness_forms(beam: &ActuatorBeam, x: &[f64]) -> StiffnessParts {
    let active = COARSE_ELEMENTS.0;
    let h = beam.rigid_root;
    // The full degrees of freedom: the clamped root's are 0; a turning root's (v, θ) are (h ψ, ψ).
    let spring = beam.clamp_compliance > 0.0;
    let psi = if spring { x[0] } else { 0.0 };
    let mut full = vec![h * psi, psi];
    full.extend_from_slice(&x[spring as usize..]);
    let elements = unit_elements(beam);
    let mut k = [0.0; 3];
    for (e, el) in elements.iter().enumerate() {
        let [va, ta, vb, tb] = [0, 1, 2, 3].map(|i| full[2 * e + i]);
        let d = nalgebra::Vector2::new(vb - va - (el.b - el.a) * ta, tb - ta);
        k[(e >= active) as usize] += d.dot(&(el.end_stiffness() * d));
    }
    k[2] = psi * psi;
    k
}

/// `xᵀM_j x` of each mass part at unit scalar (`x` as in [`stiffness_forms`]), `masses` the held mass
/// matrices of the beam with that part's scalar 1 and the others 0, as the solve places them
/// ([`mass_parts`]; the mass is linear in the scalars).
fn mass_forms(masses: &[DMatrix<f64>; 5], x: &[f64]) -> MassParts {
    let x = nalgebra::DVector::from_column_slice(x);
    masses.each_ref().map(|m| x.dot(&(m * &x)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::planform::Planform;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// A tapered thesis-like actuator with an extension (the example data's first actuator: C44 and
    /// areal masses of a 0/90/0 CF stack on 267 µm PZT-5H), with every part present: a soft clamp, a
    /// held root, a compliant extension, edge fillets and a tip mass.
    fn full() -> ActuatorBeam {
        ActuatorBeam {
            planform: Planform::new(29.7e-3, 0.072, 6.1e-3, 1.3, 0.0).unwrap(),
            bending_compliance: 0.40,
            areal_mass: 4.47,
            extension_areal_mass: 0.30,
            // Plies a third as stiff per width as the active stack: a soft extension (φ = 1).
            extension_bending_compliance: Some(1.2),
            clamp_compliance: 0.4,
            rigid_root: 1.5e-3,
            stiffness_scale: 1.0,
            edge_line_mass: 2e-3,
            tip_point_mass: 2e-6,
            end_mass: 1e-6,
        }
    }

    /// The same actuator clamped, with a rigid extension and no added mass: the common beam.
    fn plain() -> ActuatorBeam {
        ActuatorBeam {
            extension_bending_compliance: None,
            clamp_compliance: 0.0,
            rigid_root: 0.0,
            edge_line_mass: 0.0,
            tip_point_mass: 0.0,
            end_mass: 0.0,
            ..full()
        }
    }

    /// `beam` with every scalar times `exp(spread z)`, z uniform on [-1, 1].
    fn moved(beam: &ActuatorBeam, spread: f64, rng: &mut ChaCha8Rng) -> ActuatorBeam {
        let mut f = || (spread * rng.gen_range(-1.0..1.0)).exp();
        ActuatorBeam {
            bending_compliance: beam.bending_compliance * f(),
            areal_mass: beam.areal_mass * f(),
            extension_areal_mass: beam.extension_areal_mass * f(),
            extension_bending_compliance: beam.extension_bending_compliance.map(|c| c * f()),
            clamp_compliance: beam.clamp_compliance * f(),
            stiffness_scale: beam.stiffness_scale * f(),
            edge_line_mass: beam.edge_line_mass * f(),
            tip_point_mass: beam.tip_point_mass * f(),
            end_mass: beam.end_mass * f(),
            ..*beam
        }
    }

    #[test]
    fn nearby_modes_are_within_the_tolerance_of_a_solve() {
        // Every part, then the common beams: clamped and rigid extension, then a soft clamp alone.
        let bases = [
            full(),
            plain(),
            ActuatorBeam {
                extension_bending_compliance: None,
                rigid_root: 0.0,
                clamp_compliance: 2.0,
                ..full()
            },
        ];
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let mut worst: f64 = 0.0;
        let cells = ModeCache::default();
        for base in bases {
            let mut modes = NearbyModes::default();
            // Wide moves land anywhere in a cell, on many cells.
            for _ in 0..300 {
                let beam = moved(&base, 0.3, &mut rng);
                let want = beam.solve_coarse().unwrap();
                let got = modes.modal(&cells, &beam).unwrap();
                for (g, w) in [
                    (got.frequency, want.frequency),
                    (got.static_stiffness, want.static_stiffness),
                ] {
                    worst = worst.max((g / w - 1.0).abs());
                }
            }
        }
        assert!(worst < TOLERANCE, "worst relative difference {worst:e}");
        // docs/physics.md §11.6 gives the worst of these 900 beams, 1.5e-7.
        assert!(worst < 1.5e-7, "worst relative difference {worst:e}");
        // Off the cell's ratios the quotients are close, not exact.
        assert!(
            worst > 1e-12,
            "the quotients should not be exact off the cell's ratios"
        );
    }

    #[test]
    fn a_fit_s_small_steps_share_a_cell_and_a_uniform_scale_is_exact() {
        let base = full();
        let (mut modes, cells) = (NearbyModes::default(), ModeCache::default());
        let mut rng = ChaCha8Rng::seed_from_u64(12);
        for _ in 0..100 {
            modes.modal(&cells, &moved(&base, 1e-5, &mut rng)).unwrap();
        }
        assert!(modes.looked_up() <= 8, "{} cells", modes.looked_up());
        // Every stiffness and every mass doubled: the same shapes, the same cell; f1 as it was, k doubled.
        let scaled = ActuatorBeam {
            stiffness_scale: 2.0,
            extension_bending_compliance: base.extension_bending_compliance.map(|c| c / 2.0),
            clamp_compliance: base.clamp_compliance / 2.0,
            areal_mass: 2.0 * base.areal_mass,
            extension_areal_mass: 2.0 * base.extension_areal_mass,
            edge_line_mass: 2.0 * base.edge_line_mass,
            tip_point_mass: 2.0 * base.tip_point_mass,
            end_mass: 2.0 * base.end_mass,
            ..base
        };
        let want = modes.modal(&cells, &base).unwrap();
        let looked_up = modes.looked_up();
        let got = modes.modal(&cells, &scaled).unwrap();
        assert_eq!(modes.looked_up(), looked_up);
        assert!((got.frequency / want.frequency - 1.0).abs() < 1e-12);
        assert!((got.static_stiffness / (2.0 * want.static_stiffness) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn a_shared_cache_gives_each_beam_what_a_fresh_one_gives() {
        // The value is a function of the beam alone: a cache filled by other users, on other beams and
        // in another order, gives the same bits as one that solves the beam's cell itself.
        let mut rng = ChaCha8Rng::seed_from_u64(13);
        let bases = [full(), plain()];
        let beams: Vec<ActuatorBeam> = (0..40)
            .map(|i| moved(&bases[i % 2], 0.05, &mut rng))
            .collect();
        let shared = ModeCache::default();
        let mut others = NearbyModes::default();
        for beam in beams.iter().rev() {
            others.modal(&shared, beam).unwrap();
        }
        let mut user = NearbyModes::default();
        for beam in &beams {
            let fresh = NearbyModes::default()
                .modal(&ModeCache::default(), beam)
                .unwrap();
            assert_eq!(user.modal(&shared, beam).unwrap(), fresh);
        }
    }

    #[test]
    fn users_that_ask_for_one_cell_at_once_have_it_solved_once() {
        // Eight threads ask for the same forty beams at the same time, each in its own order: each
        // cell is solved once, the others wait for it, and every thread gets what a fresh cache gives.
        let mut rng = ChaCha8Rng::seed_from_u64(14);
        let beams: Vec<ActuatorBeam> = (0..40).map(|_| moved(&full(), 0.2, &mut rng)).collect();
        let want: Vec<FirstMode> = beams
            .iter()
            .map(|b| {
                NearbyModes::default()
                    .modal(&ModeCache::default(), b)
                    .unwrap()
            })
            .collect();
        let cells: std::collections::HashSet<Cell> = beams.iter().map(Cell::of).collect();
        let shared = ModeCache::default();
        let start = std::sync::Barrier::new(8);
        std::thread::scope(|scope| {
            for t in 0..8 {
                let (beams, want, shared, start) = (&beams, &want, &shared, &start);
                scope.spawn(move || {
                    let mut user = NearbyModes::default();
                    start.wait();
                    for k in (0..beams.len()).map(|k| (k * (2 * t + 1)) % beams.len()) {
                        assert_eq!(user.modal(shared, &beams[k]).unwrap(), want[k]);
                    }
                });
            }
        });
        assert_eq!(shared.solves(), cells.len());
    }

    #[test]
    fn a_beam_out_of_range_is_refused_as_the_solve_refuses_it() {
        let bad = ActuatorBeam {
            areal_mass: f64::NAN,
            ..full()
        };
        assert!(bad.solve_coarse().is_err());
        assert!(NearbyModes::default()
            .modal(&ModeCache::default(), &bad)
            .is_err());
    }

    /// The quotients with their second-order terms on the forms of one solved beam, against a solve
    /// of each moved beam: tapered with every part (soft extension, soft clamp, held root, edge fillets,
    /// tip and end masses), clamped with a rigid extension, and a soft clamp with a tip mass. Every ratio
    /// moved by `s` (alternately up and down): the worst relative error of `f1` and `k` falls eightfold
    /// as `s` halves (third order; the quotients alone fall fourfold), and at the edge of a cell it is
    /// inside [`TOLERANCE`].
    #[test]
    fn with_their_second_order_terms_the_quotients_err_at_third_order() {
        let soft_clamp = ActuatorBeam {
            extension_bending_compliance: None,
            clamp_compliance: 2.0,
            end_mass: 3e-6,
            ..full()
        };
        for base in [full(), plain(), soft_clamp] {
            let solved = Cell::of(&base).beam(&base);
            let forms = Forms::of(&solved).unwrap();
            let error = |s: f64| {
                let f = |k: usize| 1.0 + if k.is_multiple_of(2) { s } else { -s };
                let beam = ActuatorBeam {
                    extension_bending_compliance: solved
                        .extension_bending_compliance
                        .map(|c| c * f(0)),
                    clamp_compliance: solved.clamp_compliance * f(1),
                    edge_line_mass: solved.edge_line_mass * f(2),
                    extension_areal_mass: solved.extension_areal_mass * f(3),
                    tip_point_mass: solved.tip_point_mass * f(4),
                    end_mass: solved.end_mass * f(5),
                    ..solved
                };
                let want = beam.solve_coarse().unwrap();
                let got = forms.first_mode(&beam);
                ((got.frequency / want.frequency - 1.0).abs())
                    .max((got.static_stiffness / want.static_stiffness - 1.0).abs())
            };
            let (wide, half) = (error(0.08), error(0.04));
            assert!(wide / half > 6.0, "{wide:e} then {half:e}");
            // A cell is 0.8 % to 1.6 % of its ratios wide: a beam's ratios lie within 0.8 % of its
            // cell beam's.
            assert!(error(0.008) < TOLERANCE, "{:e}", error(0.008));
        }
    }

    #[test]
    fn near_a_rigid_extension_the_quotients_hold_where_the_solve_rounds() {
        // An extension φ times as compliant as plies a third as stiff as the stack: f1 and k tend to
        // the rigid extension's as φ → 0, the compliance `1/k` as `(1 + c φ) / k_rigid` (the
        // cantilever is statically determinate: the extension's bending adds to the tip deflection,
        // in proportion to its compliance; c taken at φ = 1). The solve's rounding
        // grows with the extension's stiffness (about 5e-6 at φ = 1e-5); the quotients, which take
        // the solved shapes only to second order, stay on the line.
        let base = plain();
        let rigid = base.solve_coarse().unwrap();
        let at = |phi: f64| {
            NearbyModes::default()
                .modal(
                    &ModeCache::default(),
                    &ActuatorBeam {
                        extension_bending_compliance: Some(1.2 * phi),
                        ..base
                    },
                )
                .unwrap()
        };
        // docs/physics.md §11.6: the solve's f1 wanders by about 5e-6 at φ = 1e-5.
        let solved = ActuatorBeam {
            extension_bending_compliance: Some(1.2e-5),
            ..base
        }
        .solve_coarse()
        .unwrap();
        let wander = (solved.frequency / rigid.frequency - 1.0).abs();
        assert!((1e-6..1e-5).contains(&wander), "{wander:e}");
        let c = rigid.static_stiffness / at(1.0).static_stiffness - 1.0;
        for phi in [1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7] {
            let m = at(phi);
            assert!(
                (m.frequency / rigid.frequency - 1.0).abs() < 1e-8,
                "φ {phi}"
            );
            let compliance = rigid.static_stiffness / m.static_stiffness;
            assert!(
                (compliance - (1.0 + c * phi)).abs() < 1e-3 * c * phi + 1e-9,
                "φ {phi}: {compliance}"
            );
        }
    }
}
