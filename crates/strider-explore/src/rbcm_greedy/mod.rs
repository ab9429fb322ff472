//! The `rbcm-greedy` explorer of `000` (Alg. 1): online incremental traversal-cost learning with
//! a robust Bayesian committee machine (RBCM) of GP experts on the 5-D shape + Lab descriptor
//! (Eq. 7–10), the roll-variance cost, and myopic, variance-driven goal selection.
//!
//! Each planning cycle (at `plan_hz`, and whenever the robot stops or is blocked):
//! 1. passability and the reachable set on the elevation map (Mtrv: step height above h_max and
//!    the δ_impassable inflation, decision 4);
//! 2. Mcost at its own resolution from the committee (Eq. 11–12, [`cost_map`]);
//! 3. one Dijkstra from the robot under the Eq. 14 edge cost
//!    ([`strider_plan::grid::MeanEdgeDijkstra`]); the cheapest frontier representative
//!    (Eq. 13) is ν_spatial, the reachable cell of highest median-σ score (Eq. 15) is ν_cost;
//! 4. the decision rule Eq. 16 with λ_score; the cheapest path to the goal is handed to the
//!    robot as waypoints every carrot distance (20 cm) along it, which is what the paper's
//!    follow-the-carrot controller with that look-ahead tracks.
//!
//! The cost is the roll variance over a 10 s window ([`RollVarianceCost`]), attributed to the
//! window's middle pose and paired with that cell's descriptor at that moment; one pair is kept
//! every `sample_period_s` of walking (the paper's m_max = 50 "about one expert per minute"), and
//! only from windows the robot spent walking (a standing robot's roll says nothing about the
//! terrain). Each pair is added to the newest expert, whose hyperparameters are then refitted
//! (bounded, ≤ 200 iterations, `000` §V-A).
//!
//! Decisions where the paper is silent:
//! * without a model (no expert of ≥ m_min pairs) there is no cost goal: Alg. 1 line 4 gets the
//!   experts with at least m_min observations, and the paper's robot "chooses to go towards the
//!   nearby spatial goal" while its cost and confidence are uniform;
//! * a reached cost goal is sampled: the robot walks straight on for one cost window over
//!   traversable cells (as decision 24 does for `001`), otherwise it would stand on the
//!   uncertain terrain measuring nothing; a reached spatial goal is not pursued again within
//!   2·r_robot and, with a limited field of view, the robot turns once on the spot there;
//! * planning costs are μ clamped below at the smallest cost measured so far (no terrain is
//!   cheaper than the cheapest one experienced; the zero-mean experts predict 0 far from data),
//!   and uniform before the first measurement;
//! * a cost goal just reached is not chosen again (nor any cell within δ_score/2 of it) for two
//!   cost windows, so the pairs of its sampling walk are learned before the score is judged;
//! * when the robot's motion is blocked on a cell Mtrv calls traversable (a step its legs cannot
//!   take), the Mcost cell ahead of it is excluded from then on, and a goal the robot is refused
//!   on the way to five times is given up (as if reached);
//! * the exploration ends when Eq. 16 yields no goal (or at the time limit); it also ends when
//!   the robot has had no traversable Mcost cell for 30 s.

pub mod cost_map;
pub mod goals;

use crate::kernel::{
    Actuators, Body, BodyParams, Every, FromParams, GoalCounts, LOOK_AROUND_S,
    Manoeuvre as Deadline, MissionError, Strategy, Termination, look_around,
};
use cost_map::{CostMap, PredictionCache};
use goals::{Goal, GoalKind, best_cost_goal, best_spatial_goal, frontier_representatives};
use std::time::Instant;
use strider_core::interface::MotionState;
use strider_core::snapshot::{
    GoalKind as SnapGoalKind, GoalSet, MeasuredCost, ModelLayer, Quantity, Snapshot,
};
use strider_core::{Cell, GaitId, Point2, Point3, PoseStamped, Proprioception};
use strider_learn::gp::{GpParams, HyperBounds};
use strider_learn::rbcm::{Rbcm, RbcmParams};
use strider_learn::signals::{RollVarianceCost, RollVarianceParams};
use strider_map::MapParams;
use strider_map::descriptors::shape_lab_descriptor;
use strider_map::reachability::Reachability;
use strider_map::rect::WorldRect;
use strider_plan::grid::{CostGrid, MeanEdgeDijkstra};

/// Seconds without a traversable cell under the robot after which the exploration gives up.
const NO_CELL_TIMEOUT_S: f64 = 30.0;

/// Refusals on the way to one goal after which it is given up (treated as reached).
const MAX_REFUSALS_PER_GOAL: usize = 5;

/// Everything the `000` explorer needs (defaults: `000` Table I and §V).
#[derive(Clone, Debug)]
pub struct RbcmGreedyParams {
    /// Elevation map (M2.5D) parameters; `rho_obstacle` is h_max, `r_robot` δ_impassable,
    /// `r_spatial` the frontier exclusion radius around the robot.
    pub map: MapParams,
    /// The gait walked throughout (the paper's adaptive or regular gait profile).
    pub gait: GaitId,
    /// Its maximum speed, m/s.
    pub gait_speed: f64,
    /// Mcost cell size, metres (10 cm).
    pub mcost_cell: f64,
    /// Descriptor neighbourhood δ_desc, metres.
    pub delta_desc: f64,
    /// Score neighbourhood δ_score, metres (0.5).
    pub delta_score: f64,
    /// λ_score of Eq. 16 (0.001 adaptive, 0.0005 regular).
    pub lambda_score: f64,
    /// Committee: m_max (50) and m_min (25).
    pub rbcm: RbcmParams,
    /// Initial (shared) GP hyperparameters of each expert; exponential kernel in `000`.
    pub gp: GpParams,
    /// Per-expert hyperparameter fitting bounds; `None` keeps the shared hyperparameters.
    pub fit: Option<HyperBounds>,
    /// Roll-variance window, seconds (10).
    pub window_s: f64,
    /// Proprioception and pose rates, Hz (ring sizes of the cost signal).
    pub proprio_rate_hz: f64,
    /// Pose rate, Hz.
    pub pose_rate_hz: f64,
    /// One (descriptor, cost) pair is kept per this much walking time, seconds.
    pub sample_period_s: f64,
    /// Follow-the-carrot look-ahead: waypoint spacing along the path, metres (0.2).
    pub carrot_m: f64,
    /// Control period rate, Hz.
    pub control_hz: f64,
    /// Planning (decision) rate, Hz.
    pub plan_hz: f64,
    /// Exploration bounds; frontiers outside are ignored.
    pub bounds: Option<WorldRect>,
    /// Horizontal field of view of each sensor, degrees (360: omnidirectional).
    pub sensor_hfov_deg: Vec<f64>,
    /// Mission time limit, seconds.
    pub time_limit_s: f64,
}

/// One planning cycle's timings (wall clock) and outcome.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct PlanRecord {
    /// Robot time, s.
    pub t: f64,
    /// Traversable Mcost cells.
    pub traversable_cells: usize,
    /// Passability and reachability on the elevation map, ms.
    pub trv_ms: f64,
    /// Mcost inference: descriptors and committee predictions (Eq. 11–12), ms.
    pub inference_ms: f64,
    /// Of which the descriptors, ms.
    pub descriptor_ms: f64,
    /// Of which the committee predictions, ms.
    pub predict_ms: f64,
    /// Goal selection: Eq. 14 search, Eq. 15 scores, frontiers (Eq. 13), Eq. 16, ms.
    pub goals_ms: f64,
    /// Path extraction and waypoints, ms.
    pub path_ms: f64,
    /// Everything above, ms.
    pub total_ms: f64,
    /// The goal chosen, if any.
    pub goal: Option<GoalKind>,
    /// The best Eq. 15 score (NaN without a model).
    pub best_score: f64,
}

/// One stored learning pair.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct CostRecord {
    /// Window middle time, s.
    pub t: f64,
    /// Attributed position, m.
    pub x: f64,
    /// Attributed position, m.
    pub y: f64,
    /// Roll variance over the window, rad².
    pub cost: f64,
}

/// What an `rbcm-greedy` exploration did, beyond the kernel's
/// [`RunRecord`](crate::kernel::RunRecord).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct RbcmGreedyLog {
    /// Every planning cycle.
    pub plans: Vec<PlanRecord>,
    /// Every learning pair stored.
    pub samples: Vec<CostRecord>,
    /// Cost windows dropped because their cell had no descriptor yet.
    pub undescribed_samples: usize,
    /// Wall time of each committee update (insertion and refit), ms.
    pub learning_ms: Vec<f64>,
    /// Times the robot's motion was blocked on a cell Mtrv called traversable (a step its legs
    /// cannot take); the cell ahead is then excluded from Mcost.
    pub refusals: usize,
    /// Cost goals reached (and sampled).
    pub cost_goals_reached: usize,
    /// Spatial goals reached.
    pub spatial_goals_reached: usize,
}

/// The `000` explorer: map, committee, cost signal and goal state.
pub struct RbcmGreedy {
    params: RbcmGreedyParams,
    reach: Reachability,
    rbcm: Rbcm,
    roll: RollVarianceCost,
    search: MeanEdgeDijkstra,
    cost_map: CostMap,
    cache: PredictionCache,
    walking_since: Option<f64>,
    last_sample_t: f64,
    min_cost: f64,
    goal: Option<Goal>,
    /// The sampling walk or look-around in progress.
    manoeuvre: Option<Deadline>,
    visited: Vec<Point2>,
    no_cell_since: Option<f64>,
    /// Mcost cells the robot was refused entry to (its motion reported *blocked*).
    refused: Vec<Cell>,
    /// Cost goals reached: (time, centre).
    reached_cost: Vec<(f64, Point2)>,
    blocked_on_goal: usize,
    /// The planning cycle's timer, set when the mission starts.
    plan_every: Option<Every>,
    log: RbcmGreedyLog,
}

impl RbcmGreedy {
    /// A new explorer with an empty map and committee.
    pub fn new(params: RbcmGreedyParams) -> Result<Self, MissionError> {
        let bad = |what: &str| MissionError::Params(what.to_string());
        for (name, v) in [
            ("mcost_cell", params.mcost_cell),
            ("delta_desc", params.delta_desc),
            ("delta_score", params.delta_score),
            ("gait_speed", params.gait_speed),
            ("sample_period_s", params.sample_period_s),
            ("carrot_m", params.carrot_m),
            ("control_hz", params.control_hz),
            ("plan_hz", params.plan_hz),
            ("time_limit_s", params.time_limit_s),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(bad(&format!("{name} must be a positive number, got {v}")));
            }
        }
        if !(params.lambda_score.is_finite() && params.lambda_score >= 0.0) {
            return Err(bad("lambda_score must be a non-negative number"));
        }
        let rbcm = Rbcm::new(5, params.gp.clone(), params.rbcm)
            .map_err(|e| bad(&format!("committee: {e}")))?;
        let roll = RollVarianceCost::new(RollVarianceParams {
            window_s: params.window_s,
            rate_hz: params.proprio_rate_hz,
            pose_rate_hz: params.pose_rate_hz,
        })
        .map_err(|e| bad(&e.to_string()))?;
        Ok(Self {
            reach: Reachability::default(),
            rbcm,
            roll,
            search: MeanEdgeDijkstra::new(),
            cost_map: CostMap::empty(params.mcost_cell),
            cache: PredictionCache::default(),
            walking_since: None,
            last_sample_t: f64::NEG_INFINITY,
            min_cost: f64::INFINITY,
            goal: None,
            manoeuvre: None,
            visited: Vec::new(),
            no_cell_since: None,
            refused: Vec::new(),
            reached_cost: Vec::new(),
            blocked_on_goal: 0,
            plan_every: None,
            log: RbcmGreedyLog {
                plans: Vec::new(),
                samples: Vec::new(),
                undescribed_samples: 0,
                learning_ms: Vec::new(),
                refusals: 0,
                cost_goals_reached: 0,
                spatial_goals_reached: 0,
            },
            params,
        })
    }

    /// The learned committee.
    pub fn rbcm(&self) -> &Rbcm {
        &self.rbcm
    }

    /// The cost map of the last planning cycle.
    pub fn cost_map(&self) -> &CostMap {
        &self.cost_map
    }

    /// The log so far.
    pub fn log(&self) -> &RbcmGreedyLog {
        &self.log
    }

    /// The parameters.
    pub fn params(&self) -> &RbcmGreedyParams {
        &self.params
    }

    /// Builds Mcost for the current map and committee from the robot's current cell (for a
    /// final report after the exploration; planning does this every cycle).
    pub fn refresh_cost_map(&mut self, body: &mut Body) {
        if let Some(c) = body.anchor_cell() {
            self.rebuild_cost_map(body, c);
        }
    }

    /// Mtrv (passability, reachability from elevation-map cell `rc`) and Mcost without the
    /// refused cells; returns the wall times of the two parts, ms.
    fn rebuild_cost_map(&mut self, body: &mut Body, rc: Cell) -> (f64, f64) {
        let w = Instant::now();
        body.map_mut().update_passability();
        self.reach.recompute(body.map(), rc);
        let trv_ms = ms(w);
        let w = Instant::now();
        self.cost_map = CostMap::build(
            body.map(),
            &self.reach,
            &self.rbcm,
            &mut self.cache,
            self.params.mcost_cell,
            self.params.delta_desc,
        );
        for &c in &self.refused {
            self.cost_map.exclude(c);
        }
        (trv_ms, ms(w))
    }

    /// True when the committee has an expert that takes part in predictions.
    pub fn has_model(&self) -> bool {
        let m_min = self.params.rbcm.m_min.max(1);
        self.rbcm.experts().iter().any(|e| e.len() >= m_min)
    }

    /// One cycle of Alg. 1 (lines 2–10); `Some` when the exploration ends.
    fn plan(
        &mut self,
        body: &mut Body,
        robot: &mut dyn Actuators,
        t: f64,
        state: MotionState,
    ) -> Option<Termination> {
        let Some(pos) = body.position() else {
            return None; // no pose yet
        };
        if body.map().scan_count() == 0 {
            return None; // nothing seen yet: no frontier can exist
        }
        let Some(rc) = body.anchor_cell() else {
            let since = *self.no_cell_since.get_or_insert(t);
            return (t - since >= NO_CELL_TIMEOUT_S).then_some(Termination::NoReachableGoals);
        };
        // A goal reached (or the path to it finished) first triggers its manoeuvre.
        if let Some(g) = self.goal {
            let near = (g.point.x - pos.x).hypot(g.point.y - pos.y) <= 1.5 * self.params.mcost_cell;
            if near || state.idle {
                self.goal = None;
                match g.kind {
                    GoalKind::Cost => {
                        self.log.cost_goals_reached += 1;
                        self.reached_cost.push((t, g.point));
                        if self.start_sampling(body, robot, t, pos) {
                            return None;
                        }
                    }
                    GoalKind::Spatial => {
                        self.log.spatial_goals_reached += 1;
                        self.visited.push(g.point);
                        if !body.sees_all_around()
                            && let Some(pose) = body.pose()
                        {
                            robot.follow(&look_around(&pose, body.map().cell_size()));
                            self.manoeuvre = Some(Deadline {
                                until: t + LOOK_AROUND_S,
                            });
                            return None;
                        }
                    }
                }
            }
        }
        let (trv_ms, inference_ms) = self.rebuild_cost_map(body, rc);
        let w = Instant::now();
        let traversable_cells = self.cost_map.traversable_count();
        let start = self
            .cost_map
            .cell_at(pos)
            .and_then(|c| self.cost_map.nearest_traversable(c, 3));
        let Some(start) = start else {
            let since = *self.no_cell_since.get_or_insert(t);
            return (t - since >= NO_CELL_TIMEOUT_S).then_some(Termination::NoReachableGoals);
        };
        self.no_cell_since = None;
        let floor = if self.min_cost.is_finite() && self.min_cost > 0.0 {
            self.min_cost
        } else {
            1.0
        };
        let grid = CostGrid::new(
            self.cost_map.rect,
            self.params.mcost_cell,
            self.cost_map.planning_costs(floor),
        );
        let Ok(grid) = grid else {
            return None;
        };
        if self.search.run(&grid, start).is_err() {
            return None;
        }
        let (cost_goal, best_score) = if self.has_model() {
            let mut scores = self.cost_map.scores(self.params.delta_score);
            // A cost goal just sampled is left alone until its windows are learned.
            let hold = 2.0 * self.params.window_s;
            let r_hold = 0.5 * self.params.delta_score;
            self.reached_cost.retain(|&(tr, _)| t - tr < hold);
            for (k, sc) in scores.iter_mut().enumerate() {
                let p = self.cost_map.rect.cell(k).center(self.params.mcost_cell);
                if self
                    .reached_cost
                    .iter()
                    .any(|&(_, q)| (q.x - p.x).hypot(q.y - p.y) < r_hold)
                {
                    *sc = f64::NAN;
                }
            }
            let g = best_cost_goal(&self.cost_map, &scores, &self.search);
            (g, g.map_or(f64::NAN, |g| g.value))
        } else {
            (None, f64::NAN)
        };
        let r_visited = 2.0 * self.params.map.r_robot;
        let reps = frontier_representatives(
            body.map(),
            &self.reach,
            rc,
            body.bounds(),
            &self.visited,
            r_visited,
        );
        let spatial = best_spatial_goal(&self.cost_map, &self.search, &reps, 2);
        let goal = goals::select_goal(cost_goal, spatial, self.params.lambda_score); // Eq. 16
        let goals_ms = ms(w);
        let w = Instant::now();
        let waypoints = goal.and_then(|g| self.search.path_to(g.cell)).map(|cells| {
            carrot_waypoints(&cells, self.params.mcost_cell, self.params.carrot_m, pos)
        });
        let path_ms = ms(w);
        self.log.plans.push(PlanRecord {
            t,
            traversable_cells,
            trv_ms,
            inference_ms,
            descriptor_ms: self.cost_map.descriptor_ms,
            predict_ms: self.cost_map.predict_ms,
            goals_ms,
            path_ms,
            total_ms: trv_ms + inference_ms + goals_ms + path_ms,
            goal: goal.map(|g| g.kind),
            best_score,
        });
        let Some(goal) = goal else {
            return Some(Termination::GoalsCleared); // Eq. 16: ν* = ∅
        };
        if self.goal.is_none_or(|g| g.cell != goal.cell) {
            self.blocked_on_goal = 0;
        }
        self.goal = Some(goal);
        robot.follow(&waypoints.unwrap_or_default());
        None
    }

    /// Remembers the Mcost cell one cell ahead of the robot as refused (the motion judge would
    /// not let the robot go on; Mtrv's step threshold may exceed what the legs can climb).
    fn refuse_ahead(&mut self, body: &Body) {
        let Some(p) = body.pose() else { return };
        let d = self.params.mcost_cell;
        // The motion judge refuses the first elevation cell the centre would cross: within
        // one elevation cell (diagonally √2) ahead.
        let r = body.map().cell_size() * std::f64::consts::SQRT_2;
        let ahead = Point2::new(
            p.position.x + r * p.yaw.cos(),
            p.position.y + r * p.yaw.sin(),
        );
        if let Some(c) = Cell::containing(ahead.x, ahead.y, d)
            && !self.refused.contains(&c)
        {
            self.refused.push(c);
        }
        self.log.refusals += 1;
        // A goal the robot keeps being refused on the way to is given up.
        self.blocked_on_goal += 1;
        if self.blocked_on_goal >= MAX_REFUSALS_PER_GOAL
            && let Some(g) = self.goal.take()
        {
            self.blocked_on_goal = 0;
            match g.kind {
                GoalKind::Cost => self.reached_cost.push((p.stamp, g.point)),
                GoalKind::Spatial => self.visited.push(g.point),
            }
        }
    }

    /// Walks straight on over traversable Mcost cells for one cost window from a reached cost
    /// goal; false when no direction is open.
    fn start_sampling(
        &mut self,
        body: &Body,
        robot: &mut dyn Actuators,
        t: f64,
        pos: Point2,
    ) -> bool {
        let heading = body.pose().map_or(0.0, |p| p.yaw);
        let want = self.params.gait_speed * self.params.window_s;
        let step = 0.5 * self.params.mcost_cell;
        let mut best: Option<(f64, Point2)> = None;
        for k in 0..16 {
            // Current heading first, then alternately left and right of it.
            let off = ((k + 1) / 2) as f64 * std::f64::consts::PI / 8.0;
            let a = heading + if k % 2 == 1 { off } else { -off };
            let (mut len, mut end) = (0.0, pos);
            while len + step <= want {
                let q = Point2::new(
                    pos.x + (len + step) * a.cos(),
                    pos.y + (len + step) * a.sin(),
                );
                if !self
                    .cost_map
                    .cell_at(q)
                    .is_some_and(|c| self.cost_map.is_traversable(c))
                {
                    break;
                }
                len += step;
                end = q;
            }
            if best.is_none_or(|(b, _)| len > b + 1e-9) {
                best = Some((len, end));
            }
            if len + step > want {
                break;
            }
        }
        match best {
            Some((len, end)) if len >= 2.0 * self.params.mcost_cell => {
                robot.follow(&[end]);
                // Generous: the walk at the gait's speed, plus turning towards it.
                let until = t + 2.0 * self.params.window_s + 20.0;
                self.manoeuvre = Some(Deadline { until });
                true
            }
            _ => false,
        }
    }

    /// Stores a (descriptor, cost) pair in the committee.
    fn learn(&mut self, x: &[f64; 5], cost: f64) {
        let w = Instant::now();
        let ok = match &self.params.fit {
            Some(bounds) => self.rbcm.push_fitted(x, cost, bounds),
            None => self.rbcm.push(x, cost),
        };
        self.log.learning_ms.push(ms(w));
        if ok.is_ok() {
            self.min_cost = self.min_cost.min(cost);
        }
    }
}

/// Elapsed milliseconds.
fn ms(w: Instant) -> f64 {
    w.elapsed().as_secs_f64() * 1e3
}

/// Waypoints every `carrot` metres along the cell path (centres, first cell skipped when the
/// robot stands in it), always ending at the last cell's centre.
pub fn carrot_waypoints(cells: &[Cell], cell_size: f64, carrot: f64, robot: Point2) -> Vec<Point2> {
    let pts: Vec<Point2> = cells.iter().map(|c| c.center(cell_size)).collect();
    let mut out = Vec::new();
    let mut last = robot;
    for (k, &p) in pts.iter().enumerate() {
        let is_last = k + 1 == pts.len();
        if is_last || (p.x - last.x).hypot(p.y - last.y) >= carrot {
            out.push(p);
            last = p;
        }
    }
    out
}

impl FromParams for RbcmGreedy {
    type Params = RbcmGreedyParams;

    /// The kernel's body parameters for this explorer's mission.
    fn body_params(params: &RbcmGreedyParams) -> BodyParams {
        BodyParams {
            map: params.map.clone(),
            sensor_hfov_deg: params.sensor_hfov_deg.clone(),
            bounds: params.bounds,
            time_limit_s: params.time_limit_s,
        }
    }

    fn from_params(params: RbcmGreedyParams) -> Result<Self, MissionError> {
        Self::new(params)
    }
}

impl Strategy for RbcmGreedy {
    fn name(&self) -> &'static str {
        "rbcm-greedy"
    }

    fn control_hz(&self) -> f64 {
        self.params.control_hz
    }

    fn initial_gait(&self) -> Option<GaitId> {
        Some(self.params.gait)
    }

    fn start(&mut self, _body: &mut Body, t0: f64) {
        self.plan_every = Some(Every::new(self.params.plan_hz, t0));
    }

    fn before_advance(&mut self, _body: &Body, state: MotionState, t: f64) {
        if state.idle {
            self.walking_since = None;
        } else if self.walking_since.is_none() {
            self.walking_since = Some(t);
        }
    }

    fn on_pose(&mut self, _body: &Body, pose: &PoseStamped) {
        self.roll.push_pose(pose);
    }

    fn on_proprioception(&mut self, body: &Body, p: &Proprioception) {
        let Some(s) = self.roll.push(p) else { return };
        // Only windows spent walking, one pair per sample period.
        let window_start = p.stamp - self.params.window_s;
        if !self.walking_since.is_some_and(|w| w <= window_start)
            || p.stamp - self.last_sample_t < self.params.sample_period_s
            || !s.cost.is_finite()
        {
            return;
        }
        self.last_sample_t = p.stamp;
        let map = body.map();
        let desc = map
            .cell_at(s.position.x, s.position.y)
            .and_then(|c| shape_lab_descriptor(map, c, self.params.delta_desc));
        let Some(d) = desc else {
            self.log.undescribed_samples += 1;
            return;
        };
        let x = d.map(f64::from);
        self.learn(&x, s.cost);
        self.log.samples.push(CostRecord {
            t: s.stamp,
            x: s.position.x,
            y: s.position.y,
            cost: s.cost,
        });
    }

    /// A manoeuvre runs to its end; the planning cycle runs at `plan_hz` and whenever the
    /// robot stopped or was refused.
    fn tick(
        &mut self,
        body: &mut Body,
        robot: &mut dyn Actuators,
        state: &mut MotionState,
        t: f64,
    ) -> Option<Termination> {
        if state.blocked {
            self.refuse_ahead(body);
        }
        if let Some(m) = self.manoeuvre {
            if m.runs(t, *state) {
                return None;
            }
            self.manoeuvre = None;
            robot.follow(&[]);
            state.idle = true;
        }
        let mut every = self.plan_every?;
        if every.is_due(t) || state.idle || state.blocked {
            every.ran(t);
            self.plan_every = Some(every);
            if let Some(end) = self.plan(body, robot, t, *state) {
                return Some(end);
            }
            state.idle = false;
            state.blocked = false;
        }
        None
    }

    fn describe(&self, body: &Body, snap: &mut Snapshot) {
        let map = body.map();
        let at = |p: Point2| {
            let z = map
                .cell_at(p.x, p.y)
                .and_then(|c| map.elevation(c))
                .filter(|z| z.is_finite())
                .unwrap_or(0.0) as f64;
            Point3::new(p.x, p.y, z)
        };
        for (name, kind, model) in [
            ("spatial_goal", GoalKind::Spatial, SnapGoalKind::Spatial),
            ("cost_goal", GoalKind::Cost, SnapGoalKind::Cost { model: 0 }),
        ] {
            snap.goals.push(GoalSet {
                name: name.into(),
                kind: model,
                sites: self
                    .goal
                    .filter(|g| g.kind == kind)
                    .map(|g| at(g.point))
                    .into_iter()
                    .collect(),
            });
        }
        snap.tour = self.goal.map(|g| at(g.point)).into_iter().collect();
        let cell_size = snap.cell_size;
        let Some(layers) = snap.layers.as_mut() else {
            return;
        };
        // Mcost has its own resolution: each map cell takes the Mcost cell its centre is in.
        let cm = &self.cost_map;
        let n = layers.rect.len();
        let mut layer = ModelLayer {
            name: "rbcm".into(),
            quantity: Quantity::RollVariance,
            gait: Some(self.params.gait),
            cost: Vec::with_capacity(n),
            variance: Vec::with_capacity(n),
            measured: vec![f32::NAN; n],
        };
        for c in layers.rect.cells() {
            let k = cm
                .cell_at(c.center(cell_size))
                .and_then(|m| cm.rect.index(m));
            let (mu, sd) = k.map_or((f64::NAN, f64::NAN), |k| (cm.mean[k], cm.std[k]));
            layer.cost.push(mu as f32);
            layer.variance.push((sd * sd) as f32);
        }
        for s in &self.log.samples {
            let p = Point2::new(s.x, s.y);
            if let Some(k) = map.cell_at(p.x, p.y).and_then(|c| layers.rect.index(c)) {
                layer.measured[k] = s.cost as f32;
            }
            snap.measured.push(MeasuredCost {
                at: at(p),
                cost: s.cost,
                model: 0,
            });
        }
        layers.models.push(layer);
    }

    /// The final Mcost for the current map and committee, so that reports and snapshots
    /// after the mission show what was learned last.
    fn finish(&mut self, body: &mut Body, _t: f64) {
        self.refresh_cost_map(body);
    }

    fn goal_counts(&self) -> GoalCounts {
        GoalCounts {
            spatial_goals: usize::from(self.goal.is_some_and(|g| g.kind == GoalKind::Spatial)),
            cost_goals: usize::from(self.goal.is_some_and(|g| g.kind == GoalKind::Cost)),
            learning_set: self.rbcm.len(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn carrot_spacing_and_end() {
        let cells: Vec<Cell> = (0..10).map(|i| Cell::new(i, 0)).collect();
        let w = carrot_waypoints(&cells, 0.1, 0.2, Point2::new(0.05, 0.05));
        assert_eq!(w.last().copied(), Some(Cell::new(9, 0).center(0.1)));
        for pair in w.windows(2) {
            let d = (pair[1].x - pair[0].x).hypot(pair[1].y - pair[0].y);
            assert!(d <= 0.2 + 1e-9, "{d}");
        }
        assert!(w.len() <= 6);
        assert!(carrot_waypoints(&[], 0.1, 0.2, Point2::new(0.0, 0.0)).is_empty());
    }
}
