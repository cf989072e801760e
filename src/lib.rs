//! actuator-cam

pub mod cam;
