//! actuator-cam

pub mod nest;
