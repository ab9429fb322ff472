//! The bumper in the loop: contacts fused into the haptic model (Prágr23 §4.2), the push at a
//! pushable obstacle ahead and the reflexes that follow it (§5.1).

use super::EscapeMission;
use super::contact::{ContactAcc, corridor_cells};
use super::goals::GoalKind;
use super::reflexes::{ReflexAction, ReflexInput};
use crate::kernel::{Actuators, Body};
use strider_core::interface::MotionState;
use strider_core::{Cell, Point2, Pose2, Proprioception};

impl EscapeMission {
    /// The bumper stream: filtered, then fused into the apparent obstacle cells the bumper
    /// touches (Prágr23 §4.2).
    pub(super) fn feel_bumper(&mut self, body: &Body, p: &Proprioception) {
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
        self.contact
            .get_or_insert_with(|| ContactAcc::new(p.stamp))
            .touch(
                p.stamp,
                &cells,
                self.view.as_ref(),
                self.params.haptic.f_trav,
            );
        for &(c, _) in &cells {
            self.haptic.fuse(c, z);
        }
    }

    /// Ends the open contact when the bumper has been quiet for a second (or `force`).
    pub(super) fn close_contact(&mut self, body: &Body, t: f64, force: bool) {
        let Some(acc) = &self.contact else { return };
        if !force && t - acc.last <= 1.0 {
            return;
        }
        let Some(acc) = self.contact.take() else {
            return;
        };
        let event = acc.close(
            &self.haptic,
            body.map().cell_size(),
            self.t0,
            self.params.haptic.f_trav,
        );
        self.log.contacts.push(event);
    }

    /// Walks straight at the nearest pushable obstacle cell ahead, if any, when the robot
    /// learns; true when the push started.
    pub(super) fn start_push(&mut self, body: &Body, robot: &mut dyn Actuators, t: f64) -> bool {
        if !self.learns() {
            return false;
        }
        let (Some(pose), Some(target)) = (self.robot_pose(body), self.pushable_ahead(body)) else {
            return false;
        };
        let yaw = (target.y - pose.y).atan2(target.x - pose.x);
        robot.follow(&self.reflex.start_push(t, Pose2::new(pose.x, pose.y, yaw)));
        self.log.pushes += 1;
        true
    }

    /// Steps the running reflex; true when it finished.
    pub(super) fn run_reflex(
        &mut self,
        body: &Body,
        robot: &mut dyn Actuators,
        t: f64,
        state: MotionState,
    ) -> bool {
        let Some(pose) = self.robot_pose(body) else {
            return false;
        };
        let near = !self.approach_corridor(body).is_empty() || self.contact.is_some();
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
                self.reflex_finished(body, pose);
                true
            }
        }
    }

    /// An obstacle goal is done once the reflex has run on it; a spatial goal is chosen
    /// afresh (the robot stopping here has not reached it), unless the robot stands within
    /// 2·r_robot of it: a spatial goal on a pushable obstacle is reached by pushing into it.
    fn reflex_finished(&mut self, body: &Body, pose: Pose2) {
        let Some(g) = self.current else { return };
        if g.kind != GoalKind::Spatial && self.haptic.get(g.cell).is_none() {
            self.failed.push(g.cell);
        }
        let r = 2.0 * self.params.view.r_robot;
        if g.kind == GoalKind::Spatial
            && pose.position().dist(g.cell.center(body.map().cell_size())) <= r
        {
            self.visited.push(g.cell);
        }
        self.current = None;
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

    /// The radius around an obstacle goal that its approach may enter, cells: the robot's
    /// radius plus the bumper's half width.
    pub(super) fn clear_radius_cells(&self, body: &Body) -> f64 {
        (self.params.view.r_robot + self.params.reflex.bumper_half_width) / body.map().cell_size()
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
}
