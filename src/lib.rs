//! actuator-cam

pub mod calibrate;
