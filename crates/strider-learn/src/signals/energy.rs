//! Energy per metre and the cost of transport over the power stream.

use strider_core::geom::Point3;
use strider_core::msg::{GaitId, PoseStamped, Proprioception};

use super::common::{SignalError, SkipCounts, check_non_negative, check_positive};
use super::ring::Scalar;
use super::window::AttributedWindow;

/// Standard gravity, m/s², used by the cost of transport.
pub const STANDARD_GRAVITY: f64 = 9.806_65;

/// The hotel load per metre P_hotel / v, J/m, that the MartinCorke energy model adds to the learned
/// motive energy per metre (decision 12) for a gait walking at `speed` m/s. `None` when the speed
/// is not finite and positive or the load is not finite and non-negative.
pub fn hotel_load_per_metre(hotel_load_w: f64, speed: f64) -> Option<f64> {
    if speed.is_finite() && speed > 0.0 && hotel_load_w.is_finite() && hotel_load_w >= 0.0 {
        Some(hotel_load_w / speed)
    } else {
        None
    }
}

/// Parameters of [`EnergyCost`].
#[derive(Clone, Debug, PartialEq)]
pub struct EnergyParams {
    /// Window, seconds.
    pub window_s: f64,
    /// Robot mass m, kg (cost of transport).
    pub mass_kg: f64,
    /// Gravitational acceleration g, m/s².
    pub gravity: f64,
    /// Hotel load P_hotel, W: the constant draw of computers and sensors (MartinCorke).
    pub hotel_load_w: f64,
    /// Windows with a path shorter than this, metres, emit nothing (energy per metre is unbounded
    /// as the distance vanishes).
    pub min_distance_m: f64,
    /// Maximum proprioception rate, Hz; sizes the power ring.
    pub rate_hz: f64,
    /// Maximum pose rate, Hz; sizes the pose ring.
    pub pose_rate_hz: f64,
}

impl EnergyParams {
    /// Parameters with standard gravity, a 1 mm minimum distance and 20 Hz streams.
    pub fn new(window_s: f64, mass_kg: f64, hotel_load_w: f64) -> Self {
        Self {
            window_s,
            mass_kg,
            gravity: STANDARD_GRAVITY,
            hotel_load_w,
            min_distance_m: 1e-3,
            rate_hz: 20.0,
            pose_rate_hz: 20.0,
        }
    }
}

/// An energy measurement over one window, attributed to the window's middle pose.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EnergySample {
    /// Stamp of the middle pose.
    pub stamp: f64,
    /// Position of the middle pose.
    pub position: Point3,
    /// The gait used throughout the window.
    pub gait: GaitId,
    /// Total energy per metre E / d, J/m (MartinCorke).
    pub energy_per_m: f64,
    /// Motive energy per metre (E − P_hotel · T) / d, J/m: what the MartinCorke GP learns
    /// (decision 12).
    /// Can be slightly negative with noisy power readings; not clamped.
    pub motive_energy_per_m: f64,
    /// Hotel load per metre P_hotel / v̄ = P_hotel · T / d, J/m, at the window's mean speed.
    pub hotel_per_m: f64,
    /// Cost of transport P̄ / (m g v̄) = E / (m g d), dimensionless (Prágr18).
    pub cost_of_transport: f64,
    /// Horizontal distance travelled in the window, metres.
    pub distance_m: f64,
    /// Window duration T, seconds.
    pub duration_s: f64,
    /// Energy E = ∫P dt over the window, J (trapezoid rule on the power samples).
    pub energy_j: f64,
}

/// Energy per metre and cost of transport over a sliding window of the power stream
/// (MartinCorke, Prágr18). Emitted each proprioception tick once the window `[t − W, t]` is
/// full, the pose track covers it, the gait was constant and the distance is at least
/// `min_distance_m`; never inf or NaN.
#[derive(Clone, Debug)]
pub struct EnergyCost {
    params: EnergyParams,
    window: AttributedWindow,
    short_windows: u64,
}

impl EnergyCost {
    /// A new estimator; fails on invalid parameters.
    pub fn new(params: EnergyParams) -> Result<Self, SignalError> {
        check_positive("window_s", params.window_s)?;
        check_positive("mass_kg", params.mass_kg)?;
        check_positive("gravity", params.gravity)?;
        check_non_negative("hotel_load_w", params.hotel_load_w)?;
        check_positive("min_distance_m", params.min_distance_m)?;
        Ok(Self {
            window: AttributedWindow::new(params.window_s, params.rate_hz, params.pose_rate_hz)?,
            params,
            short_windows: 0,
        })
    }

    /// Feeds a pose of the pose stream (distance, attribution and gait).
    pub fn push_pose(&mut self, pose: &PoseStamped) {
        self.window.push_pose(pose);
    }

    /// Feeds a proprioceptive reading (its `power_w`); returns the window's energy figures.
    /// Negative power readings are treated as invalid (skipped as non-finite are).
    pub fn push(&mut self, p: &Proprioception) -> Option<EnergySample> {
        if p.power_w < 0.0 {
            self.window.skips.non_finite += 1;
            return None;
        }
        let (t0, t1) = (self.window.push(p.stamp, p.power_w)?, p.stamp);
        let track = &self.window.track;
        let gait = track.constant_gait(t0, t1)?;
        let distance = track.path_length(t0, t1)?;
        let mid = track.nearest(0.5 * (t0 + t1))?;
        if distance < self.params.min_distance_m {
            self.short_windows += 1;
            return None;
        }
        let energy = trapezoid_integral(self.window.values.iter());
        let duration = t1 - t0;
        let hotel = self.params.hotel_load_w * duration;
        let mg = self.params.mass_kg * self.params.gravity;
        let out = EnergySample {
            stamp: mid.stamp,
            position: mid.position,
            gait,
            energy_per_m: energy / distance,
            motive_energy_per_m: (energy - hotel) / distance,
            hotel_per_m: hotel / distance,
            cost_of_transport: energy / (mg * distance),
            distance_m: distance,
            duration_s: duration,
            energy_j: energy,
        };
        let finite = out.energy_per_m.is_finite()
            && out.motive_energy_per_m.is_finite()
            && out.hotel_per_m.is_finite()
            && out.cost_of_transport.is_finite();
        finite.then_some(out)
    }

    /// Counts of skipped samples (poses and readings).
    pub fn skips(&self) -> SkipCounts {
        self.window.skips
    }

    /// Full windows that emitted nothing because the distance was below `min_distance_m`.
    pub fn short_windows(&self) -> u64 {
        self.short_windows
    }

    /// Total capacity of the internal ring buffers; fixed at construction.
    pub fn capacity(&self) -> usize {
        self.window.capacity()
    }
}

/// ∫ value dt over time-ordered samples by the trapezoid rule (0 for fewer than two).
fn trapezoid_integral(samples: impl Iterator<Item = Scalar>) -> f64 {
    let mut integral = 0.0;
    let mut prev: Option<Scalar> = None;
    for s in samples {
        if let Some(q) = prev {
            integral += 0.5 * (q.value + s.value) * (s.stamp - q.stamp);
        }
        prev = Some(s);
    }
    integral
}
