//! Where the robot's time goes: driving, turning on the spot, the look-around, sampling, the
//! stuck reflex, or standing still.

use super::TourExplorer;
use crate::kernel::Body;
use strider_core::interface::MotionState;

/// Below this fraction of the fastest gait's v_max the robot counts as standing (turning on
/// the spot, or waiting).
const STANDING_OF_V_MAX: f64 = 0.1;
/// Above this heading rate a standing robot counts as turning, rad/s.
const TURNING_RAD_S: f64 = 0.05;

/// Robot time per activity over a mission, s.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct Activity {
    /// Moving along a path (or a sampling walk's ends are not separated: see `sampling`).
    pub driving: f64,
    /// Turning on the spot while following a path (no look-around running).
    pub turning: f64,
    /// The look-around at a reached spatial goal.
    pub look_around: f64,
    /// The sampling manoeuvre at a cost goal.
    pub sampling: f64,
    /// The stuck reflex (the rough gait's fallback).
    pub stuck_reflex: f64,
    /// Standing without turning: no path, or waiting for a replan.
    pub waiting: f64,
}

impl Activity {
    /// Total robot time, s.
    pub fn total(&self) -> f64 {
        self.driving
            + self.turning
            + self.look_around
            + self.sampling
            + self.stuck_reflex
            + self.waiting
    }
}

/// The last control tick: its time, the pose it saw and how that pose was moving.
#[derive(Clone, Copy, Debug)]
pub(super) struct LastTick {
    t: f64,
    stamp: f64,
    x: f64,
    y: f64,
    yaw: f64,
    motion: Motion,
}

/// How the robot moved between its last two poses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Motion {
    Driving,
    Turning,
    Standing,
}

impl TourExplorer {
    /// Adds the time since the last control tick to what the robot is doing now. Poses may
    /// arrive more slowly than control ticks: the motion is measured between poses and holds
    /// until the next one.
    pub(super) fn track_activity(&mut self, body: &Body, state: MotionState, t: f64) {
        let Some(pose) = body.pose() else {
            return;
        };
        let (x, y, yaw, stamp) = (pose.position.x, pose.position.y, pose.yaw, pose.stamp);
        let motion = match self.last_tick {
            Some(l) if stamp > l.stamp => {
                let dt = stamp - l.stamp;
                let speed = (x - l.x).hypot(y - l.y) / dt;
                let turn = (yaw - l.yaw).sin().atan2((yaw - l.yaw).cos()).abs() / dt;
                if speed >= STANDING_OF_V_MAX * self.params.v_max() {
                    Motion::Driving
                } else if turn > TURNING_RAD_S {
                    Motion::Turning
                } else {
                    Motion::Standing
                }
            }
            Some(l) => l.motion,
            None => Motion::Standing,
        };
        let now = LastTick {
            t,
            stamp,
            x,
            y,
            yaw,
            motion,
        };
        let Some(last) = self.last_tick.replace(now) else {
            return;
        };
        let dt = t - last.t;
        if !(dt > 0.0 && dt.is_finite()) {
            return;
        }
        let a = &mut self.log.activity_s;
        let slot = if self.looking.is_some() {
            &mut a.look_around
        } else if self.sampling.is_some() {
            &mut a.sampling
        } else if self.fallback.is_active(t) {
            &mut a.stuck_reflex
        } else {
            match motion {
                Motion::Driving if !state.idle => &mut a.driving,
                Motion::Turning => &mut a.turning,
                _ => &mut a.waiting,
            }
        };
        *slot += dt;
    }
}
