//! Cost-aware path planning on dense rasters of the global cell lattice (Prágr22 Eq. 1–4, 12–13,
//! Alg. 4; decisions 4, 21, 22, 23).
//!
//! * [`cost_grid`] — [`CostGrid`], per-cell per-metre cost with `+∞` for inadmissible cells;
//! * [`dijkstra`] — reusable 8-connected Dijkstra / A* ([`Dijkstra`]), source-cell edge costs;
//! * [`all_pairs`](mod@all_pairs) — parallel cost matrix between sites ([`SiteCosts`]);
//! * [`hierarchy`] — site costs on large grids through a graph of portals between clusters;
//! * [`transform`] — best-gait grid, c_loss distance transform, footprint max, gait choice;
//! * [`smooth`] — any-angle line-of-sight smoothing of a cell path for driving;
//! * [`mean_edge`] — Dijkstra with the symmetric mean edge cost of Prágr19 Eq. 14;
//! * [`lcb`] — the softplus/ReLU lower-confidence-bound cost and path of Nardi19 Eq. 7–8
//!   (decision 26), on the same search.

pub mod all_pairs;
pub mod cost_grid;
pub mod dijkstra;
pub mod hierarchy;
pub mod lcb;
pub mod mean_edge;
pub mod smooth;
pub mod transform;

pub use all_pairs::{SiteCosts, all_pairs};
pub use cost_grid::{CostGrid, GridError};
pub use dijkstra::{Dijkstra, NO_PRED, SearchError, path_cost};
pub use hierarchy::{SiteCostCache, site_costs};
pub use mean_edge::MeanEdgeDijkstra;
pub use smooth::{segment_cost, segment_cost_between, smooth_between, smooth_path};
pub use transform::{
    BestGait, best_gait, choose_gait, choose_gait_with, distance_transform, footprint_max,
    planning_grid,
};
