//! Thesis C4: exploration with online learning of traversable yet visually rigid obstacles
//! (the `escape` strategy, C4 Alg. 2) and the `rigid` baseline that treats every apparent
//! obstacle as impassable.
//!
//! * [`haptic`]: bumper filtering, per-cell Kalman fusion of the force to pass through (C4
//!   Eq. 9) and the traversability fusion of C4 Eq. 4.
//! * [`force_predictor`]: the GP force predictor on Lab (a, b) or the 8-bin histogram and its
//!   information gain (C4 Eq. 10–19).
//! * [`view`]: the Eq. 4 classification of the map and the planning grid of C4 Eq. 20.
//! * [`goals`]: goal selection of C4 Alg. 2 (Eq. 22–26).
//! * [`reflexes`]: the approach/push and sample/retreat reflexes of C4 §5.1.
//!
//! [`EscapeMission`] runs C4 Alg. 2 on the mission kernel ([`crate::kernel`]): the map is
//! updated from every fused scan (line 4), the predictor relearned at 0.03 Hz (line 5), predictions applied and spatial goals
//! identified at `view_hz` (lines 6–10), and a goal chosen (lines 11–20) whenever the view was
//! rebuilt, the robot stopped, or a reflex ended. It reads only what the robot reports (poses,
//! clouds, the bumper force, the motion state).
//!
//! Decisions where the thesis is silent:
//! * the predictor is learned as soon as the first haptic measurement exists (Alg. 2 line 12
//!   distinguishes "P is not learned"; waiting up to 33 s for the first scheduled relearn would
//!   send the robot to sample the obstacle it just sampled), then at the fixed rate;
//! * the bumper force is assigned to the apparent obstacle cells nearest ahead of the robot in
//!   a narrow corridor (`contact_half_width`) reaching r_robot beyond the body centre;
//! * a spatial goal counts as reached within 1.5 cells or at the end of its path, or when a
//!   push reflex ends within 2·r_robot of it (a goal on a pushable obstacle); the robot then
//!   turns on the spot once (its cameras look front and back only) and the goal is not pursued
//!   again within 2·r_robot, as in the `001` mission;
//! * an obstacle goal whose approach ends without a bumper measurement on it is not pursued
//!   again within `exclusion_m`;
//! * the exploration ends when no goal has been found for `no_goal_grace_s`.

pub mod force_predictor;
pub mod goals;
pub mod haptic;
pub mod reflexes;
pub mod view;

use crate::kernel::{
    Actuators, Body, BodyParams, Every, FromParams, GoalCounts, LOOK_AROUND_S, Manoeuvre,
    MissionError, Strategy, Termination, look_around, site,
};
use force_predictor::{ForcePrediction, ForcePredictor, PredictorParams, describe};
use goals::{Goal, GoalInputs, GoalKind, select_goal};
use haptic::{BumperFilter, HapticModel, HapticParams};
use reflexes::{Reflex, ReflexAction, ReflexInput, ReflexParams};
use std::collections::BTreeSet;
use strider_core::interface::MotionState;
use strider_core::snapshot::{
    GoalKind as SnapGoalKind, GoalSet, MeasuredCost, ModelLayer, Quantity, Snapshot,
};
use strider_core::{Cell, Point2, Pose2, Proprioception};
use strider_map::information_gain::model_information;
use strider_map::params::MapParams;
use strider_map::rect::WorldRect;
use strider_map::{ElevationMap, Reachability, SpatialGoal, cluster_information, information_gain};
use strider_plan::grid::{Dijkstra, smooth_path};
use view::{CellStates, ObstacleState, TravView, ViewParams, is_proud};

/// Which C4 strategy runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum EscapeMode {
    /// C4 Alg. 2 with haptic learning.
    Escape,
    /// Every apparent obstacle is impassable; spatial goals only.
    Rigid,
}

impl EscapeMode {
    /// The command-line name.
    pub fn name(self) -> &'static str {
        match self {
            Self::Escape => "escape",
            Self::Rigid => "rigid",
        }
    }

    /// Parses a command-line name.
    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "escape" => Some(Self::Escape),
            "rigid" => Some(Self::Rigid),
            _ => None,
        }
    }
}

/// Everything an escape mission needs.
#[derive(Clone, Debug, PartialEq)]
pub struct EscapeParams {
    /// The strategy.
    pub mode: EscapeMode,
    /// Map parameters (t_trav = `rho_obstacle`, r_sensor, r_robot; `c_radius` and `c_min_cells`
    /// are C4 d_cl and n_cl).
    pub map: MapParams,
    /// Walking speed, m/s (sizes the retreat).
    pub v_max: f64,
    /// Horizontal field of view per sensor, degrees (a robot that does not see all around
    /// looks around at spatial goals).
    pub sensor_hfov_deg: Vec<f64>,
    /// Exploration bounds.
    pub bounds: Option<WorldRect>,
    /// Time limit, s.
    pub time_limit_s: f64,
    /// Haptic model.
    pub haptic: HapticParams,
    /// Force predictor.
    pub predictor: PredictorParams,
    /// Reflexes.
    pub reflex: ReflexParams,
    /// Planning grid.
    pub view: ViewParams,
    /// Control tick, Hz.
    pub control_hz: f64,
    /// Rate of Alg. 2 lines 6–10 (predictions applied, spatial goals), Hz.
    pub view_hz: f64,
    /// Rate of the time series in the log, Hz.
    pub record_hz: f64,
    /// The exploration ends after this long without a goal, s.
    pub no_goal_grace_s: f64,
    /// Radius around a failed obstacle goal that is not pursued again, m.
    pub exclusion_m: f64,
    /// A newly chosen goal this close to the current one (same rule) keeps the current path, m.
    pub same_goal_m: f64,
    /// Spacing of the Eq. 8 candidate lattice, m (`None`: max(0.2 m, r_sensor/20)).
    pub info_gain_spacing_m: Option<f64>,
}

impl EscapeParams {
    /// C4 Table 3 values around the given map, robot speed and sensors.
    pub fn new(
        mode: EscapeMode,
        map: MapParams,
        v_max: f64,
        sensor_hfov_deg: Vec<f64>,
        bounds: Option<WorldRect>,
    ) -> Self {
        let view = ViewParams {
            r_robot: map.r_robot,
            ..ViewParams::default()
        };
        Self {
            mode,
            map: MapParams {
                c_radius: 1.0,
                c_min_cells: 10,
                ..map
            },
            v_max,
            sensor_hfov_deg,
            bounds,
            time_limit_s: 3600.0,
            haptic: HapticParams::default(),
            predictor: PredictorParams::lab(),
            reflex: ReflexParams::default(),
            view,
            control_hz: 10.0,
            view_hz: 0.5,
            record_hz: 0.2,
            no_goal_grace_s: 10.0,
            exclusion_m: 0.15,
            same_goal_m: 0.25,
            info_gain_spacing_m: None,
        }
    }

    fn validate(&self) -> Result<(), MissionError> {
        let pos = |v: f64| v.is_finite() && v > 0.0;
        if !(pos(self.v_max)
            && pos(self.control_hz)
            && pos(self.view_hz)
            && pos(self.record_hz)
            && pos(self.predictor.learn_hz)
            && pos(self.time_limit_s)
            && pos(self.map.cell_size))
        {
            return Err(MissionError::Params(
                "speeds, rates, cell size and time limit must be positive".into(),
            ));
        }
        Ok(())
    }
}

/// One sample of the time series (C4 Figs. 11–12 and the explored area).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct TimelineSample {
    /// Robot time since the start, s.
    pub t: f64,
    /// Observed map area, m².
    pub explored_m2: f64,
    /// Apparent obstacle cells by state.
    pub states: CellStates,
    /// Cells with haptic ground truth.
    pub haptic_cells: usize,
}

/// One contact of the bumper with an apparent obstacle.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct ContactEvent {
    /// Start, s since the mission start.
    pub t_start: f64,
    /// End, s.
    pub t_end: f64,
    /// Centroid of the touched cells, m.
    pub x: f64,
    /// Centroid of the touched cells, m.
    pub y: f64,
    /// Cells touched.
    pub cells: usize,
    /// Mean fused force over the touched cells at the end, N.
    pub force: f64,
    /// Mean prediction over the touched cells before the contact (`None`: no predictor).
    pub predicted: Option<ForcePrediction>,
    /// The contact contradicted a prediction of "traversable" (C4 §5.2, an over-optimistic
    /// prediction corrected).
    pub corrected: bool,
}

/// One goal chosen.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct GoalEvent {
    /// s since the mission start.
    pub t: f64,
    /// Rule.
    pub kind: GoalKind,
    /// Goal position, m.
    pub x: f64,
    /// Goal position, m.
    pub y: f64,
}

/// What an escape mission did, beyond the kernel's [`RunRecord`](crate::kernel::RunRecord).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct EscapeLog {
    /// Strategy.
    pub mode: EscapeMode,
    /// Explored area and cell states over time.
    pub timeline: Vec<TimelineSample>,
    /// Bumper contacts.
    pub contacts: Vec<ContactEvent>,
    /// Goals chosen (each change of goal).
    pub goals: Vec<GoalEvent>,
    /// Push reflexes started.
    pub pushes: usize,
    /// Sample-and-retreat reflexes.
    pub samplings: usize,
    /// Predictor relearnings.
    pub relearns: usize,
}

/// An open bumper contact.
struct ContactAcc {
    t_start: f64,
    last: f64,
    cells: BTreeSet<(i32, i32)>,
    predicted: Vec<ForcePrediction>,
    predicted_traversable: bool,
}

/// The C4 escape mission (see the module docs).
pub struct EscapeMission {
    params: EscapeParams,
    haptic: HapticModel,
    filter: BumperFilter,
    predictor: ForcePredictor,
    reflex: Reflex,
    view: Option<TravView>,
    spatial: Vec<SpatialGoal>,
    visited: Vec<Cell>,
    failed: Vec<Cell>,
    current: Option<Goal>,
    looking: Option<Manoeuvre>,
    dij: Dijkstra,
    no_goal_since: Option<f64>,
    contact: Option<ContactAcc>,
    hard_contact: bool,
    t0: f64,
    /// Module timers, set when the mission starts.
    modules: Option<Modules>,
    /// The goal is chosen afresh at the next tick.
    replan: bool,
    log: EscapeLog,
}

/// The module timers of C4 Alg. 2.
#[derive(Clone, Copy, Debug)]
struct Modules {
    /// Alg. 2 line 5: relearning the predictor.
    learn: Every,
    /// Lines 6–10: predictions applied, spatial goals.
    view: Every,
    /// The log's time series.
    record: Every,
}

impl EscapeMission {
    /// A mission with an empty map and no predictor.
    pub fn new(params: EscapeParams) -> Result<Self, MissionError> {
        params.validate()?;
        Ok(Self {
            haptic: HapticModel::new(params.haptic.clone()),
            filter: BumperFilter::default(),
            predictor: ForcePredictor::new(params.predictor.clone()),
            reflex: Reflex::new(params.reflex.clone()),
            view: None,
            spatial: Vec::new(),
            visited: Vec::new(),
            failed: Vec::new(),
            current: None,
            looking: None,
            dij: Dijkstra::new(),
            no_goal_since: None,
            contact: None,
            hard_contact: false,
            t0: 0.0,
            modules: None,
            replan: true,
            log: EscapeLog {
                mode: params.mode,
                timeline: Vec::new(),
                contacts: Vec::new(),
                goals: Vec::new(),
                pushes: 0,
                samplings: 0,
                relearns: 0,
            },
            params,
        })
    }

    /// The haptic model.
    pub fn haptic(&self) -> &HapticModel {
        &self.haptic
    }

    /// The force predictor.
    pub fn predictor(&self) -> &ForcePredictor {
        &self.predictor
    }

    /// The latest traversability view.
    pub fn view(&self) -> Option<&TravView> {
        self.view.as_ref()
    }

    /// The parameters.
    pub fn params(&self) -> &EscapeParams {
        &self.params
    }

    /// The log so far.
    pub fn log(&self) -> &EscapeLog {
        &self.log
    }

    fn learns(&self) -> bool {
        self.params.mode == EscapeMode::Escape
    }

    fn robot_pose(&self, body: &Body) -> Option<Pose2> {
        body.pose()
            .map(|p| Pose2::new(p.position.x, p.position.y, p.yaw))
    }

    /// Steps the running reflex; true when it finished.
    fn run_reflex(
        &mut self,
        body: &Body,
        robot: &mut dyn Actuators,
        t: f64,
        state: MotionState,
    ) -> bool {
        let Some(pose) = self.robot_pose(body) else {
            return false;
        };
        let near = self.obstacle_ahead(body, |_| true) || self.contact.is_some();
        let input = ReflexInput {
            t,
            pose,
            hard_contact: self.hard_contact,
            near,
            idle: state.idle,
            blocked: state.blocked,
        };
        match self.reflex.step(input, self.params.v_max) {
            ReflexAction::Continue => false,
            ReflexAction::Follow(path) => {
                robot.follow(&path);
                false
            }
            ReflexAction::Finished { sampled } => {
                if sampled {
                    self.log.samplings += 1;
                }
                robot.follow(&[]);
                // An obstacle goal is done once the reflex has run on it; a spatial goal is
                // chosen afresh (the robot stopping here has not reached it).
                if let Some(g) = self.current {
                    if g.kind != GoalKind::Spatial && self.haptic.get(g.cell).is_none() {
                        self.failed.push(g.cell);
                    }
                    // A spatial goal on a pushable obstacle is reached by pushing into it.
                    let r = 2.0 * self.params.view.r_robot;
                    if g.kind == GoalKind::Spatial
                        && pose.position().dist(g.cell.center(body.map().cell_size())) <= r
                    {
                        self.visited.push(g.cell);
                    }
                    self.current = None;
                }
                true
            }
        }
    }

    /// The nearest apparent obstacle cell within `approach_m` ahead of the bumper that the robot
    /// means to pass (predicted or known traversable) or to sample (the current obstacle goal's
    /// neighbourhood).
    fn pushable_ahead(&self, body: &Body) -> Option<Point2> {
        let goal = self.current.filter(|g| g.kind != GoalKind::Spatial);
        let clear = self.clear_radius_cells(body);
        let view = self.view.as_ref();
        self.approach_corridor(body)
            .into_iter()
            .find(|&(c, _)| {
                goal.is_some_and(|g| g.cell.dist_cells(c) <= clear)
                    || view.is_some_and(|v| v.is_traversable(c))
            })
            .map(|(c, _)| c.center(body.map().cell_size()))
    }

    fn clear_radius_cells(&self, body: &Body) -> f64 {
        (self.params.view.r_robot + self.params.reflex.bumper_half_width) / body.map().cell_size()
    }

    /// Whether an apparent obstacle cell accepted by `accept` lies in the bumper corridor within
    /// `approach_m` of the bumper.
    fn obstacle_ahead(&self, body: &Body, accept: impl Fn(Cell) -> bool) -> bool {
        self.approach_corridor(body)
            .into_iter()
            .any(|(c, _)| accept(c))
    }

    /// The apparent obstacle cells in the bumper corridor within `approach_m` of the bumper,
    /// nearest first (empty without a pose).
    fn approach_corridor(&self, body: &Body) -> Vec<(Cell, f64)> {
        let Some(pose) = self.robot_pose(body) else {
            return Vec::new();
        };
        corridor_cells(
            body.map(),
            pose,
            self.params.view.r_robot + self.params.reflex.approach_m,
            self.params.reflex.bumper_half_width,
            body.map().params().rho_obstacle,
        )
    }

    /// Alg. 2 line 5: P ← learn({(A(ν), F(ν))}).
    fn relearn(&mut self, body: &Body) {
        let samples: Vec<(Vec<f64>, f64)> = self
            .haptic
            .cells()
            .into_iter()
            .filter_map(|(c, h)| {
                describe(body.map(), c, self.predictor.params()).map(|d| (d, h.force))
            })
            .collect();
        if let Ok(n) = self.predictor.learn(&samples)
            && n > 0
        {
            self.log.relearns += 1;
        }
    }

    /// Alg. 2 lines 6–10: predictions applied, spatial goals.
    fn update_view(&mut self, body: &mut Body) {
        body.map_mut().update_passability();
        let pred = self.learns().then_some(&self.predictor);
        self.view = TravView::build(
            body.map(),
            &self.haptic,
            pred,
            self.params.bounds.as_ref(),
            &self.params.view,
        );
        self.spatial.clear();
        let (Some(view), Some(anchor)) = (self.view.as_ref(), self.anchor(body)) else {
            return;
        };
        let reach =
            Reachability::from_admissible(body.map(), anchor, view.rect, &view.goal_admissible());
        let bounds = self.params.bounds.as_ref();
        let mut gain = information_gain(body.map(), &reach, bounds);
        // Alg. 2 line 7 computes I_geom on every traversable cell, apparent obstacles learnt to
        // be traversable included. The Eq. 8 lattice (every `stride` cells) can miss a curtain
        // two cells thick, and the top of a pushable obstacle is exactly where the robot can
        // see past it: such cells are evaluated on a lattice of two cells (which any obstacle
        // two cells thick meets) in addition.
        let lattice = body.map().params().info_gain_stride.max(1) as i32;
        let extra: Vec<(Cell, f64)> = (0..view.rect.len())
            .filter(|&k| view.obstacle[k].is_some() && view.traversable[k])
            .map(|k| view.rect.cell(k))
            .filter(|c| {
                c.i.rem_euclid(2) == 0
                    && c.j.rem_euclid(2) == 0
                    && !(c.i.rem_euclid(lattice) == 0 && c.j.rem_euclid(lattice) == 0)
                    && reach.is_goal_cell(*c)
            })
            .map(|c| (c, model_information(body.map(), c, bounds)))
            .filter(|&(_, g)| g > 0.0)
            .collect();
        if !extra.is_empty() {
            gain.cells.extend(extra);
            gain.cells.sort_by_key(|&(c, _)| (c.j, c.i));
        }
        self.spatial = cluster_information(body.map(), &gain, &reach, bounds);
        let r = 2.0 * self.params.view.r_robot / body.map().cell_size();
        let visited = &self.visited;
        self.spatial
            .retain(|g| visited.iter().all(|v| v.dist_cells(g.cell) > r));
    }

    fn record(&mut self, body: &Body, t: f64) {
        let d = body.map().cell_size();
        let states = self
            .view
            .as_ref()
            .map(|v| v.cell_states(!self.learns()))
            .unwrap_or_default();
        self.log.timeline.push(TimelineSample {
            t: t - self.t0,
            explored_m2: body.map().observed_count() as f64 * d * d,
            states,
            haptic_cells: self.haptic.len(),
        });
    }

    /// The cell plans start from: the robot's cell when it is a goal cell of the view, else the
    /// nearest such cell within 3·r_robot, else the nearest admissible one.
    fn anchor(&self, body: &Body) -> Option<Cell> {
        let view = self.view.as_ref()?;
        let ok = |c: Cell| view.is_goal_cell(c);
        let adm = |c: Cell| view.rect.index(c).is_some_and(|k| view.admissible[k]);
        body.nearest_within_anchor_disc(ok)
            .or_else(|| body.nearest_within_anchor_disc(adm))
    }

    /// Alg. 2 lines 11–24 for the current state; `Some` ends the exploration.
    fn decide(
        &mut self,
        body: &mut Body,
        robot: &mut dyn Actuators,
        t: f64,
        state: MotionState,
    ) -> Option<Termination> {
        let anchor = self.anchor(body)?;
        // The current goal reached?
        if let Some(g) = self.current {
            match g.kind {
                GoalKind::Spatial => {
                    if anchor.dist_cells(g.cell) <= 1.5 || state.idle {
                        self.visited.push(g.cell);
                        let r = 2.0 * self.params.view.r_robot / body.map().cell_size();
                        self.spatial.retain(|s| s.cell.dist_cells(g.cell) > r);
                        self.current = None;
                        if !body.sees_all_around()
                            && let Some(p) = body.pose()
                        {
                            robot.follow(&look_around(&p, body.map().cell_size()));
                            self.looking = Some(Manoeuvre {
                                until: t + LOOK_AROUND_S,
                            });
                            return None;
                        }
                    }
                }
                _ => {
                    if self.haptic.get(g.cell).is_some() || state.idle {
                        if self.haptic.get(g.cell).is_none() {
                            self.failed.push(g.cell);
                        }
                        self.current = None;
                    }
                }
            }
        }
        let view = self.view.as_ref()?;
        if self.dij.run(&view.grid, anchor).is_err() {
            return None;
        }
        let inputs = GoalInputs {
            dist: self.dij.distances(),
            spatial: &self.spatial,
            learn: self.learns(),
            predictor_learned: self.predictor.is_learned(),
            entropy_threshold: self.params.predictor.entropy_threshold,
            r_robot: self.params.view.r_robot,
            reach: 2.0 * body.map().cell_size(),
            excluded: &self.failed,
            exclusion_cells: self.params.exclusion_m / body.map().cell_size(),
            bounds: self.params.bounds.as_ref(),
        };
        let Some(goal) = select_goal(view, &inputs) else {
            robot.follow(&[]);
            self.current = None;
            let since = *self.no_goal_since.get_or_insert(t);
            return (t - since >= self.params.no_goal_grace_s).then_some(Termination::GoalsCleared);
        };
        self.no_goal_since = None;
        // The same goal (a spatial goal's representative drifts by a few cells as the map
        // grows): keep following the path already commanded, so a robot turning on the spot is
        // not re-commanded at every view update.
        if let Some(g) = self.current
            && g.kind == goal.kind
            && g.cell.dist_cells(goal.cell) <= self.params.same_goal_m / body.map().cell_size()
            && !state.idle
            && !state.blocked
        {
            return None;
        }
        let d = body.map().cell_size();
        let path = if goal.kind == GoalKind::Spatial {
            self.dij
                .path_to(goal.cell)
                .map(|p| smooth_path(&view.grid, &p))
        } else {
            let r = self.clear_radius_cells(body) * d;
            view.cleared_grid(goal.cell, r).and_then(|g| {
                let cost = self.dij.astar(&g, anchor, goal.cell).ok()?;
                if !cost.is_finite() {
                    return None;
                }
                self.dij.path_to(goal.cell).map(|p| smooth_path(&g, &p))
            })
        };
        let Some(path) = path else {
            self.failed.push(goal.cell);
            self.current = None;
            return None;
        };
        let pts: Vec<Point2> = path.iter().map(|c| c.center(d)).collect();
        robot.follow(&pts);
        if self
            .current
            .is_none_or(|g| g.cell != goal.cell || g.kind != goal.kind)
        {
            let p = goal.cell.center(d);
            self.log.goals.push(GoalEvent {
                t: t - self.t0,
                kind: goal.kind,
                x: p.x,
                y: p.y,
            });
        }
        self.current = Some(goal);
        None
    }

    /// Ends the open contact when the bumper has been quiet for a second (or `force`).
    fn close_contact(&mut self, body: &Body, t: f64, force: bool) {
        let Some(acc) = &self.contact else { return };
        if !force && t - acc.last <= 1.0 {
            return;
        }
        let Some(acc) = self.contact.take() else {
            return;
        };
        let d = body.map().cell_size();
        let cells: Vec<Cell> = acc.cells.iter().map(|&(i, j)| Cell::new(i, j)).collect();
        let n = cells.len().max(1) as f64;
        let (mut x, mut y, mut f) = (0.0, 0.0, 0.0);
        for c in &cells {
            let p = c.center(d);
            x += p.x / n;
            y += p.y / n;
            f += self.haptic.get(*c).map_or(0.0, |h| h.force) / n;
        }
        let predicted = (!acc.predicted.is_empty()).then(|| {
            let m = acc.predicted.len() as f64;
            ForcePrediction {
                mean: acc.predicted.iter().map(|p| p.mean).sum::<f64>() / m,
                variance: acc.predicted.iter().map(|p| p.variance).sum::<f64>() / m,
                entropy: acc.predicted.iter().map(|p| p.entropy).sum::<f64>() / m,
            }
        });
        let corrected = acc.predicted_traversable && f > self.params.haptic.f_trav;
        self.log.contacts.push(ContactEvent {
            t_start: acc.t_start - self.t0,
            t_end: acc.last - self.t0,
            x,
            y,
            cells: cells.len(),
            force: f,
            predicted,
            corrected,
        });
    }
}

/// Apparent obstacle cells in the bumper corridor: cells whose centre lies ahead of the robot
/// centre by at most `reach` and within `half_width` of its heading line, nearest first, keeping
/// only those within two cells of the nearest (the face the bumper touches).
pub fn corridor_cells(
    map: &ElevationMap,
    pose: Pose2,
    reach: f64,
    half_width: f64,
    t_trav: f64,
) -> Vec<(Cell, f64)> {
    let d = map.cell_size();
    let (s, c) = pose.yaw.sin_cos();
    let r = reach.max(half_width) + d;
    let (Some(lo), Some(hi)) = (
        Cell::containing(pose.x - r, pose.y - r, d),
        Cell::containing(pose.x + r, pose.y + r, d),
    ) else {
        return Vec::new();
    };
    let mut out = Vec::new();
    for j in lo.j..=hi.j {
        for i in lo.i..=hi.i {
            let cell = Cell::new(i, j);
            let p = cell.center(d);
            let (dx, dy) = (p.x - pose.x, p.y - pose.y);
            let along = dx * c + dy * s;
            let lat = (-dx * s + dy * c).abs();
            if along >= -d && along <= reach && lat <= half_width && is_proud(map, cell, t_trav) {
                out.push((cell, along));
            }
        }
    }
    out.sort_by(|a, b| a.1.total_cmp(&b.1));
    if let Some(&(_, first)) = out.first() {
        out.retain(|&(_, a)| a <= first + 2.0 * d);
    }
    out
}

impl FromParams for EscapeMission {
    type Params = EscapeParams;

    /// The kernel's body parameters for this mission: Eq. 8 on a stride lattice as in the
    /// `001` mission (decision 5), each candidate standing for stride² cells in the minimum
    /// cluster size.
    fn body_params(params: &EscapeParams) -> BodyParams {
        BodyParams {
            map: crate::kernel::lattice_map_params(&params.map, params.info_gain_spacing_m),
            sensor_hfov_deg: params.sensor_hfov_deg.clone(),
            bounds: params.bounds,
            time_limit_s: params.time_limit_s,
        }
    }

    fn from_params(params: EscapeParams) -> Result<Self, MissionError> {
        Self::new(params)
    }
}

impl Strategy for EscapeMission {
    fn name(&self) -> &'static str {
        self.params.mode.name()
    }

    fn control_hz(&self) -> f64 {
        self.params.control_hz
    }

    fn start(&mut self, _body: &mut Body, t0: f64) {
        self.t0 = t0;
        self.modules = Some(Modules {
            learn: Every::new(self.params.predictor.learn_hz, t0),
            view: Every::new(self.params.view_hz, t0),
            record: Every::new(self.params.record_hz, t0),
        });
    }

    /// Alg. 2: relearning, the view and spatial goals at their rates, the running reflex or
    /// look-around to its end, a push at a pushable obstacle ahead, then a goal whenever the
    /// view was rebuilt, the robot stopped, or a reflex ended.
    fn tick(
        &mut self,
        body: &mut Body,
        robot: &mut dyn Actuators,
        state: &mut MotionState,
        t: f64,
    ) -> Option<Termination> {
        let state = *state;
        let mut m = self.modules?;
        self.close_contact(body, t, false);
        if self.learns()
            && (m.learn.is_due(t) || (!self.predictor.is_learned() && !self.haptic.is_empty()))
        {
            self.relearn(body);
            m.learn.ran(t);
        }
        if m.view.due(t) {
            self.update_view(body);
            self.replan = true;
        }
        if m.record.due(t) {
            self.record(body, t);
        }
        self.modules = Some(m);
        if self.reflex.is_active() {
            if self.run_reflex(body, robot, t, state) {
                self.replan = true;
            } else {
                return None;
            }
        }
        if let Some(l) = self.looking {
            if l.runs(t, state) {
                return None;
            }
            self.looking = None;
            self.replan = true;
        }
        if self.learns()
            && !state.idle
            && let (Some(pose), Some(target)) = (self.robot_pose(body), self.pushable_ahead(body))
        {
            // Walk straight at the obstacle (the nearest pushable cell ahead).
            let yaw = (target.y - pose.y).atan2(target.x - pose.x);
            robot.follow(&self.reflex.start_push(t, Pose2::new(pose.x, pose.y, yaw)));
            self.log.pushes += 1;
            return None;
        }
        if self.replan || state.idle || state.blocked {
            self.replan = false;
            return self.decide(body, robot, t, state);
        }
        None
    }

    fn finish(&mut self, body: &mut Body, t: f64) {
        self.close_contact(body, t, true);
        self.update_view(body);
        self.record(body, t);
    }

    fn describe(&self, body: &Body, snap: &mut Snapshot) {
        snap.goals.push(GoalSet {
            name: "spatial_goals".into(),
            kind: SnapGoalKind::Spatial,
            sites: self.spatial.iter().map(|g| site(body, g.cell)).collect(),
        });
        let obstacle = self.current.filter(|g| g.kind != GoalKind::Spatial);
        snap.goals.push(GoalSet {
            name: "obstacle_goal".into(),
            kind: SnapGoalKind::Cost { model: 0 },
            sites: obstacle.map(|g| site(body, g.cell)).into_iter().collect(),
        });
        snap.tour = self
            .current
            .map(|g| site(body, g.cell))
            .into_iter()
            .collect();
        let Some(layers) = snap.layers.as_mut() else {
            return;
        };
        let n = layers.rect.len();
        let mut layer = ModelLayer {
            name: "force".into(),
            quantity: Quantity::PushForce,
            gait: None,
            cost: vec![f32::NAN; n],
            variance: vec![f32::NAN; n],
            measured: vec![f32::NAN; n],
        };
        for (k, c) in layers.rect.cells().enumerate() {
            if let Some(h) = self.haptic.get(c) {
                layer.measured[k] = h.force as f32;
            }
            match self.view.as_ref().and_then(|v| v.obstacle(c)) {
                Some(ObstacleState::Haptic { force, .. }) => layer.cost[k] = force as f32,
                Some(ObstacleState::Predicted(p)) => {
                    layer.cost[k] = p.mean as f32;
                    layer.variance[k] = p.variance as f32;
                }
                _ => {}
            }
        }
        layers.models.push(layer);
        for (c, h) in self.haptic.cells() {
            snap.measured.push(MeasuredCost {
                at: site(body, c),
                cost: h.force,
                model: 0,
            });
        }
    }

    fn goal_counts(&self) -> GoalCounts {
        GoalCounts {
            spatial_goals: self.spatial.len(),
            cost_goals: usize::from(self.current.is_some_and(|g| g.kind != GoalKind::Spatial)),
            learning_set: self.predictor.len(),
        }
    }

    /// The bumper stream: filtered, then fused into the apparent obstacle cells the bumper
    /// touches (C4 §4.2).
    fn on_proprioception(&mut self, body: &Body, p: &Proprioception) {
        let Some(pose) = self.robot_pose(body) else {
            return;
        };
        let z = self.filter.push(p.bumper_force, &self.params.haptic);
        self.hard_contact = z.is_some_and(|z| z > self.params.haptic.f_trav);
        let Some(z) = z else { return };
        let cells = corridor_cells(
            body.map(),
            pose,
            self.params.view.r_robot + body.map().cell_size(),
            self.params.reflex.contact_half_width,
            body.map().params().rho_obstacle,
        );
        if cells.is_empty() {
            return;
        }
        let acc = self.contact.get_or_insert_with(|| ContactAcc {
            t_start: p.stamp,
            last: p.stamp,
            cells: BTreeSet::new(),
            predicted: Vec::new(),
            predicted_traversable: false,
        });
        acc.last = p.stamp;
        for &(c, _) in &cells {
            if acc.cells.insert((c.i, c.j)) {
                // What the robot believed before touching the cell.
                if let Some(ObstacleState::Predicted(fp)) =
                    self.view.as_ref().and_then(|v| v.obstacle(c))
                {
                    acc.predicted.push(fp);
                    acc.predicted_traversable |= fp.mean <= self.params.haptic.f_trav;
                }
            }
            self.haptic.fuse(c, z);
        }
    }
}
