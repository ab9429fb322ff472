//! The explorer on the kernel: its body, the roll stream, the planning cycle's schedule and its
//! part of a snapshot.

use super::goals::GoalKind;
use super::{RbcmGreedy, RbcmGreedyParams};
use crate::kernel::{
    Actuators, Body, BodyParams, Every, FromParams, GoalCounts, MissionError, Strategy,
    Termination, site_at,
};
use strider_core::interface::MotionState;
use strider_core::snapshot::{
    GoalKind as SnapGoalKind, GoalSet, MeasuredCost, ModelLayer, Quantity, Snapshot,
};
use strider_core::{GaitId, Point2, PoseStamped, Proprioception};

impl FromParams for RbcmGreedy {
    type Params = RbcmGreedyParams;

    /// The kernel's body parameters for this explorer's mission.
    fn body_params(params: &RbcmGreedyParams) -> BodyParams {
        BodyParams::new(
            params.map.clone(),
            &params.sensor_hfov_deg,
            params.bounds,
            params.time_limit_s,
        )
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
        self.feel_roll(body, p);
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
            if let Some(end) = self.plan(body, robot, t, state.idle) {
                return Some(end);
            }
            state.idle = false;
            state.blocked = false;
        }
        None
    }

    fn describe(&self, body: &Body, snap: &mut Snapshot) {
        let map = body.map();
        let at = |p: Point2| site_at(body, p);
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
        let mut layer =
            ModelLayer::unknown("rbcm", Quantity::RollVariance, Some(self.params.gait), n);
        for (k, c) in layers.rect.cells().enumerate() {
            let m = cm
                .cell_at(c.center(cell_size))
                .and_then(|m| cm.rect.index(m));
            let (mu, sd) = m.map_or((f64::NAN, f64::NAN), |m| (cm.mean[m], cm.std[m]));
            layer.cost[k] = mu as f32;
            layer.variance[k] = (sd * sd) as f32;
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
