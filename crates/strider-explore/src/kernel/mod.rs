//! The mission kernel: one robot body, one run loop, and the [`Strategy`] that decides.
//!
//! A [`Mission`] drives a [`Robot`] in the robot's own time. Each control tick the robot
//! advances by one control period, reporting its sensor stream: poses and fused scans go to
//! the [`Body`] (pose, elevation map, keyframes, distance and trajectory), then to the
//! strategy's own signals (cost measurement, haptics). After the tick the strategy runs the
//! modules that are due at their rates ([`Every`]), decides goals, tour, path and gait, and
//! commands the robot. The kernel stops the mission at the time limit or when the strategy
//! reports a [`Termination`]. Every strategy reaches the robot only through [`Actuators`] and
//! the body, so the same loop runs on a simulator, a robot or a recorded log.

pub mod body;
pub mod goals;
pub mod keyframes;
pub mod manoeuvres;
pub mod record;
pub mod snapshot;
pub mod strategy;

pub use body::{Body, BodyParams, lattice_map_params};
pub use goals::drop_visited;
pub use manoeuvres::{Every, LOOK_AROUND_S, Manoeuvre, look_around, start_look_around};
pub use record::{
    GoalCounts, MissionError, MissionProgress, RunRecord, Termination, TrajectorySample,
};
pub use snapshot::{map_layers, site, site_at, spatial_goal_set};
pub use strategy::{Actuators, Strategy};

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;
use strider_core::interface::{MotionState, Robot, SensorSink};
use strider_core::snapshot::Snapshot;
use strider_core::{GaitId, Point2, PointCloud, PoseStamped, Proprioception};

/// A strategy made from its own parameter struct, which also says what body it needs.
pub trait FromParams: Strategy + Sized {
    /// The strategy's parameters.
    type Params;
    /// The body the strategy needs with `params`.
    fn body_params(params: &Self::Params) -> BodyParams;
    /// The strategy with `params`.
    fn from_params(params: Self::Params) -> Result<Self, MissionError>;
    /// A mission of the strategy with `params`.
    fn mission(params: Self::Params) -> Result<Mission<Self>, MissionError> {
        let body = Self::body_params(&params);
        Mission::new(body, Self::from_params(params)?)
    }
}

/// A mission: the body, the strategy and the run loop (see the module docs).
pub struct Mission<S> {
    body: Body,
    strategy: S,
    /// The latest path commanded.
    commanded: Vec<Point2>,
    /// The latest gait commanded.
    gait: Option<GaitId>,
    /// Robot time of the latest tick, s.
    now: f64,
    /// Set from outside (e.g. by a Ctrl-C handler) to stop the run at the next tick.
    cancel: Option<Arc<AtomicBool>>,
    /// The latest run stopped because `cancel` was set.
    interrupted: bool,
}

impl<S: Strategy> Mission<S> {
    /// A mission of `strategy` with a body of `body` parameters.
    pub fn new(body: BodyParams, strategy: S) -> Result<Self, MissionError> {
        if body.time_limit_s.is_nan() || body.time_limit_s <= 0.0 {
            return Err(MissionError::Params(format!(
                "time_limit_s must be positive, got {}",
                body.time_limit_s
            )));
        }
        let hz = strategy.control_hz();
        if !(hz.is_finite() && hz > 0.0) {
            return Err(MissionError::Params(format!(
                "control_hz must be a positive number, got {hz}"
            )));
        }
        Ok(Self {
            body: Body::new(body),
            strategy,
            commanded: Vec::new(),
            gait: None,
            now: 0.0,
            cancel: None,
            interrupted: false,
        })
    }

    /// Lets `flag` stop a run: once it is set (e.g. by a Ctrl-C handler on another thread),
    /// the run loop ends at the next control tick and winds down as at the time limit (the
    /// strategy's `finish`, the record), and [`Mission::interrupted`] says so.
    pub fn cancel_on(&mut self, flag: Arc<AtomicBool>) {
        self.cancel = Some(flag);
    }

    /// Whether the latest run stopped because the flag of [`Mission::cancel_on`] was set,
    /// before the time limit or the strategy ended it.
    pub fn interrupted(&self) -> bool {
        self.interrupted
    }

    /// The body: map, pose, run record.
    pub fn body(&self) -> &Body {
        &self.body
    }

    /// The strategy.
    pub fn strategy(&self) -> &S {
        &self.strategy
    }

    /// The strategy, for its own post-mission work (e.g. a final cost map).
    pub fn strategy_mut(&mut self) -> &mut S {
        &mut self.strategy
    }

    /// The body and the strategy together.
    pub fn parts_mut(&mut self) -> (&mut Body, &mut S) {
        (&mut self.body, &mut self.strategy)
    }

    /// Termination, time, distance, trajectory and wall time.
    pub fn record(&self) -> &RunRecord {
        &self.body.record
    }

    /// The latest path commanded.
    pub fn commanded_path(&self) -> &[Point2] {
        &self.commanded
    }

    /// The latest gait commanded, if any.
    pub fn commanded_gait(&self) -> Option<GaitId> {
        self.gait
    }

    /// The progress display's figures at robot time `time_s` since the start.
    pub fn progress(&self, time_s: f64) -> MissionProgress {
        let c = self.strategy.goal_counts();
        MissionProgress {
            time_s,
            time_limit_s: self.body.params().time_limit_s,
            observed_cells: self.body.map().observed_count(),
            spatial_goals: c.spatial_goals,
            cost_goals: c.cost_goals,
            learning_set: c.learning_set,
        }
    }

    /// Runs the strategy until it ends the mission or the time limit.
    ///
    /// The loop's parallel parts (fusion, learning, all-pairs costs, and the simulator's ray
    /// casting) use rayon's pool. Called from outside the pool, the calling thread sleeps
    /// through each of them while the pool's idle threads spin between them; called on a pool
    /// thread (`rayon::scope(|_| mission.run(robot))`, as `strider run` does) it runs faster on
    /// few cores, with the same result.
    pub fn run<R: Robot>(&mut self, robot: &mut R) -> Result<&RunRecord, MissionError> {
        self.run_watched(robot, |_, _| {})
    }

    /// [`Mission::run`] with an observer called about once per simulated second with the
    /// mission (body, strategy) and its progress, e.g. for a progress display or a recording;
    /// it cannot change the mission.
    pub fn run_watched<R: Robot>(
        &mut self,
        robot: &mut R,
        observe: impl FnMut(&Self, &MissionProgress),
    ) -> Result<&RunRecord, MissionError> {
        self.run_loop(robot, false, observe)
    }

    /// Ingests a recorded log behind the robot interface: the body maps every delivered scan
    /// and the strategy measures and learns ([`Strategy::ingest_tick`]) tick by tick as in the
    /// recorded run, without goals, planning or commands (commands to a log are pointless).
    /// Runs until the time limit: set it to the log's length.
    pub fn ingest<R: Robot>(
        &mut self,
        robot: &mut R,
        observe: impl FnMut(&Self, &MissionProgress),
    ) -> Result<&RunRecord, MissionError> {
        self.run_loop(robot, true, observe)
    }

    fn run_loop<R: Robot>(
        &mut self,
        robot: &mut R,
        passive: bool,
        mut observe: impl FnMut(&Self, &MissionProgress),
    ) -> Result<&RunRecord, MissionError> {
        let wall = Instant::now();
        let dt = 1.0 / self.strategy.control_hz();
        let limit = self.body.params().time_limit_s;
        let t0 = robot.now();
        let mut next_report = t0;
        if !passive && let Some(g) = self.strategy.initial_gait() {
            self.driver(robot).set_gait(g);
        }
        self.strategy.start(&mut self.body, t0);
        let mut state = MotionState {
            idle: true,
            blocked: false,
        };
        self.interrupted = false;
        loop {
            let t = robot.now();
            if t - t0 >= limit {
                self.body.record.termination = Termination::TimeLimit;
                break;
            }
            if self
                .cancel
                .as_ref()
                .is_some_and(|c| c.load(Ordering::Relaxed))
            {
                self.interrupted = true;
                break;
            }
            self.strategy.before_advance(&self.body, state, t);
            let w = Instant::now();
            let mut sink = Sink {
                body: &mut self.body,
                strategy: &mut self.strategy,
            };
            state = robot.advance(dt, &mut sink).map_err(MissionError::robot)?;
            self.body.robot_wall_s += w.elapsed().as_secs_f64();
            let t = robot.now();
            self.now = t;
            if passive {
                self.strategy.ingest_tick(&mut self.body, &mut state, t);
            } else {
                let mut driver = Driver {
                    robot: &mut *robot,
                    commanded: &mut self.commanded,
                    gait: &mut self.gait,
                };
                let end = self
                    .strategy
                    .tick(&mut self.body, &mut driver, &mut state, t);
                if let Some(end) = end {
                    self.body.record.termination = end;
                    break;
                }
            }
            if t >= next_report {
                next_report = t + 1.0;
                observe(self, &self.progress(t - t0));
            }
        }
        if !passive {
            self.driver(robot).follow(&[]);
        }
        let t = robot.now();
        self.strategy.finish(&mut self.body, t);
        self.body.record.exploration_time_s = t - t0;
        self.body.record.wall_s = wall.elapsed().as_secs_f64();
        Ok(&self.body.record)
    }

    /// The mission's state now (see [`Snapshot`]); `layers` adds the map and model layers over
    /// the known part of the map (a pass over it) and the measured costs.
    pub fn snapshot(&self, layers: bool) -> Snapshot {
        let map = self.body.map();
        let layers = layers.then(|| map_layers(map));
        let mut snap = Snapshot::new(self.now, self.strategy.name(), map.cell_size());
        snap.robot = self.body.pose();
        snap.gait = self.gait;
        snap.path = self.commanded.clone();
        snap.layers = layers;
        self.strategy.describe(&self.body, &mut snap);
        // A model layer of the wrong size (a strategy's mistake) is dropped, not indexed.
        if let Some(l) = snap.layers.as_mut() {
            l.drop_misfit_models();
        }
        snap
    }

    fn driver<'a, R: Robot>(&'a mut self, robot: &'a mut R) -> Driver<'a, R> {
        Driver {
            robot,
            commanded: &mut self.commanded,
            gait: &mut self.gait,
        }
    }
}

/// The robot's commands, remembered for observers.
struct Driver<'a, R> {
    robot: &'a mut R,
    commanded: &'a mut Vec<Point2>,
    gait: &'a mut Option<GaitId>,
}

impl<R: Robot> Actuators for Driver<'_, R> {
    fn now(&self) -> f64 {
        self.robot.now()
    }

    fn follow(&mut self, path: &[Point2]) {
        self.robot.follow(path);
        self.commanded.clear();
        self.commanded.extend_from_slice(path);
    }

    fn set_gait(&mut self, gait: GaitId) {
        self.robot.set_gait(gait);
        *self.gait = Some(gait);
    }
}

/// The sensor stream into the body, then the strategy.
struct Sink<'a, S> {
    body: &'a mut Body,
    strategy: &'a mut S,
}

impl<S: Strategy> SensorSink for Sink<'_, S> {
    fn on_pose(&mut self, pose: &PoseStamped) {
        if self.body.take_pose(pose) {
            self.strategy.on_pose(self.body, pose);
        }
    }

    fn wants_cloud(&self, sensor: u8) -> bool {
        self.body.wants_cloud(sensor)
    }

    fn on_cloud(&mut self, cloud: &PointCloud) {
        self.body.fuse(cloud);
    }

    fn on_proprioception(&mut self, p: &Proprioception) {
        self.strategy.on_proprioception(self.body, p);
    }
}
