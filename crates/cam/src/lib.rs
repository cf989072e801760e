//! actuator-cam: design files, predictions, laser-cut layer geometry and reports for piezoelectric bimorph
//! bending actuators, on top of the `actuator-model` physics crate.

pub mod batch;
pub mod book;
pub mod calibrate;
pub mod cam;
pub mod cutsheet;
pub mod design;
pub mod drive;
pub mod input;
pub mod layout;
pub mod linkage;
pub mod markdown;
pub mod optimize;
pub mod output;
pub mod parts;
pub mod pipeline;
pub mod plot;
pub mod prediction;
pub mod process;
pub mod sweep;
pub mod transmission;
