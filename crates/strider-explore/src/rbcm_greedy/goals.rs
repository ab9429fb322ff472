//! Goal selection of Prágr19 Alg. 1: the cheapest spatial goal (getBestSpatialGoal, Eq. 13–14),
//! the best cost goal (getBestCostGoal, Eq. 15) and the decision rule (Eq. 16).

use super::cost_map::CostMap;
use strider_core::{Cell, Point2};
use strider_map::ElevationMap;
use strider_map::frontiers::{components, frontier_cells, kmeans_representatives};
use strider_map::reachability::Reachability;
use strider_map::rect::WorldRect;
use strider_plan::grid::MeanEdgeDijkstra;

/// Which kind of goal Eq. 16 chose.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum GoalKind {
    /// ν_cost: the cell of highest score (model exploration).
    Cost,
    /// ν_spatial: the cheapest-to-reach frontier representative.
    Spatial,
}

/// A navigation goal on Mcost.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Goal {
    /// Cost or spatial goal.
    pub kind: GoalKind,
    /// The Mcost cell.
    pub cell: Cell,
    /// Its centre, metres.
    pub point: Point2,
    /// Eq. 15 score for a cost goal, the Eq. 14 path cost for a spatial goal.
    pub value: f64,
}

/// Frontier representatives of Prágr19 Eq. 13 on the elevation map: frontier cells (reachable,
/// admissible, next to unknown, inside the bounds, at least r_spatial from the robot) that are
/// not within `r_visited` of an already reached spatial goal, split per 8-connected component
/// into n_r = 1 + ⌊f/D + 0.5⌋ representatives. Returns their centres.
pub fn frontier_representatives(
    map: &ElevationMap,
    reach: &Reachability,
    robot: Cell,
    bounds: Option<&WorldRect>,
    visited: &[Point2],
    r_visited: f64,
) -> Vec<Point2> {
    let d = map.cell_size();
    let d_cells = map.params().r_sensor / d;
    let cells: Vec<Cell> = frontier_cells(map, reach, robot, bounds)
        .into_iter()
        .filter(|c| {
            let p = c.center(d);
            visited
                .iter()
                .all(|v| (v.x - p.x).hypot(v.y - p.y) >= r_visited)
        })
        .collect();
    let mut out = Vec::new();
    for comp in components(&cells) {
        let n_r = strider_map::frontiers::representative_count(comp.len(), d_cells); // Eq. 13
        for (c, _) in kmeans_representatives(&comp, n_r) {
            out.push(c.center(d));
        }
    }
    out
}

/// getBestSpatialGoal: the representative cheapest to reach from the robot's Mcost cell under
/// Eq. 14, given a search already run from it. Representatives are placed on the traversable
/// Mcost cell nearest them (within `snap` cells).
pub fn best_spatial_goal(
    cost_map: &CostMap,
    search: &MeanEdgeDijkstra,
    representatives: &[Point2],
    snap: i32,
) -> Option<Goal> {
    let mut best: Option<Goal> = None;
    for &p in representatives {
        let Some(c) = cost_map
            .cell_at(p)
            .and_then(|c| cost_map.nearest_traversable(c, snap))
        else {
            continue;
        };
        let Some(v) = search.cost(c) else { continue };
        if best.is_none_or(|b| v < b.value) {
            best = Some(Goal {
                kind: GoalKind::Spatial,
                cell: c,
                point: c.center(cost_map.cell_size),
                value: v,
            });
        }
    }
    best
}

/// getBestCostGoal: the reachable cell of highest Eq. 15 score (ties: first in row-major order),
/// given the scores of [`CostMap::scores`] and a search run from the robot.
pub fn best_cost_goal(
    cost_map: &CostMap,
    scores: &[f64],
    search: &MeanEdgeDijkstra,
) -> Option<Goal> {
    let mut best: Option<(usize, f64)> = None;
    for (k, &s) in scores.iter().enumerate() {
        if !s.is_finite() || search.cost(cost_map.rect.cell(k)).is_none() {
            continue;
        }
        if best.is_none_or(|(_, b)| s > b) {
            best = Some((k, s));
        }
    }
    best.map(|(k, s)| {
        let c = cost_map.rect.cell(k);
        Goal {
            kind: GoalKind::Cost,
            cell: c,
            point: c.center(cost_map.cell_size),
            value: s,
        }
    })
}

/// The decision rule of Prágr19 Eq. 16: the cost goal when its score exceeds λ_score, else the
/// spatial goal if any, else none (exploration ends).
pub fn select_goal(cost: Option<Goal>, spatial: Option<Goal>, lambda_score: f64) -> Option<Goal> {
    match cost {
        Some(c) if c.value > lambda_score => Some(c),
        _ => spatial,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn goal(kind: GoalKind, value: f64) -> Goal {
        Goal {
            kind,
            cell: Cell::new(0, 0),
            point: Point2::new(0.0, 0.0),
            value,
        }
    }

    #[test]
    fn eq16_prefers_uncertain_terrain_then_frontiers() {
        let c = Some(goal(GoalKind::Cost, 0.002));
        let s = Some(goal(GoalKind::Spatial, 3.0));
        assert_eq!(select_goal(c, s, 0.001).unwrap().kind, GoalKind::Cost);
        assert_eq!(select_goal(c, s, 0.005).unwrap().kind, GoalKind::Spatial);
        assert_eq!(select_goal(c, None, 0.005), None);
        assert_eq!(select_goal(None, None, 0.001), None);
        // The threshold is strict (Eq. 16: score > λ_score).
        assert_eq!(
            select_goal(Some(goal(GoalKind::Cost, 0.001)), None, 0.001),
            None
        );
    }
}
