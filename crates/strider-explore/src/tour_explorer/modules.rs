//! The spatial and learning modules at their rates: spatial goals (Alg. 3 on Eq. 11) and the
//! per-gait model updates with their cost goals (Alg. 6).

use super::{Modules, TourExplorer};
use crate::kernel::{Body, drop_visited};
use crate::timing::ms_since;
use rayon::prelude::*;
use std::time::Instant;
use strider_map::cluster_information;

impl TourExplorer {
    /// Learning and cost-goal identification when due.
    pub(super) fn learning_tick(&mut self, body: &mut Body, m: &mut Modules, t: f64) {
        if m.learning.due(t) {
            let w = Instant::now();
            let before = self.log.learning_ms.len();
            self.update_learning(body);
            if self.log.learning_ms.len() > before {
                self.log.learning_at_s.push(t);
            }
            self.log.phase_wall_s.learning += w.elapsed().as_secs_f64();
        }
    }

    /// Alg. 2 lines 3–5: passability, information gain, spatial goals (Alg. 3).
    ///
    /// The goals are a function of the map, the anchor cell and the visited goals only; when
    /// none of them changed since the last run (no scan fused: a slow gait moves less than a
    /// keyframe step between runs) the previous goals stand and nothing is recomputed (nor
    /// logged as a goal-identification time).
    pub(super) fn update_spatial(&mut self, body: &mut Body) {
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
            self.reach.follow(map, c);
            let reach = &self.reach;
            let bounds = body.bounds();
            let gain = self.gain.compute(map, reach, bounds);
            self.log.gain_evaluated += self.gain.last_evaluated();
            self.log.gain_updated += self.gain.last_updated();
            self.spatial = cluster_information(map, &gain, reach, bounds);
            let r = 2.0 * map.params().r_robot / map.cell_size();
            drop_visited(&mut self.spatial, &self.visited, r);
            self.spatial_once = true;
        }
        let ms = ms_since(w);
        self.log.spatial_goal_ms.push(ms);
        self.goal_ms_since_replan.0 = ms;
    }

    /// Alg. 6 for every gait: descriptors, then each model's update.
    fn update_learning(&mut self, body: &mut Body) {
        let w = Instant::now();
        body.map_mut().update_passability();
        let map = body.map();
        // Only the histograms the map's changes can have touched are recomputed; the field
        // equals a full computation over the known bounds.
        if self
            .desc
            .follow_color_histograms(map, &mut self.desc_revision)
            .is_none()
        {
            return;
        }
        self.cost_goals.clear();
        // The gaits' models are independent: update them side by side.
        let desc = &self.desc;
        let updates: Vec<_> = self
            .models
            .par_iter_mut()
            .map(|m| m.update(map, desc))
            .collect();
        // Every model has read the field's change logs up to now: they need not keep them.
        self.desc.forget_changes();
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
        let ms = ms_since(w);
        self.log.learning_ms.push(ms);
        self.goal_ms_since_replan.1 = ms;
    }
}
