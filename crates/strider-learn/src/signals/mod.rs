//! Cost measurements from the robot's streams: what the learners are taught.
//!
//! Every estimator here is *streaming* and *allocation-free per tick*: all storage is a set of
//! fixed-capacity ring buffers (`Box<[T]>`, which cannot grow) allocated in the constructor, sized
//! from the window length and the stream's maximum rate. A tick does O(window) arithmetic and no
//! allocation.
//!
//! * [`InverseVelocityCost`] — the inverse-velocity cost of Prágr22 Eq. 19–20 with the tanh
//!   bound of decision 8: each pose tick, v⁻¹ = T / L over the last Δt of the trajectory (T the
//!   window's duration, L the horizontal path length along the sampled poses); a value is
//!   emitted only when the gait did not change within the window, attributed to the window's
//!   middle pose, smoothed by a moving average over the last Δt of raw values, and transformed
//!   by c = c_high · tanh((v⁻¹ / v_max⁻¹) / c_high) ([`tanh_bound`]). It also reports stuck
//!   (decision 9: v⁻¹ / v_max⁻¹ > c_max over a window walked in one gait).
//! * [`TurningTime`] — seconds spent turning within the cost window and within a smoothed
//!   sample's support, so that turns on the spot neither teach a cost nor trigger the stuck
//!   reflex.
//! * [`FallbackTimer`] — the stuck reflex's timer (decision 9: the rough-terrain gait for
//!   Δt_fallback).
//! * [`RollVarianceCost`] — the variance of the body roll over a sliding window (Prágr19 §IV:
//!   10 s, the gait-cycle duration), attributed to the window's middle pose.
//! * [`EnergyCost`] — energy per metre ∫P dt / distance over a window (MartinCorke), its
//!   motive part (total minus the hotel load), the hotel load per metre P_hotel / v̄, and the
//!   cost of transport P̄ / (m g v̄) (Prágr18).
//!
//! Input hygiene: samples with a non-finite stamp, position or value, and samples whose stamp does
//! not increase, are skipped and counted ([`SkipCounts`]); no output is ever NaN or infinite.
//! Distances are horizontal (x, y): the maps are 2.5D, costs multiply horizontal edge lengths in
//! the planner, and v_max is a horizontal walking speed.
//!
//! Files: `ring` (the fixed-capacity buffer) and `pose_track` (path length, gait and nearest pose
//! over a window) under every estimator, `window` (a proprioceptive scalar beside its pose track,
//! shared by roll variance and energy), `common` (parameter checks, skip counts, the cost
//! sample), then one file per signal.

mod common;
mod energy;
mod fallback;
mod inverse_velocity;
mod pose_track;
mod ring;
mod roll_variance;
mod turning;
mod window;

pub use common::{CostSample, SignalError, SkipCounts};
pub use energy::{EnergyCost, EnergyParams, EnergySample, STANDARD_GRAVITY, hotel_load_per_metre};
pub use fallback::FallbackTimer;
pub use inverse_velocity::{InverseVelocityCost, InverseVelocityParams, RATIO_CAP, tanh_bound};
pub use roll_variance::{RollVarianceCost, RollVarianceParams};
pub use turning::TurningTime;
