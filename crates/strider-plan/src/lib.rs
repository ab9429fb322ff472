//! Strider exploration-tour planning.
//!
//! * [`tsplib`] reads TSPLIB / GTSPLIB instance and tour files into a dense
//!   [`Instance`](tsplib::Instance).
//! * [`gtsp`] solves the (open or closed, symmetric or asymmetric)
//!   Generalized Traveling Salesman Problem: visit exactly one vertex of every
//!   set at minimum cost. See the module docs for the algorithm.

pub mod gtsp;
pub mod tsplib;

pub use gtsp::{Mode, Solution, SolveError, SolverParams, solve};
pub use tsplib::{CostMatrix, Instance, InstanceError, TsplibError};
