//! The modules of Prágr23 Alg. 2 at their rates: relearning the force predictor (line 5), the
//! traversability view with its spatial goals (lines 6–10), and the log's time series.

use super::EscapeMission;
use super::force_predictor::describe;
use super::log::TimelineSample;
use super::view::TravView;
use crate::kernel::{Body, drop_visited};
use strider_core::Cell;
use strider_map::information_gain::model_information;
use strider_map::rect::WorldRect;
use strider_map::{ElevationMap, InfoGain, Reachability, cluster_information, information_gain};

impl EscapeMission {
    /// Alg. 2 line 5: P ← learn({(A(ν), F(ν))}).
    pub(super) fn relearn(&mut self, body: &Body) {
        let samples: Vec<(Vec<f64>, f64)> = self
            .haptic
            .cells()
            .into_iter()
            .filter_map(|(c, h)| {
                describe(body.map(), c, self.predictor.params()).map(|d| (d, h.force))
            })
            .collect();
        if let Ok(n) = self.predictor.learn(&samples)
            && n > 0
        {
            self.log.relearns += 1;
        }
    }

    /// Alg. 2 lines 6–10: predictions applied, spatial goals.
    pub(super) fn update_view(&mut self, body: &mut Body) {
        body.map_mut().update_passability();
        let pred = self.learns().then_some(&self.predictor);
        self.view = TravView::build(
            body.map(),
            &self.haptic,
            pred,
            self.params.bounds.as_ref(),
            &self.params.view,
        );
        self.spatial.clear();
        let (Some(view), Some(anchor)) = (self.view.as_ref(), self.anchor(body)) else {
            return;
        };
        let map = body.map();
        let reach = Reachability::from_admissible(map, anchor, view.rect, &view.goal_admissible());
        let bounds = self.params.bounds.as_ref();
        let mut gain = information_gain(map, &reach, bounds);
        add_pushable_tops(&mut gain, view, map, &reach, bounds);
        self.spatial = cluster_information(map, &gain, &reach, bounds);
        let r = 2.0 * self.params.view.r_robot / map.cell_size();
        drop_visited(&mut self.spatial, &self.visited, r);
    }

    /// One sample of the log's time series at robot time `t`.
    pub(super) fn record(&mut self, body: &Body, t: f64) {
        let d = body.map().cell_size();
        let states = self
            .view
            .as_ref()
            .map(|v| v.cell_states(!self.learns()))
            .unwrap_or_default();
        self.log.timeline.push(TimelineSample {
            t: t - self.t0,
            explored_m2: body.map().observed_count() as f64 * d * d,
            states,
            haptic_cells: self.haptic.len(),
        });
    }
}

/// Alg. 2 line 7 computes I_geom on every traversable cell, apparent obstacles learnt to be
/// traversable included. The Eq. 8 lattice (every `stride` cells) can miss a curtain two cells
/// thick, and the top of a pushable obstacle is exactly where the robot can see past it: such
/// cells are evaluated on a lattice of two cells (which any obstacle two cells thick meets) in
/// addition to `gain`'s.
fn add_pushable_tops(
    gain: &mut InfoGain,
    view: &TravView,
    map: &ElevationMap,
    reach: &Reachability,
    bounds: Option<&WorldRect>,
) {
    let lattice = map.params().info_gain_stride.max(1) as i32;
    let extra: Vec<(Cell, f64)> = (0..view.rect.len())
        .filter(|&k| view.obstacle[k].is_some() && view.traversable[k])
        .map(|k| view.rect.cell(k))
        .filter(|c| {
            c.i.rem_euclid(2) == 0
                && c.j.rem_euclid(2) == 0
                && !(c.i.rem_euclid(lattice) == 0 && c.j.rem_euclid(lattice) == 0)
                && reach.is_goal_cell(*c)
        })
        .map(|c| (c, model_information(map, c, bounds)))
        .filter(|&(_, g)| g > 0.0)
        .collect();
    if !extra.is_empty() {
        gain.cells.extend(extra);
        gain.cells.sort_by_key(|&(c, _)| (c.j, c.i));
    }
}
