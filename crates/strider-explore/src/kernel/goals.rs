//! What the strategies with spatial goals share about them: a goal near a place the robot
//! already reached is not pursued again (what could not be seen from there, e.g. the sensor's
//! blind zone around the robot, will not be seen by returning).

use strider_core::Cell;
use strider_map::SpatialGoal;

/// Drops the goals within `r_cells` of any of the `visited` cells.
pub fn drop_visited(goals: &mut Vec<SpatialGoal>, visited: &[Cell], r_cells: f64) {
    goals.retain(|g| visited.iter().all(|v| v.dist_cells(g.cell) > r_cells));
}
