//! The exploration mission of `001` Alg. 1 with navigation by Alg. 4.
//!
//! The mission drives a [`Robot`] in the robot's own time. Each module runs at its rate of
//! `001` Tbl. 4 and sees only the latest outputs of the others, as the processes on the robot
//! do: mapping whenever a scan arrives, cost measurement on every pose (20 Hz), spatial goals at
//! 0.33 Hz, learning and cost-goal identification at 0.1 Hz, the tour and path at 1 Hz when the
//! goal set changed or the current goal was reached. The robot is reached only through the
//! [`Robot`] and [`SensorSink`] interface, so the same loop runs on a simulator or a robot.
//!
//! Decisions where the paper is silent:
//! * a goal counts as reached when the robot is within 1.5 cells of its site or has finished
//!   the path to it;
//! * cost samples are taken only while the robot follows a path (a standing robot measures no
//!   terrain) and not when it turned (heading rate above 0.1 rad/s) within the sample's
//!   support, the window and the moving average before it (turning in place at path corners is
//!   the path's time, not the terrain's, and one such window's ratio would enter Δt of smoothed
//!   samples); the stuck reflex fires only while the robot is commanded to move and not over a
//!   window in which it turned (a turn on the spot makes no headway but is not stuck);
//! * at a reached spatial goal a robot whose sensors do not see all around turns once on the
//!   spot, so a limited field of view sees the r_sensor disc Eq. 11 assumed; a reached spatial
//!   goal is not pursued again within 2·r_robot; nor is a cost-goal site within 2·r_robot of
//!   where the same gait already sampled (a robot stuck beside a site measures the cells it
//!   stands on, the site stays a site, and the goal would draw the robot back for ever);
//! * the robot commits to the goal it pursues: a replan before it is reached (the goal set
//!   changed) keeps it first and re-orders the other goals behind it, for the GTSP tour and the
//!   greedy choice alike. Goal keys drift as the map and models change, so the pursued goal is
//!   recognised as the goal with its key, else the spatial goal nearest its site within
//!   c_radius, else a cost goal of its gait that still lists its site. Without this, every
//!   goal-set change (spatial goals at 0.33 Hz) may flip an open tour's direction between
//!   near-equal alternatives, and the robot walked back and forth between them;
//! * plans start from the nearest cell where the planning grid lets the centre be (known,
//!   admissible, the footprint inside the exploration bounds), the sampling manoeuvre walks only
//!   over such cells, and a path that starts in the robot's own cell does not send it to that
//!   cell's centre first;
//! * goals none of whose sites is reachable on the current planning grid are not pursued; the
//!   exploration ends (decision 25) when no reachable goal remains after the spatial and
//!   learning modules have both run, or at the time limit.

use crate::params::{MissionParams, Strategy};
use crate::planner::{
    CostMode, GoalKey, PlanningView, TourGoal, farthest_point_subsample, nearest_where, plan_tour,
};
use rayon::prelude::*;
use std::time::Instant;
use strider_core::interface::{MotionState, Robot, SensorSink};
use strider_core::{Cell, GaitId, Point2, PointCloud, PoseStamped};
use strider_learn::cost_model::{CostGoal, GaitCostModel, ModelUpdate};
use strider_learn::descriptor_field::DescriptorField;
use strider_learn::signals::{FallbackTimer, InverseVelocityCost, TurningTime};
use strider_map::descriptors::{TA_BINS, color_histograms};
use strider_map::information_gain::GainCache;
use strider_map::reachability::Reachability;
use strider_map::{ElevationMap, SpatialGoal, cluster_information};
use strider_plan::grid::Dijkstra;

/// Heading rate, rad/s, above which a pose tick counts as turning ([`TurningTime`]): cost
/// samples whose support saw turning measure the path's turns rather than the terrain and are
/// not stored, and windows that saw turning do not trigger the stuck reflex. Well below the
/// profiles' turn rates (0.3–0.5 rad/s), well above the heading drift of straight walking.
pub(crate) const TURNING_RATE: f64 = 0.1;

/// Elevation hysteresis of the incremental Eq. 11 ([`GainCache`]), metres: the order of the
/// depth noise, so that the Kalman refinement of ground already seen does not re-evaluate the
/// gain of every candidate within r_sensor of the sensor footprint at each spatial update.
const GAIN_DZ: f64 = 0.01;

/// The stuck reflex's test (decision 9), shared by missions and benchmark tours: the signal
/// is stuck over its window and the window saw no turning, since a turn on the spot makes no
/// headway but is the commanded turn's slowness, not the terrain's.
pub(crate) fn reflex_stuck(signal: &InverseVelocityCost, turns: &TurningTime) -> bool {
    signal.is_stuck() && turns.in_window() == 0.0
}

/// Why a mission stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum Termination {
    /// Every model and the spatial explorer report no (reachable) goal.
    GoalsCleared,
    /// Goals remain but none has been reachable for a whole learning period.
    NoReachableGoals,
    /// The time limit was reached first.
    TimeLimit,
}

/// Errors of a mission.
#[derive(Debug, thiserror::Error)]
pub enum MissionError {
    /// The robot failed.
    #[error("robot: {0}")]
    Robot(String),
    /// Invalid parameters.
    #[error("mission parameters: {0}")]
    Params(String),
}

/// One logged trajectory sample.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct TrajectorySample {
    /// Robot time, s.
    pub t: f64,
    /// Position, m.
    pub x: f64,
    /// Position, m.
    pub y: f64,
    /// Gait in use.
    pub gait: u8,
}

/// What every exploration run records, whatever its strategy ([`MissionLog`],
/// [`crate::rbcm_greedy::RbcmGreedyLog`], [`crate::escape::EscapeLog`]); serialised flat into
/// each log's JSON.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct RunRecord {
    /// Why it stopped.
    pub termination: Termination,
    /// Robot time from start to termination, s.
    pub exploration_time_s: f64,
    /// Distance driven (from the pose stream), m.
    pub driven_m: f64,
    /// Trajectory at 2 Hz.
    pub trajectory: Vec<TrajectorySample>,
    /// Wall time of the run, s.
    pub wall_s: f64,
}

impl RunRecord {
    /// A run not started yet: `termination` until it stops, nothing driven.
    pub fn new(termination: Termination) -> Self {
        Self {
            termination,
            exploration_time_s: 0.0,
            driven_m: 0.0,
            trajectory: Vec::new(),
            wall_s: 0.0,
        }
    }
}

/// What a mission did.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct MissionLog {
    /// Termination, time, distance, trajectory and wall time.
    #[serde(flatten)]
    pub run: RunRecord,
    /// Wall-clock latency of each replan (planning grid, all-pairs, GTSP, path), ms.
    pub replan_ms: Vec<f64>,
    /// The parts of each replan, in the order of `replan_ms`.
    pub replan_parts: Vec<ReplanParts>,
    /// Per replan, in the order of `replan_ms`: the replan plus the latest spatial goal
    /// identification and the latest learning update (with its cost goals) that ran since the
    /// previous replan, ms: the time from the newest data to a new tour when the modules run
    /// one after the other. Earlier runs between two replans were superseded by the latest and
    /// are not on that path.
    pub goals_to_tour_ms: Vec<f64>,
    /// Wall-clock latency of each spatial goal identification (passability, reachability,
    /// Eq. 11, Alg. 3), ms.
    pub spatial_goal_ms: Vec<f64>,
    /// Wall-clock latency of each learning update (descriptors, Alg. 5–10 for every gait, cost
    /// goals), ms.
    pub learning_ms: Vec<f64>,
    /// Cost goals reached and sampled, per gait.
    pub samplings: Vec<usize>,
    /// Cost samples stored per gait.
    pub cost_samples: Vec<usize>,
    /// Stuck-reflex activations.
    pub stuck_events: usize,
    /// Cost samples dropped because the robot turned within their support ([`TurningTime`]).
    pub turn_skipped: usize,
    /// Wall time per part of the loop, s.
    pub phase_wall_s: PhaseWall,
    /// Eq. 11 sums evaluated afresh over all spatial updates.
    pub gain_evaluated: usize,
    /// Eq. 11 sums updated incrementally from nearby map changes over all spatial updates.
    pub gain_updated: usize,
}

/// What one replan did and where its time went (wall clock, ms).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct ReplanParts {
    /// Robot time of the replan, s.
    pub t: f64,
    /// Rebuilding the planning view (0 when the map and models had not changed).
    pub view_ms: f64,
    /// The all-pairs site costs.
    pub all_pairs_ms: f64,
    /// The GTSP solve.
    pub gtsp_ms: f64,
    /// Vertices of the GTSP instance (robot + reachable sites).
    pub vertices: usize,
}

/// Wall time spent in each part of the mission loop, s.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct PhaseWall {
    /// The robot (simulator) advancing, including the mapping and cost measurement it calls
    /// back into.
    pub robot: f64,
    /// Mapping alone (scan fusion in the sensor callback).
    pub mapping: f64,
    /// Spatial goals (passability, reachability, Eq. 11, Alg. 3).
    pub spatial: f64,
    /// Learning and cost-goal identification.
    pub learning: f64,
    /// Tour and path planning.
    pub planning: f64,
    /// Gait choice (Alg. 4).
    pub gait: f64,
}

/// A snapshot for progress displays.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MissionProgress {
    /// Robot time since the start, s.
    pub time_s: f64,
    /// The mission's time limit, s.
    pub time_limit_s: f64,
    /// Observed map cells.
    pub observed_cells: usize,
    /// Current spatial goals.
    pub spatial_goals: usize,
    /// Current cost-model goals (all gaits).
    pub cost_goals: usize,
    /// Learning-set sizes summed over gaits.
    pub learning_set: usize,
}

/// The sampling manoeuvre in progress (decision 24).
#[derive(Clone, Copy, Debug)]
struct Sampling {
    gait: GaitId,
    until: f64,
}

/// The exploration mission's state: the map, the per-gait models and the navigation state.
pub struct Mission {
    params: MissionParams,
    map: ElevationMap,
    models: Vec<GaitCostModel>,
    signal: InverseVelocityCost,
    fallback: FallbackTimer,
    desc: DescriptorField,
    spatial: Vec<SpatialGoal>,
    cost_goals: Vec<(u8, CostGoal)>,
    dij: Dijkstra,
    current: Option<(GoalKey, Cell)>,
    goal_keys: Vec<GoalKey>,
    sampling: Option<Sampling>,
    gait: GaitId,
    pose: Option<PoseStamped>,
    moving: bool,
    learned_once: bool,
    spatial_once: bool,
    log: MissionLog,
    path: crate::keyframes::PathRecorder,
    unreachable_since: Option<f64>,
    /// Time spent turning over the stuck test's window and over a cost sample's support.
    turns: TurningTime,
    /// Pose (x, y, yaw) of the last fused scan per sensor.
    keyframes: crate::keyframes::Keyframes,
    /// The latest planning view (per-gait grids for Alg. 4, the merged grid for paths).
    view: Option<PlanningView>,
    /// What the view was built from: (fused scans, learning updates, cost mode).
    view_key: Option<(u64, u64, CostMode)>,
    /// What the spatial goals were computed from: scans fused, anchor cell, visited goals.
    spatial_key: Option<(u64, Option<Cell>, usize)>,
    /// Wall time of the latest spatial and learning runs since the last replan, ms (see
    /// `MissionLog::goals_to_tour_ms`).
    goal_ms_since_replan: (f64, f64),
    /// Learning updates so far.
    learn_generation: u64,
    /// Offsets of the 3·r_robot disc the anchor cell is searched in (nearest first).
    anchor_offsets: Vec<(i32, i32)>,
    /// End time of the look-around in progress.
    looking: Option<f64>,
    /// The last Alg. 6 outcome per gait model.
    updates: Vec<ModelUpdate>,
    /// Spatial goals reached so far: goals within 2·r_robot of one are not pursued again (what
    /// could not be seen from there, e.g. the sensor's blind zone around the robot, will not be
    /// seen by returning).
    visited: Vec<Cell>,
    /// (gait, cell) of every cost-goal site sampled and of where the robot stood then.
    sampled: Vec<(u8, Cell)>,
    /// Eq. 11 kept between spatial updates.
    gain: GainCache,
    /// The last tour's (goal, site) order, the warm start of the next GTSP solve.
    last_tour: Vec<(GoalKey, Cell)>,
    /// Ingesting a recorded log ([`Mission::ingest`]): no spatial goals, planning or gait
    /// choice.
    passive: bool,
}

impl Mission {
    /// A mission with an empty map and untrained models.
    pub fn new(params: MissionParams) -> Result<Self, MissionError> {
        if params.gaits.is_empty() || params.gaits.len() > u8::MAX as usize {
            return Err(MissionError::Params("the robot needs 1–255 gaits".into()));
        }
        let turns = {
            let iv = params.inverse_velocity();
            TurningTime::new(
                iv.window_s,
                iv.window_s + iv.smoothing_s,
                iv.rate_hz,
                TURNING_RATE,
                params.turning_baseline_s,
            )
            .map_err(|e| MissionError::Params(e.to_string()))?
        };
        let signal = InverseVelocityCost::new(params.inverse_velocity())
            .map_err(|e| MissionError::Params(e.to_string()))?;
        let fallback = FallbackTimer::new(params.dt_fallback)
            .map_err(|e| MissionError::Params(e.to_string()))?;
        let models = (0..params.gaits.len())
            .map(|g| {
                GaitCostModel::new(
                    GaitId(g as u8),
                    TA_BINS,
                    params.cost_model.clone(),
                    params.seed,
                )
                .map_err(|e| MissionError::Params(e.to_string()))
            })
            .collect::<Result<Vec<_>, _>>()?;
        let n = params.gaits.len();
        // Start with the fastest gait.
        let fastest = params.fastest_gait();
        // Decision 5 allows a stride lattice for Eq. 11: candidates every max(0.2 m,
        // r_sensor/20) (I_model sums over the whole r_sensor disc, so it varies on that scale),
        // each standing for stride² cells in Alg. 3's minimum cluster size.
        let mut map_params = params.map.clone();
        let spacing = 0.2f64.max(map_params.r_sensor / 20.0);
        let stride = ((spacing / map_params.cell_size).round() as u32).max(1);
        if map_params.info_gain_stride <= 1 && stride > 1 {
            map_params.info_gain_stride = stride;
            let s2 = (stride * stride) as usize;
            map_params.c_min_cells = (map_params.c_min_cells.div_ceil(s2)).max(1);
        }
        Ok(Self {
            map: ElevationMap::new(map_params),
            models,
            signal,
            fallback,
            desc: DescriptorField::empty(
                strider_core::CellRect::new(Cell::new(0, 0), 0, 0),
                TA_BINS,
            ),
            spatial: Vec::new(),
            cost_goals: Vec::new(),
            dij: Dijkstra::new(),
            current: None,
            goal_keys: Vec::new(),
            sampling: None,
            gait: fastest,
            pose: None,
            moving: false,
            learned_once: false,
            spatial_once: false,
            log: MissionLog {
                run: RunRecord::new(Termination::TimeLimit),
                replan_ms: Vec::new(),
                goals_to_tour_ms: Vec::new(),
                replan_parts: Vec::new(),
                spatial_goal_ms: Vec::new(),
                learning_ms: Vec::new(),
                samplings: vec![0; n],
                cost_samples: vec![0; n],
                stuck_events: 0,
                turn_skipped: 0,
                phase_wall_s: PhaseWall::default(),
                gain_evaluated: 0,
                gain_updated: 0,
            },
            path: crate::keyframes::PathRecorder::default(),
            unreachable_since: None,
            keyframes: crate::keyframes::Keyframes::default(),
            turns,
            visited: Vec::new(),
            sampled: Vec::new(),
            gain: GainCache::new(GAIN_DZ),
            last_tour: Vec::new(),
            passive: false,
            updates: vec![ModelUpdate::default(); n],
            looking: None,
            view: None,
            view_key: None,
            spatial_key: None,
            goal_ms_since_replan: (0.0, 0.0),
            learn_generation: 0,
            anchor_offsets: strider_core::grid::disc_offsets(
                3.0 * params.map.r_robot,
                params.map.cell_size,
            ),
            params,
        })
    }

    /// The map built so far.
    pub fn map(&self) -> &ElevationMap {
        &self.map
    }

    /// The per-gait cost models.
    pub fn models(&self) -> &[GaitCostModel] {
        &self.models
    }

    /// The last learning update (classes, H^GT, goals) of each gait model.
    pub fn model_updates(&self) -> &[ModelUpdate] {
        &self.updates
    }

    /// The latest descriptors.
    pub fn descriptors(&self) -> &DescriptorField {
        &self.desc
    }

    /// The parameters.
    pub fn params(&self) -> &MissionParams {
        &self.params
    }

    /// The log so far.
    pub fn log(&self) -> &MissionLog {
        &self.log
    }

    fn robot_cell(&self) -> Option<Cell> {
        let p = self.pose?;
        self.map.cell_at(p.position.x, p.position.y)
    }

    /// The cell plans and reachability start from: the robot's cell when it is observed and
    /// admissible, else the nearest such cell within 3·r_robot (a forward-looking sensor never
    /// sees the ground under the robot at the start).
    fn anchor_cell(&self) -> Option<Cell> {
        let here = self.robot_cell()?;
        nearest_where(here, &self.anchor_offsets, |c| {
            self.map.is_observed(c) && self.map.is_admissible(c)
        })
    }

    /// Runs Alg. 1 until every goal is cleared or the time limit.
    ///
    /// The loop's parallel parts (fusion, learning, all-pairs costs, and the simulator's ray
    /// casting) use rayon's pool. Called from outside the pool, the calling thread sleeps
    /// through each of them while the pool's idle threads spin between them; calling it on a
    /// pool thread (`rayon::scope(|_| mission.run(robot))`, as `strider run` does) was 13 %
    /// faster on two cores, with the same result.
    pub fn run<R: Robot>(&mut self, robot: &mut R) -> Result<&MissionLog, MissionError> {
        self.run_observed(robot, |_| {})
    }

    /// [`Mission::run`], calling `progress` about once per simulated second (for a progress
    /// display; it cannot change the mission).
    pub fn run_observed<R: Robot>(
        &mut self,
        robot: &mut R,
        mut progress: impl FnMut(&MissionProgress),
    ) -> Result<&MissionLog, MissionError> {
        self.passive = false;
        self.run_loop(robot, |_, p| progress(p))
    }

    /// [`Mission::run_observed`] with an observer that sees the whole mission (map, models,
    /// goals, tour; see the accessors) at the same moments, e.g. to record it.
    pub fn run_watched<R: Robot>(
        &mut self,
        robot: &mut R,
        observe: impl FnMut(&Mission, &MissionProgress),
    ) -> Result<&MissionLog, MissionError> {
        self.passive = false;
        self.run_loop(robot, observe)
    }

    /// Ingests a recorded log behind the robot interface: the mapping (every delivered scan),
    /// the cost measurement (every pose) and the learning (at `learning_hz`) of
    /// [`Mission::run`], tick by tick as in the recorded run, without spatial goals, planning
    /// or gait choice (commands to a log are pointless; the gait in use arrives with each
    /// pose). Runs until the time limit: set it to the log's length.
    pub fn ingest<R: Robot>(
        &mut self,
        robot: &mut R,
        observe: impl FnMut(&Mission, &MissionProgress),
    ) -> Result<&MissionLog, MissionError> {
        self.passive = true;
        let r = self.run_loop(robot, observe).map(|_| ());
        self.passive = false;
        r.map(|()| &self.log)
    }

    /// The loop of Alg. 1 behind [`Mission::run_observed`] and [`Mission::ingest`].
    fn run_loop<R: Robot>(
        &mut self,
        robot: &mut R,
        mut observe: impl FnMut(&Mission, &MissionProgress),
    ) -> Result<&MissionLog, MissionError> {
        let wall = Instant::now();
        let mut next_report = robot.now();
        let rates = self.params.rates;
        let dt = 1.0 / rates.control_hz;
        let t0 = robot.now();
        let (mut next_spatial, mut next_learn, mut next_tour) = (t0, t0, t0);
        robot.set_gait(self.gait);
        let mut state = MotionState {
            idle: true,
            blocked: false,
        };
        loop {
            let t = robot.now();
            if t - t0 >= self.params.time_limit_s {
                self.log.run.termination = Termination::TimeLimit;
                break;
            }
            self.moving = !state.idle;
            let w = Instant::now();
            state = robot
                .advance(dt, self)
                .map_err(|e| MissionError::Robot(e.to_string()))?;
            self.log.phase_wall_s.robot += w.elapsed().as_secs_f64();
            let t = robot.now();
            if state.idle {
                self.signal.reset();
            }
            // Stuck reflex (decision 9), only while commanded to move.
            let stuck = !state.idle && reflex_stuck(&self.signal, &self.turns);
            let was = self.fallback.is_active(t);
            if self.fallback.update(t, stuck) && !was {
                self.log.stuck_events += 1;
            }
            if t >= next_spatial && !self.passive {
                let w = Instant::now();
                self.update_spatial();
                self.log.phase_wall_s.spatial += w.elapsed().as_secs_f64();
                next_spatial = t + 1.0 / rates.spatial_hz;
            }
            if t >= next_learn {
                let w = Instant::now();
                self.update_learning();
                self.log.phase_wall_s.learning += w.elapsed().as_secs_f64();
                next_learn = t + 1.0 / rates.learning_hz;
            }
            if t >= next_tour || state.idle || state.blocked {
                let w = Instant::now();
                let end = if self.passive {
                    None
                } else {
                    self.decide(robot, t, state)
                };
                self.log.phase_wall_s.planning += w.elapsed().as_secs_f64();
                if let Some(end) = end {
                    self.log.run.termination = end;
                    break;
                }
                next_tour = t + 1.0 / rates.tour_hz;
                state.idle = false;
            }
            if t >= next_report {
                next_report = t + 1.0;
                let p = MissionProgress {
                    time_s: t - t0,
                    time_limit_s: self.params.time_limit_s,
                    observed_cells: self.map.observed_count(),
                    spatial_goals: self.spatial.len(),
                    cost_goals: self.cost_goals.len(),
                    learning_set: self.models.iter().map(|m| m.learning_set_len()).sum(),
                };
                observe(self, &p);
            }
            if self.passive {
                continue;
            }
            let w = Instant::now();
            let g = self.choose_gait(t);
            self.log.phase_wall_s.gait += w.elapsed().as_secs_f64();
            if g != self.gait {
                self.gait = g;
                robot.set_gait(g);
            }
        }
        robot.follow(&[]);
        self.log.run.exploration_time_s = robot.now() - t0;
        self.log.run.wall_s = wall.elapsed().as_secs_f64();
        Ok(&self.log)
    }

    /// Alg. 2 lines 3–5: passability, information gain, spatial goals (Alg. 3).
    ///
    /// The goals are a function of the map, the anchor cell and the visited goals only; when
    /// none of them changed since the last run (no scan fused: a slow gait moves less than a
    /// keyframe step between runs) the previous goals stand and nothing is recomputed (nor
    /// logged as a goal-identification time).
    fn update_spatial(&mut self) {
        let w = Instant::now();
        self.map.update_passability();
        let anchor = self.anchor_cell();
        let key = (self.map.scan_count(), anchor, self.visited.len());
        if self.spatial_key == Some(key) {
            return;
        }
        self.spatial_key = Some(key);
        self.spatial.clear();
        if let Some(c) = anchor {
            let reach = Reachability::compute(&self.map, c);
            let bounds = self.params.bounds;
            let gain = self.gain.compute(&self.map, &reach, bounds.as_ref());
            self.log.gain_evaluated += self.gain.last_evaluated();
            self.log.gain_updated += self.gain.last_updated();
            self.spatial = cluster_information(&self.map, &gain, &reach, bounds.as_ref());
            let r = 2.0 * self.map.params().r_robot / self.map.cell_size();
            let visited = &self.visited;
            self.spatial
                .retain(|g| visited.iter().all(|v| v.dist_cells(g.cell) > r));
            self.spatial_once = true;
        }
        let ms = w.elapsed().as_secs_f64() * 1e3;
        self.log.spatial_goal_ms.push(ms);
        self.goal_ms_since_replan.0 = ms;
    }

    /// Alg. 6 for every gait: descriptors, then each model's update.
    fn update_learning(&mut self) {
        let w = Instant::now();
        self.map.update_passability();
        let Some(rect) = self.map.known_bounds() else {
            return;
        };
        let raster = color_histograms(&self.map, rect, self.map.params().r_hist);
        self.desc = DescriptorField::from_raster(&raster);
        self.cost_goals.clear();
        // The gaits' models are independent: update them side by side.
        let (map, desc) = (&self.map, &self.desc);
        let updates: Vec<_> = self
            .models
            .par_iter_mut()
            .map(|m| m.update(map, desc))
            .collect();
        for (g, u) in updates.into_iter().enumerate() {
            if let Ok(u) = u {
                for goal in &u.goals {
                    self.cost_goals.push((g as u8, goal.clone()));
                }
                self.updates[g] = u;
            }
        }
        self.learned_once = true;
        // The costs changed: the planning view is rebuilt by the next tour decision (the
        // planner's module, at most 1 / tour_hz later), not here, where it would be built
        // twice on the way from new data to a new tour (the map changes in between).
        self.learn_generation += 1;
        let ms = w.elapsed().as_secs_f64() * 1e3;
        self.log.learning_ms.push(ms);
        self.goal_ms_since_replan.1 = ms;
    }

    /// The goal set pursued by the strategy.
    fn goals(&self) -> Vec<TourGoal> {
        let mut goals: Vec<TourGoal> = self
            .spatial
            .iter()
            .map(|s| TourGoal {
                key: GoalKey::Spatial(s.cell),
                sites: vec![s.cell],
            })
            .collect();
        if self.params.strategy != Strategy::SpatialOnly {
            let r = 2.0 * self.map.params().r_robot / self.map.cell_size();
            for (g, goal) in &self.cost_goals {
                let fresh = unsampled_sites(&goal.sites, *g, &self.sampled, r);
                if fresh.is_empty() {
                    continue;
                }
                goals.push(TourGoal {
                    key: GoalKey::Cost {
                        gait: *g,
                        class: goal.class.map_or(u32::MAX, |c| c.0),
                    },
                    sites: farthest_point_subsample(&fresh, self.params.max_sites_per_goal),
                });
            }
        }
        goals
    }

    /// The index in `goals` of the goal being pursued, if it is still a goal: the same key, or
    /// (goal keys drift as the map and models change) a spatial goal within c_radius of the
    /// pursued site, or a cost goal of the same gait that still lists the pursued site.
    fn committed_goal(&self, goals: &[TourGoal]) -> Option<usize> {
        let (key, site) = self.current?;
        if let Some(i) = goals.iter().position(|g| g.key == key) {
            return Some(i);
        }
        match key {
            GoalKey::Spatial(_) => {
                let r = self.map.params().c_radius / self.map.cell_size();
                goals
                    .iter()
                    .enumerate()
                    .filter(|(_, g)| matches!(g.key, GoalKey::Spatial(_)))
                    .map(|(i, g)| (i, g.sites[0].dist_cells(site)))
                    .filter(|&(_, d)| d <= r)
                    .min_by(|a, b| a.1.total_cmp(&b.1))
                    .map(|(i, _)| i)
            }
            GoalKey::Cost { gait, .. } => goals.iter().position(|g| {
                matches!(g.key, GoalKey::Cost { gait: h, .. } if h == gait)
                    && g.sites.contains(&site)
            }),
        }
    }

    /// Rebuilds the planning view unless the map (fused scans), the models (learning updates)
    /// and the cost mode are those it was built from.
    fn refresh_view(&mut self, mode: CostMode) {
        let key = (self.map.scan_count(), self.learn_generation, mode);
        if self.view.is_some() && self.view_key == Some(key) {
            return;
        }
        self.view = PlanningView::build(
            &self.map,
            &self.models,
            mode,
            self.params.c_loss,
            self.params.bounds.as_ref(),
        );
        self.view_key = Some(key);
    }

    /// The planner's module at `tour_hz`: Alg. 1 lines 11–25, then, when no new tour was
    /// planned, the planning view brought to the latest models (the gait choice reads it; a
    /// new tour has just rebuilt it). Returns the termination when the exploration is finished.
    fn decide<R: Robot>(
        &mut self,
        robot: &mut R,
        t: f64,
        state: MotionState,
    ) -> Option<Termination> {
        let end = self.decide_tour(robot, t, state);
        if end.is_none()
            && self.params.strategy != Strategy::SpatialOnly
            && self.view_key.is_some_and(|k| k.1 != self.learn_generation)
        {
            self.map.update_passability();
            self.refresh_view(CostMode::Learned);
        }
        end
    }

    /// Alg. 1 lines 11–25. Returns the termination when the exploration is finished.
    fn decide_tour<R: Robot>(
        &mut self,
        robot: &mut R,
        t: f64,
        state: MotionState,
    ) -> Option<Termination> {
        let here = self.anchor_cell()?;
        // A look-around runs to its end.
        if let Some(until) = self.looking {
            if t < until && !state.idle && !state.blocked {
                return None;
            }
            self.looking = None;
            self.current = None;
        }
        // A sampling manoeuvre runs to its end.
        if let Some(s) = self.sampling {
            if t < s.until && !state.idle && !state.blocked {
                return None;
            }
            self.sampling = None;
            self.current = None;
        }
        let reached = self
            .current
            .is_some_and(|(_, site)| here.dist_cells(site) <= 1.5 || state.idle);
        if reached && let Some((GoalKey::Spatial(c), _)) = self.current {
            self.visited.push(c);
            let r = 2.0 * self.map.params().r_robot / self.map.cell_size();
            self.spatial.retain(|g| g.cell.dist_cells(c) > r);
            if self.params.needs_look_around() {
                self.start_look_around(robot, t);
                return None;
            }
            self.current = None;
        }
        if reached && let Some((GoalKey::Cost { gait, .. }, site)) = self.current {
            // Lines 12–15: sample the reached cost goal with its gait.
            self.log.samplings[gait as usize] += 1;
            self.sampled.push((gait, site));
            self.sampled.push((gait, here));
            self.start_sampling(robot, t, GaitId(gait));
            return None;
        }
        let goals = self.goals();
        let mut keys: Vec<GoalKey> = goals.iter().map(|g| g.key).collect();
        keys.sort_unstable();
        let changed = keys != self.goal_keys;
        if goals.is_empty() && self.learned_once && self.spatial_once {
            // Alg. 1 lines 21–24: no spatial goal and every model has a regressor and no goal.
            let models_done = self.params.strategy == Strategy::SpatialOnly
                || self.models.iter().all(|m| m.has_regressor());
            if models_done {
                return Some(Termination::GoalsCleared);
            }
        }
        if !(changed || reached || self.current.is_none() || state.blocked) {
            return None;
        }
        self.goal_keys = keys;
        let w = Instant::now();
        let mode = if self.params.strategy == Strategy::SpatialOnly {
            CostMode::Flat
        } else {
            CostMode::Learned
        };
        self.map.update_passability();
        let wv = Instant::now();
        self.refresh_view(mode);
        let view_ms = wv.elapsed().as_secs_f64() * 1e3;
        // A replan re-orders the goals behind the one being pursued rather than abandoning it.
        let commit = if reached {
            None
        } else {
            self.committed_goal(&goals)
        };
        let view = self.view.take();
        // Plans start where the planning grid lets the centre be: the map may call the robot's
        // cell admissible while the view does not (the exploration bounds, unknown cells), e.g.
        // after a sampling manoeuvre walked to the edge of the bounds; from there every site
        // would look unreachable.
        let here = view
            .as_ref()
            .and_then(|v| nearest_where(here, &self.anchor_offsets, |c| v.grid.is_admissible(c)))
            .unwrap_or(here);
        let tour = view.as_ref().and_then(|v| {
            plan_tour(
                v,
                here,
                &goals,
                self.params.strategy == Strategy::Greedy,
                self.params.seed,
                &self.last_tour,
                commit,
            )
        });
        let mut path_found = false;
        self.last_tour = tour.as_ref().map_or_else(Vec::new, |t| t.order.clone());
        if let (Some(v), Some(tour)) = (&view, &tour) {
            for &(key, site) in &tour.order {
                if let Some(path) = v.path(&mut self.dij, here, site) {
                    let pts = match self.pose {
                        Some(p) => v.drive_waypoints_from(&path, p.position.xy()),
                        None => v.drive_waypoints(&path),
                    };
                    robot.follow(&pts);
                    self.current = Some((key, site));
                    path_found = true;
                    break;
                }
            }
        }
        self.view = view;
        let ms = w.elapsed().as_secs_f64() * 1e3;
        self.log.replan_ms.push(ms);
        self.log
            .goals_to_tour_ms
            .push(ms + self.goal_ms_since_replan.0 + self.goal_ms_since_replan.1);
        self.goal_ms_since_replan = (0.0, 0.0);
        self.log.replan_parts.push(ReplanParts {
            t,
            view_ms,
            all_pairs_ms: tour.as_ref().map_or(0.0, |t| t.all_pairs_ms),
            gtsp_ms: tour.as_ref().map_or(0.0, |t| t.gtsp_ms),
            vertices: tour.as_ref().map_or(0, |t| t.vertices),
        });
        if !path_found {
            self.current = None;
            robot.follow(&[]);
            // Nothing reachable: give the map and the models one learning period to change
            // that, then stop.
            let since = *self.unreachable_since.get_or_insert(t);
            if self.learned_once
                && self.spatial_once
                && t - since > 1.0 / self.params.rates.learning_hz + 1.0
            {
                return Some(Termination::NoReachableGoals);
            }
        } else {
            self.unreachable_since = None;
        }
        None
    }

    /// At a reached spatial goal the robot turns once on the spot (four waypoints 0.75 cells
    /// around it, a quarter turn apart): Eq. 11 counts every observable cell within r_sensor
    /// whatever the heading, which a camera with a limited field of view only honours if it
    /// looks around.
    fn start_look_around<R: Robot>(&mut self, robot: &mut R, t: f64) {
        let Some(p) = self.pose else { return };
        let r = 0.75 * self.map.cell_size();
        let pts: Vec<Point2> = (1..=4)
            .map(|k| {
                let a = p.yaw + k as f64 * std::f64::consts::FRAC_PI_2;
                Point2::new(p.position.x + r * a.cos(), p.position.y + r * a.sin())
            })
            .collect();
        robot.follow(&pts);
        // Generous: a full turn at the slowest plausible rate, plus the short steps.
        self.looking = Some(t + 60.0);
    }

    /// Decision 24: enforce `gait` and walk straight ahead (or the most open direction when
    /// the heading is blocked) for Δt_sample over cells where the centre may be.
    fn start_sampling<R: Robot>(&mut self, robot: &mut R, t: f64, gait: GaitId) {
        let Some(p) = self.pose else { return };
        let d = self.map.cell_size();
        let v = self.params.gaits[gait.0 as usize].v_max;
        let len = (v * self.params.dt_sample).max(2.0 * d);
        let start = Point2::new(p.position.x, p.position.y);
        let mut best: Option<(usize, Vec<Point2>)> = None;
        for k in [0.0f64, 1.0, -1.0, 2.0, -2.0, 3.0, -3.0, 4.0] {
            let yaw = p.yaw + k * std::f64::consts::FRAC_PI_4;
            let (dx, dy) = (yaw.cos(), yaw.sin());
            let mut pts = vec![start];
            let steps = (len / (0.5 * d)).ceil() as usize;
            for s in 1..=steps {
                let q = Point2::new(
                    start.x + dx * s as f64 * 0.5 * d,
                    start.y + dy * s as f64 * 0.5 * d,
                );
                if !self.centre_may_be(q) {
                    break;
                }
                pts.push(q);
            }
            let n = pts.len();
            if n > steps / 2 {
                best = Some((n, pts));
                break;
            }
            if best.as_ref().is_none_or(|(bn, _)| n > *bn) {
                best = Some((n, pts));
            }
        }
        let Some((_, pts)) = best else { return };
        robot.follow(&pts);
        self.sampling = Some(Sampling {
            gait,
            until: t + self.params.dt_sample,
        });
    }

    /// True where the robot's centre may be: a finite cell of the latest planning grid (known,
    /// admissible, the footprint inside the exploration bounds), or before the first view an
    /// admissible map cell.
    fn centre_may_be(&self, q: Point2) -> bool {
        match (&self.view, self.map.cell_at(q.x, q.y)) {
            (Some(v), Some(c)) => v.grid.is_admissible(c),
            _ => self.map.is_admissible_at(q.x, q.y),
        }
    }

    /// Alg. 4: the enforced gait, the stuck reflex's rough gait, or the best gait at the robot.
    fn choose_gait(&mut self, t: f64) -> GaitId {
        if let Some(s) = self.sampling {
            return s.gait;
        }
        if self.fallback.is_active(t) {
            return self.params.rough_gait();
        }
        if self.params.strategy == Strategy::SpatialOnly {
            // Reactive: the fastest gait unless stuck.
            return self.params.fastest_gait();
        }
        let Some(here) = self.anchor_cell() else {
            return self.gait;
        };
        // Alg. 4 line 6 on the per-gait grids of the latest planning view (rebuilt at every
        // replan, and at the first tour decision after a learning update); keep the gait where
        // no gait's footprint is admissible.
        self.view
            .as_ref()
            .and_then(|v| v.choose_gait(here))
            .unwrap_or(self.gait)
    }
}

/// What observers (recorders, visualisers) read of a running mission.
impl Mission {
    /// The current spatial goals (Alg. 3).
    pub fn spatial_goals(&self) -> &[SpatialGoal] {
        &self.spatial
    }

    /// The current cost-model goals with their gait index.
    pub fn cost_goals(&self) -> &[(u8, CostGoal)] {
        &self.cost_goals
    }

    /// The last planned tour: goals in visiting order with their chosen sites.
    pub fn tour(&self) -> &[(GoalKey, Cell)] {
        &self.last_tour
    }

    /// The goal being pursued and its site.
    pub fn current_goal(&self) -> Option<(GoalKey, Cell)> {
        self.current
    }

    /// The gait the mission commands.
    pub fn gait(&self) -> GaitId {
        self.gait
    }

    /// Learning updates (Alg. 6 over every gait) run so far.
    pub fn learning_updates(&self) -> u64 {
        self.learn_generation
    }

    /// How many learning updates the planning view (the tour's costs and the gait choice)
    /// reflects; `None` before the first view. It catches up with
    /// [`learning_updates`](Self::learning_updates) at the next tour decision.
    pub fn view_learning_updates(&self) -> Option<u64> {
        self.view.as_ref().and(self.view_key).map(|k| k.1)
    }
}

impl SensorSink for Mission {
    fn on_pose(&mut self, pose: &PoseStamped) {
        if !(pose.position.x.is_finite() && pose.position.y.is_finite()) {
            return;
        }
        let (d, sample) = self.path.push(pose);
        self.log.run.driven_m += d;
        self.log.run.trajectory.extend(sample);
        self.pose = Some(*pose);
        self.turns.push(pose.stamp, pose.yaw);
        if !self.moving {
            return;
        }
        let sample = self.signal.push(pose, pose.gait);
        if sample.is_some() && self.turns.in_support() > 0.0 {
            // The robot spent part of the window turning: that time is the path's, not the
            // terrain's.
            self.log.turn_skipped += 1;
            return;
        }
        if let Some(s) = sample
            && let Some(cell) = self.map.cell_at(s.position.x, s.position.y)
            && let Some(m) = self.models.get_mut(s.gait.0 as usize)
            && let Ok(ins) = m.insert_measurement(cell, s.cost, &self.desc)
            && ins == strider_learn::cost_model::Insertion::Stored
        {
            self.log.cost_samples[s.gait.0 as usize] += 1;
        }
    }

    /// Scan keyframes ([`crate::keyframes`]).
    fn wants_cloud(&self, sensor: u8) -> bool {
        self.keyframes.wants(
            sensor,
            self.pose.as_ref(),
            self.map.params(),
            &self.params.sensor_hfov_deg,
        )
    }

    fn on_cloud(&mut self, cloud: &PointCloud) {
        let w = Instant::now();
        self.map.integrate(cloud);
        self.log.phase_wall_s.mapping += w.elapsed().as_secs_f64();
        self.keyframes.record(cloud.sensor, self.pose.as_ref());
    }
}

/// The sites of a cost goal of gait `gait` that are farther than `r` cells from every site and
/// position where that gait already sampled (`sampled`: (gait, cell) pairs). A robot stuck
/// beside a site measures the cells it stands on, not the site, which stays a site of the goal
/// and would draw the robot back for ever; other gaits still sample there.
fn unsampled_sites(sites: &[Cell], gait: u8, sampled: &[(u8, Cell)], r: f64) -> Vec<Cell> {
    sites
        .iter()
        .copied()
        .filter(|s| {
            sampled
                .iter()
                .all(|&(h, c)| h != gait || c.dist_cells(*s) > r)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sites_where_the_same_gait_sampled_are_not_pursued_again() {
        let sites = [Cell::new(0, 0), Cell::new(10, 0), Cell::new(20, 0)];
        // Gait 1 sampled at (10, 0) while standing stuck at (3, 0).
        let sampled = [(1, Cell::new(10, 0)), (1, Cell::new(3, 0))];
        assert_eq!(
            unsampled_sites(&sites, 1, &sampled, 4.0),
            vec![Cell::new(20, 0)]
        );
        // A site 3 cells from where the robot stood, with a radius just below 3: pursued.
        assert_eq!(
            unsampled_sites(&sites, 1, &sampled, 2.9),
            vec![Cell::new(0, 0), Cell::new(20, 0)]
        );
        // Another gait's samples do not count.
        assert_eq!(unsampled_sites(&sites, 0, &sampled, 4.0), sites.to_vec());
        assert_eq!(unsampled_sites(&sites, 1, &[], 4.0), sites.to_vec());
    }
}
