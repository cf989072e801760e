//! actuator-cam

pub mod layout;
