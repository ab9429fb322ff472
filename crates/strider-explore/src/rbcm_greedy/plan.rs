//! One planning cycle of Prágr19 Alg. 1 (lines 2–10): a reached goal's manoeuvre, Mtrv and
//! Mcost, the Eq. 14 search from the robot, the cost goal (Eq. 15) and the spatial goal
//! (Eq. 13), the decision rule Eq. 16 and the path to the goal; and the refusals and sampling
//! walks around it.

use super::carrot::carrot_waypoints;
use super::goals::{
    self, Goal, GoalKind, best_cost_goal, best_spatial_goal, frontier_representatives,
};
use super::log::PlanRecord;
use super::{MAX_REFUSALS_PER_GOAL, NO_CELL_TIMEOUT_S, RbcmGreedy};
use crate::kernel::{Actuators, Body, Manoeuvre, Termination, start_look_around};
use crate::timing::ms_since;
use std::time::Instant;
use strider_core::{Cell, Point2};
use strider_map::rect::WorldRect;
use strider_plan::grid::CostGrid;

impl RbcmGreedy {
    /// One cycle of Alg. 1 (lines 2–10) at `t`, `stopped` when the robot has finished its
    /// path; `Some` when the exploration ends.
    pub(super) fn plan(
        &mut self,
        body: &mut Body,
        robot: &mut dyn Actuators,
        t: f64,
        stopped: bool,
    ) -> Option<Termination> {
        let Some(pos) = body.position() else {
            return None; // no pose yet
        };
        if body.map().scan_count() == 0 {
            return None; // nothing seen yet: no frontier can exist
        }
        let Some(rc) = body.anchor_cell() else {
            return self.without_cell(t);
        };
        // A goal reached (or the path to it finished) first triggers its manoeuvre.
        if self.goal_reached(body, robot, t, pos, stopped) {
            return None;
        }
        let (trv_ms, inference_ms) = self.rebuild_cost_map(body, rc);
        let w = Instant::now();
        let traversable_cells = self.cost_map.traversable_count();
        let start = self
            .cost_map
            .cell_at(pos)
            .and_then(|c| self.cost_map.nearest_traversable(c, 3));
        let Some(start) = start else {
            return self.without_cell(t);
        };
        self.no_cell_since = None;
        let grid = self.planning_grid().ok()?;
        if self.search.run(&grid, start).is_err() {
            return None;
        }
        let (cost_goal, best_score) = self.cost_goal(t, body.bounds().copied());
        let reps = frontier_representatives(
            body.map(),
            &self.reach,
            rc,
            body.bounds(),
            &self.visited,
            2.0 * self.params.map.r_robot,
        );
        let spatial = best_spatial_goal(&self.cost_map, &self.search, &reps, 2);
        let goal = goals::select_goal(cost_goal, spatial, self.params.lambda_score); // Eq. 16
        let goals_ms = ms_since(w);
        let w = Instant::now();
        let waypoints = goal.and_then(|g| self.search.path_to(g.cell)).map(|cells| {
            carrot_waypoints(&cells, self.params.mcost_cell, self.params.carrot_m, pos)
        });
        let path_ms = ms_since(w);
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

    /// No traversable cell under the robot: the exploration ends once that has lasted
    /// [`NO_CELL_TIMEOUT_S`].
    fn without_cell(&mut self, t: f64) -> Option<Termination> {
        let since = *self.no_cell_since.get_or_insert(t);
        (t - since >= NO_CELL_TIMEOUT_S).then_some(Termination::NoReachableGoals)
    }

    /// The goal reached at `pos` (or the path to it finished, `stopped`): a cost goal is sampled, a
    /// spatial goal is visited and, with a limited field of view, looked around from. True
    /// when a manoeuvre started.
    fn goal_reached(
        &mut self,
        body: &Body,
        robot: &mut dyn Actuators,
        t: f64,
        pos: Point2,
        stopped: bool,
    ) -> bool {
        let Some(g) = self.goal else { return false };
        let near = (g.point.x - pos.x).hypot(g.point.y - pos.y) <= 1.5 * self.params.mcost_cell;
        if !(near || stopped) {
            return false;
        }
        self.goal = None;
        match g.kind {
            GoalKind::Cost => {
                self.log.cost_goals_reached += 1;
                self.reached_cost.push((t, g.point));
                self.start_sampling(body, robot, t, pos)
            }
            GoalKind::Spatial => {
                self.log.spatial_goals_reached += 1;
                self.visited.push(g.point);
                match start_look_around(body, robot, t) {
                    Some(m) => {
                        self.manoeuvre = Some(m);
                        true
                    }
                    None => false,
                }
            }
        }
    }

    /// Mtrv (passability, reachability from elevation-map cell `rc`) and Mcost without the
    /// refused cells; returns the wall times of the two parts, ms.
    pub(super) fn rebuild_cost_map(&mut self, body: &mut Body, rc: Cell) -> (f64, f64) {
        let w = Instant::now();
        body.map_mut().update_passability();
        self.reach.recompute(body.map(), rc);
        let trv_ms = ms_since(w);
        let w = Instant::now();
        self.cost_map = super::cost_map::CostMap::build(
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
        (trv_ms, ms_since(w))
    }

    /// The Eq. 14 search grid: μ clamped below at the smallest cost measured so far, uniform
    /// before the first measurement.
    fn planning_grid(&self) -> Result<CostGrid, strider_plan::grid::GridError> {
        let floor = if self.min_cost.is_finite() && self.min_cost > 0.0 {
            self.min_cost
        } else {
            1.0
        };
        CostGrid::new(
            self.cost_map.rect,
            self.params.mcost_cell,
            self.cost_map.planning_costs(floor),
        )
    }

    /// The reachable cell of highest Eq. 15 score and that score (none, NaN without a
    /// model); a cost goal just sampled is left alone until its windows are learned.
    fn cost_goal(&mut self, t: f64, bounds: Option<WorldRect>) -> (Option<Goal>, Option<f64>) {
        if !self.has_model() {
            return (None, None);
        }
        let mut scores = self.cost_map.scores(self.params.delta_score);
        let hold = 2.0 * self.params.window_s;
        let r_hold = 0.5 * self.params.delta_score;
        self.reached_cost.retain(|&(tr, _)| t - tr < hold);
        for (k, sc) in scores.iter_mut().enumerate() {
            let p = self.cost_map.rect.cell(k).center(self.params.mcost_cell);
            // Cost goals obey the exploration bounds as spatial goals do.
            if bounds.is_some_and(|b| !b.contains(p)) {
                *sc = f64::NAN;
                continue;
            }
            if self
                .reached_cost
                .iter()
                .any(|&(_, q)| (q.x - p.x).hypot(q.y - p.y) < r_hold)
            {
                *sc = f64::NAN;
            }
        }
        let g = best_cost_goal(&self.cost_map, &scores, &self.search);
        (g, g.map(|g| g.value))
    }

    /// Remembers the Mcost cell one cell ahead of the robot as refused (the motion judge would
    /// not let the robot go on; Mtrv's step threshold may exceed what the legs can climb).
    pub(super) fn refuse_ahead(&mut self, body: &Body) {
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
                self.manoeuvre = Some(Manoeuvre { until });
                true
            }
            _ => false,
        }
    }
}
