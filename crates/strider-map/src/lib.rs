//! # strider-map (skeleton; filled by the map work)
pub mod params;
pub mod passability;
pub use params::{ColorMode, MapParams};
pub use passability::Passability;
