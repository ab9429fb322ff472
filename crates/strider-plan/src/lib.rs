//! Strider exploration-tour planning.
//!
//! * [`tsplib`] reads TSPLIB / GTSPLIB instance and tour files into the solver's dense
//!   [`Instance`].
//! * [`gtsp`] solves the (open or closed, symmetric or asymmetric)
//!   Generalized Traveling Salesman Problem: visit exactly one vertex of every
//!   set at minimum cost. See the module docs for the algorithm.
//! * [`memory`]: the memory budget ([`memory::MEMORY_LIMIT_BYTES`]) the reader and the solver
//!   check before allocating their dense matrices.
//! * [`grid`] plans cheapest 8-connected paths on cost rasters (Dijkstra, A*, parallel
//!   all-pairs site costs) and builds the planning cost grid (best gait, c_loss distance
//!   transform, footprint max, gait choice).

pub mod grid;
pub mod gtsp;
pub mod memory;
pub mod tsplib;

pub use gtsp::{
    CostMatrix, Instance, InstanceError, MAX_TOUR_COST, Mode, Solution, SolveError, SolverParams,
    solve,
};
pub use memory::{MEMORY_LIMIT_BYTES, MemoryError};
pub use tsplib::TsplibError;
