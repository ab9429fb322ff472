//! Pacing a mission to wall-clock time (`--rate R`): R × real time, so that a recorded log
//! (or a simulated mission) can be watched live. [`Paced`] wraps the robot and waits before
//! each control step until the wall clock has caught up with the robot time the step reaches;
//! what the robot delivers, and so every result, is unchanged. A step that computes longer
//! than its share is not waited for, and the next steps wait less until the clock is caught up.
//! Waiting stops as soon as the cancellation flag is set (Ctrl-C), so an interrupt is seen at
//! the next control tick.

use std::thread;
use std::time::{Duration, Instant};

use strider_core::GaitId;
use strider_core::Point2;
use strider_core::interface::{MotionState, Robot, SensorSink};

use crate::cancel::Cancel;

/// A pacing rate: robot seconds per wall second (1.0 = real time).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rate(f64);

impl Rate {
    /// The slowest rate: a hundredth of real time (a 20 Hz log then shows a pose every 5 s),
    /// slower would only look frozen.
    pub const MIN: f64 = 0.01;
    /// The fastest rate: beyond it pacing no longer slows a mission (replay runs at a few
    /// hundred to a few thousand times real time).
    pub const MAX: f64 = 1e4;

    /// `r`, if finite and within [`Rate::MIN`] ..= [`Rate::MAX`].
    pub fn new(r: f64) -> Result<Self, RateError> {
        if r.is_finite() && (Self::MIN..=Self::MAX).contains(&r) {
            Ok(Self(r))
        } else {
            Err(RateError(r))
        }
    }

    /// Robot seconds per wall second.
    pub fn get(self) -> f64 {
        self.0
    }
}

/// A rate out of range.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
#[error(
    "must be a finite multiple of real time from {min} to {max:e} (1 = recorded speed), got {0}",
    min = Rate::MIN,
    max = Rate::MAX
)]
pub struct RateError(pub f64);

/// The longest single sleep while pacing: how late a Ctrl-C is seen at worst.
const POLL: Duration = Duration::from_millis(50);

/// Keeps robot time at a rate of wall time, from the first step on.
#[derive(Debug)]
pub struct Pacer {
    rate: f64,
    /// Wall clock and robot time of the first step.
    start: Option<(Instant, f64)>,
    cancel: Cancel,
}

impl Pacer {
    /// Paces at `rate`, waiting no more once `cancel` is requested.
    pub fn new(rate: Rate, cancel: Cancel) -> Self {
        Self {
            rate: rate.get(),
            start: None,
            cancel,
        }
    }

    /// Waits until the wall time since the first call reaches the robot time from `now` (the
    /// robot time of the first call) to `until`, divided by the rate.
    pub fn step(&mut self, now: f64, until: f64) {
        let Some(due) = self.deadline(now, until) else {
            return;
        };
        while !self.cancel.requested() {
            let left = due.saturating_duration_since(Instant::now());
            if left.is_zero() {
                break;
            }
            thread::sleep(left.min(POLL));
        }
    }

    /// When robot time `until` is due on the wall clock (`now` starts the clock on the first
    /// call); `None` when it is due at once.
    fn deadline(&mut self, now: f64, until: f64) -> Option<Instant> {
        let (wall0, t0) = *self.start.get_or_insert((Instant::now(), now));
        let due = (until - t0) / self.rate;
        // Robot time is bounded (10⁶ s), the cap only keeps the Duration in range.
        (due.is_finite() && due > 0.0).then(|| wall0 + Duration::from_secs_f64(due.min(1e9)))
    }
}

/// A robot whose steps are paced by a [`Pacer`] (or not, without one).
pub struct Paced<'a, R> {
    robot: &'a mut R,
    pacer: Option<Pacer>,
}

impl<'a, R: Robot> Paced<'a, R> {
    /// `robot`, paced by `pacer` if given.
    pub fn new(robot: &'a mut R, pacer: Option<Pacer>) -> Self {
        Self { robot, pacer }
    }
}

impl<R: Robot> Robot for Paced<'_, R> {
    type Error = R::Error;

    fn now(&self) -> f64 {
        self.robot.now()
    }

    fn follow(&mut self, path: &[Point2]) {
        self.robot.follow(path);
    }

    fn set_gait(&mut self, gait: GaitId) {
        self.robot.set_gait(gait);
    }

    /// Waits until the step's end is due, then lets the robot deliver it: messages go out when
    /// the wall clock reaches their robot time.
    fn advance(&mut self, dt: f64, sink: &mut dyn SensorSink) -> Result<MotionState, R::Error> {
        if let Some(p) = &mut self.pacer {
            let now = self.robot.now();
            p.step(now, now + dt);
        }
        self.robot.advance(dt, sink)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rates_out_of_range_are_refused_with_the_range() {
        for r in [0.0, -1.0, 0.001, 1e5, f64::NAN, f64::INFINITY] {
            let e = Rate::new(r).unwrap_err().to_string();
            assert!(e.contains("from 0.01 to 1e4"), "{e}");
        }
        assert_eq!(Rate::new(1.0).unwrap().get(), 1.0);
    }

    #[test]
    fn a_cancelled_pacer_does_not_wait() {
        let cancel = Cancel::new();
        let mut p = Pacer::new(Rate::new(Rate::MIN).unwrap(), cancel.clone());
        p.step(0.0, 0.0);
        cancel.request();
        // 1000 robot s at a hundredth of real time would be a day of waiting.
        p.step(0.0, 1000.0);
    }

    #[test]
    fn robot_time_is_due_at_its_share_of_wall_time() {
        let mut p = Pacer::new(Rate::new(10.0).unwrap(), Cancel::new());
        assert_eq!(p.deadline(5.0, 5.0), None);
        let (wall0, _) = p.start.unwrap();
        assert_eq!(
            p.deadline(5.0, 6.0),
            Some(wall0 + Duration::from_millis(100))
        );
        // The clock runs from the first step: later steps are due relative to it.
        assert_eq!(p.deadline(9.0, 25.0), Some(wall0 + Duration::from_secs(2)));
        assert_eq!(p.deadline(9.0, 4.0), None);
    }
}
