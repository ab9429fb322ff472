//! Cost measurements from the robot's streams: what the learners are taught.
//!
//! Every estimator here is *streaming* and *allocation-free per tick*: all storage is a set of
//! fixed-capacity ring buffers (`Box<[T]>`, which cannot grow) allocated in the constructor, sized
//! from the window length and the stream's maximum rate. A tick does O(window) arithmetic and no
//! allocation.
//!
//! * [`InverseVelocityCost`] — the inverse-velocity cost of `001` Eq. 19–20 with the tanh bound of
//!   decision 8: each pose tick, v⁻¹ = T / L over the last Δt of the trajectory (T the window's
//!   duration, L the horizontal path length along the sampled poses); a value is emitted only when
//!   the gait did not change within the window, attributed to the window's middle pose, smoothed by
//!   a moving average over the last Δt of raw values, and transformed by
//!   c = c_high · tanh((v⁻¹ / v_max⁻¹) / c_high) ([`tanh_bound`]). It also reports stuck
//!   (decision 9: v⁻¹ / v_max⁻¹ > c_max over a window walked in one gait).
//! * [`TurningTime`] — seconds spent turning within the cost window and within a smoothed
//!   sample's support, so that turns on the spot neither teach a cost nor trigger the stuck
//!   reflex.
//! * [`FallbackTimer`] — the stuck reflex's timer (decision 9: the rough-terrain gait for
//!   Δt_fallback).
//! * [`RollVarianceCost`] — the variance of the body roll over a sliding window (`000` §IV: 10 s,
//!   the gait-cycle duration), attributed to the window's middle pose.
//! * [`EnergyCost`] — energy per metre ∫P dt / distance over a window (`003`), its motive part
//!   (total minus the hotel load), the hotel load per metre P_hotel / v̄, and the cost of transport
//!   P̄ / (m g v̄) (thesis C1).
//!
//! Input hygiene: samples with a non-finite stamp, position or value, and samples whose stamp does
//! not increase, are skipped and counted ([`SkipCounts`]); no output is ever NaN or infinite.
//! Distances are horizontal (x, y): the maps are 2.5D, costs multiply horizontal edge lengths in
//! the planner, and v_max is a horizontal walking speed.

use strider_core::geom::Point3;
use strider_core::msg::{GaitId, PoseStamped, Proprioception};
use thiserror::Error;

/// Standard gravity, m/s², used by the cost of transport.
pub const STANDARD_GRAVITY: f64 = 9.806_65;

/// Cap on the speed ratio (v⁻¹ / v_max⁻¹) used when the path length over a window is zero or
/// vanishingly small: a stuck robot's ratio is "infinite", which this finite stand-in represents
/// without producing inf/NaN in the moving average. `tanh(RATIO_CAP / c_high)` is exactly 1 in f64
/// for any sane c_high, so the transformed cost saturates at c_high as the true limit would.
pub const RATIO_CAP: f64 = 1e9;

/// Errors of the signal estimators (invalid construction parameters).
#[derive(Clone, Debug, Error, PartialEq)]
pub enum SignalError {
    /// A parameter is non-finite or outside its valid range.
    #[error("invalid parameter {name} = {value}: {reason}")]
    InvalidParameter {
        /// The parameter's name.
        name: &'static str,
        /// The offending value.
        value: f64,
        /// What was expected.
        reason: &'static str,
    },
}

fn check_positive(name: &'static str, value: f64) -> Result<f64, SignalError> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(SignalError::InvalidParameter {
            name,
            value,
            reason: "must be finite and > 0",
        })
    }
}

fn check_non_negative(name: &'static str, value: f64) -> Result<f64, SignalError> {
    if value.is_finite() && value >= 0.0 {
        Ok(value)
    } else {
        Err(SignalError::InvalidParameter {
            name,
            value,
            reason: "must be finite and >= 0",
        })
    }
}

/// Ring capacity for a window of `window_s` seconds at up to `rate_hz` samples per second: the
/// window's samples, one before it, and a 25 % margin for rate jitter.
fn ring_capacity(window_s: f64, rate_hz: f64) -> usize {
    let n = (window_s * rate_hz * 1.25).ceil();
    // Parameters are validated finite and positive; bound the size against absurd values.
    (n.min(1e7) as usize) + 4
}

/// The c = c_high · tanh(r / c_high) bound of `001` Eq. 20 (decision 8) for a speed ratio
/// r = v⁻¹ / v_max⁻¹: ≈ r for small r (ideal terrain at v_max gives ≈ 1), saturating at c_high.
/// A non-finite or negative ratio is treated as saturated (c_high) resp. 0.
pub fn tanh_bound(ratio: f64, c_high: f64) -> f64 {
    if ratio.is_nan() || ratio == f64::INFINITY {
        return c_high;
    }
    c_high * (ratio.max(0.0) / c_high).tanh()
}

/// The hotel load per metre P_hotel / v, J/m, that the `003` energy model adds to the learned
/// motive energy per metre (decision 12) for a gait walking at `speed` m/s. `None` when the speed
/// is not finite and positive or the load is not finite and non-negative.
pub fn hotel_load_per_metre(hotel_load_w: f64, speed: f64) -> Option<f64> {
    if speed.is_finite() && speed > 0.0 && hotel_load_w.is_finite() && hotel_load_w >= 0.0 {
        Some(hotel_load_w / speed)
    } else {
        None
    }
}

// ---------------------------------------------------------------------------------------------
// Fixed-capacity ring buffer.

/// A fixed-capacity FIFO: the storage is a boxed slice allocated once, so pushing can never
/// allocate. Pushing onto a full ring drops the oldest element.
#[derive(Clone, Debug)]
struct Ring<T> {
    buf: Box<[T]>,
    head: usize,
    len: usize,
}

impl<T: Copy + Default> Ring<T> {
    fn new(capacity: usize) -> Self {
        Self {
            buf: vec![T::default(); capacity.max(1)].into_boxed_slice(),
            head: 0,
            len: 0,
        }
    }

    fn capacity(&self) -> usize {
        self.buf.len()
    }

    fn len(&self) -> usize {
        self.len
    }

    fn clear(&mut self) {
        self.head = 0;
        self.len = 0;
    }

    /// Appends `v`; returns true when the ring was full and its oldest element was dropped.
    fn push_back(&mut self, v: T) -> bool {
        let cap = self.buf.len();
        let dropped = self.len == cap;
        if dropped {
            self.head = (self.head + 1) % cap;
            self.len -= 1;
        }
        let k = (self.head + self.len) % cap;
        self.buf[k] = v;
        self.len += 1;
        dropped
    }

    fn pop_front(&mut self) -> Option<T> {
        if self.len == 0 {
            return None;
        }
        let v = self.buf[self.head];
        self.head = (self.head + 1) % self.buf.len();
        self.len -= 1;
        Some(v)
    }

    fn get(&self, i: usize) -> Option<T> {
        (i < self.len).then(|| self.buf[(self.head + i) % self.buf.len()])
    }

    fn front(&self) -> Option<T> {
        self.get(0)
    }

    fn back(&self) -> Option<T> {
        self.len.checked_sub(1).and_then(|i| self.get(i))
    }

    fn iter(&self) -> impl Iterator<Item = T> + Clone + '_ {
        (0..self.len).map(move |i| self.buf[(self.head + i) % self.buf.len()])
    }

    /// The number of leading elements for which `pred` holds (the ring must be partitioned by
    /// it, as `slice::partition_point` requires): a binary search, O(log len).
    fn partition_point(&self, pred: impl Fn(&T) -> bool) -> usize {
        let (mut lo, mut hi) = (0, self.len);
        while lo < hi {
            let mid = lo + (hi - lo) / 2;
            if pred(&self.buf[(self.head + mid) % self.buf.len()]) {
                lo = mid + 1;
            } else {
                hi = mid;
            }
        }
        lo
    }
}

// ---------------------------------------------------------------------------------------------
// Shared pieces.

/// Counts of input samples an estimator skipped, by reason.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SkipCounts {
    /// Samples with a non-finite stamp, position or value.
    pub non_finite: u64,
    /// Samples whose stamp did not increase over the previous accepted one.
    pub out_of_order: u64,
    /// Poses of a gait with no configured v_max ([`InverseVelocityCost`] only).
    pub unknown_gait: u64,
    /// Samples that arrived faster than the configured rate and pushed the oldest window sample
    /// out of its ring (the window is then short and nothing is emitted until it refills).
    pub overrun: u64,
}

impl SkipCounts {
    /// Total number of samples that were not used (overruns are used, so not counted here).
    pub fn skipped(&self) -> u64 {
        self.non_finite + self.out_of_order + self.unknown_gait
    }
}

/// A cost measurement attributed to a place: the output of [`InverseVelocityCost`] and
/// [`RollVarianceCost`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CostSample {
    /// Stamp of the pose the value is attributed to (the window's middle pose).
    pub stamp: f64,
    /// Position of that pose; the caller maps it to a cell.
    pub position: Point3,
    /// The gait used throughout the window.
    pub gait: GaitId,
    /// The cost: c of Eq. 20 for [`InverseVelocityCost`], the roll variance (rad²) for
    /// [`RollVarianceCost`].
    pub cost: f64,
    /// The untransformed measurement: the smoothed speed ratio v⁻¹ / v_max⁻¹ for
    /// [`InverseVelocityCost`] (capped at [`RATIO_CAP`]), the roll variance for
    /// [`RollVarianceCost`].
    pub raw: f64,
}

/// One pose as kept by the pose tracks.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct TrackPose {
    stamp: f64,
    position: Point3,
    gait: GaitId,
    /// Horizontal path length from the track's first pose ever to this one, m: the length over
    /// any interval is a difference of two interpolated values instead of a sum over the window.
    arc: f64,
    /// Count of gait changes before this pose: the gait is constant between two poses exactly
    /// when their counts are equal.
    run: u64,
}

fn pose_is_finite(p: &PoseStamped) -> bool {
    p.stamp.is_finite()
        && p.position.x.is_finite()
        && p.position.y.is_finite()
        && p.position.z.is_finite()
}

/// A fixed-capacity, time-ordered track of recent poses.
#[derive(Clone, Debug)]
struct PoseTrack {
    ring: Ring<TrackPose>,
    /// Stamp tolerance, seconds (a quarter of the nominal sample period).
    tol: f64,
}

impl PoseTrack {
    fn new(capacity: usize, tol: f64) -> Self {
        Self {
            ring: Ring::new(capacity),
            tol,
        }
    }

    /// Accepts a pose (after validation); updates `skips`. Returns false when skipped.
    fn push(&mut self, pose: &PoseStamped, gait: GaitId, skips: &mut SkipCounts) -> bool {
        if !pose_is_finite(pose) {
            skips.non_finite += 1;
            return false;
        }
        if let Some(last) = self.ring.back()
            && pose.stamp <= last.stamp
        {
            skips.out_of_order += 1;
            return false;
        }
        let (arc, run) = match self.ring.back() {
            Some(last) => (
                last.arc + last.position.xy().dist(pose.position.xy()),
                last.run + u64::from(last.gait != gait),
            ),
            None => (0.0, 0),
        };
        if self.ring.push_back(TrackPose {
            stamp: pose.stamp,
            position: pose.position,
            gait,
            arc,
            run,
        }) {
            skips.overrun += 1;
        }
        true
    }

    /// Drops old poses, keeping the newest pose at or before `t` (so the track still covers `t`).
    fn retain_covering(&mut self, t: f64) {
        while self.ring.len() >= 2 && self.ring.get(1).is_some_and(|p| p.stamp <= t) {
            self.ring.pop_front();
        }
    }

    /// True when the track covers `[t0, t1]` up to the tolerance.
    fn covers(&self, t0: f64, t1: f64) -> bool {
        match (self.ring.front(), self.ring.back()) {
            (Some(a), Some(b)) => a.stamp <= t0 + self.tol && b.stamp >= t1 - self.tol,
            _ => false,
        }
    }

    /// Horizontal path length over `[t0, t1]` along the poses, interpolating linearly inside the
    /// end segments. `None` when the track does not cover the interval.
    fn path_length(&self, t0: f64, t1: f64) -> Option<f64> {
        if t1 < t0 || !self.covers(t0, t1) {
            return None;
        }
        Some((self.arc_at(t1) - self.arc_at(t0)).max(0.0))
    }

    /// The cumulative path length at time `t`, interpolated linearly inside its segment and
    /// clamped to the track's ends. The track must not be empty.
    fn arc_at(&self, t: f64) -> f64 {
        let n = self.ring.len();
        let k = self.ring.partition_point(|p| p.stamp <= t);
        match (
            k.checked_sub(1).and_then(|i| self.ring.get(i)),
            self.ring.get(k),
        ) {
            (Some(q), Some(p)) => {
                let frac = ((t - q.stamp) / (p.stamp - q.stamp)).clamp(0.0, 1.0);
                q.arc + (p.arc - q.arc) * frac
            }
            (Some(q), None) => q.arc,
            (None, Some(p)) => p.arc,
            (None, None) => {
                debug_assert_eq!(n, 0);
                0.0
            }
        }
    }

    /// The gait when every pose bracketing `[t0, t1]` has the same one, else `None`. A pose
    /// matters when it lies inside the interval or is the last one before `t0` or the first one
    /// after `t1`.
    fn constant_gait(&self, t0: f64, t1: f64) -> Option<GaitId> {
        let n = self.ring.len();
        if n == 0 {
            return None;
        }
        // First relevant: the last pose at or before t0 (poses before it are followed by one
        // at or before t0); last relevant: the first pose at or after t1.
        let first = self
            .ring
            .partition_point(|p| p.stamp <= t0)
            .saturating_sub(1);
        let last = self.ring.partition_point(|p| p.stamp < t1).min(n - 1);
        if first > last {
            return None;
        }
        let (a, b) = (self.ring.get(first)?, self.ring.get(last)?);
        (a.run == b.run).then_some(a.gait)
    }

    /// The pose whose stamp is nearest `t` (the earlier one on a tie); `None` when that pose is
    /// farther than one tolerance outside the track.
    fn nearest(&self, t: f64) -> Option<TrackPose> {
        if !self.covers(t, t) {
            return None;
        }
        // Stamps increase, so the nearest pose is the last one before t or the first at/after.
        let k = self.ring.partition_point(|p| p.stamp < t);
        match (
            k.checked_sub(1).and_then(|i| self.ring.get(i)),
            self.ring.get(k),
        ) {
            (Some(a), Some(b)) => Some(if t - a.stamp <= b.stamp - t { a } else { b }),
            (a, b) => a.or(b),
        }
    }
}

/// A scalar sample of the proprioceptive stream.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Scalar {
    stamp: f64,
    value: f64,
}

/// Pushes `s` onto a scalar ring with the same validation as the pose track; false when skipped.
fn push_scalar(ring: &mut Ring<Scalar>, s: Scalar, skips: &mut SkipCounts) -> bool {
    if !(s.stamp.is_finite() && s.value.is_finite()) {
        skips.non_finite += 1;
        return false;
    }
    if let Some(last) = ring.back()
        && s.stamp <= last.stamp
    {
        skips.out_of_order += 1;
        return false;
    }
    if ring.push_back(s) {
        skips.overrun += 1;
    }
    true
}

/// Drops old samples, keeping the newest one at or before `t`.
fn retain_covering(ring: &mut Ring<Scalar>, t: f64) {
    while ring.len() >= 2 && ring.get(1).is_some_and(|p| p.stamp <= t) {
        ring.pop_front();
    }
}

// ---------------------------------------------------------------------------------------------
// Inverse velocity.

/// Parameters of [`InverseVelocityCost`] (`001` Table 3 names in brackets).
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

/// The inverse-velocity cost (`001` Eq. 19–20, decision 8) and stuck detector (decision 9) over
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
        let mean = self.smoothing.iter().map(|s| s.value).sum::<f64>() / n as f64;
        Some(CostSample {
            stamp: mid.stamp,
            position: mid.position,
            gait,
            cost: tanh_bound(mean, self.params.c_high),
            raw: mean,
        })
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

// ---------------------------------------------------------------------------------------------
// Turning time.

/// Time spent turning, summed over two trailing spans of the pose stream: the cost window Δt,
/// over which [`InverseVelocityCost::is_stuck`] measures v⁻¹, and a smoothed cost sample's whole
/// *support* (the window plus the moving average before it, decision 8), every raw ratio of
/// which enters the sample. A pose tick counts as turning when the heading rate exceeds
/// `omega_turn`; the tick's duration is then added.
///
/// The heading rate is measured over a *baseline* of `baseline_s` seconds: from the newest
/// earlier pose at least `baseline_s` old (the first pose of the stream while it is younger) to
/// the new one. Tick to tick, heading noise would swamp it: a logged pose with 5 mrad of
/// independent heading jitter at 20 Hz gives rate noise of 0.14 rad/s, above any useful
/// threshold, so every tick would count as turning and a real robot would store no cost sample;
/// over 0.5 s the noise is 0.014 rad/s. A turn is then seen for up to `baseline_s` after it
/// ends, which only widens the spans that are dropped.
///
/// A robot that turns on the spot at a path corner makes no headway for the length of the turn:
/// a window spanning the turn measures the path's corner, not the terrain, and reads as stuck.
/// The mission drops samples whose support saw any turning and does not let windows that did
/// trigger the reflex. (A fixed heading-change budget instead would depend on the robot's turn
/// rate and the window: at 0.5 rad/s a 45° budget is spent in 1.6 s, less than the large
/// simulation's 2 s support, and whole windows of turning on the spot got through.)
#[derive(Clone, Debug)]
pub struct TurningTime {
    window_s: f64,
    support_s: f64,
    omega_turn: f64,
    baseline_s: f64,
    /// (stamp, yaw) of the poses of the last `baseline_s`, and the newest one before.
    baseline: Ring<(f64, f64)>,
    /// (stamp, seconds of turning since the previous pose) over the support span.
    poses: Ring<(f64, f64)>,
    /// How many of the newest `poses` lie in the window span.
    in_window_len: usize,
    sum_window: f64,
    sum_support: f64,
    skips: SkipCounts,
}

impl TurningTime {
    /// A tracker over a `window_s` window and a `support_s` support (raised to `window_s` if
    /// shorter) for a pose stream of at most `rate_hz`, counting ticks whose heading rate over
    /// a `baseline_s`-second baseline exceeds `omega_turn` rad/s; fails on a parameter that is
    /// not finite and positive.
    pub fn new(
        window_s: f64,
        support_s: f64,
        rate_hz: f64,
        omega_turn: f64,
        baseline_s: f64,
    ) -> Result<Self, SignalError> {
        check_positive("window_s", window_s)?;
        check_positive("support_s", support_s)?;
        check_positive("rate_hz", rate_hz)?;
        check_positive("omega_turn", omega_turn)?;
        check_positive("baseline_s", baseline_s)?;
        let support_s = support_s.max(window_s);
        Ok(Self {
            window_s,
            support_s,
            omega_turn,
            baseline_s,
            baseline: Ring::new(ring_capacity(baseline_s, rate_hz) + 1),
            poses: Ring::new(ring_capacity(support_s, rate_hz)),
            in_window_len: 0,
            sum_window: 0.0,
            sum_support: 0.0,
            skips: SkipCounts::default(),
        })
    }

    /// Feeds the heading `yaw` (radians) at `stamp`. Non-finite values and stamps that do not
    /// increase are skipped and counted.
    pub fn push(&mut self, stamp: f64, yaw: f64) {
        if !(stamp.is_finite() && yaw.is_finite()) {
            self.skips.non_finite += 1;
            return;
        }
        if self.poses.back().is_some_and(|(t, _)| stamp <= t) {
            self.skips.out_of_order += 1;
            return;
        }
        // Keep the newest pose at least baseline_s old at the front of the baseline.
        while self.baseline.len() >= 2
            && self
                .baseline
                .get(1)
                .is_some_and(|(t, _)| t <= stamp - self.baseline_s)
        {
            self.baseline.pop_front();
        }
        let rate = self
            .baseline
            .front()
            .map(|(t0, y0)| strider_core::geom::wrap_angle(yaw - y0).abs() / (stamp - t0));
        let turn = match (self.poses.back(), rate) {
            (Some((t, _)), Some(r)) if r > self.omega_turn => stamp - t,
            _ => 0.0,
        };
        // (A faster stream than the ring was sized for drops the oldest: a shorter baseline.)
        self.baseline.push_back((stamp, yaw));
        if self.poses.len() == self.poses.capacity() {
            // A faster stream than the ring was sized for: the oldest pose leaves both spans.
            self.skips.overrun += 1;
            self.drop_front();
        }
        self.poses.push_back((stamp, turn));
        self.in_window_len += 1;
        self.sum_window += turn;
        self.sum_support += turn;
        while self.in_window_len > 0 {
            let Some((t, turn)) = self.poses.get(self.poses.len() - self.in_window_len) else {
                break;
            };
            if t >= stamp - self.window_s {
                break;
            }
            self.sum_window -= turn;
            self.in_window_len -= 1;
        }
        while self
            .poses
            .front()
            .is_some_and(|(t, _)| t < stamp - self.support_s)
        {
            self.drop_front();
        }
        // Running sums of durations: exact zeros when nothing in a span turned.
        if self.in_window_len == 0 || self.sum_window < 1e-9 {
            self.sum_window = 0.0;
        }
        if self.sum_support < 1e-9 {
            self.sum_support = 0.0;
        }
    }

    fn drop_front(&mut self) {
        if let Some((_, turn)) = self.poses.pop_front() {
            self.sum_support -= turn;
            if self.in_window_len > self.poses.len() {
                self.sum_window -= turn;
                self.in_window_len = self.poses.len();
            }
        }
    }

    /// Seconds of turning among the poses of the window span (each pose's tick since the
    /// previous pose).
    pub fn in_window(&self) -> f64 {
        self.sum_window
    }

    /// Seconds of turning among the poses of the support span.
    pub fn in_support(&self) -> f64 {
        self.sum_support
    }

    /// Counts of skipped poses.
    pub fn skips(&self) -> SkipCounts {
        self.skips
    }

    /// Forgets the stream (keeps the buffers and the skip counts).
    pub fn reset(&mut self) {
        self.poses.clear();
        self.baseline.clear();
        self.in_window_len = 0;
        self.sum_window = 0.0;
        self.sum_support = 0.0;
    }
}

// ---------------------------------------------------------------------------------------------
// Stuck reflex timer.

/// The stuck reflex's timer (decision 9): once stuck is detected, the rough-terrain gait is used
/// for Δt_fallback seconds. A stuck report while the fallback is active does not extend it (the
/// fallback gait gets exactly Δt_fallback); if the robot is still stuck when it expires, the next
/// stuck report re-arms it.
#[derive(Clone, Debug, PartialEq)]
pub struct FallbackTimer {
    dt_fallback: f64,
    until: Option<f64>,
    triggers: u64,
}

impl FallbackTimer {
    /// A disarmed timer with duration `dt_fallback` seconds (`001` Table 3 `dt_fallback`: 30 s
    /// small sim, 3 s real robot).
    pub fn new(dt_fallback: f64) -> Result<Self, SignalError> {
        check_positive("dt_fallback", dt_fallback)?;
        Ok(Self {
            dt_fallback,
            until: None,
            triggers: 0,
        })
    }

    /// Updates with the stuck flag at time `now`; returns true while the fallback is active.
    /// A non-finite `now` changes nothing.
    pub fn update(&mut self, now: f64, stuck: bool) -> bool {
        if !now.is_finite() {
            return self.until.is_some();
        }
        if self.until.is_some_and(|u| now >= u) {
            self.until = None;
        }
        if stuck && self.until.is_none() {
            self.until = Some(now + self.dt_fallback);
            self.triggers += 1;
        }
        self.until.is_some()
    }

    /// True while the fallback is active at `now`.
    pub fn is_active(&self, now: f64) -> bool {
        self.until.is_some_and(|u| now < u)
    }

    /// How many times the fallback was armed.
    pub fn triggers(&self) -> u64 {
        self.triggers
    }
}

// ---------------------------------------------------------------------------------------------
// Roll variance.

/// Parameters of [`RollVarianceCost`].
#[derive(Clone, Debug, PartialEq)]
pub struct RollVarianceParams {
    /// Sliding window, seconds (`000` §IV: 10 s, the gait-cycle duration).
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

/// The roll-variance cost of `000`: the sample variance (n − 1) of the roll angles in the window
/// `[t − W, t]` (the newest sample at or before t − W included), emitted each proprioception tick
/// once the window is full and attributed to the pose nearest the window's middle time. Only
/// emitted when the gait did not change within the window.
///
/// Numerics: a corrected two-pass variance over the ring on every tick (O(window) flops, no
/// running sums), so a large common offset (e.g. 1e3 rad) causes no catastrophic cancellation.
#[derive(Clone, Debug)]
pub struct RollVarianceCost {
    params: RollVarianceParams,
    rolls: Ring<Scalar>,
    track: PoseTrack,
    skips: SkipCounts,
}

impl RollVarianceCost {
    /// A new estimator; fails on non-finite or non-positive parameters.
    pub fn new(params: RollVarianceParams) -> Result<Self, SignalError> {
        check_positive("window_s", params.window_s)?;
        check_positive("rate_hz", params.rate_hz)?;
        check_positive("pose_rate_hz", params.pose_rate_hz)?;
        let pose_window = params.window_s + 2.0 / params.pose_rate_hz;
        Ok(Self {
            rolls: Ring::new(ring_capacity(params.window_s, params.rate_hz)),
            track: PoseTrack::new(
                ring_capacity(pose_window, params.pose_rate_hz),
                0.25 / params.pose_rate_hz,
            ),
            params,
            skips: SkipCounts::default(),
        })
    }

    /// Feeds a pose of the pose stream (for attribution and the gait).
    pub fn push_pose(&mut self, pose: &PoseStamped) {
        if self.track.push(pose, pose.gait, &mut self.skips) {
            let t = pose.stamp - self.params.window_s - 2.0 / self.params.pose_rate_hz;
            self.track.retain_covering(t);
        }
    }

    /// Feeds a proprioceptive reading; returns the roll variance over the window when it is
    /// full, a pose covers its middle and the gait was constant.
    pub fn push(&mut self, p: &Proprioception) -> Option<CostSample> {
        let s = Scalar {
            stamp: p.stamp,
            value: p.roll,
        };
        if !push_scalar(&mut self.rolls, s, &mut self.skips) {
            return None;
        }
        let tol = 0.25 / self.params.rate_hz;
        let start = p.stamp - self.params.window_s;
        retain_covering(&mut self.rolls, start + tol);
        let first = self.rolls.front()?;
        if first.stamp > start + tol || self.rolls.len() < 2 {
            return None;
        }
        let gait = self.track.constant_gait(first.stamp, p.stamp)?;
        if !self.track.covers(first.stamp, p.stamp) {
            return None;
        }
        let mid = self.track.nearest(0.5 * (first.stamp + p.stamp))?;
        let var = two_pass_variance(self.rolls.iter().map(|s| s.value), self.rolls.len());
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
        self.skips
    }

    /// Total capacity of the internal ring buffers; fixed at construction.
    pub fn capacity(&self) -> usize {
        self.rolls.capacity() + self.track.ring.capacity()
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

// ---------------------------------------------------------------------------------------------
// Energy.

/// Parameters of [`EnergyCost`].
#[derive(Clone, Debug, PartialEq)]
pub struct EnergyParams {
    /// Window, seconds.
    pub window_s: f64,
    /// Robot mass m, kg (cost of transport).
    pub mass_kg: f64,
    /// Gravitational acceleration g, m/s².
    pub gravity: f64,
    /// Hotel load P_hotel, W: the constant draw of computers and sensors (`003`).
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
    /// Total energy per metre E / d, J/m (`003`).
    pub energy_per_m: f64,
    /// Motive energy per metre (E − P_hotel · T) / d, J/m: what the `003` GP learns (decision 12).
    /// Can be slightly negative with noisy power readings; not clamped.
    pub motive_energy_per_m: f64,
    /// Hotel load per metre P_hotel / v̄ = P_hotel · T / d, J/m, at the window's mean speed.
    pub hotel_per_m: f64,
    /// Cost of transport P̄ / (m g v̄) = E / (m g d), dimensionless (thesis C1).
    pub cost_of_transport: f64,
    /// Horizontal distance travelled in the window, metres.
    pub distance_m: f64,
    /// Window duration T, seconds.
    pub duration_s: f64,
    /// Energy E = ∫P dt over the window, J (trapezoid rule on the power samples).
    pub energy_j: f64,
}

/// Energy per metre and cost of transport over a sliding window of the power stream
/// (`003`, thesis C1). Emitted each proprioception tick once the window `[t − W, t]` is full, the
/// pose track covers it, the gait was constant and the distance is at least `min_distance_m`;
/// never inf or NaN.
#[derive(Clone, Debug)]
pub struct EnergyCost {
    params: EnergyParams,
    power: Ring<Scalar>,
    track: PoseTrack,
    skips: SkipCounts,
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
        check_positive("rate_hz", params.rate_hz)?;
        check_positive("pose_rate_hz", params.pose_rate_hz)?;
        let pose_window = params.window_s + 2.0 / params.pose_rate_hz;
        Ok(Self {
            power: Ring::new(ring_capacity(params.window_s, params.rate_hz)),
            track: PoseTrack::new(
                ring_capacity(pose_window, params.pose_rate_hz),
                0.25 / params.pose_rate_hz,
            ),
            params,
            skips: SkipCounts::default(),
            short_windows: 0,
        })
    }

    /// Feeds a pose of the pose stream (distance, attribution and gait).
    pub fn push_pose(&mut self, pose: &PoseStamped) {
        if self.track.push(pose, pose.gait, &mut self.skips) {
            let t = pose.stamp - self.params.window_s - 2.0 / self.params.pose_rate_hz;
            self.track.retain_covering(t);
        }
    }

    /// Feeds a proprioceptive reading (its `power_w`); returns the window's energy figures.
    /// Negative power readings are treated as invalid (skipped as non-finite are).
    pub fn push(&mut self, p: &Proprioception) -> Option<EnergySample> {
        if p.power_w < 0.0 {
            self.skips.non_finite += 1;
            return None;
        }
        let s = Scalar {
            stamp: p.stamp,
            value: p.power_w,
        };
        if !push_scalar(&mut self.power, s, &mut self.skips) {
            return None;
        }
        let tol = 0.25 / self.params.rate_hz;
        let start = p.stamp - self.params.window_s;
        retain_covering(&mut self.power, start + tol);
        let first = self.power.front()?;
        if first.stamp > start + tol || self.power.len() < 2 {
            return None;
        }
        let (t0, t1) = (first.stamp, p.stamp);
        let gait = self.track.constant_gait(t0, t1)?;
        let distance = self.track.path_length(t0, t1)?;
        let mid = self.track.nearest(0.5 * (t0 + t1))?;
        if distance < self.params.min_distance_m {
            self.short_windows += 1;
            return None;
        }
        let mut energy = 0.0;
        let mut prev: Option<Scalar> = None;
        for s in self.power.iter() {
            if let Some(q) = prev {
                energy += 0.5 * (q.value + s.value) * (s.stamp - q.stamp);
            }
            prev = Some(s);
        }
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
        self.skips
    }

    /// Full windows that emitted nothing because the distance was below `min_distance_m`.
    pub fn short_windows(&self) -> u64 {
        self.short_windows
    }

    /// Total capacity of the internal ring buffers; fixed at construction.
    pub fn capacity(&self) -> usize {
        self.power.capacity() + self.track.ring.capacity()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ring_drops_oldest_when_full() {
        let mut r: Ring<u32> = Ring::new(3);
        assert!(!r.push_back(1));
        assert!(!r.push_back(2));
        assert!(!r.push_back(3));
        assert!(r.push_back(4));
        assert_eq!(r.iter().collect::<Vec<_>>(), vec![2, 3, 4]);
        assert_eq!(r.pop_front(), Some(2));
        assert_eq!(r.front(), Some(3));
        assert_eq!(r.back(), Some(4));
        assert_eq!(r.capacity(), 3);
    }

    #[test]
    fn two_pass_matches_textbook() {
        let v = [1.0, 2.0, 3.0, 4.0];
        let var = two_pass_variance(v.iter().copied(), 4);
        assert!((var - 5.0 / 3.0).abs() < 1e-15);
    }

    /// The window queries by definition, O(n) scans over every pose (the reference the O(log n)
    /// queries are checked against).
    fn brute_path_length(t: &PoseTrack, t0: f64, t1: f64) -> f64 {
        let v: Vec<TrackPose> = t.ring.iter().collect();
        v.windows(2)
            .map(|w| {
                let (q, p) = (w[0], w[1]);
                let (a, b) = (t0.max(q.stamp), t1.min(p.stamp));
                if b > a {
                    q.position.xy().dist(p.position.xy()) * ((b - a) / (p.stamp - q.stamp)).min(1.0)
                } else {
                    0.0
                }
            })
            .sum()
    }

    fn brute_constant_gait(t: &PoseTrack, t0: f64, t1: f64) -> Option<GaitId> {
        let v: Vec<TrackPose> = t.ring.iter().collect();
        let mut gait = None;
        for (i, p) in v.iter().enumerate() {
            let next = v.get(i + 1).map_or(f64::INFINITY, |q| q.stamp);
            let prev = if i == 0 {
                f64::NEG_INFINITY
            } else {
                v[i - 1].stamp
            };
            if (p.stamp >= t0 || next > t0) && (p.stamp <= t1 || prev < t1) {
                match gait {
                    None => gait = Some(p.gait),
                    Some(g) if g != p.gait => return None,
                    Some(_) => {}
                }
            }
        }
        gait
    }

    fn brute_nearest(t: &PoseTrack, at: f64) -> Option<f64> {
        let mut best: Option<(f64, f64)> = None;
        for p in t.ring.iter() {
            let d = (p.stamp - at).abs();
            if best.is_none_or(|(bd, _)| d < bd) {
                best = Some((d, p.stamp));
            }
        }
        best.map(|(_, s)| s)
    }

    proptest::proptest! {
        /// Cumulative arc length, gait-run counts and binary search give what the window scans
        /// give, for wrapped rings, gait changes and intervals reaching past the track's ends.
        #[test]
        fn window_queries_match_scans(
            steps in proptest::collection::vec((0.01f64..0.2, -0.3f64..0.3, -0.3f64..0.3, 0u8..3), 2..60),
            cap in 3usize..40,
            q in proptest::collection::vec((-0.5f64..1.5, 0.0f64..1.0), 1..12),
        ) {
            let mut t = PoseTrack::new(cap, 1e-3);
            let mut sk = SkipCounts::default();
            let (mut stamp, mut x, mut y) = (0.0, 0.0, 0.0);
            for &(dt, dx, dy, g) in &steps {
                stamp += dt;
                x += dx;
                y += dy;
                let p = PoseStamped {
                    stamp,
                    position: Point3::new(x, y, 0.0),
                    ..Default::default()
                };
                t.push(&p, GaitId(g / 2), &mut sk);
            }
            let (lo, hi) = (t.ring.front().unwrap().stamp, t.ring.back().unwrap().stamp);
            for &(a, w) in &q {
                let t0 = lo + a * (hi - lo);
                let t1 = t0 + w * (hi - lo);
                if let Some(len) = t.path_length(t0, t1) {
                    proptest::prop_assert!((len - brute_path_length(&t, t0, t1)).abs() < 1e-9);
                }
                proptest::prop_assert_eq!(t.constant_gait(t0, t1), brute_constant_gait(&t, t0, t1));
                if let Some(p) = t.nearest(t0) {
                    proptest::prop_assert_eq!(Some(p.stamp), brute_nearest(&t, t0));
                }
            }
        }
    }

    #[test]
    fn path_length_interpolates_end_segments() {
        let mut t = PoseTrack::new(8, 0.01);
        let mut sk = SkipCounts::default();
        for k in 0..4 {
            let p = PoseStamped {
                stamp: k as f64,
                position: Point3::new(k as f64, 0.0, 0.0),
                ..Default::default()
            };
            assert!(t.push(&p, GaitId(0), &mut sk));
        }
        assert!((t.path_length(0.5, 2.25).unwrap() - 1.75).abs() < 1e-12);
        assert!(t.path_length(-1.0, 2.0).is_none());
    }

    #[test]
    fn tanh_bound_limits() {
        assert_eq!(tanh_bound(f64::INFINITY, 20.0), 20.0);
        assert_eq!(tanh_bound(f64::NAN, 20.0), 20.0);
        assert_eq!(tanh_bound(RATIO_CAP, 20.0), 20.0);
        assert!((tanh_bound(1.0, 20.0) - 20.0 * (0.05f64).tanh()).abs() < 1e-15);
    }
}
