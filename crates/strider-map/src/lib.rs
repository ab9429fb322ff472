//! # strider-map
//!
//! The robot's colored 2.5D elevation map M_2.5D (Prágr22 §4.2, Prágr19 §IV) and everything computed
//! on it, one module per concept:
//!
//! * [`tiles`]: lazily allocated square tiles, one [`TiledLayer`] per layer (decision 1).
//! * [`map`]: [`ElevationMap`], its layers and dense rasters for rendering.
//! * [`changes`]: which blocks of cells changed since a revision, for incremental consumers.
//! * [`fusion`]: per-cell 1-D Kalman fusion of RGB-D scans with a Mahalanobis gate and the
//!   mixed-cell rule (Prágr22 Alg. 2 line 2, decision 2–3).
//! * [`passability`]: roughness and passability, Prágr22 Eq. 7–9, and configuration-space
//!   inflation (decision 4), maintained incrementally.
//! * [`reachability`]: cells reachable from the robot over admissible cells.
//! * [`descriptors`]: the 9-bin colour histogram ta(ν) (Prágr22 §4.2), the Prágr23 8-bin
//!   histogram, Lab (a, b) and the 5-D shape + Lab descriptor (Prágr19 Eq. 10, decision 7).
//! * [`c1_descriptors`]: the Prágr18 descriptor family (RGB/Lab of the cell or its
//!   neighbourhood; height, shape, orientation features) for the learner benchmark.
//! * [`observability`]: observable(ν, ν') by ray casting (Prágr22 Eq. 11, decision 5).
//! * [`information_gain`](mod@information_gain): I_cell (Prágr22 Eq. 10) and I_model (Prágr22 Eq. 11) on candidate cells.
//! * [`clustering`]: spatial goals by Prágr22 Alg. 3.
//! * [`frontiers`]: frontier representatives, n_r by Prágr19 Eq. 13.
//!
//! The crate knows nothing of the simulator or scenarios: it consumes
//! [`strider_core::PointCloud`]s and answers queries on cells of the global lattice.

pub mod c1_descriptors;
pub mod changes;
pub mod clustering;
pub mod descriptors;
pub mod frontiers;
pub mod fusion;
pub mod information_gain;
pub mod map;
pub mod observability;
pub mod params;
pub mod passability;
pub mod reachability;
pub mod rect;
pub mod tiles;

#[cfg(test)]
mod testing;

pub use clustering::{SpatialGoal, cluster_information};
pub use frontiers::{FrontierGoal, frontier_goals};
pub use fusion::FuseStats;
pub use information_gain::{InfoGain, information_gain};
pub use map::ElevationMap;
pub use observability::observable;
pub use params::{ColorMode, MapParams, ParamError};
pub use passability::Passability;
pub use reachability::Reachability;
pub use rect::WorldRect;
pub use tiles::TiledLayer;
