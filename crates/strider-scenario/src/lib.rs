//! # strider-scenario (skeleton; filled by the scenario work)
pub mod model;
pub use model::*;
