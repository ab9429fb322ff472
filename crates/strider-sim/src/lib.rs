//! # strider-sim
//!
//! The 2.5D simulator: a source of sensor data and a judge of motion, nothing else. No mapping,
//! planning or learning happens here; the autonomy stack reaches the simulator only through the
//! sensor/actuator interface [`strider_core::interface::Robot`] that a real robot or a recorded
//! log implements too.
//!
//! ## Design
//!
//! The world of a [`strider_scenario::Scenario`] is a set of co-registered layers (elevation,
//! colour, terrain type) on the global cell lattice. The simulator sees the elevation as
//! flat-topped cell columns ([`heightfield`]) and casts the rays of its range sensors against them
//! exactly ([`sensor`]); it moves the robot along commanded polylines at the speed the terrain
//! allows its gait, refusing steps it cannot climb ([`motion`]); and it reports what a legged
//! robot feels ([`proprio`]): roll, power, vibration, bumper force. [`simulator`] ties these
//! into a [`Simulator`] that emits poses, clouds and proprioception in time order.
//! [`coverage`] is a scripted driving harness (coverage paths, ground-truth visibility) for the
//! CLI's map building and evaluation; it may read ground truth because it is not an algorithm.
//!
//! ## Determinism
//!
//! Time is simulated, never wall time. Every random draw comes from a ChaCha8 stream keyed by the
//! simulation seed and a purpose (motion, proprioception, pose noise, and per scan and per chunk
//! of rays), so runs are bit-identical for a seed and a command sequence, whatever the number of
//! rayon threads used to cast rays.
//!
//! ## Modules
//!
//! * [`heightfield`]: ray casting and line of sight against cell columns.
//! * [`sensor`]: RGB-D and omnidirectional sensors with depth and colour noise.
//! * [`motion`]: path following, terrain-dependent speed, steps, pushing through obstacles.
//! * [`proprio`]: roll process, power, vibration, bumper.
//! * [`bumper`]: the Prágr23 bumper's torque→force calibration (Table 4) and faults.
//! * [`terrain`]: the terrain table resolved per gait.
//! * [`simulator`]: the [`Simulator`] and its event loop.
//! * [`coverage`]: coverage paths and ground-truth visibility for harnesses.
//! * [`error`]: the error type [`SimError`].

pub mod bumper;
pub mod coverage;
pub mod error;
pub mod heightfield;
pub mod motion;
pub mod proprio;
mod seed;
pub mod sensor;
pub mod simulator;
pub mod terrain;

pub use bumper::{BumperCalibration, BumperParams};
pub use coverage::{admissible_cells, coverage_path, visible_cells};
pub use error::SimError;
pub use heightfield::{Face, Heightfield, RayHit};
pub use motion::{MotionParams, StepReport};
pub use proprio::ProprioParams;
pub use sensor::{RangeSensor, ScanNoise};
pub use simulator::{ModelParams, Simulator};
