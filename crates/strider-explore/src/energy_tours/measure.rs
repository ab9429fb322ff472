//! What a tour measures: the tour energy E_t of MartinCorke §3 and the motive energy per metre
//! samples the map learns from.
//!
//! * **E_t** = ∫ P dt over the tour, trapezoids between consecutive power readings (total power:
//!   motive plus hotel load, as the battery sees it).
//! * **Energy per metre**: [`EnergyCost`] over a window of `energy_window_s`, its motive part
//!   (E − P_h·T) / d, attributed to the window's middle pose. MartinCorke §4 estimates the velocity from
//!   the tracked position; the tracker's pose is noisy (millimetres at 30 Hz, while the robot moves
//!   3 mm per frame), and the length of a path through raw noisy poses measures mostly the noise.
//!   So the signal is fed a centred moving average of the pose stream over `pose_smoothing_s`:
//!   each smoothed pose is the mean of an odd number of raw poses, stamped with their mean time
//!   (exact for steady motion), which shrinks the noise of a frame-to-frame step by the window
//!   length. Power readings wait in a queue until the smoothed stream has passed their stamp, so
//!   every window is covered by smoothed poses.
//! * **Gates**: a window during which the smoothed heading turned faster than
//!   `turn_rate_threshold` is dropped: the robot turned in place (at a waypoint or a kink), its
//!   energy belongs to the turn, not to the ground, and MartinCorke models no turning energy. A window
//!   whose mean speed is below `min_speed_fraction` of the commanded speed is dropped by the
//!   signal itself (its `min_distance_m`).

use std::collections::VecDeque;

use serde::Serialize;
use strider_core::geom::wrap_angle;
use strider_core::interface::{Robot, SensorSink};
use strider_core::{Point2, Point3, PoseStamped, Proprioception};
use strider_learn::signals::{EnergyCost, EnergyParams};

use super::route::PlannedTour;
use super::{EnergyTourParams, TourError};

/// A tour that stays blocked this long (robot time) has failed.
const MAX_BLOCKED_S: f64 = 5.0;

/// Trajectory samples kept per second (for figures).
const TRAJECTORY_HZ: f64 = 3.0;

/// The figures of one driven tour.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TourMeasurement {
    /// Robot time at the start, seconds.
    pub start_s: f64,
    /// Duration, seconds.
    pub duration_s: f64,
    /// Tour energy E_t = ∫ P dt, joules (motive plus hotel load).
    pub energy_j: f64,
    /// Its motive part E_t − P_h · T, joules (what a log of the motor current alone shows).
    pub motive_energy_j: f64,
    /// Distance driven along the smoothed pose stream, metres.
    pub driven_m: f64,
    /// Energy-per-metre samples accepted for learning during this tour.
    pub samples: usize,
    /// Windows dropped because the robot turned in them.
    pub turn_rejected: usize,
    /// Windows dropped because the robot hardly moved in them.
    pub slow_rejected: u64,
    /// Mean motive energy per metre of the accepted samples, J/m.
    pub mean_motive_j_per_m: Option<f64>,
    /// The largest distance between a waypoint and the closest pose of the tour, metres.
    pub max_waypoint_miss_m: f64,
    /// Poses of the tour at about 3 Hz (raw, for figures).
    pub trajectory: Vec<Point2>,
}

/// A smoothed pose with the turn flag derived from it.
#[derive(Clone, Copy, Debug)]
struct Mark {
    stamp: f64,
    turning: bool,
}

/// The sensor sink of the repeated tours: integrates the power, smooths the poses, turns
/// power and smoothed poses into energy-per-metre samples, and records the trajectory.
pub(super) struct EnergyMeter {
    signal: EnergyCost,
    window_s: f64,
    turn_rate: f64,
    smoothing_n: usize,
    raw: VecDeque<PoseStamped>,
    last_smoothed: Option<(f64, f64, Point2)>,
    marks: VecDeque<Mark>,
    pending: VecDeque<Proprioception>,
    last_power: Option<(f64, f64)>,
    energy_j: f64,
    driven_m: f64,
    samples: Vec<(Point2, f64)>,
    turn_rejected: usize,
    last_pose: Option<PoseStamped>,
    poses: u64,
    trajectory_every: u64,
    trajectory: Vec<Point2>,
    closest: Vec<f64>,
    waypoints: Vec<Point2>,
}

impl EnergyMeter {
    /// A meter for the streams and gates of `params`.
    pub(super) fn new(params: &EnergyTourParams) -> Result<Self, TourError> {
        let window = params.energy_window_s;
        let signal = EnergyCost::new(EnergyParams {
            rate_hz: params.power_rate_hz,
            pose_rate_hz: params.pose_rate_hz,
            // The signal requires a positive minimum; without a speed gate, a micrometre.
            min_distance_m: (params.min_speed_fraction * params.speed_mps * window).max(1e-6),
            ..EnergyParams::new(window, params.mass_kg, params.hotel_load_w)
        })?;
        // An odd count, so the mean stamp is a stamp of the stream.
        let n = (params.pose_smoothing_s * params.pose_rate_hz)
            .round()
            .max(1.0) as usize;
        Ok(Self {
            signal,
            window_s: window,
            turn_rate: params.turn_rate_threshold,
            smoothing_n: n | 1,
            raw: VecDeque::with_capacity(n | 1),
            last_smoothed: None,
            marks: VecDeque::new(),
            pending: VecDeque::new(),
            last_power: None,
            energy_j: 0.0,
            driven_m: 0.0,
            samples: Vec::new(),
            turn_rejected: 0,
            last_pose: None,
            poses: 0,
            trajectory_every: ((params.pose_rate_hz / TRAJECTORY_HZ).round() as u64).max(1),
            trajectory: Vec::new(),
            closest: vec![f64::INFINITY; params.waypoints.len()],
            waypoints: params.waypoints.clone(),
        })
    }

    /// The samples accepted since the last call: (position, motive energy per metre in J/m).
    pub(super) fn take_samples(&mut self) -> Vec<(Point2, f64)> {
        std::mem::take(&mut self.samples)
    }

    /// Drives `plan` once as tour number `tour` and returns what was measured. The samples stay
    /// in the meter until [`Self::take_samples`].
    pub(super) fn drive<R: Robot>(
        &mut self,
        robot: &mut R,
        params: &EnergyTourParams,
        plan: &PlannedTour,
        tour: usize,
    ) -> Result<TourMeasurement, TourError> {
        let start_s = robot.now();
        let (e0, d0, n0, turn0) = (
            self.energy_j,
            self.driven_m,
            self.samples.len(),
            self.turn_rejected,
        );
        let slow0 = self.signal.short_windows();
        self.trajectory.clear();
        self.closest.iter_mut().for_each(|c| *c = f64::INFINITY);
        if let Some(p) = self.last_pose {
            self.note_pose(&p);
        }
        let limit = params.timeout_factor * plan.length_m / params.speed_mps + 60.0;
        robot.follow(&plan.path);
        let mut blocked_s = 0.0;
        loop {
            let st = robot
                .advance(params.control_dt_s, self)
                .map_err(|e| TourError::Robot(e.to_string()))?;
            if st.idle {
                break;
            }
            if st.blocked {
                blocked_s += params.control_dt_s;
                if blocked_s > MAX_BLOCKED_S {
                    let p = self.last_pose.ok_or(TourError::NoPose { tour })?;
                    return Err(TourError::Blocked {
                        tour,
                        x: p.position.x,
                        y: p.position.y,
                    });
                }
            } else {
                blocked_s = 0.0;
            }
            if robot.now() - start_s > limit {
                return Err(TourError::Timeout {
                    tour,
                    limit_s: limit,
                });
            }
        }
        robot.follow(&[]);
        if self.last_pose.is_none() {
            return Err(TourError::NoPose { tour });
        }
        let mut worst = 0.0f64;
        for (index, &c) in self.closest.iter().enumerate() {
            // Every waypoint is on every tour (the TSP visits them all).
            if c > params.cell_size {
                return Err(TourError::WaypointMissed {
                    tour,
                    index,
                    dist_m: c,
                });
            }
            worst = worst.max(c);
        }
        let new = &self.samples[n0..];
        let mean =
            (!new.is_empty()).then(|| new.iter().map(|s| s.1).sum::<f64>() / new.len() as f64);
        let duration_s = robot.now() - start_s;
        Ok(TourMeasurement {
            start_s,
            duration_s,
            energy_j: self.energy_j - e0,
            motive_energy_j: self.energy_j - e0 - params.hotel_load_w * duration_s,
            driven_m: self.driven_m - d0,
            samples: new.len(),
            turn_rejected: self.turn_rejected - turn0,
            slow_rejected: self.signal.short_windows() - slow0,
            mean_motive_j_per_m: mean,
            max_waypoint_miss_m: worst,
            trajectory: self.trajectory.clone(),
        })
    }

    /// Waypoint distances and the trajectory from a raw pose.
    fn note_pose(&mut self, p: &PoseStamped) {
        let xy = p.position.xy();
        for (c, w) in self.closest.iter_mut().zip(&self.waypoints) {
            *c = c.min(xy.dist(*w));
        }
        if self.poses.is_multiple_of(self.trajectory_every) {
            self.trajectory.push(xy);
        }
    }

    /// The centred mean of the raw window, once it is full.
    fn smoothed(&self) -> Option<PoseStamped> {
        let n = self.raw.len();
        if n < self.smoothing_n {
            return None;
        }
        let nf = n as f64;
        let (mut t, mut x, mut y, mut z, mut s, mut c) = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
        for p in &self.raw {
            t += p.stamp;
            x += p.position.x;
            y += p.position.y;
            z += p.position.z;
            s += p.yaw.sin();
            c += p.yaw.cos();
        }
        let mid = self.raw[n / 2];
        Some(PoseStamped {
            stamp: t / nf,
            position: Point3::new(x / nf, y / nf, z / nf),
            yaw: s.atan2(c),
            ..mid
        })
    }

    /// Feeds the queued power readings up to `until` into the signal and gates its samples.
    fn drain_pending(&mut self, until: f64) {
        while let Some(p) = self.pending.front().copied() {
            if p.stamp > until + 1e-9 {
                break;
            }
            self.pending.pop_front();
            let Some(s) = self.signal.push(&p) else {
                continue;
            };
            // The marks cover the window: the smoothed stream has passed its end.
            let from = p.stamp - self.window_s - 1e-9;
            let turned = self
                .marks
                .iter()
                .any(|m| m.turning && m.stamp >= from && m.stamp <= p.stamp + 1e-9);
            if turned {
                self.turn_rejected += 1;
            } else {
                self.samples.push((s.position.xy(), s.motive_energy_per_m));
            }
        }
    }
}

impl SensorSink for EnergyMeter {
    /// The rover has no range sensor to read, and the loop needs none.
    fn wants_cloud(&self, _sensor: u8) -> bool {
        false
    }

    fn on_pose(&mut self, pose: &PoseStamped) {
        let finite = pose.stamp.is_finite()
            && pose.position.x.is_finite()
            && pose.position.y.is_finite()
            && pose.position.z.is_finite()
            && pose.yaw.is_finite();
        let in_order = self.raw.back().is_none_or(|q| pose.stamp > q.stamp);
        if !(finite && in_order) {
            return;
        }
        self.poses += 1;
        self.last_pose = Some(*pose);
        self.note_pose(pose);
        if self.raw.len() == self.smoothing_n {
            self.raw.pop_front();
        }
        self.raw.push_back(*pose);
        let Some(sm) = self.smoothed() else {
            return;
        };
        let xy = sm.position.xy();
        let turning = match self.last_smoothed {
            Some((t, yaw, prev)) if sm.stamp > t => {
                self.driven_m += prev.dist(xy);
                wrap_angle(sm.yaw - yaw).abs() / (sm.stamp - t) > self.turn_rate
            }
            _ => false,
        };
        self.last_smoothed = Some((sm.stamp, sm.yaw, xy));
        self.marks.push_back(Mark {
            stamp: sm.stamp,
            turning,
        });
        // Marks older than the longest window still to be judged are not needed.
        let keep_from = sm.stamp - 2.0 * self.window_s - 1.0;
        while self.marks.front().is_some_and(|m| m.stamp < keep_from) {
            self.marks.pop_front();
        }
        self.signal.push_pose(&sm);
        self.drain_pending(sm.stamp);
    }

    fn on_proprioception(&mut self, p: &Proprioception) {
        if !(p.stamp.is_finite() && p.power_w.is_finite() && p.power_w >= 0.0) {
            return;
        }
        if let Some((t, w)) = self.last_power {
            if p.stamp <= t {
                return;
            }
            self.energy_j += 0.5 * (w + p.power_w) * (p.stamp - t);
        }
        self.last_power = Some((p.stamp, p.power_w));
        self.pending.push_back(*p);
        // Without smoothing lag (or before the first pose) the queue would only grow: bound it
        // to what the smoothed stream can still be behind by.
        let horizon = p.stamp - 2.0 * self.window_s - 5.0;
        while self.pending.front().is_some_and(|q| q.stamp < horizon) {
            self.pending.pop_front();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn params() -> EnergyTourParams {
        crate::energy_tours::test_params(vec![Point2::new(0.2, 0.2), Point2::new(1.0, 0.2)])
    }

    fn pose(t: f64, x: f64, y: f64, yaw: f64) -> PoseStamped {
        PoseStamped {
            stamp: t,
            position: Point3::new(x, y, 0.0),
            yaw,
            ..Default::default()
        }
    }

    fn power(t: f64, w: f64) -> Proprioception {
        Proprioception {
            stamp: t,
            power_w: w,
            ..Default::default()
        }
    }

    /// Straight driving at 0.1 m/s with ±3 mm alternating pose jitter: the smoothed path length
    /// stays within 1 % of the truth, and the motive J/m is (P − P_h) / v.
    #[test]
    fn smoothing_removes_pose_jitter_from_distance() {
        let p = params();
        let mut m = EnergyMeter::new(&p).unwrap();
        for k in 0..=300u32 {
            let t = k as f64 / 30.0;
            let jitter = if k.is_multiple_of(2) { 0.003 } else { -0.003 };
            m.on_pose(&pose(t, 0.1 * t + jitter, 0.5 - jitter, 0.0));
            if k.is_multiple_of(3) {
                m.on_proprioception(&power(t, 0.8));
            }
        }
        // The raw jittered path would be about twice as long as the true one.
        // The smoothed stream starts and ends half a window (7 of 15 poses) inside the run.
        let truth = 0.1 * (10.0 - 14.0 / 30.0);
        assert!((m.driven_m - truth).abs() < 0.01 * truth, "{}", m.driven_m);
        let s = m.take_samples();
        assert!(s.len() > 70, "{}", s.len());
        for (_, e) in &s {
            assert!((e - 6.0).abs() < 0.2, "{e}");
        }
        // 10 s at 0.8 W.
        assert!((m.energy_j - 8.0).abs() < 1e-9, "{}", m.energy_j);
    }

    /// A turn in place in the middle of a straight run: the windows that contain it are dropped,
    /// the others kept.
    #[test]
    fn windows_with_a_turn_are_not_learnt() {
        let p = params();
        let mut m = EnergyMeter::new(&p).unwrap();
        let mut x = 0.0;
        let mut yaw = 0.0;
        for k in 0..=600u32 {
            let t = k as f64 / 30.0;
            // Turn in place at 1 rad/s between 8 s and 9.5 s, drive otherwise.
            if (8.0..9.5).contains(&t) {
                yaw += 1.0 / 30.0;
            } else {
                x += 0.1 / 30.0;
            }
            m.on_pose(&pose(t, x, 0.5, yaw));
            if k.is_multiple_of(3) {
                m.on_proprioception(&power(t, 0.8));
            }
        }
        assert!(m.turn_rejected >= 5, "{}", m.turn_rejected);
        let s = m.take_samples();
        assert!(s.len() > 120, "{}", s.len());
        // No accepted window has the inflated J/m of standing still.
        assert!(s.iter().all(|(_, e)| *e < 7.0), "{s:?}");
    }

    #[test]
    fn bad_readings_are_ignored() {
        let p = params();
        let mut m = EnergyMeter::new(&p).unwrap();
        m.on_proprioception(&power(0.0, 1.0));
        m.on_proprioception(&power(f64::NAN, 1.0));
        m.on_proprioception(&power(0.5, -1.0));
        m.on_proprioception(&power(0.2, f64::INFINITY));
        m.on_proprioception(&power(1.0, 1.0));
        m.on_proprioception(&power(0.9, 5.0));
        assert!((m.energy_j - 1.0).abs() < 1e-12);
        m.on_pose(&pose(f64::NAN, 0.0, 0.0, 0.0));
        m.on_pose(&pose(1.0, f64::INFINITY, 0.0, 0.0));
        assert!(m.last_pose.is_none());
    }
}
