//! The exploration strategies of `001` Alg. 1 with navigation by Alg. 4 on the mission kernel:
//! `gtsp` (spatial and cost-model goals ordered by an open GTSP tour), `greedy` (the same goals,
//! cheapest next) and `spatial-only` (spatial goals, reactive gait).
//!
//! Each module runs at its rate of `001` Tbl. 4 and sees only the latest outputs of the others,
//! as the processes on the robot do: mapping whenever a scan arrives (the kernel's body), cost
//! measurement on every pose (20 Hz), spatial goals at 0.33 Hz, learning and cost-goal
//! identification at 0.1 Hz, the tour and path at 1 Hz when the goal set changed or the current
//! goal was reached.
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

use crate::kernel::{
    Actuators, Body, BodyParams, Every, FromParams, GoalCounts, Manoeuvre, MissionError,
    Strategy as KernelStrategy, Termination, look_around, site,
};
use crate::params::{MissionParams, Strategy};
use crate::planner::{
    CostMode, GoalKey, PlanningView, TourGoal, TourOrder, farthest_point_subsample, plan_tour,
};
use rayon::prelude::*;
use std::collections::HashMap;
use std::time::Instant;
use strider_core::interface::MotionState;
use strider_core::snapshot::{
    GoalKind as SnapGoalKind, GoalSet, MeasuredCost, ModelLayer, Quantity, Snapshot,
};
use strider_core::{Cell, GaitId, Point2, PoseStamped};
use strider_learn::cost_model::{CostGoal, GaitCostModel, ModelUpdate};
use strider_learn::descriptor_field::DescriptorField;
use strider_learn::signals::{FallbackTimer, InverseVelocityCost, TurningTime};
use strider_map::descriptors::{TA_BINS, color_histograms};
use strider_map::information_gain::GainCache;
use strider_map::reachability::Reachability;
use strider_map::{SpatialGoal, cluster_information};
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

/// What a `001` exploration did, beyond the kernel's [`RunRecord`](crate::kernel::RunRecord).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct MissionLog {
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

/// The sampling manoeuvre in progress (decision 24).
#[derive(Clone, Copy, Debug)]
struct Sampling {
    gait: GaitId,
    until: f64,
}

/// What distinguishes the three `001` strategies, decided once from the planner.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Behaviour {
    /// Cost-model goals are pursued, and the exploration ends only once every model has a
    /// regressor.
    cost_goals: bool,
    /// Planning costs.
    costs: CostMode,
    /// The gait is chosen by Alg. 4 on the learned costs (else the fastest, reactively).
    learned_gait: bool,
    /// The cheapest goal next instead of the GTSP tour.
    cheapest_next: bool,
}

impl Behaviour {
    fn of(planner: Strategy) -> Self {
        let learned = Self {
            cost_goals: true,
            costs: CostMode::Learned,
            learned_gait: true,
            cheapest_next: false,
        };
        match planner {
            Strategy::Gtsp => learned,
            Strategy::Greedy => Self {
                cheapest_next: true,
                ..learned
            },
            Strategy::SpatialOnly => Self {
                cost_goals: false,
                costs: CostMode::Flat,
                learned_gait: false,
                cheapest_next: false,
            },
        }
    }
}

/// The module timers of `001` Tbl. 4.
#[derive(Clone, Copy, Debug)]
struct Modules {
    spatial: Every,
    learning: Every,
    tour: Every,
}

/// The `001` explorer's state: the per-gait models and the navigation state (the map is the
/// kernel's body).
pub struct TourExplorer {
    params: MissionParams,
    behaviour: Behaviour,
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
    moving: bool,
    learned_once: bool,
    spatial_once: bool,
    log: MissionLog,
    unreachable_since: Option<f64>,
    /// Time spent turning over the stuck test's window and over a cost sample's support.
    turns: TurningTime,
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
    /// The look-around in progress.
    looking: Option<Manoeuvre>,
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
    /// Module timers, set when the mission starts.
    modules: Option<Modules>,
}

impl TourExplorer {
    /// An explorer with untrained models.
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
        Ok(Self {
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
            // Start with the fastest gait.
            gait: params.fastest_gait(),
            moving: false,
            learned_once: false,
            spatial_once: false,
            log: MissionLog {
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
            unreachable_since: None,
            turns,
            visited: Vec::new(),
            sampled: Vec::new(),
            gain: GainCache::new(GAIN_DZ),
            last_tour: Vec::new(),
            updates: vec![ModelUpdate::default(); n],
            looking: None,
            view: None,
            view_key: None,
            spatial_key: None,
            goal_ms_since_replan: (0.0, 0.0),
            learn_generation: 0,
            modules: None,
            behaviour: Behaviour::of(params.strategy),
            params,
        })
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

    /// The gait the explorer commands.
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

    /// Measurement every tick: the cost signal restarts when the robot stands, and the stuck
    /// reflex (decision 9) fires only while it is commanded to move.
    fn measure_tick(&mut self, state: MotionState, t: f64) {
        if state.idle {
            self.signal.reset();
        }
        let stuck = !state.idle && reflex_stuck(&self.signal, &self.turns);
        let was = self.fallback.is_active(t);
        if self.fallback.update(t, stuck) && !was {
            self.log.stuck_events += 1;
        }
    }

    /// Learning and cost-goal identification when due.
    fn learning_tick(&mut self, body: &mut Body, m: &mut Modules, t: f64) {
        if m.learning.due(t) {
            let w = Instant::now();
            self.update_learning(body);
            self.log.phase_wall_s.learning += w.elapsed().as_secs_f64();
        }
    }

    /// Alg. 2 lines 3–5: passability, information gain, spatial goals (Alg. 3).
    ///
    /// The goals are a function of the map, the anchor cell and the visited goals only; when
    /// none of them changed since the last run (no scan fused: a slow gait moves less than a
    /// keyframe step between runs) the previous goals stand and nothing is recomputed (nor
    /// logged as a goal-identification time).
    fn update_spatial(&mut self, body: &mut Body) {
        let w = Instant::now();
        body.map_mut().update_passability();
        let anchor = body.anchor_cell();
        let map = body.map();
        let key = (map.scan_count(), anchor, self.visited.len());
        if self.spatial_key == Some(key) {
            return;
        }
        self.spatial_key = Some(key);
        self.spatial.clear();
        if let Some(c) = anchor {
            let reach = Reachability::compute(map, c);
            let bounds = body.bounds();
            let gain = self.gain.compute(map, &reach, bounds);
            self.log.gain_evaluated += self.gain.last_evaluated();
            self.log.gain_updated += self.gain.last_updated();
            self.spatial = cluster_information(map, &gain, &reach, bounds);
            let r = 2.0 * map.params().r_robot / map.cell_size();
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
    fn update_learning(&mut self, body: &mut Body) {
        let w = Instant::now();
        body.map_mut().update_passability();
        let map = body.map();
        let Some(rect) = map.known_bounds() else {
            return;
        };
        let raster = color_histograms(map, rect, map.params().r_hist);
        self.desc = DescriptorField::from_raster(&raster);
        self.cost_goals.clear();
        // The gaits' models are independent: update them side by side.
        let desc = &self.desc;
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
    fn goals(&self, body: &Body) -> Vec<TourGoal> {
        let mut goals: Vec<TourGoal> = self
            .spatial
            .iter()
            .map(|s| TourGoal {
                key: GoalKey::Spatial(s.cell),
                sites: vec![s.cell],
            })
            .collect();
        if self.behaviour.cost_goals {
            let map = body.map();
            let r = 2.0 * map.params().r_robot / map.cell_size();
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
    fn committed_goal(&self, body: &Body, goals: &[TourGoal]) -> Option<usize> {
        let (key, site) = self.current?;
        if let Some(i) = goals.iter().position(|g| g.key == key) {
            return Some(i);
        }
        match key {
            GoalKey::Spatial(_) => {
                let map = body.map();
                let r = map.params().c_radius / map.cell_size();
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
    fn refresh_view(&mut self, body: &Body, mode: CostMode) {
        let key = (body.map().scan_count(), self.learn_generation, mode);
        if self.view.is_some() && self.view_key == Some(key) {
            return;
        }
        self.view = PlanningView::build(
            body.map(),
            &self.models,
            mode,
            self.params.c_loss,
            body.bounds(),
        );
        self.view_key = Some(key);
    }

    /// The planner's module at `tour_hz`: Alg. 1 lines 11–25, then, when no new tour was
    /// planned, the planning view brought to the latest models (the gait choice reads it; a
    /// new tour has just rebuilt it). Returns the termination when the exploration is finished.
    fn decide(
        &mut self,
        body: &mut Body,
        robot: &mut dyn Actuators,
        t: f64,
        state: MotionState,
    ) -> Option<Termination> {
        let end = self.decide_tour(body, robot, t, state);
        if end.is_none()
            && self.behaviour.costs == CostMode::Learned
            && self.view_key.is_some_and(|k| k.1 != self.learn_generation)
        {
            body.map_mut().update_passability();
            self.refresh_view(body, CostMode::Learned);
        }
        end
    }

    /// Alg. 1 lines 11–25. Returns the termination when the exploration is finished.
    fn decide_tour(
        &mut self,
        body: &mut Body,
        robot: &mut dyn Actuators,
        t: f64,
        state: MotionState,
    ) -> Option<Termination> {
        let here = body.anchor_cell()?;
        // A look-around runs to its end.
        if let Some(m) = self.looking {
            if m.runs(t, state) {
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
            let map = body.map();
            let r = 2.0 * map.params().r_robot / map.cell_size();
            self.spatial.retain(|g| g.cell.dist_cells(c) > r);
            if self.params.look_around && !body.sees_all_around() {
                self.start_look_around(body, robot, t);
                return None;
            }
            self.current = None;
        }
        if reached && let Some((GoalKey::Cost { gait, .. }, site)) = self.current {
            // Lines 12–15: sample the reached cost goal with its gait.
            self.log.samplings[gait as usize] += 1;
            self.sampled.push((gait, site));
            self.sampled.push((gait, here));
            self.start_sampling(body, robot, t, GaitId(gait));
            return None;
        }
        let goals = self.goals(body);
        let mut keys: Vec<GoalKey> = goals.iter().map(|g| g.key).collect();
        keys.sort_unstable();
        let changed = keys != self.goal_keys;
        if goals.is_empty() && self.learned_once && self.spatial_once {
            // Alg. 1 lines 21–24: no spatial goal and every model has a regressor and no goal.
            let models_done =
                !self.behaviour.cost_goals || self.models.iter().all(|m| m.has_regressor());
            if models_done {
                return Some(Termination::GoalsCleared);
            }
        }
        if !(changed || reached || self.current.is_none() || state.blocked) {
            return None;
        }
        self.goal_keys = keys;
        let w = Instant::now();
        let mode = self.behaviour.costs;
        body.map_mut().update_passability();
        let wv = Instant::now();
        self.refresh_view(body, mode);
        let view_ms = wv.elapsed().as_secs_f64() * 1e3;
        // A replan re-orders the goals behind the one being pursued rather than abandoning it.
        let commit = if reached || !self.params.commit_to_goal {
            None
        } else {
            self.committed_goal(body, &goals)
        };
        let view = self.view.take();
        // Plans start where the planning grid lets the centre be: the map may call the robot's
        // cell admissible while the view does not (the exploration bounds, unknown cells), e.g.
        // after a sampling manoeuvre walked to the edge of the bounds; from there every site
        // would look unreachable.
        let here = view
            .as_ref()
            .and_then(|v| body.nearest_in_anchor_disc(here, |c| v.grid.is_admissible(c)))
            .unwrap_or(here);
        let tour = view.as_ref().and_then(|v| {
            plan_tour(
                v,
                here,
                &goals,
                if self.behaviour.cheapest_next {
                    TourOrder::CheapestNext
                } else {
                    TourOrder::Gtsp(&self.params.solver)
                },
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
                    let pts = match body.pose() {
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

    /// At a reached spatial goal the robot turns once on the spot ([`look_around`]).
    fn start_look_around(&mut self, body: &Body, robot: &mut dyn Actuators, t: f64) {
        let Some(p) = body.pose() else { return };
        robot.follow(&look_around(&p, body.map().cell_size()));
        self.looking = Some(Manoeuvre {
            until: t + crate::kernel::manoeuvres::LOOK_AROUND_S,
        });
    }

    /// Decision 24: enforce `gait` and walk straight ahead (or the most open direction when
    /// the heading is blocked) for Δt_sample over cells where the centre may be.
    fn start_sampling(&mut self, body: &Body, robot: &mut dyn Actuators, t: f64, gait: GaitId) {
        let Some(p) = body.pose() else { return };
        let d = body.map().cell_size();
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
                if !self.centre_may_be(body, q) {
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
    fn centre_may_be(&self, body: &Body, q: Point2) -> bool {
        let map = body.map();
        match (&self.view, map.cell_at(q.x, q.y)) {
            (Some(v), Some(c)) => v.grid.is_admissible(c),
            _ => map.is_admissible_at(q.x, q.y),
        }
    }

    /// Alg. 4: the enforced gait, the stuck reflex's rough gait, or the best gait at the robot.
    fn choose_gait(&mut self, body: &Body, t: f64) -> GaitId {
        if let Some(s) = self.sampling {
            return s.gait;
        }
        if self.fallback.is_active(t) {
            return self.params.rough_gait();
        }
        if !self.behaviour.learned_gait {
            // Reactive: the fastest gait unless stuck.
            return self.params.fastest_gait();
        }
        let Some(here) = body.anchor_cell() else {
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

impl FromParams for TourExplorer {
    type Params = MissionParams;

    /// The kernel's body parameters for this explorer's mission.
    fn body_params(params: &MissionParams) -> BodyParams {
        BodyParams {
            map: crate::kernel::lattice_map_params(&params.map, params.info_gain_spacing_m),
            sensor_hfov_deg: params.sensor_hfov_deg.clone(),
            bounds: params.bounds,
            time_limit_s: params.time_limit_s,
        }
    }

    fn from_params(params: MissionParams) -> Result<Self, MissionError> {
        Self::new(params)
    }
}

impl KernelStrategy for TourExplorer {
    fn name(&self) -> &'static str {
        self.params.strategy.name()
    }

    fn control_hz(&self) -> f64 {
        self.params.rates.control_hz
    }

    fn initial_gait(&self) -> Option<GaitId> {
        Some(self.gait)
    }

    fn start(&mut self, _body: &mut Body, t0: f64) {
        let r = self.params.rates;
        self.modules = Some(Modules {
            spatial: Every::new(r.spatial_hz, t0),
            learning: Every::new(r.learning_hz, t0),
            tour: Every::new(r.tour_hz, t0),
        });
    }

    fn before_advance(&mut self, _body: &Body, state: MotionState, _t: f64) {
        self.moving = !state.idle;
    }

    fn on_pose(&mut self, body: &Body, pose: &PoseStamped) {
        self.turns.push(pose.stamp, pose.yaw);
        if !self.moving {
            return;
        }
        let sample = self.signal.push(pose, pose.gait);
        if sample.is_some() && !self.params.stuck_samples && self.signal.is_stuck() {
            // A window that finds the robot stuck is left out when the strategy asks so.
            return;
        }
        if sample.is_some() && self.turns.in_support() > 0.0 {
            // The robot spent part of the window turning: that time is the path's, not the
            // terrain's.
            self.log.turn_skipped += 1;
            return;
        }
        if let Some(s) = sample
            && let Some(cell) = body.map().cell_at(s.position.x, s.position.y)
            && let Some(m) = self.models.get_mut(s.gait.0 as usize)
            && let Ok(ins) = m.insert_measurement(cell, s.cost, &self.desc)
            && ins == strider_learn::cost_model::Insertion::Stored
        {
            self.log.cost_samples[s.gait.0 as usize] += 1;
        }
    }

    fn tick(
        &mut self,
        body: &mut Body,
        robot: &mut dyn Actuators,
        state: &mut MotionState,
        t: f64,
    ) -> Option<Termination> {
        let mut m = self.modules?;
        self.measure_tick(*state, t);
        if m.spatial.due(t) {
            let w = Instant::now();
            self.update_spatial(body);
            self.log.phase_wall_s.spatial += w.elapsed().as_secs_f64();
        }
        self.learning_tick(body, &mut m, t);
        if m.tour.is_due(t) || state.idle || state.blocked {
            let w = Instant::now();
            let end = self.decide(body, robot, t, *state);
            self.log.phase_wall_s.planning += w.elapsed().as_secs_f64();
            if end.is_some() {
                self.modules = Some(m);
                return end;
            }
            m.tour.ran(t);
            state.idle = false;
        }
        self.modules = Some(m);
        let w = Instant::now();
        let g = self.choose_gait(body, t);
        self.log.phase_wall_s.gait += w.elapsed().as_secs_f64();
        if g != self.gait {
            self.gait = g;
            robot.set_gait(g);
        }
        None
    }

    /// The mapping, cost measurement and learning of a live mission, tick by tick; the gait in
    /// use arrives with each pose.
    fn ingest_tick(&mut self, body: &mut Body, state: &mut MotionState, t: f64) {
        let Some(mut m) = self.modules else { return };
        self.measure_tick(*state, t);
        self.learning_tick(body, &mut m, t);
        if m.tour.is_due(t) || state.idle || state.blocked {
            // The planner's slot of a live mission: nothing to plan, but the motion state is
            // treated as a live mission treats it after a decision.
            m.tour.ran(t);
            state.idle = false;
        }
        self.modules = Some(m);
    }

    fn finish(&mut self, body: &mut Body, _t: f64) {
        self.log.phase_wall_s.robot = body.robot_wall_s();
        self.log.phase_wall_s.mapping = body.mapping_wall_s();
    }

    fn describe(&self, body: &Body, snap: &mut Snapshot) {
        snap.goals.push(GoalSet {
            name: "spatial_goals".into(),
            kind: SnapGoalKind::Spatial,
            sites: self.spatial.iter().map(|g| site(body, g.cell)).collect(),
        });
        for (g, spec) in self.params.gaits.iter().enumerate() {
            let sites = self
                .cost_goals
                .iter()
                .filter(|(gg, _)| *gg as usize == g)
                .flat_map(|(_, goal)| goal.sites.iter())
                .map(|&c| site(body, c))
                .collect();
            snap.goals.push(GoalSet {
                name: format!("cost_goals_{}", spec.name),
                kind: SnapGoalKind::Cost { model: g },
                sites,
            });
        }
        snap.tour = self.last_tour.iter().map(|&(_, c)| site(body, c)).collect();
        let Some(layers) = snap.layers.as_mut() else {
            return;
        };
        let rect = layers.rect;
        for (g, md) in self.models.iter().enumerate() {
            let plan = md.planning_costs(rect);
            let class_var: HashMap<u32, f64> = self.updates[g]
                .classes
                .iter()
                .map(|c| (c.id.0, c.variance))
                .collect();
            let mut layer = ModelLayer {
                name: self.params.gaits[g].name.clone(),
                quantity: Quantity::InverseVelocity {
                    v_max: self.params.v_max(),
                    c_high: self.params.c_high,
                },
                gait: Some(GaitId(g as u8)),
                cost: Vec::with_capacity(rect.len()),
                variance: Vec::with_capacity(rect.len()),
                measured: Vec::with_capacity(rect.len()),
            };
            for (k, c) in rect.cells().enumerate() {
                let v = md
                    .planning_class(c)
                    .and_then(|t| class_var.get(&t.0).copied())
                    .map_or(f32::NAN, |v| v as f32);
                let cost = if layers.observed[k] {
                    plan[k]
                } else {
                    f32::NAN
                };
                layer.cost.push(cost);
                layer.variance.push(v);
                layer
                    .measured
                    .push(md.cell_cost(c).map_or(f32::NAN, |cc| cc.cost as f32));
            }
            layers.models.push(layer);
            for &c in md.measured_cells() {
                if let Some(cc) = md.cell_cost(c) {
                    snap.measured.push(MeasuredCost {
                        at: site(body, c),
                        cost: cc.cost,
                        model: g,
                    });
                }
            }
        }
    }

    fn goal_counts(&self) -> GoalCounts {
        GoalCounts {
            spatial_goals: self.spatial.len(),
            cost_goals: self.cost_goals.len(),
            learning_set: self.models.iter().map(|m| m.learning_set_len()).sum(),
        }
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
