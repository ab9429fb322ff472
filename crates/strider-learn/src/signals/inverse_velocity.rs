//! The inverse-velocity cost and the stuck detector over the pose stream.

use strider_core::msg::{GaitId, PoseStamped};

use super::common::{CostSample, SignalError, SkipCounts, check_positive, ring_capacity};
use super::pose_track::PoseTrack;
use super::ring::{Ring, Scalar, push_scalar};

/// Cap on the speed ratio (v⁻¹ / v_max⁻¹) used when the path length over a window is zero or
/// vanishingly small: a stuck robot's ratio is "infinite", which this finite stand-in represents
/// without producing inf/NaN in the moving average. `tanh(RATIO_CAP / c_high)` is exactly 1 in f64
/// for any sane c_high, so the transformed cost saturates at c_high as the true limit would.
pub const RATIO_CAP: f64 = 1e9;

/// The c = c_high · tanh(r / c_high) bound of Prágr22 Eq. 20 (decision 8) for a speed ratio
/// r = v⁻¹ / v_max⁻¹: ≈ r for small r (ideal terrain at v_max gives ≈ 1), saturating at c_high.
/// A non-finite or negative ratio is treated as saturated (c_high) resp. 0.
pub fn tanh_bound(ratio: f64, c_high: f64) -> f64 {
    if ratio.is_nan() || ratio == f64::INFINITY {
        return c_high;
    }
    c_high * (ratio.max(0.0) / c_high).tanh()
}

/// Parameters of [`InverseVelocityCost`] (Prágr22 Table 3 names in brackets).
#[derive(Clone, Debug, PartialEq)]
pub struct InverseVelocityParams {
    /// Window Δt over which v⁻¹ is measured, seconds (`delta_t`: 5 s small sim, 1 s large/real).
    pub window_s: f64,
    /// Length of the moving average over raw values, seconds (decision 8: Δt).
    pub smoothing_s: f64,
    /// Maximum (nominal) speed v_max of each gait, m/s, indexed by [`GaitId`] (`v_max`).
    pub v_max: Vec<f64>,
    /// Bound of the tanh transform (`c_high`, 20).
    pub c_high: f64,
    /// Stuck threshold on v⁻¹ / v_max⁻¹ (`c_max`, 20; decision 9).
    pub c_max: f64,
    /// Maximum pose rate, Hz; sizes the ring buffers (the pose stream is 20 Hz).
    pub rate_hz: f64,
}

impl InverseVelocityParams {
    /// Parameters with the moving average as long as the window (decision 8) and a 20 Hz stream.
    pub fn new(window_s: f64, v_max: Vec<f64>, c_high: f64, c_max: f64) -> Self {
        Self {
            window_s,
            smoothing_s: window_s,
            v_max,
            c_high,
            c_max,
            rate_hz: 20.0,
        }
    }
}

/// The inverse-velocity cost (Prágr22 Eq. 19–20, decision 8) and stuck detector (decision 9) over
/// the pose stream. See the module documentation for the exact procedure.
#[derive(Clone, Debug)]
pub struct InverseVelocityCost {
    params: InverseVelocityParams,
    track: PoseTrack,
    /// Raw speed ratios of the emitted ticks, for the moving average.
    smoothing: Ring<Scalar>,
    gait: Option<GaitId>,
    last_ratio: Option<f64>,
    stuck: bool,
    skips: SkipCounts,
}

impl InverseVelocityCost {
    /// A new estimator; fails when a parameter is non-finite or not positive (v_max of every
    /// gait included), or no gait is configured.
    pub fn new(params: InverseVelocityParams) -> Result<Self, SignalError> {
        check_positive("window_s", params.window_s)?;
        check_positive("smoothing_s", params.smoothing_s)?;
        check_positive("c_high", params.c_high)?;
        check_positive("c_max", params.c_max)?;
        check_positive("rate_hz", params.rate_hz)?;
        if params.v_max.is_empty() {
            return Err(SignalError::InvalidParameter {
                name: "v_max",
                value: 0.0,
                reason: "at least one gait speed is required",
            });
        }
        for &v in &params.v_max {
            check_positive("v_max", v)?;
        }
        let tol = 0.25 / params.rate_hz;
        Ok(Self {
            track: PoseTrack::new(ring_capacity(params.window_s, params.rate_hz), tol),
            smoothing: Ring::new(ring_capacity(params.smoothing_s, params.rate_hz)),
            params,
            gait: None,
            last_ratio: None,
            stuck: false,
            skips: SkipCounts::default(),
        })
    }

    /// The parameters.
    pub fn params(&self) -> &InverseVelocityParams {
        &self.params
    }

    /// Feeds the pose `pose` walked in gait `gait` (one 20 Hz tick). Returns the smoothed,
    /// transformed cost attributed to the window's middle pose when the window is full and the
    /// gait did not change within it.
    pub fn push(&mut self, pose: &PoseStamped, gait: GaitId) -> Option<CostSample> {
        let Some(&v_max) = self.params.v_max.get(gait.0 as usize) else {
            self.skips.unknown_gait += 1;
            return None;
        };
        if !self.track.push(pose, gait, &mut self.skips) {
            return None;
        }
        if self.gait != Some(gait) {
            // Raw ratios of another gait must not be averaged into this gait's values.
            self.gait = Some(gait);
            self.smoothing.clear();
        }
        let t = pose.stamp;
        let tol = self.track.tol;
        let start = t - self.params.window_s;
        self.track.retain_covering(start + tol);
        self.stuck = false;
        self.last_ratio = None;
        let first = self.track.ring.front()?;
        if first.stamp > start + tol {
            return None; // window not yet full
        }
        let duration = t - first.stamp;
        let length = self.track.path_length(first.stamp, t)?;
        // v⁻¹ / v_max⁻¹ = v_max · T / L, saturated without dividing by a vanishing length.
        let num = v_max * duration;
        let ratio = if length * RATIO_CAP > num {
            num / length
        } else {
            RATIO_CAP
        };
        self.last_ratio = Some(ratio);
        let gait_ok = self.track.constant_gait(first.stamp, t) == Some(gait);
        if !gait_ok {
            return None;
        }
        // Judged on a window walked in one gait only, the window a cost sample is taken from:
        // the tick that finds the robot stuck also teaches this gait's model the stuck cost.
        self.stuck = ratio > self.params.c_max;
        let mid = self.track.nearest(0.5 * (first.stamp + t))?;
        let mean = self.smoothed(t, ratio)?;
        Some(CostSample {
            stamp: mid.stamp,
            position: mid.position,
            gait,
            cost: tanh_bound(mean, self.params.c_high),
            raw: mean,
        })
    }

    /// Adds the raw ratio of the tick at `t` to the moving average over the last `smoothing_s`
    /// seconds and returns the average.
    fn smoothed(&mut self, t: f64, ratio: f64) -> Option<f64> {
        let tol = self.track.tol;
        if push_scalar(
            &mut self.smoothing,
            Scalar {
                stamp: t,
                value: ratio,
            },
            &mut SkipCounts::default(),
        ) {
            let keep_after = t - self.params.smoothing_s + tol;
            while self
                .smoothing
                .front()
                .is_some_and(|s| s.stamp <= keep_after)
            {
                self.smoothing.pop_front();
            }
        }
        let n = self.smoothing.len();
        if n == 0 {
            return None;
        }
        Some(self.smoothing.iter().map(|s| s.value).sum::<f64>() / n as f64)
    }

    /// [`push`](Self::push) with the gait recorded in the pose.
    pub fn push_pose(&mut self, pose: &PoseStamped) -> Option<CostSample> {
        self.push(pose, pose.gait)
    }

    /// True when, over the last full window, v⁻¹ / v_max⁻¹ > c_max (decision 9). Evaluated every
    /// tick whose full window was walked in the current gait (the windows cost samples come
    /// from, so the stuck window is also a sample); false while the window is not full or the
    /// gait changed within it.
    pub fn is_stuck(&self) -> bool {
        self.stuck
    }

    /// The raw (unsmoothed) v⁻¹ / v_max⁻¹ of the last tick with a full window, capped at
    /// [`RATIO_CAP`].
    pub fn last_ratio(&self) -> Option<f64> {
        self.last_ratio
    }

    /// Counts of skipped poses.
    pub fn skips(&self) -> SkipCounts {
        self.skips
    }

    /// Total capacity of the internal ring buffers; fixed at construction.
    pub fn capacity(&self) -> usize {
        self.track.ring.capacity() + self.smoothing.capacity()
    }

    /// Forgets the stream (keeps the buffers and the skip counts).
    pub fn reset(&mut self) {
        self.track.ring.clear();
        self.smoothing.clear();
        self.gait = None;
        self.last_ratio = None;
        self.stuck = false;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tanh_bound_limits() {
        assert_eq!(tanh_bound(f64::INFINITY, 20.0), 20.0);
        assert_eq!(tanh_bound(f64::NAN, 20.0), 20.0);
        assert_eq!(tanh_bound(RATIO_CAP, 20.0), 20.0);
        assert!((tanh_bound(1.0, 20.0) - 20.0 * (0.05f64).tanh()).abs() < 1e-15);
    }
}
