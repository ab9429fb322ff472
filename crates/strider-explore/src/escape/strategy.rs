//! The escape mission on the kernel: its body, its control tick and its part of a snapshot.

use super::goals::GoalKind;
use super::view::ObstacleState;
use super::{EscapeMission, EscapeParams, Modules};
use crate::kernel::{
    Actuators, Body, BodyParams, Every, FromParams, GoalCounts, MissionError, Strategy,
    Termination, lattice_map_params, site, spatial_goal_set,
};
use strider_core::Proprioception;
use strider_core::interface::MotionState;
use strider_core::snapshot::{
    GoalKind as SnapGoalKind, GoalSet, MeasuredCost, ModelLayer, Quantity, Snapshot,
};

impl FromParams for EscapeMission {
    type Params = EscapeParams;

    /// The kernel's body parameters for this mission: Eq. 8 on a stride lattice as in the
    /// Prágr22 mission (decision 5), each candidate standing for stride² cells in the minimum
    /// cluster size.
    fn body_params(params: &EscapeParams) -> BodyParams {
        BodyParams::new(
            lattice_map_params(&params.map, params.info_gain_spacing_m),
            &params.sensor_hfov_deg,
            params.bounds,
            params.time_limit_s,
        )
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
        if !state.idle && self.start_push(body, robot, t) {
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
        snap.goals.push(spatial_goal_set(body, &self.spatial));
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
        let mut layer = ModelLayer::unknown("force", Quantity::PushForce, None, n);
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

    fn on_proprioception(&mut self, body: &Body, p: &Proprioception) {
        self.feel_bumper(body, p);
    }
}
