//! How a Python strategy's goal becomes a path: the cheapest route on the map (path length,
//! the robot's footprint kept off obstacles and inside the exploration bounds), planned with the
//! same planning view and search the built-in explorers use, so a prototype in Python is driven
//! as a Rust strategy would be.

use strider_core::{Cell, GaitId, Point2};
use strider_explore::planner::{CostMode, PlanningView, nearest_where};
use strider_learn::cost_model::{CostModelParams, GaitCostModel};
use strider_map::rect::WorldRect;
use strider_map::{ElevationMap, MapParams};
use strider_plan::grid::Dijkstra;

/// Flat (path-length) planning for a robot with `gaits` gaits.
pub struct GoalPlanner {
    /// One empty model per gait: the flat view needs the gait count only.
    models: Vec<GaitCostModel>,
    c_loss: f64,
    bounds: Option<WorldRect>,
    /// Where a start or goal off the admissible cells looks for the nearest admissible one.
    near: Vec<(i32, i32)>,
    dij: Dijkstra,
    /// The last view and the map's scan count it was built at: a strategy that decides more
    /// often than scans arrive plans on the same view instead of rebuilding it.
    view: Option<(u64, PlanningView)>,
}

impl GoalPlanner {
    pub fn new(
        gaits: usize,
        c_loss: f64,
        bounds: Option<WorldRect>,
        map: &MapParams,
    ) -> Result<Self, String> {
        let models = (0..gaits)
            .map(|g| GaitCostModel::new(GaitId(g as u8), 1, CostModelParams::default(), 0))
            .collect::<Result<Vec<_>, _>>()
            .map_err(|e| e.to_string())?;
        let near = strider_core::grid::disc_offsets(3.0 * map.r_robot, map.cell_size);
        Ok(Self {
            models,
            c_loss,
            bounds,
            near,
            dij: Dijkstra::new(),
            view: None,
        })
    }

    /// The waypoints from `from` to `goal`, or `None` when no admissible route is known.
    pub fn route(&mut self, map: &ElevationMap, from: Point2, goal: Point2) -> Option<Vec<Point2>> {
        let scans = map.scan_count();
        if self.view.as_ref().is_none_or(|(k, _)| *k != scans) {
            self.view = PlanningView::build(
                map,
                &self.models,
                CostMode::Flat,
                self.c_loss,
                self.bounds.as_ref(),
            )
            .map(|v| (scans, v));
        }
        let (_, view) = self.view.as_ref()?;
        let ok = |c: Cell| view.grid.is_admissible(c);
        let src = nearest_where(map.cell_at(from.x, from.y)?, &self.near, ok)?;
        let dst = nearest_where(map.cell_at(goal.x, goal.y)?, &self.near, ok)?;
        let cells = view.path(&mut self.dij, src, dst)?;
        Some(view.drive_waypoints_between(&cells, from, goal))
    }
}
