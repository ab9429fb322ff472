//! Cost measurement (the inverse-velocity signal on every pose) and the stuck reflex
//! (decision 9).

use super::TourExplorer;
use super::stuck::reflex_stuck;
use crate::kernel::Body;
use strider_core::PoseStamped;
use strider_core::interface::MotionState;
use strider_learn::cost_model::Insertion;

impl TourExplorer {
    /// Measurement every tick: the cost signal restarts when the robot stands, and the stuck
    /// reflex (decision 9) fires only while it is commanded to move.
    pub(super) fn measure_tick(&mut self, state: MotionState, t: f64) {
        if state.idle {
            self.signal.reset();
        }
        let stuck = !state.idle && reflex_stuck(&self.signal, &self.turns);
        let was = self.fallback.is_active(t);
        if self.fallback.update(t, stuck) && !was {
            self.log.stuck_events += 1;
        }
    }

    /// A pose into the turning time and, while the robot moves, into the cost signal; a
    /// finished cost sample is stored in its gait's model unless the robot turned within its
    /// support (or was stuck over it and the strategy leaves such windows out).
    pub(super) fn measure_pose(&mut self, body: &Body, pose: &PoseStamped) {
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
            && ins == Insertion::Stored
        {
            self.log.cost_samples[s.gait.0 as usize] += 1;
        }
    }
}
