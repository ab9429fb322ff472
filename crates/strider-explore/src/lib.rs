//! # strider-explore
//!
//! Exploration missions with active traversal-cost learning (Prágr22 Alg. 1 and 4, decisions
//! 8–9, 16, 22–25):
//!
//! * [`params`]: what a mission needs to know about the robot and the task ([`MissionParams`]).
//! * [`planner`]: the merged planning grid (Eq. 12–13 with the distance transform of decision
//!   21), cheapest paths, gait choice (Alg. 4) and the exploration tour from an open GTSP over
//!   goal sets (Alg. 1 line 17, decision 23), or cheapest-goal-next for the greedy baseline.
//! * [`kernel`]: the mission kernel — one robot body (pose, map, keyframes, trajectory), one
//!   run loop, the shared manoeuvres, and the [`kernel::Strategy`] trait every method
//!   implements.
//! * [`tour_explorer`]: Prágr22 Alg. 1 on the kernel (`gtsp`, `greedy`, `spatial-only`) at the
//!   module rates of Tbl. 4, the sampling manoeuvre (decision 24), the stuck reflex (decision 9)
//!   and termination (decision 25).
//! * [`evaluate`]: benchmark tours after exploration under the flat, gait-selection and learned
//!   navigation modes (Prágr22 §5, Tbl. 5), timed per segment.
//! * [`registry`]: every strategy by name with its paper, typed parameters and needs.
//! * [`energy_tours`]: MartinCorke energy-optimal repeated tours — a zero-mean GP of motive energy
//!   per metre learnt from the power stream, waypoints ordered by the exact TSP, re-planned
//!   after every tour until the tour stops changing.
//! * [`escape`]: Prágr23 (thesis C4) escape exploration with a haptic bumper and a GP force predictor.
//! * [`rbcm_greedy`]: the Prágr19 explorer — RBCM of GP experts on the 5-D shape + Lab
//!   descriptor, roll-variance cost, cost map Mcost, frontier and median-σ goals, Eq. 16.
//! * [`navigate`]: Nardi19 repeated start–goal navigation with a GP mixture model and a softplus
//!   lower-confidence-bound planning cost.
//!
//! The crate reaches the robot only through [`strider_core::interface::Robot`]; it does not
//! depend on the simulator or on the scenario crate (which holds the ground-truth world), so the
//! learned models cannot read ground truth.

pub mod energy_tours;
pub mod escape;
pub mod evaluate;
pub mod kernel;
pub mod navigate;
pub mod params;
pub mod planner;
pub mod rbcm_greedy;
pub mod registry;
pub mod shadow;
mod timing;
pub mod tour_explorer;

pub use kernel::{
    Body, BodyParams, FromParams, Mission, MissionError, MissionProgress, RunRecord,
    Strategy as MissionStrategy, Termination,
};
pub use params::{GaitSpec, MissionParams, Rates, Strategy};
pub use tour_explorer::{Activity, MissionLog, PhaseWall, TourExplorer};
