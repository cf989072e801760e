//! actuator-cam
pub mod optimize;
pub mod sweep;
