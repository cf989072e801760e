//! actuator-model
