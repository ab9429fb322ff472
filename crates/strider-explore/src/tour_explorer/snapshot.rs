//! The explorer's part of a snapshot: its goals and tour, each gait model's layer and the
//! costs measured so far.

use super::TourExplorer;
use crate::kernel::{Body, site, spatial_goal_set};
use std::collections::HashMap;
use strider_core::GaitId;
use strider_core::snapshot::{
    GoalKind, GoalSet, Layers, MeasuredCost, ModelLayer, Quantity, Snapshot,
};
use strider_learn::cost_model::GaitCostModel;

impl TourExplorer {
    /// The spatial goals, each gait's cost goals and the tour.
    pub(super) fn describe_goals(&self, body: &Body, snap: &mut Snapshot) {
        snap.goals.push(spatial_goal_set(body, &self.spatial));
        for (g, spec) in self.params.gaits.iter().enumerate() {
            let sites = self
                .cost_goals
                .iter()
                .filter(|(gg, _)| *gg as usize == g)
                .flat_map(|(_, goal)| goal.sites.iter())
                .map(|&c| site(body, c))
                .collect();
            snap.goals.push(GoalSet {
                name: format!("cost_goals_{}", spec.name),
                kind: GoalKind::Cost { model: g },
                sites,
            });
        }
        snap.tour = self.last_tour.iter().map(|&(_, c)| site(body, c)).collect();
    }

    /// Each gait model's layer over `snap.layers` (when present) and its measured costs.
    pub(super) fn describe_models(&self, body: &Body, snap: &mut Snapshot) {
        let Some(layers) = snap.layers.as_mut() else {
            return;
        };
        for (g, md) in self.models.iter().enumerate() {
            layers.models.push(self.model_layer(g, md, layers));
            for &c in md.measured_cells() {
                if let Some(cc) = md.cell_cost(c) {
                    snap.measured.push(MeasuredCost {
                        at: site(body, c),
                        cost: cc.cost,
                        model: g,
                    });
                }
            }
        }
    }

    /// The layer of gait `g`'s model `md`: planning cost where observed, the variance of each
    /// cell's class, and the measured cost.
    fn model_layer(&self, g: usize, md: &GaitCostModel, layers: &Layers) -> ModelLayer {
        let rect = layers.rect;
        let plan = md.planning_costs(rect);
        let class_var: HashMap<u32, f64> = self.updates[g]
            .classes
            .iter()
            .map(|c| (c.id.0, c.variance))
            .collect();
        let n = rect.len();
        let (mut cost, mut variance) = (Vec::with_capacity(n), Vec::with_capacity(n));
        let (mut measured, mut classes) = (Vec::with_capacity(n), Vec::with_capacity(n));
        for (k, c) in rect.cells().enumerate() {
            let class = md.planning_class(c);
            classes.push(class.map_or(-1, |t| i32::try_from(t.0).unwrap_or(i32::MAX)));
            let v = class
                .and_then(|t| class_var.get(&t.0).copied())
                .map_or(f32::NAN, |v| v as f32);
            cost.push(if layers.observed[k] {
                plan[k]
            } else {
                f32::NAN
            });
            variance.push(v);
            measured.push(md.cell_cost(c).map_or(f32::NAN, |cc| cc.cost as f32));
        }
        ModelLayer {
            name: self.params.gaits[g].name.clone(),
            quantity: Quantity::InverseVelocity {
                v_max: self.params.v_max(),
                c_high: self.params.c_high,
            },
            gait: Some(GaitId(g as u8)),
            cost,
            variance,
            measured,
            classes: Some(classes),
        }
    }
}
