//! The process template: how a lab builds an actuator by one manufacturing method — the layers and their
//! materials, sheets, kerfs and spacings, the clamp panel, the cure recipe, and which laser operation each
//! drawn feature gets. Read once through the input layer; the layout pipeline and the reports use it.

mod cure;
pub mod drawn;
mod features;
pub mod laser;
pub mod linkage;
mod read;
pub mod template;

pub use drawn::DrawnSheet;
pub use features::{Feature, FeatureMap};
pub use template::Template;
