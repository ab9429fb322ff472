//! The explorer on the mission kernel: its body, its module timers and its control tick.

use super::{Modules, TourExplorer};
use crate::kernel::{
    Actuators, Body, BodyParams, Every, FromParams, GoalCounts, MissionError, Strategy,
    Termination, lattice_map_params,
};
use crate::params::MissionParams;
use std::time::Instant;
use strider_core::interface::MotionState;
use strider_core::snapshot::Snapshot;
use strider_core::{GaitId, PoseStamped};

impl FromParams for TourExplorer {
    type Params = MissionParams;

    /// The kernel's body parameters for this explorer's mission.
    fn body_params(params: &MissionParams) -> BodyParams {
        BodyParams::new(
            lattice_map_params(&params.map, params.info_gain_spacing_m),
            &params.sensor_hfov_deg,
            params.bounds,
            params.time_limit_s,
        )
    }

    fn from_params(params: MissionParams) -> Result<Self, MissionError> {
        Self::new(params)
    }
}

impl Strategy for TourExplorer {
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
        self.measure_pose(body, pose);
    }

    fn tick(
        &mut self,
        body: &mut Body,
        robot: &mut dyn Actuators,
        state: &mut MotionState,
        t: f64,
    ) -> Option<Termination> {
        let mut m = self.modules?;
        self.track_activity(body, *state, t);
        self.measure_tick(*state, t);
        if m.spatial.due(t) {
            let w = Instant::now();
            self.update_spatial(body);
            self.log.phase_wall_s.spatial += w.elapsed().as_secs_f64();
        }
        self.learning_tick(body, &mut m, t);
        if m.tour.is_due(t) || state.idle || state.blocked {
            let w = Instant::now();
            let end = self.decide_tour(body, robot, t, *state);
            if end.is_none() {
                self.catch_up_view(body);
            }
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
        self.describe_goals(body, snap);
        self.describe_models(body, snap);
    }

    fn goal_counts(&self) -> GoalCounts {
        GoalCounts {
            spatial_goals: self.spatial.len(),
            cost_goals: self.cost_goals.len(),
            learning_set: self.models.iter().map(|m| m.learning_set_len()).sum(),
        }
    }
}
