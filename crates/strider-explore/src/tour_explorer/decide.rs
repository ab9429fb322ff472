//! The planner's module (Prágr22 Alg. 1 lines 11–25): goals reached, the goal set, the tour and
//! the path to its first goal; and the gait choice of Alg. 4 at every control tick.

use super::{ReplanParts, TourExplorer};
use crate::kernel::{Actuators, Body, Termination, drop_visited, start_look_around};
use crate::planner::{
    CostMode, GoalKey, PlanningView, Tour, TourGoal, TourOrder, horizon, plan_tour, retain_sites,
    window_around,
};
use crate::timing::ms_since;
use std::borrow::Cow;
use std::time::Instant;
use strider_core::interface::MotionState;
use strider_core::{Cell, CellRect, GaitId};

impl TourExplorer {
    /// After a tour decision that planned no new tour: the planning view brought to the
    /// latest models (the gait choice reads it; a new tour has just rebuilt it).
    pub(super) fn catch_up_view(&mut self, body: &mut Body) {
        if self.behaviour.costs == CostMode::Learned
            && self.view_key.is_some_and(|k| k.1 != self.learn_generation)
        {
            body.map_mut().update_passability();
            let window = self.view_key.and_then(|k| k.3);
            self.refresh_view(body, CostMode::Learned, window);
        }
    }

    /// The planner's module at `tour_hz`: Alg. 1 lines 11–25. Returns the termination when
    /// the exploration is finished.
    pub(super) fn decide_tour(
        &mut self,
        body: &mut Body,
        robot: &mut dyn Actuators,
        t: f64,
        state: MotionState,
    ) -> Option<Termination> {
        let here = body.anchor_cell()?;
        if self.manoeuvre_runs(t, state) {
            return None;
        }
        let reached = self
            .current
            .is_some_and(|(_, site)| here.dist_cells(site) <= 1.5 || state.idle);
        if reached && self.act_on_reached_goal(body, robot, here, t) {
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
        self.replan(body, robot, here, t, &goals, reached)
    }

    /// True while a look-around or a sampling manoeuvre runs; one that ended drops the goal it
    /// was for.
    fn manoeuvre_runs(&mut self, t: f64, state: MotionState) -> bool {
        if let Some(m) = self.looking {
            if m.runs(t, state) {
                return true;
            }
            self.looking = None;
            self.current = None;
        }
        if let Some(s) = self.sampling {
            if s.walk.runs(t, state) {
                return true;
            }
            self.sampling = None;
            self.current = None;
        }
        false
    }

    /// The pursued goal was reached at `here`: a spatial goal is marked visited (and looked
    /// around from), a cost goal is sampled with its gait (lines 12–15). True when a manoeuvre
    /// started.
    fn act_on_reached_goal(
        &mut self,
        body: &Body,
        robot: &mut dyn Actuators,
        here: Cell,
        t: f64,
    ) -> bool {
        match self.current {
            Some((GoalKey::Spatial(c), _)) => {
                self.visited.push(c);
                let map = body.map();
                let r = 2.0 * map.params().r_robot / map.cell_size();
                drop_visited(&mut self.spatial, &[c], r);
                if self.params.look_around
                    && let Some(m) = start_look_around(body, robot, t)
                {
                    self.looking = Some(m);
                    return true;
                }
                self.current = None;
                false
            }
            Some((GoalKey::Cost { gait, .. }, site)) => {
                self.log.samplings[gait as usize] += 1;
                self.sampled.push((gait, site));
                self.sampled.push((gait, here));
                self.start_sampling(body, robot, t, GaitId(gait));
                true
            }
            None => false,
        }
    }

    /// A new tour over `goals` from `here` and the path to its first reachable goal (Alg. 1
    /// lines 16–20), logged; the exploration ends when nothing has been reachable for a
    /// learning period after both goal modules ran.
    fn replan(
        &mut self,
        body: &mut Body,
        robot: &mut dyn Actuators,
        here: Cell,
        t: f64,
        goals: &[TourGoal],
        reached: bool,
    ) -> Option<Termination> {
        let w = Instant::now();
        let mode = self.behaviour.costs;
        body.map_mut().update_passability();
        // A replan re-orders the goals behind the one being pursued rather than abandoning it.
        let commit = if reached || !self.params.commit_to_goal {
            None
        } else {
            self.committed_goal(body, goals)
        };
        let (near, near_commit, window) = self.horizon(body, here, goals, commit);
        let wv = Instant::now();
        self.refresh_view(body, mode, window);
        let mut view_ms = ms_since(wv);
        let (mut tour, mut path_found) =
            self.plan_and_follow(body, robot, here, &near, near_commit);
        let whole_map = !path_found && window.is_some();
        if whole_map {
            // Nothing reachable among the near goals within their window, perhaps only round
            // it or beyond the horizon: every goal on the whole map.
            let wv = Instant::now();
            self.refresh_view(body, mode, None);
            view_ms += ms_since(wv);
            (tour, path_found) = self.plan_and_follow(body, robot, here, goals, commit);
        }
        self.log_replan(ms_since(w), t, view_ms, tour.as_ref(), whole_map);
        if path_found {
            self.unreachable_since = None;
            return None;
        }
        self.current = None;
        robot.follow(&[]);
        // Nothing reachable: give the map and the models one learning period to change that,
        // then stop.
        let since = *self.unreachable_since.get_or_insert(t);
        (self.learned_once
            && self.spatial_once
            && t - since > 1.0 / self.params.rates.learning_hz + 1.0)
            .then_some(Termination::NoReachableGoals)
    }

    /// The tour over `goals` from `here` on the current view, with goal `commit` first, and
    /// the path to its first goal handed to the robot: the tour, and whether a path was found.
    fn plan_and_follow(
        &mut self,
        body: &Body,
        robot: &mut dyn Actuators,
        here: Cell,
        goals: &[TourGoal],
        commit: Option<usize>,
    ) -> (Option<Tour>, bool) {
        let view = self.view.take();
        // Plans start where the planning grid lets the centre be: the map may call the robot's
        // cell admissible while the view does not (the exploration bounds, unknown cells), e.g.
        // after a sampling manoeuvre walked to the edge of the bounds; from there every site
        // would look unreachable.
        let here = view
            .as_ref()
            .and_then(|v| body.nearest_in_anchor_disc(here, |c| v.grid.is_admissible(c)))
            .unwrap_or(here);
        let tour = view
            .as_ref()
            .and_then(|v| self.plan(v, here, goals, commit));
        self.last_tour = tour.as_ref().map_or_else(Vec::new, |t| t.order.clone());
        let path_found = match (&view, &tour) {
            (Some(v), Some(tour)) => self.follow_tour(v, body, robot, here, tour),
            _ => false,
        };
        self.view = view;
        (tour, path_found)
    }

    /// The goals of the tour's horizon from `here` ([`horizon`]; every goal for the greedy
    /// baseline or without a bound), the committed goal's index among them, and the window to
    /// plan them on (`None`: the whole map, when the horizon holds every goal).
    ///
    /// A bounded horizon takes its sites among those in the reachable set of the last spatial
    /// update only: a site outside it cannot be reached on any planning view (whose admissible
    /// cells are the map's, known and within bounds), and a horizon of such sites would leave
    /// the window's plan empty and send every replan to the whole map. Without any such site,
    /// every goal is planned on the whole map.
    fn horizon<'g>(
        &self,
        body: &Body,
        here: Cell,
        goals: &'g [TourGoal],
        commit: Option<usize>,
    ) -> (Cow<'g, [TourGoal]>, Option<usize>, Option<CellRect>) {
        let solver = &self.params.solver;
        let bound = solver.max_sites.filter(|_| !self.behaviour.cheapest_next);
        let total: usize = goals.iter().map(|g| g.sites.len()).sum();
        if bound.is_none_or(|b| total <= b) {
            return (Cow::Borrowed(goals), commit, None);
        }
        let (reachable, reachable_commit) = self.reachable_sites(goals, commit);
        if reachable.is_empty() {
            return (Cow::Borrowed(goals), commit, None);
        }
        let (near, near_commit) = horizon(&reachable, here, reachable_commit, bound);
        let near = near.into_owned();
        let margin = (solver.window_margin_m / body.map().cell_size()).ceil();
        let window = window_around(here, &near, margin.min(u32::MAX as f64) as u32);
        (Cow::Owned(near), near_commit, Some(window))
    }

    /// `goals` with only their sites in the reachable set of the last spatial update (goals
    /// left without one dropped), and the committed goal's index among them.
    fn reachable_sites(
        &self,
        goals: &[TourGoal],
        commit: Option<usize>,
    ) -> (Vec<TourGoal>, Option<usize>) {
        retain_sites(goals, commit, |_, _, s| self.reach.contains(s))
    }

    /// The tour over `goals` on `view` from `here`, with goal `commit` first.
    fn plan(
        &self,
        view: &PlanningView,
        here: Cell,
        goals: &[TourGoal],
        commit: Option<usize>,
    ) -> Option<Tour> {
        let order = if self.behaviour.cheapest_next {
            TourOrder::CheapestNext
        } else {
            TourOrder::Gtsp(&self.params.solver)
        };
        plan_tour(
            view,
            here,
            goals,
            order,
            self.params.seed,
            &self.last_tour,
            commit,
        )
    }

    /// Follows the path from `here` to the first goal of `tour` that has one; false when
    /// none has.
    fn follow_tour(
        &mut self,
        view: &PlanningView,
        body: &Body,
        robot: &mut dyn Actuators,
        here: Cell,
        tour: &Tour,
    ) -> bool {
        for &(key, site) in &tour.order {
            if let Some(path) = view.path(&mut self.dij, here, site) {
                let pts = match body.pose() {
                    Some(p) => view.drive_waypoints_from(&path, p.position.xy()),
                    None => view.drive_waypoints(&path),
                };
                robot.follow(&pts);
                self.current = Some((key, site));
                return true;
            }
        }
        false
    }

    /// Logs a replan of `ms` at robot time `t`.
    fn log_replan(&mut self, ms: f64, t: f64, view_ms: f64, tour: Option<&Tour>, whole_map: bool) {
        self.log.replan_ms.push(ms);
        self.log
            .goals_to_tour_ms
            .push(ms + self.goal_ms_since_replan.0 + self.goal_ms_since_replan.1);
        self.goal_ms_since_replan = (0.0, 0.0);
        self.log.replan_parts.push(ReplanParts {
            t,
            view_ms,
            all_pairs_ms: tour.map_or(0.0, |t| t.all_pairs_ms),
            gtsp_ms: tour.map_or(0.0, |t| t.gtsp_ms),
            vertices: tour.map_or(0, |t| t.vertices),
            whole_map,
            view_cells: self.view.as_ref().map_or(0, |v| v.rect().len()),
        });
    }

    /// Rebuilds the planning view over `window` (the whole map for `None`) unless the map
    /// (fused scans), the models (learning updates), the cost mode and the window are those it
    /// was built from.
    fn refresh_view(&mut self, body: &Body, mode: CostMode, window: Option<CellRect>) {
        let key = (body.map().scan_count(), self.learn_generation, mode, window);
        if self.view.is_some() && self.view_key == Some(key) {
            return;
        }
        let mut view = PlanningView::build_within(
            body.map(),
            &self.models,
            mode,
            self.params.c_loss,
            body.bounds(),
            window,
        );
        if let (Some(new), Some(old)) = (view.as_mut(), self.view.as_ref()) {
            new.keep_site_costs_of(old);
        }
        self.view = view;
        self.view_key = Some(key);
    }

    /// Alg. 4: the enforced gait, the stuck reflex's rough gait, or the best gait at the robot.
    pub(super) fn choose_gait(&mut self, body: &Body, t: f64) -> GaitId {
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
