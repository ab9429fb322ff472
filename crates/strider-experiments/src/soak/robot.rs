//! The simulator behind the robot interface with the soak's judge watching: the true pose at
//! every pose tick, every commanded path and gait, and a wall-clock bound.
//!
//! The kernel advances the robot once per control tick (10–20 Hz), possibly over several pose
//! ticks. To see the true pose at each of them, [`Judged`] advances the simulator to each pose
//! tick in turn. That must not change the mission: the simulator integrates on its own grid
//! cut at every message time, and stops an advance at the first of its instants within
//! [`SIM_TIME_EPS`] of the advance's end. A split at an instant the simulator stops at anyway
//! changes nothing, provided that (a) the piece ends exactly on that instant (its length is
//! chosen so that the simulator's own sum lands on it) and (b) no other instant of the
//! simulator lies just before it (within the tolerance, where the split advance would stop
//! early). Pose ticks that fail either are not split at; the pose is then judged at the end of
//! the advance. A test checks that a mission with the judge is the same mission as without.

use std::time::{Duration, Instant};

use strider_core::interface::{MotionState, Robot, SensorSink};
use strider_core::{GaitId, Point2};
use strider_scenario::Scenario;
use strider_sim::{SimError, Simulator};

use super::judge::Judge;
use super::violation::{Findings, Kind};

/// The simulator's tolerance on times (`strider_sim::simulator`'s `TIME_EPS`), s: instants
/// closer than this are one instant to it.
pub const SIM_TIME_EPS: f64 = 1e-9;

/// Pose ticks in one advance beyond which the judge does not split it (a control period this
/// long is a parameter error the mission reports itself; splitting it would only cost time).
const MAX_PIECES: f64 = 10_000.0;

/// What stops a judged robot.
#[derive(Debug, thiserror::Error)]
pub enum JudgedError {
    /// The simulator failed.
    #[error(transparent)]
    Sim(#[from] SimError),
    /// The mission ran longer than its wall-clock bound.
    #[error("the mission ran past its wall-clock bound of {0:.0} s")]
    WallBound(f64),
}

/// The instants the simulator stops at, from its parameters.
#[derive(Clone, Debug)]
struct Clock {
    dt: f64,
    pose_hz: f64,
    /// Proprioception and every sensor.
    other_hz: Vec<f64>,
}

impl Clock {
    fn of(sc: &Scenario) -> Self {
        let mut other_hz = vec![sc.sim.proprio_rate_hz];
        other_hz.extend(sc.robot.sensors.iter().map(|s| s.rate_hz));
        Self {
            dt: sc.sim.dt,
            pose_hz: sc.sim.pose_rate_hz,
            other_hz,
        }
    }

    /// Whether another instant of the simulator lies within the tolerance before `t`.
    fn crowded(&self, t: f64) -> bool {
        let near = |s: f64| s >= t - SIM_TIME_EPS && s < t;
        let grid = |k: f64| k * self.dt + self.dt;
        let kg = (t / self.dt).round() - 1.0;
        [kg - 1.0, kg, kg + 1.0]
            .into_iter()
            .any(|k| k >= 0.0 && near(grid(k)))
            || self.other_hz.iter().any(|&hz| {
                let m = (t * hz).round();
                [m - 1.0, m, m + 1.0]
                    .into_iter()
                    .any(|m| m >= 0.0 && near(m / hz))
            })
    }

    /// The lengths of the pieces an advance by `dt` from time `a` is split into, one ending on
    /// each pose tick it crosses where that is exact (see the module docs); `[dt]` when none.
    fn pieces(&self, a: f64, dt: f64) -> Vec<f64> {
        let end = a + dt;
        if !(end.is_finite() && dt > 0.0 && dt * self.pose_hz <= MAX_PIECES) {
            return vec![dt];
        }
        let mut pieces = Vec::new();
        let mut at = a;
        // The first pose tick the simulator has not emitted at time `a`.
        let mut n = ((a + SIM_TIME_EPS) * self.pose_hz).floor().max(0.0);
        while n / self.pose_hz <= a + SIM_TIME_EPS {
            n += 1.0;
        }
        loop {
            let tick = n / self.pose_hz;
            if tick >= end - SIM_TIME_EPS {
                break;
            }
            if !self.crowded(tick)
                && let Some(x) = exact_piece(at, tick)
            {
                pieces.push(x);
                at = tick;
            }
            n += 1.0;
        }
        match exact_piece(at, end) {
            Some(x) if !pieces.is_empty() => {
                pieces.push(x);
                pieces
            }
            _ => vec![dt],
        }
    }
}

/// A length `x` with `from + x == to` in floating point, if one is near `to - from`.
fn exact_piece(from: f64, to: f64) -> Option<f64> {
    let x = to - from;
    [
        x,
        x.next_up(),
        x.next_down(),
        x.next_up().next_up(),
        x.next_down().next_down(),
    ]
    .into_iter()
    .find(|&x| x >= 0.0 && from + x == to)
}

/// What the judge counted while the mission ran.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counts {
    /// True poses judged.
    pub poses: u64,
    /// Of them, with the centre in a cell the map's rule on the true elevation calls
    /// inadmissible (counted only).
    pub near_obstacles: u64,
    /// Commanded paths judged.
    pub paths: u64,
    /// Advances the judge could not split at every pose tick.
    pub unsplit: u64,
}

/// The simulator with the judge watching (see the module docs).
pub struct Judged<'a> {
    sim: Simulator,
    judge: &'a Judge,
    clock: Clock,
    deadline: Instant,
    bound_s: f64,
    timed_out: bool,
    /// Violations seen.
    pub findings: Findings,
    /// What was judged.
    pub counts: Counts,
}

impl<'a> Judged<'a> {
    /// `sim` of scenario `sc`, judged by `judge`; advancing fails once `wall_bound` has passed.
    pub fn new(sim: Simulator, sc: &Scenario, judge: &'a Judge, wall_bound: Duration) -> Self {
        Self {
            sim,
            judge,
            clock: Clock::of(sc),
            deadline: Instant::now() + wall_bound,
            bound_s: wall_bound.as_secs_f64(),
            timed_out: false,
            findings: Findings::default(),
            counts: Counts::default(),
        }
    }

    /// The simulator (the ground truth).
    pub fn sim(&self) -> &Simulator {
        &self.sim
    }

    /// The judge (borrowed for as long as the judged robot is).
    pub fn judge(&self) -> &'a Judge {
        self.judge
    }

    /// Whether an advance failed for the wall-clock bound.
    pub fn timed_out(&self) -> bool {
        self.timed_out
    }

    fn judge_pose(&mut self) {
        let (pose, ground) = (self.sim.pose(), self.sim.body_z());
        self.counts.poses += 1;
        if !self.judge.clear_of_obstacles(pose.position()) {
            self.counts.near_obstacles += 1;
        }
        if let Err(e) = self.judge.pose(pose, ground) {
            let t = self.sim.now();
            self.findings.add(Kind::Pose, || format!("t {t:.2} s: {e}"));
        }
    }
}

impl Robot for Judged<'_> {
    type Error = JudgedError;

    fn now(&self) -> f64 {
        self.sim.now()
    }

    fn follow(&mut self, path: &[Point2]) {
        self.counts.paths += 1;
        for &p in path {
            if let Err(e) = self.judge.waypoint(p) {
                let t = self.sim.now();
                self.findings.add(Kind::Plan, || format!("t {t:.2} s: {e}"));
            }
        }
        self.sim.follow(path);
    }

    fn set_gait(&mut self, gait: GaitId) {
        let n = self.judge.gaits();
        if gait.0 as usize >= n {
            let t = self.sim.now();
            self.findings.add(Kind::Plan, || {
                format!("t {t:.2} s: gait {} commanded, the robot has {n}", gait.0)
            });
        }
        self.sim.set_gait(gait);
    }

    fn advance(&mut self, dt: f64, sink: &mut dyn SensorSink) -> Result<MotionState, JudgedError> {
        if Instant::now() > self.deadline {
            self.timed_out = true;
            return Err(JudgedError::WallBound(self.bound_s));
        }
        let pieces = self.clock.pieces(self.sim.now(), dt);
        if pieces.len() == 1 && dt * self.clock.pose_hz > 1.0 + SIM_TIME_EPS {
            self.counts.unsplit += 1;
        }
        let mut state = MotionState::default();
        for d in pieces {
            state = self.sim.advance(d, sink)?;
            self.judge_pose();
        }
        Ok(state)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn clock() -> Clock {
        Clock {
            dt: 0.05,
            pose_hz: 20.0,
            other_hz: vec![20.0, 5.0],
        }
    }

    #[test]
    fn an_advance_is_split_exactly_on_the_pose_ticks_it_crosses() {
        let c = clock();
        let mut t = 0.0;
        for _ in 0..2000 {
            let pieces = c.pieces(t, 0.1);
            let mut at = t;
            for &p in &pieces {
                at += p;
            }
            assert_eq!(at, t + 0.1, "the pieces end where the advance does");
            assert!(pieces.len() <= 2);
            t += 0.1;
        }
        // Most control ticks of 10 Hz cross one pose tick of 20 Hz and are split there.
        let split = (0..2000)
            .filter(|&i| c.pieces(i as f64 * 0.1, 0.1).len() == 2)
            .count();
        assert!(split > 1000, "{split} of 2000 split");
        // One pose tick per advance: nothing to split.
        assert_eq!(c.pieces(0.0, 0.05), vec![0.05]);
        assert_eq!(c.pieces(0.0, f64::NAN).len(), 1);
    }

    #[test]
    fn an_instant_just_before_a_tick_prevents_the_split() {
        let mut c = clock();
        assert!(!c.crowded(0.5));
        c.other_hz.push(1.0 / (0.5 - 0.5e-9));
        assert!(c.crowded(0.5));
    }
}
