//! Time spent turning over the cost window and a cost sample's support.

#[cfg(doc)]
use super::InverseVelocityCost;
use super::common::{SignalError, SkipCounts, check_positive, ring_capacity};
use super::ring::Ring;

/// Time spent turning, summed over two trailing spans of the pose stream: the cost window Δt,
/// over which [`InverseVelocityCost::is_stuck`] measures v⁻¹, and a smoothed cost sample's whole
/// *support* (the window plus the moving average before it, decision 8), every raw ratio of
/// which enters the sample. A pose tick counts as turning when the heading rate exceeds
/// `omega_turn`; the tick's duration is then added.
///
/// The heading rate is measured over a *baseline*: from the newest earlier pose that is at
/// least `baseline_s` old **and** at least `baseline_s · rate_hz` poses back (the first pose of
/// the stream while there is none) to the new one. Tick to tick, heading noise would swamp it:
/// a logged pose with 5 mrad of independent heading jitter at 20 Hz gives rate noise of
/// 0.14 rad/s, above any useful threshold, so every tick would count as turning and a real
/// robot would store no cost sample; over 0.5 s the noise is 0.014 rad/s.
///
/// The pose count adapts the baseline to the pose rate: `baseline_s` is meant at the nominal
/// `rate_hz`, and a slower stream gets a proportionally longer baseline (10 poses: 0.5 s at
/// 20 Hz, 1.8 s for wheel odometry logged at 5.5 Hz), so the estimate always spans as many pose
/// intervals. Over fewer, the jitter of a slow stream's stamps (poses stamped when logged,
/// 0.06–0.33 s apart for a nominal 0.18 s) and its heading steps read as turning where the
/// robot drove straight. At or above the nominal rate the time condition is the stricter one
/// and the baseline is `baseline_s`. A turn is seen for up to one baseline after it ends, which
/// only widens the spans that are dropped.
///
/// A robot that turns on the spot at a path corner makes no headway for the length of the turn:
/// a window spanning the turn measures the path's corner, not the terrain, and reads as stuck.
/// The mission drops samples whose support saw any turning and does not let windows that did
/// trigger the reflex. (A fixed heading-change budget instead would depend on the robot's turn
/// rate and the window: at 0.5 rad/s a 45° budget is spent in 1.6 s, less than the large
/// simulation's 2 s support, so whole windows of turning on the spot would pass.)
#[derive(Clone, Debug)]
pub struct TurningTime {
    window_s: f64,
    support_s: f64,
    omega_turn: f64,
    baseline_s: f64,
    /// The fewest poses the baseline spans.
    baseline_poses: usize,
    /// (stamp, yaw) of the poses of the baseline, and the newest one before.
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
    /// shorter) for a pose stream of nominally (and at most) `rate_hz`, counting ticks whose
    /// heading rate over a baseline of at least `baseline_s` seconds and `baseline_s · rate_hz`
    /// poses exceeds `omega_turn` rad/s; fails on a parameter that is not finite and positive.
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
        let capacity = ring_capacity(baseline_s, rate_hz) + 1;
        // Fewer than the ring holds (it holds 1.25 times as many, and more).
        let baseline_poses = ((baseline_s * rate_hz).round() as usize).clamp(1, capacity - 1);
        Ok(Self {
            window_s,
            support_s,
            omega_turn,
            baseline_s,
            baseline_poses,
            baseline: Ring::new(capacity),
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
        // Keep the newest pose at least baseline_s old and baseline_poses back at the front of
        // the baseline (the pose after the front is len - 1 poses back from the new one).
        while self.baseline.len() > self.baseline_poses
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
