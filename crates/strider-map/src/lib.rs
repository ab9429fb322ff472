//! # strider-map (skeleton; filled by the map work)
pub mod params;
pub use params::{ColorMode, MapParams};
