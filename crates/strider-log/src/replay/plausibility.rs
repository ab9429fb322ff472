//! Plausibility checks of a log, made once it is read: a pose stream faster than the robot's
//! gaits, pose jumps, stamps going backwards on a topic, and clouds without a pose near them.
//! None of them stops the replay; they are counted and said once as warnings, since each makes
//! the learned costs or the map wrong without an error.

use super::poses::TimedPose;
use crate::ros2::nanos_to_seconds;
use serde::Serialize;
use strider_core::GaitSpec;

/// Baseline over which the speed is measured, s: from each pose back to the newest pose at
/// least this much older, in the same gait and after the latest jump. Tick to tick, stamp jitter and position noise would make speeds far
/// above the true ones (a 20 Hz stream with 3 mm of noise reads ±0.1 m/s); over 2 s the noise
/// is a few mm/s, and the straight line between the two poses only underestimates the speed.
pub const SPEED_BASELINE_S: f64 = 2.0;

/// How far the measured speed may exceed the gait's v_max before it counts, as a fraction of
/// v_max: robots overshoot their nominal top speed a little, and a profile within 20 % of the
/// robot's speed still learns sensible costs.
pub const SPEED_MARGIN: f64 = 0.2;

/// Shortest pose step that can be a jump, m: well above one step of any pose stream (a robot
/// at 2 m/s logged at 5 Hz moves 0.4 m).
pub const JUMP_MIN_M: f64 = 0.5;

/// A step of at least [`JUMP_MIN_M`] is a jump when it is also longer than this many times the
/// distance the fastest gait covers in the step's interval: a relocalisation, an odometry
/// reset or a teleport, not driving (a gap in the log, where the robot drove on, is not).
pub const JUMP_SPEED_FACTOR: f64 = 3.0;

/// What the checks found (counts and extremes; all zero for a plausible log).
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Plausibility {
    /// Poses whose speed over [`SPEED_BASELINE_S`] exceeds their gait's v_max by more than
    /// [`SPEED_MARGIN`].
    pub too_fast_poses: usize,
    /// Poses the speed was measured at.
    pub speed_checked_poses: usize,
    /// The highest speed measured, m/s.
    pub max_speed_mps: f64,
    /// The gait of the pose with the highest speed over its v_max, and that v_max (m/s).
    pub max_speed_gait: Option<(String, f64)>,
    /// Pose steps that are jumps ([`JUMP_MIN_M`], [`JUMP_SPEED_FACTOR`]).
    pub pose_jumps: usize,
    /// The longest jump, m.
    pub max_jump_m: f64,
    /// Messages stamped before the previous message of their topic (in file order) on the
    /// pose and cloud topics and the base frame's transforms; the replay orders them by stamp.
    pub backward_stamps: usize,
    /// The first such message: (topic, index on the topic).
    pub first_backward: Option<(String, usize)>,
    /// Clouds with no pose within `[tf] tolerance_s` of their stamp (mapped from a pose the
    /// robot may not have had).
    pub clouds_without_pose: usize,
    /// The tolerance they were judged by, s.
    pub pose_tolerance_s: f64,
}

impl Plausibility {
    /// The warnings, one line each, in a fixed order; none for a plausible log.
    pub fn warnings(&self) -> Vec<String> {
        let mut w = Vec::new();
        if self.too_fast_poses > 0 {
            let gait = self
                .max_speed_gait
                .as_ref()
                .map(|(g, v)| format!("; gait {g:?} has v_max = {v} m/s"))
                .unwrap_or_default();
            w.push(format!(
                "the robot moved faster than its gait's v_max at {} of {} poses (speed over \
                 {SPEED_BASELINE_S} s more than {:.0} % above v_max; up to {:.3} m/s{gait}): \
                 the profile's gaits are slower than the robot, so the learned costs are too \
                 low; give the gaits the robot's top speeds",
                self.too_fast_poses,
                self.speed_checked_poses,
                SPEED_MARGIN * 100.0,
                self.max_speed_mps,
            ));
        }
        if self.pose_jumps > 0 {
            w.push(format!(
                "{} pose jumps (steps over {JUMP_MIN_M} m and over {JUMP_SPEED_FACTOR} times \
                 what the fastest gait covers in their interval; the longest {:.2} m): cost \
                 windows across a jump measure it, not the terrain",
                self.pose_jumps, self.max_jump_m
            ));
        }
        if let Some((topic, index)) = &self.first_backward {
            w.push(format!(
                "{} messages are stamped before the previous one on their topic (the first: \
                 {topic}, message {index}); they are replayed in stamp order",
                self.backward_stamps
            ));
        }
        if self.clouds_without_pose > 0 {
            w.push(format!(
                "{} clouds have no pose within [tf] tolerance_s = {} s of their stamp: the \
                 pose stream has gaps there",
                self.clouds_without_pose, self.pose_tolerance_s
            ));
        }
        w
    }

    /// Counts speeds above the gaits' v_max and pose jumps over `poses` (in stamp order).
    pub(super) fn check_poses(&mut self, poses: &[TimedPose], gaits: &[GaitSpec]) {
        let v_fastest = gaits.iter().map(|g| g.v_max).fold(0.0, f64::max);
        let planar = |a: &TimedPose, b: &TimedPose| {
            (a.2.position.x - b.2.position.x).hypot(a.2.position.y - b.2.position.y)
        };
        // The baseline pose of the speed: never before the latest jump or gait change (a span
        // of two gaits is held to neither's v_max).
        let mut base = 0;
        let mut worst_excess = f64::NEG_INFINITY;
        for i in 1..poses.len() {
            let (prev, p) = (&poses[i - 1], &poses[i]);
            let dt = nanos_to_seconds(p.0 - prev.0);
            let step = planar(prev, p);
            if step > JUMP_MIN_M && step > JUMP_SPEED_FACTOR * v_fastest * dt {
                self.pose_jumps += 1;
                self.max_jump_m = self.max_jump_m.max(step);
                base = i;
                continue;
            }
            if p.2.gait != prev.2.gait {
                base = i;
                continue;
            }
            while base + 1 < i && nanos_to_seconds(p.0 - poses[base + 1].0) >= SPEED_BASELINE_S {
                base += 1;
            }
            let span = nanos_to_seconds(p.0 - poses[base].0);
            if span < SPEED_BASELINE_S {
                continue;
            }
            let speed = planar(&poses[base], p) / span;
            self.speed_checked_poses += 1;
            self.max_speed_mps = self.max_speed_mps.max(speed);
            let Some(g) = gaits.get(p.2.gait.0 as usize) else {
                continue;
            };
            if speed > g.v_max * (1.0 + SPEED_MARGIN) {
                self.too_fast_poses += 1;
            }
            if speed - g.v_max > worst_excess {
                worst_excess = speed - g.v_max;
                self.max_speed_gait = Some((g.name.clone(), g.v_max));
            }
        }
        if self.too_fast_poses == 0 {
            self.max_speed_gait = None;
        }
    }

    /// Counts the clouds stamped at `clouds` (ns relative to the start, any order) with no pose
    /// of `poses` (in stamp order) within `tolerance_ns`.
    pub(super) fn check_clouds(&mut self, clouds: &[i64], poses: &[TimedPose], tolerance_ns: i64) {
        self.pose_tolerance_s = nanos_to_seconds(tolerance_ns);
        for &c in clouds {
            let k = poses.partition_point(|p| p.0 < c);
            let near = |j: usize| {
                poses
                    .get(j)
                    .is_some_and(|p| p.0.abs_diff(c) <= tolerance_ns as u64)
            };
            if !(near(k) || (k > 0 && near(k - 1))) {
                self.clouds_without_pose += 1;
            }
        }
    }
}
