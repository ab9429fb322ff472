//! Goal choice and the path to it (Prágr23 Alg. 2 lines 11–24): the current goal reached or
//! given up, the next goal by the rules of [`select_goal`], and its path on the planning grid.

use super::EscapeMission;
use super::goals::{Goal, GoalInputs, GoalKind, select_goal};
use super::log::GoalEvent;
use super::view::TravView;
use crate::kernel::{Actuators, Body, Termination, drop_visited, start_look_around};
use strider_core::interface::MotionState;
use strider_core::{Cell, Point2};
use strider_plan::grid::{Dijkstra, smooth_path};

impl EscapeMission {
    /// The cell plans start from: the robot's cell when it is a goal cell of the view, else the
    /// nearest such cell within 3·r_robot, else the nearest admissible one.
    pub(super) fn anchor(&self, body: &Body) -> Option<Cell> {
        let view = self.view.as_ref()?;
        let ok = |c: Cell| view.is_goal_cell(c);
        let adm = |c: Cell| view.rect.index(c).is_some_and(|k| view.admissible[k]);
        body.nearest_within_anchor_disc(ok)
            .or_else(|| body.nearest_within_anchor_disc(adm))
    }

    /// Alg. 2 lines 11–24 for the current state; `Some` ends the exploration.
    pub(super) fn decide(
        &mut self,
        body: &Body,
        robot: &mut dyn Actuators,
        t: f64,
        state: MotionState,
    ) -> Option<Termination> {
        let anchor = self.anchor(body)?;
        if self.check_current_goal(body, robot, anchor, t, state) {
            return None;
        }
        let view = self.view.as_ref()?;
        if self.dij.run(&view.grid, anchor).is_err() {
            return None;
        }
        let Some(goal) = select_goal(view, &self.goal_inputs(body)) else {
            robot.follow(&[]);
            self.current = None;
            let since = *self.no_goal_since.get_or_insert(t);
            return (t - since >= self.params.no_goal_grace_s).then_some(Termination::GoalsCleared);
        };
        self.no_goal_since = None;
        if self.keeps_path(body, goal, state) {
            return None;
        }
        let d = body.map().cell_size();
        let clear_r = self.clear_radius_cells(body) * d;
        let Some(path) = goal_path(&mut self.dij, view, anchor, goal, clear_r) else {
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

    /// Drops the current goal once reached: a spatial goal within 1.5 cells of the anchor or at
    /// the end of its path (then visited, and looked around from), an obstacle goal once
    /// measured or at the end of its path (failed when not measured). True when a
    /// look-around started.
    fn check_current_goal(
        &mut self,
        body: &Body,
        robot: &mut dyn Actuators,
        anchor: Cell,
        t: f64,
        state: MotionState,
    ) -> bool {
        let Some(g) = self.current else { return false };
        if g.kind != GoalKind::Spatial {
            let measured = self.haptic.get(g.cell).is_some();
            if measured || state.idle {
                if !measured {
                    self.failed.push(g.cell);
                }
                self.current = None;
            }
            return false;
        }
        if !(anchor.dist_cells(g.cell) <= 1.5 || state.idle) {
            return false;
        }
        self.visited.push(g.cell);
        let r = 2.0 * self.params.view.r_robot / body.map().cell_size();
        drop_visited(&mut self.spatial, &[g.cell], r);
        self.current = None;
        if let Some(m) = start_look_around(body, robot, t) {
            self.looking = Some(m);
            return true;
        }
        false
    }

    /// What goal selection reads, on the distances of the latest search from the anchor.
    fn goal_inputs(&self, body: &Body) -> GoalInputs<'_> {
        let d = body.map().cell_size();
        GoalInputs {
            dist: self.dij.distances(),
            spatial: &self.spatial,
            learn: self.learns(),
            predictor_learned: self.predictor.is_learned(),
            entropy_threshold: self.params.predictor.entropy_threshold,
            r_robot: self.params.view.r_robot,
            reach: 2.0 * d,
            excluded: &self.failed,
            exclusion_cells: self.params.exclusion_m / d,
            bounds: self.params.bounds.as_ref(),
        }
    }

    /// The same goal (a spatial goal's representative drifts by a few cells as the map grows)
    /// while the robot moves keeps the path already commanded, so a robot turning on the spot
    /// is not re-commanded at every view update.
    fn keeps_path(&self, body: &Body, goal: Goal, state: MotionState) -> bool {
        self.current.is_some_and(|g| {
            g.kind == goal.kind
                && g.cell.dist_cells(goal.cell) <= self.params.same_goal_m / body.map().cell_size()
        }) && !state.idle
            && !state.blocked
    }
}

/// The smoothed path from `anchor` to `goal`: on the planning grid searched from the anchor
/// for a spatial goal; for an obstacle goal on the grid with the disc of radius `clear_r`
/// around it cleared (Prágr23 §4.5).
fn goal_path(
    dij: &mut Dijkstra,
    view: &TravView,
    anchor: Cell,
    goal: Goal,
    clear_r: f64,
) -> Option<Vec<Cell>> {
    if goal.kind == GoalKind::Spatial {
        return dij.path_to(goal.cell).map(|p| smooth_path(&view.grid, &p));
    }
    let g = view.cleared_grid(goal.cell, clear_r)?;
    let cost = dij.astar(&g, anchor, goal.cell).ok()?;
    if !cost.is_finite() {
        return None;
    }
    dij.path_to(goal.cell).map(|p| smooth_path(&g, &p))
}
