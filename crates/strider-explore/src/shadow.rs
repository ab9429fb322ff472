//! A strategy with a passive Prágr22 learner alongside: the per-gait traversal-cost models a
//! `gtsp` explorer would learn from the very data the strategy collects (its poses, gaits and
//! scans), without a say in what the robot does. Comparisons of strategies that learn
//! different quantities (inverse velocity, roll variance, force) use it as one yardstick: the
//! benchmark tour driven with learned navigation on the shadow's models measures how useful
//! the strategy's exploration data is for planning cheap paths.

use crate::kernel::{Actuators, Body, GoalCounts, Strategy, Termination};
use crate::tour_explorer::TourExplorer;
use strider_core::interface::MotionState;
use strider_core::snapshot::Snapshot;
use strider_core::{GaitId, PoseStamped, Proprioception};

/// `main` decides; `learner` only measures and learns ([`Strategy::ingest_tick`]).
pub struct Shadowed<S> {
    main: S,
    learner: TourExplorer,
}

impl<S: Strategy> Shadowed<S> {
    /// `main` with `learner` (a Prágr22 explorer) learning alongside.
    pub fn new(main: S, learner: TourExplorer) -> Self {
        Self { main, learner }
    }

    /// The strategy that decides.
    pub fn main(&self) -> &S {
        &self.main
    }

    /// The passive learner.
    pub fn learner(&self) -> &TourExplorer {
        &self.learner
    }
}

impl<S: Strategy> Strategy for Shadowed<S> {
    fn name(&self) -> &'static str {
        self.main.name()
    }

    fn control_hz(&self) -> f64 {
        self.main.control_hz()
    }

    fn initial_gait(&self) -> Option<GaitId> {
        self.main.initial_gait()
    }

    fn start(&mut self, body: &mut Body, t0: f64) {
        self.main.start(body, t0);
        self.learner.start(body, t0);
    }

    fn before_advance(&mut self, body: &Body, state: MotionState, t: f64) {
        self.main.before_advance(body, state, t);
        self.learner.before_advance(body, state, t);
    }

    fn on_pose(&mut self, body: &Body, pose: &PoseStamped) {
        self.main.on_pose(body, pose);
        self.learner.on_pose(body, pose);
    }

    fn on_proprioception(&mut self, body: &Body, p: &Proprioception) {
        self.main.on_proprioception(body, p);
    }

    fn tick(
        &mut self,
        body: &mut Body,
        robot: &mut dyn Actuators,
        state: &mut MotionState,
        t: f64,
    ) -> Option<Termination> {
        // The strategy decides first, as it would alone; the learner then sees the motion state
        // the robot reported. (The learner refreshes the map's derived passability layer at its
        // learning rate, so a strategy that reads that layer before refreshing it itself may
        // see it fresher than alone.)
        let seen = *state;
        let end = self.main.tick(body, robot, state, t);
        let mut seen = seen;
        self.learner.ingest_tick(body, &mut seen, t);
        end
    }

    fn ingest_tick(&mut self, body: &mut Body, state: &mut MotionState, t: f64) {
        let mut seen = *state;
        self.learner.ingest_tick(body, &mut seen, t);
        self.main.ingest_tick(body, state, t);
    }

    fn finish(&mut self, body: &mut Body, t: f64) {
        self.main.finish(body, t);
        self.learner.finish(body, t);
    }

    fn goal_counts(&self) -> GoalCounts {
        self.main.goal_counts()
    }

    fn describe(&self, body: &Body, snap: &mut Snapshot) {
        self.main.describe(body, snap);
    }
}
