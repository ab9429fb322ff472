//! What a strategy is to the kernel: the [`Strategy`] trait every exploration method
//! implements, and the [`Actuators`] it commands the robot through.

use super::body::Body;
use super::record::{GoalCounts, Termination};
use strider_core::interface::MotionState;
use strider_core::snapshot::Snapshot;
use strider_core::{GaitId, Point2, PoseStamped, Proprioception};

/// The commands a strategy gives the robot.
pub trait Actuators {
    /// Current robot time, s.
    fn now(&self) -> f64;
    /// Replaces the path being followed (world waypoints, first one nearest the robot).
    fn follow(&mut self, path: &[Point2]);
    /// Selects the gait used from now on.
    fn set_gait(&mut self, gait: GaitId);
}

/// An exploration method on the kernel: what it measures from the sensor stream, and the
/// goals, tour, path and gait it decides from the body's state.
pub trait Strategy {
    /// The strategy's registry name (e.g. `gtsp`).
    fn name(&self) -> &'static str;
    /// The control tick's rate, Hz.
    fn control_hz(&self) -> f64;
    /// The gait commanded before the first tick (`None`: the robot's own).
    fn initial_gait(&self) -> Option<GaitId> {
        None
    }
    /// Called once before the first tick, at robot time `t0`.
    fn start(&mut self, _body: &mut Body, _t0: f64) {}
    /// Called before each advance with the motion state of the previous tick and its time.
    fn before_advance(&mut self, _body: &Body, _state: MotionState, _t: f64) {}
    /// A pose with a finite position and heading, after the body took it.
    fn on_pose(&mut self, _body: &Body, _pose: &PoseStamped) {}
    /// Proprioceptive readings.
    fn on_proprioception(&mut self, _body: &Body, _p: &Proprioception) {}
    /// One control tick at robot time `t` after the robot advanced: the modules that are due,
    /// then the decisions. `state` persists across ticks (a strategy may clear its flags once
    /// it acted on them). `Some` ends the mission.
    fn tick(
        &mut self,
        body: &mut Body,
        robot: &mut dyn Actuators,
        state: &mut MotionState,
        t: f64,
    ) -> Option<Termination>;
    /// One tick of ingesting a recorded log (`Mission::ingest`): measurement and learning
    /// only, no goals, planning or commands. Default: nothing beyond the body's mapping.
    fn ingest_tick(&mut self, _body: &mut Body, _state: &mut MotionState, _t: f64) {}
    /// Called once after the last tick at robot time `t` (the robot is stopped).
    fn finish(&mut self, _body: &mut Body, _t: f64) {}
    /// The strategy's part of the progress display.
    fn goal_counts(&self) -> GoalCounts;
    /// The strategy's part of a [`Snapshot`]: its goals and tour and, when `snap.layers` is
    /// present, its models' layers over `layers.rect` and the costs measured so far.
    fn describe(&self, body: &Body, snap: &mut Snapshot);
}

/// A boxed strategy is a strategy: missions of strategies chosen at run time, and of
/// strategies written outside this crate.
impl<S: Strategy + ?Sized> Strategy for Box<S> {
    fn name(&self) -> &'static str {
        (**self).name()
    }
    fn control_hz(&self) -> f64 {
        (**self).control_hz()
    }
    fn initial_gait(&self) -> Option<GaitId> {
        (**self).initial_gait()
    }
    fn start(&mut self, body: &mut Body, t0: f64) {
        (**self).start(body, t0)
    }
    fn before_advance(&mut self, body: &Body, state: MotionState, t: f64) {
        (**self).before_advance(body, state, t)
    }
    fn on_pose(&mut self, body: &Body, pose: &PoseStamped) {
        (**self).on_pose(body, pose)
    }
    fn on_proprioception(&mut self, body: &Body, p: &Proprioception) {
        (**self).on_proprioception(body, p)
    }
    fn tick(
        &mut self,
        body: &mut Body,
        robot: &mut dyn Actuators,
        state: &mut MotionState,
        t: f64,
    ) -> Option<Termination> {
        (**self).tick(body, robot, state, t)
    }
    fn ingest_tick(&mut self, body: &mut Body, state: &mut MotionState, t: f64) {
        (**self).ingest_tick(body, state, t)
    }
    fn finish(&mut self, body: &mut Body, t: f64) {
        (**self).finish(body, t)
    }
    fn goal_counts(&self) -> GoalCounts {
        (**self).goal_counts()
    }
    fn describe(&self, body: &Body, snap: &mut Snapshot) {
        (**self).describe(body, snap)
    }
}
