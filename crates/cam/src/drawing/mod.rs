//! From geometry to laser files: the drawing model, SVG and DXF writers, kerf offsets and a
//! single-stroke label font. Units are millimetres throughout; the model's y axis points up.

mod arc;
pub mod decimal;
pub mod dxf;
pub mod kerf;
pub mod label;
pub mod model;
pub mod palette;
pub mod svg;
