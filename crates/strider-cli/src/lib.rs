//! # strider-cli (library part)
//!
//! The glue between scenarios, the simulator and the mission that the `strider` binary and the
//! mission integration tests share: [`trial`] turns a scenario into mission parameters, runs a
//! mission in the simulator and drives the benchmark tours. The algorithms (map, learn, plan,
//! explore) do not depend on this crate or on the simulator.

pub mod c4_vegetation;
pub mod compare;
pub mod escape_trial;
pub mod trial;
