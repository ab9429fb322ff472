//! Prágr23 (thesis C4) Alg. 2 lines 9–20 and Eq. 22–26: the next exploration goal.
//!
//! 1. The closest spatial goal (Eq. 23) by the cost of the cheapest path (Eq. 20–21), when any
//!    reachable spatial goal exists (Alg. 2 lines 9–11; the goals are the Alg. 1 clusters of
//!    cells with I_geom > 0, d_cl = 1 m, n_cl = 10).
//! 2. Else, while no predictor exists, the closest apparent obstacle (Eq. 26, line 13).
//! 3. Else the apparent obstacle of highest prediction entropy (Eq. 25, lines 15–18) if it
//!    exceeds I^thr_predict; otherwise there is no goal and the exploration ends (line 24).
//!
//! Apparent obstacles with haptic ground truth carry no information (C4 §4.3) and are not
//! candidates. The cost of an obstacle is that of the cheapest admissible cell within
//! r_robot + `reach` of it (the robot cannot stand on the obstacle, it approaches it; the
//! neighbourhood is then cleared so the path reaches the obstacle itself, C4 §4.5). The rigid
//! baseline stops after step 1.

use super::view::{ObstacleState, TravView};
use strider_core::Cell;
use strider_core::grid::disc_offsets;
use strider_map::SpatialGoal;

/// Which rule of Alg. 2 chose a goal.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum GoalKind {
    /// Eq. 23: the closest spatial goal.
    Spatial,
    /// Eq. 26: the closest apparent obstacle (no predictor yet).
    ClosestObstacle,
    /// Eq. 25: the most uncertain apparent obstacle.
    UncertainObstacle,
}

/// A chosen goal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Goal {
    /// The rule.
    pub kind: GoalKind,
    /// The goal cell (a spatial goal's representative or the obstacle cell).
    pub cell: Cell,
    /// Path cost to it (to its approach for obstacles).
    pub cost: f64,
    /// Prediction entropy of an uncertain obstacle, nat (NaN otherwise).
    pub entropy: f64,
}

/// What goal selection reads besides the view.
pub struct GoalInputs<'a> {
    /// Cheapest-path cost from the robot to every view cell (row-major over the view).
    pub dist: &'a [f64],
    /// The current spatial goals.
    pub spatial: &'a [SpatialGoal],
    /// Whether apparent obstacles are candidates at all (false: rigid baseline).
    pub learn: bool,
    /// Whether the predictor P exists.
    pub predictor_learned: bool,
    /// I^thr_predict, nat.
    pub entropy_threshold: f64,
    /// Robot footprint radius, m.
    pub r_robot: f64,
    /// Extra approach distance beyond r_robot, m.
    pub reach: f64,
    /// Obstacle cells not to pursue again (a failed approach).
    pub excluded: &'a [Cell],
    /// Exclusion radius around `excluded`, cells.
    pub exclusion_cells: f64,
    /// Exploration bounds: obstacle goals outside are not pursued.
    pub bounds: Option<&'a strider_map::rect::WorldRect>,
}

/// Alg. 2 lines 9–20 (see the module docs).
pub fn select_goal(view: &TravView, inp: &GoalInputs) -> Option<Goal> {
    let dist_at = |c: Cell| {
        view.rect.index(c).map_or(f64::INFINITY, |k| {
            inp.dist.get(k).copied().unwrap_or(f64::INFINITY)
        })
    };
    // Eq. 23.
    let spatial = inp
        .spatial
        .iter()
        .map(|g| (dist_at(g.cell), g.cell))
        .filter(|(d, _)| d.is_finite())
        .min_by(|a, b| {
            a.0.total_cmp(&b.0)
                .then((a.1.j, a.1.i).cmp(&(b.1.j, b.1.i)))
        });
    if let Some((cost, cell)) = spatial {
        return Some(Goal {
            kind: GoalKind::Spatial,
            cell,
            cost,
            entropy: f64::NAN,
        });
    }
    if !inp.learn {
        return None;
    }
    let disc = disc_offsets(inp.r_robot + inp.reach, view.cell_size);
    let approach = |c: Cell| {
        disc.iter()
            .map(|&(di, dj)| dist_at(Cell::new(c.i + di, c.j + dj)))
            .fold(f64::INFINITY, f64::min)
    };
    let mut best: Option<Goal> = None;
    for (k, o) in view.obstacle.iter().enumerate() {
        let Some(state) = o else { continue };
        if !view.observed[k] {
            continue;
        }
        let c = view.rect.cell(k);
        if inp
            .bounds
            .is_some_and(|b| !b.contains_cell(c, view.cell_size))
        {
            continue;
        }
        if inp
            .excluded
            .iter()
            .any(|e| e.dist_cells(c) <= inp.exclusion_cells)
        {
            continue;
        }
        let entropy = match (state, inp.predictor_learned) {
            (ObstacleState::Haptic { .. }, _) => continue,
            (_, false) => f64::NAN,
            (ObstacleState::Predicted(fp), true) if fp.entropy > inp.entropy_threshold => {
                fp.entropy
            }
            _ => continue,
        };
        let cost = approach(c);
        if !cost.is_finite() {
            continue;
        }
        let better = match &best {
            None => true,
            Some(b) if inp.predictor_learned => {
                entropy > b.entropy || (entropy == b.entropy && cost < b.cost)
            }
            Some(b) => cost < b.cost,
        };
        if better {
            best = Some(Goal {
                kind: if inp.predictor_learned {
                    GoalKind::UncertainObstacle
                } else {
                    GoalKind::ClosestObstacle
                },
                cell: c,
                cost,
                entropy,
            });
        }
    }
    best
}
