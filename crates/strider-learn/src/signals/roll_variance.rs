//! The roll-variance cost over the proprioceptive stream.

use strider_core::msg::{PoseStamped, Proprioception};

use super::common::{CostSample, SignalError, SkipCounts};
use super::window::AttributedWindow;

/// Parameters of [`RollVarianceCost`].
#[derive(Clone, Debug, PartialEq)]
pub struct RollVarianceParams {
    /// Sliding window, seconds (Prágr19 §IV: 10 s, the gait-cycle duration).
    pub window_s: f64,
    /// Maximum proprioception rate, Hz; sizes the roll ring.
    pub rate_hz: f64,
    /// Maximum pose rate, Hz; sizes the pose ring.
    pub pose_rate_hz: f64,
}

impl Default for RollVarianceParams {
    fn default() -> Self {
        Self {
            window_s: 10.0,
            rate_hz: 20.0,
            pose_rate_hz: 20.0,
        }
    }
}

/// The roll-variance cost of Prágr19: the sample variance (n − 1) of the roll angles in the window
/// `[t − W, t]` (the newest sample at or before t − W included), emitted each proprioception tick
/// once the window is full and attributed to the pose nearest the window's middle time. Only
/// emitted when the gait did not change within the window.
///
/// Numerics: a corrected two-pass variance over the ring on every tick (O(window) flops, no
/// running sums), so a large common offset (e.g. 1e3 rad) causes no catastrophic cancellation.
#[derive(Clone, Debug)]
pub struct RollVarianceCost {
    window: AttributedWindow,
}

impl RollVarianceCost {
    /// A new estimator; fails on non-finite or non-positive parameters.
    pub fn new(params: RollVarianceParams) -> Result<Self, SignalError> {
        Ok(Self {
            window: AttributedWindow::new(params.window_s, params.rate_hz, params.pose_rate_hz)?,
        })
    }

    /// Feeds a pose of the pose stream (for attribution and the gait).
    pub fn push_pose(&mut self, pose: &PoseStamped) {
        self.window.push_pose(pose);
    }

    /// Feeds a proprioceptive reading; returns the roll variance over the window when it is
    /// full, a pose covers its middle and the gait was constant.
    pub fn push(&mut self, p: &Proprioception) -> Option<CostSample> {
        let t0 = self.window.push(p.stamp, p.roll)?;
        let track = &self.window.track;
        let gait = track.constant_gait(t0, p.stamp)?;
        if !track.covers(t0, p.stamp) {
            return None;
        }
        let mid = track.nearest(0.5 * (t0 + p.stamp))?;
        let rolls = &self.window.values;
        let var = two_pass_variance(rolls.iter().map(|s| s.value), rolls.len());
        Some(CostSample {
            stamp: mid.stamp,
            position: mid.position,
            gait,
            cost: var,
            raw: var,
        })
    }

    /// Counts of skipped samples (poses and readings).
    pub fn skips(&self) -> SkipCounts {
        self.window.skips
    }

    /// Total capacity of the internal ring buffers; fixed at construction.
    pub fn capacity(&self) -> usize {
        self.window.capacity()
    }
}

/// Corrected two-pass sample variance (n − 1) of `n ≥ 2` values.
fn two_pass_variance<I: Iterator<Item = f64> + Clone>(values: I, n: usize) -> f64 {
    let nf = n as f64;
    let mean = values.clone().sum::<f64>() / nf;
    let (mut s2, mut s1) = (0.0, 0.0);
    for v in values {
        let d = v - mean;
        s2 += d * d;
        s1 += d;
    }
    ((s2 - s1 * s1 / nf) / (nf - 1.0)).max(0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_pass_matches_textbook() {
        let v = [1.0, 2.0, 3.0, 4.0];
        let var = two_pass_variance(v.iter().copied(), 4);
        assert!((var - 5.0 / 3.0).abs() < 1e-15);
    }
}
