//! actuator-model: the physics of piezoelectric bimorph bending actuators (PZT / passive / PZT), as in
//! Lenzen, AFIT 2013, after Wood, Steltz & Fearing, Sensors and Actuators A 119 (2005).
//!
//! SI units throughout; no file or terminal I/O. The usual path:
//! [`Laminate::bimorph`] → [`Section::new`] at a [`Drive`] → [`performance::evaluate`] for a [`Planform`],
//! or [`model::predict`] to choose between the original, thesis-adjusted, nonlinear-ceramic and
//! Euler-Bernoulli models.

mod banded;
mod beam_element;
pub mod calibrated_base;
pub mod capacitance;
pub mod ceramic;
pub mod drive;
pub mod drive_energy;
pub mod dynamics;
pub mod effects;
pub mod empirical;
pub mod error;
pub mod euler_bernoulli;
pub mod flapping;
pub mod flexure;
pub mod fourbar;
pub mod kinematics;
pub mod lamina;
pub mod laminate;
pub mod large_deflection;
pub mod material;
pub mod model;
mod nearby_curvature;
pub mod nearby_modes;
pub mod nonlinear;
pub mod performance;
pub mod planform;
pub mod plate;
pub mod poling;
pub mod primitives;
mod quadrature;
pub mod rayleigh_tip_mass;
pub mod section;
pub mod transmission;
pub mod weibull;
pub mod wing;

pub use calibrated_base::Base;
pub use drive::{Drive, DriveMode};
pub use effects::{Actuator, Effects};
pub use error::ModelError;
pub use laminate::{Laminate, Layer, LayerRole};
pub use material::Material;
pub use model::{
    CalibratedModel, DeclaredEffect, EffectModel, MeasuredLoss, ModelChoice, ModelKind,
};
pub use performance::{MassBreakdown, Performance};
pub use planform::Planform;
pub use plate::PlatePeak;
pub use section::Section;
pub use weibull::Weibull;
