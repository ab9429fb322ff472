//! What the strategies with spatial goals share about them: a goal near a place the robot
//! already reached is not pursued again (what could not be seen from there, e.g. the sensor's
//! blind zone around the robot, will not be seen by returning).

use std::collections::HashMap;
use strider_core::Cell;
use strider_map::SpatialGoal;

/// Below this many visited cells the goals are compared with each of them directly.
const FEW_VISITED: usize = 32;

/// Drops the goals within `r_cells` of any of the `visited` cells.
///
/// The visited cells are bucketed in squares of side ⌈r_cells⌉, so each goal looks only at the
/// 3 × 3 squares around its own: a long mission visits thousands of places and makes hundreds
/// of goals at every spatial update, and comparing every pair grew with both. The result is
/// that of comparing every pair.
pub fn drop_visited(goals: &mut Vec<SpatialGoal>, visited: &[Cell], r_cells: f64) {
    let near = |g: Cell, v: &Cell| v.dist_cells(g) <= r_cells;
    let side = r_cells.ceil();
    if visited.len() < FEW_VISITED || !(1.0..=1e15).contains(&side) {
        // Also where r_cells is NaN: no distance is then "> r_cells", so every goal goes.
        goals.retain(|g| visited.iter().all(|v| v.dist_cells(g.cell) > r_cells));
        return;
    }
    let side = side as i64;
    let square = |c: Cell| ((c.i as i64).div_euclid(side), (c.j as i64).div_euclid(side));
    let mut squares: HashMap<(i64, i64), Vec<Cell>> = HashMap::new();
    for &v in visited {
        squares.entry(square(v)).or_default().push(v);
    }
    goals.retain(|g| {
        let (x, y) = square(g.cell);
        !(-1..=1).any(|dy| {
            (-1..=1).any(|dx| {
                squares
                    .get(&(x + dx, y + dy))
                    .is_some_and(|vs| vs.iter().any(|v| near(g.cell, v)))
            })
        })
    });
}

#[cfg(test)]
mod tests {
    use super::*;
    use strider_core::Point2;

    fn goal(c: Cell) -> SpatialGoal {
        SpatialGoal {
            cell: c,
            centroid: Point2::new(0.0, 0.0),
            information: 1.0,
            members: 1,
        }
    }

    proptest::proptest! {
        /// The bucketed test keeps exactly the goals a comparison with every visited cell
        /// keeps, in their order, for radii below, at and above one cell.
        #[test]
        fn bucketed_dropping_equals_comparing_every_pair(
            goals in proptest::collection::vec((-60..60i32, -60..60i32), 0..80),
            visited in proptest::collection::vec((-60..60i32, -60..60i32), 0..120),
            r in proptest::prop_oneof![0.0..12.0f64, proptest::strategy::Just(5.0), proptest::strategy::Just(1.0)],
        ) {
            let goals: Vec<SpatialGoal> = goals.into_iter().map(|(i, j)| goal(Cell::new(i, j))).collect();
            let visited: Vec<Cell> = visited.into_iter().map(|(i, j)| Cell::new(i, j)).collect();
            let mut want = goals.clone();
            want.retain(|g| visited.iter().all(|v| v.dist_cells(g.cell) > r));
            let mut got = goals;
            drop_visited(&mut got, &visited, r);
            let cells = |gs: &[SpatialGoal]| gs.iter().map(|g| g.cell).collect::<Vec<_>>();
            proptest::prop_assert_eq!(cells(&got), cells(&want));
        }
    }
}
