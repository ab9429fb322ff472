//! A proprioceptive scalar over a sliding window beside the pose track that places it: what the
//! roll-variance and the energy estimators share.

use strider_core::msg::PoseStamped;

use super::common::{SignalError, SkipCounts, check_positive, ring_capacity};
use super::pose_track::PoseTrack;
use super::ring::{Ring, Scalar, push_scalar};

/// The readings of one proprioceptive scalar in the window `[t − W, t]` (the newest reading at
/// or before t − W included), and the track of the poses over the window, which gives its path
/// length, its gait and its middle pose.
#[derive(Clone, Debug)]
pub(super) struct AttributedWindow {
    window_s: f64,
    rate_hz: f64,
    pose_rate_hz: f64,
    pub(super) values: Ring<Scalar>,
    pub(super) track: PoseTrack,
    pub(super) skips: SkipCounts,
}

impl AttributedWindow {
    /// A window of `window_s` seconds over a stream of at most `rate_hz` readings and
    /// `pose_rate_hz` poses per second; fails on a value that is not finite and positive.
    pub(super) fn new(window_s: f64, rate_hz: f64, pose_rate_hz: f64) -> Result<Self, SignalError> {
        check_positive("window_s", window_s)?;
        check_positive("rate_hz", rate_hz)?;
        check_positive("pose_rate_hz", pose_rate_hz)?;
        let pose_window = window_s + 2.0 / pose_rate_hz;
        Ok(Self {
            window_s,
            rate_hz,
            pose_rate_hz,
            values: Ring::new(ring_capacity(window_s, rate_hz)),
            track: PoseTrack::new(
                ring_capacity(pose_window, pose_rate_hz),
                0.25 / pose_rate_hz,
            ),
            skips: SkipCounts::default(),
        })
    }

    /// Feeds a pose of the pose stream; poses older than the window (but the one covering its
    /// start) leave the track.
    pub(super) fn push_pose(&mut self, pose: &PoseStamped) {
        if self.track.push(pose, pose.gait, &mut self.skips) {
            let t = pose.stamp - self.window_s - 2.0 / self.pose_rate_hz;
            self.track.retain_covering(t);
        }
    }

    /// Feeds a reading; returns the stamp of the window's first reading when the window
    /// `[stamp − W, stamp]` is full and holds at least two readings. A skipped reading (not
    /// finite, or not newer than the last) returns `None` and is counted.
    pub(super) fn push(&mut self, stamp: f64, value: f64) -> Option<f64> {
        if !push_scalar(&mut self.values, Scalar { stamp, value }, &mut self.skips) {
            return None;
        }
        let tol = 0.25 / self.rate_hz;
        let start = stamp - self.window_s;
        // Drop old readings, keeping the newest one at or before the window's start.
        while self.values.len() >= 2 && self.values.get(1).is_some_and(|p| p.stamp <= start + tol) {
            self.values.pop_front();
        }
        let first = self.values.front()?;
        if first.stamp > start + tol || self.values.len() < 2 {
            return None;
        }
        Some(first.stamp)
    }

    /// Total capacity of the ring buffers; fixed at construction.
    pub(super) fn capacity(&self) -> usize {
        self.values.capacity() + self.track.ring.capacity()
    }
}
