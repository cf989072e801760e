//! actuator-cam
