//! Frontier representatives of Prágr19 §IV (spatial goals of the cost-aware explorer).
//!
//! Frontier cells: reachable admissible known cells with an unknown 8-neighbour (inside the
//! exploration bounds), ignoring those closer than r_spatial to the robot. Each 8-connected
//! component of frontier cells with f cells is split into
//! n_r = 1 + ⌊f / D + 0.5⌋ representatives (Eq. 13, D = sensor range in cells) by deterministic
//! k-means (farthest-point initialisation from the component's first cell in row-major order,
//! a fixed number of Lloyd iterations); each representative is snapped to the nearest member.

use crate::map::ElevationMap;
use crate::reachability::Reachability;
use crate::rect::{WorldRect, in_bounds};
use std::collections::VecDeque;
use strider_core::Cell;
use strider_core::grid::NEIGHBOURS8;

/// Lloyd iterations of the frontier k-means.
const KMEANS_ITERATIONS: usize = 10;

/// A frontier representative.
#[derive(Clone, Debug, PartialEq)]
pub struct FrontierGoal {
    /// The representative: a member cell of the component.
    pub cell: Cell,
    /// Frontier cells assigned to this representative.
    pub members: usize,
    /// Index of the component (in order of its first cell, row-major).
    pub component: usize,
    /// Number of frontier cells f in the component.
    pub component_size: usize,
}

/// n_r of Prágr19 Eq. 13: 1 + ⌊f / D + 0.5⌋ for `f` frontier cells and sensor range `d_cells`.
pub fn representative_count(f: usize, d_cells: f64) -> usize {
    if d_cells <= 0.0 {
        return f.max(1);
    }
    1 + (f as f64 / d_cells + 0.5).floor() as usize
}

/// The frontier cells in row-major order.
pub fn frontier_cells(
    map: &ElevationMap,
    reach: &Reachability,
    robot: Cell,
    bounds: Option<&WorldRect>,
) -> Vec<Cell> {
    let d = map.cell_size();
    let r_spatial = map.params().r_spatial / d;
    let unknown = |c: Cell| !map.is_observed(c) && in_bounds(bounds, c, d);
    reach
        .cells()
        .filter(|&c| {
            reach.is_goal_cell(c)
                && in_bounds(bounds, c, d)
                && c.dist_cells(robot) >= r_spatial
                && c.neighbours8().any(unknown)
        })
        .collect()
}

/// 8-connected components of `cells` (row-major input), each in row-major order, ordered by
/// their first cell.
pub fn components(cells: &[Cell]) -> Vec<Vec<Cell>> {
    let set: std::collections::HashMap<Cell, usize> =
        cells.iter().enumerate().map(|(k, &c)| (c, k)).collect();
    let mut seen = vec![false; cells.len()];
    let mut out = Vec::new();
    let mut queue = VecDeque::new();
    for s in 0..cells.len() {
        if seen[s] {
            continue;
        }
        seen[s] = true;
        queue.push_back(s);
        let mut comp = Vec::new();
        while let Some(k) = queue.pop_front() {
            comp.push(cells[k]);
            for &(di, dj) in &NEIGHBOURS8 {
                if let Some(&n) = set.get(&cells[k].offset(di, dj))
                    && !seen[n]
                {
                    seen[n] = true;
                    queue.push_back(n);
                }
            }
        }
        comp.sort_by_key(|c| (c.j, c.i));
        out.push(comp);
    }
    out
}

/// Deterministic k-means of `cells` into `k` groups: farthest-point initialisation starting at
/// the first cell, then `KMEANS_ITERATIONS` Lloyd iterations. Returns each centre snapped to its
/// nearest member cell and the number of cells assigned to it.
pub fn kmeans_representatives(cells: &[Cell], k: usize) -> Vec<(Cell, usize)> {
    let k = k.clamp(1, cells.len().max(1));
    if cells.is_empty() {
        return Vec::new();
    }
    let pts: Vec<(f64, f64)> = cells.iter().map(|c| (c.i as f64, c.j as f64)).collect();
    let d2 = |a: (f64, f64), b: (f64, f64)| (a.0 - b.0).powi(2) + (a.1 - b.1).powi(2);
    let mut centres = vec![pts[0]];
    let mut nearest: Vec<f64> = pts.iter().map(|&p| d2(p, pts[0])).collect();
    while centres.len() < k {
        let (far, _) = nearest
            .iter()
            .enumerate()
            .fold((0, -1.0), |b, (i, &v)| if v > b.1 { (i, v) } else { b });
        centres.push(pts[far]);
        for (n, &p) in nearest.iter_mut().zip(&pts) {
            *n = n.min(d2(p, pts[far]));
        }
    }
    let assign = |centres: &[(f64, f64)]| -> Vec<usize> {
        pts.iter()
            .map(|&p| {
                (0..centres.len())
                    .min_by(|&a, &b| d2(p, centres[a]).total_cmp(&d2(p, centres[b])))
                    .unwrap_or(0)
            })
            .collect()
    };
    let mut labels = assign(&centres);
    for _ in 0..KMEANS_ITERATIONS {
        let mut sum = vec![(0.0, 0.0, 0usize); k];
        for (&p, &l) in pts.iter().zip(&labels) {
            sum[l] = (sum[l].0 + p.0, sum[l].1 + p.1, sum[l].2 + 1);
        }
        for (c, s) in centres.iter_mut().zip(&sum) {
            if s.2 > 0 {
                *c = (s.0 / s.2 as f64, s.1 / s.2 as f64);
            }
        }
        labels = assign(&centres);
    }
    centres
        .iter()
        .enumerate()
        .map(|(ci, &c)| {
            let snap = (0..pts.len())
                .min_by(|&a, &b| d2(pts[a], c).total_cmp(&d2(pts[b], c)))
                .unwrap_or(0);
            (cells[snap], labels.iter().filter(|&&l| l == ci).count())
        })
        .collect()
}

/// Frontier representatives (Prágr19 Eq. 13) for a robot at `robot`.
pub fn frontier_goals(
    map: &ElevationMap,
    reach: &Reachability,
    robot: Cell,
    bounds: Option<&WorldRect>,
) -> Vec<FrontierGoal> {
    let d_cells = map.params().r_sensor / map.cell_size();
    let cells = frontier_cells(map, reach, robot, bounds);
    let mut goals = Vec::new();
    for (ci, comp) in components(&cells).iter().enumerate() {
        let n_r = representative_count(comp.len(), d_cells); // Eq. 13
        for (cell, members) in kmeans_representatives(comp, n_r) {
            goals.push(FrontierGoal {
                cell,
                members,
                component: ci,
                component_size: comp.len(),
            });
        }
    }
    goals
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::MapParams;
    use crate::testing::{block, flat};

    #[test]
    fn eq13_counts() {
        assert_eq!(representative_count(0, 50.0), 1);
        assert_eq!(representative_count(24, 50.0), 1);
        assert_eq!(representative_count(25, 50.0), 2);
        assert_eq!(representative_count(74, 50.0), 2);
        assert_eq!(representative_count(75, 50.0), 3);
    }

    #[test]
    fn frontier_of_a_corridor() {
        // Known strip 0 ≤ i < 40, 0 ≤ j < 3, sensor range 1.0 m = 10 cells, r_spatial 0.4 m.
        let p = MapParams {
            cell_size: 0.1,
            r_sensor: 1.0,
            r_robot: 0.0,
            r_spatial: 0.4,
            ..MapParams::default()
        };
        let mut m = ElevationMap::new(p);
        flat(&mut m, block(0, 0, 40, 3));
        let robot = Cell::new(0, 1);
        let reach = Reachability::compute(&m, robot);
        let f = frontier_cells(&m, &reach, robot, None);
        // Rows 0 and 2 (80 cells) plus the end cells (39, 1) and (0, 1), minus the cells within
        // 4 cells of the robot: (0..=3, 0), (0..=3, 2) and (0, 1) (distance < 4 for i ≤ 3).
        assert_eq!(f.len(), 80 + 2 - 9);
        let goals = frontier_goals(&m, &reach, robot, None);
        // All frontier cells form one component (rows 0 and 2 join through column 39).
        assert!(goals.iter().all(|g| g.component == 0));
        assert_eq!(goals.len(), representative_count(73, 10.0));
        assert_eq!(goals.len(), 8);
        assert_eq!(goals.iter().map(|g| g.members).sum::<usize>(), 73);
        for g in &goals {
            assert!(f.contains(&g.cell));
        }
        // Two disjoint components when the corridor end is closed off by bounds.
        let b = crate::rect::WorldRect::new(
            strider_core::Point2::new(-10.0, -10.0),
            strider_core::Point2::new(3.9, 10.0),
        );
        let goals = frontier_goals(&m, &reach, robot, Some(&b));
        let comps: std::collections::BTreeSet<usize> = goals.iter().map(|g| g.component).collect();
        assert_eq!(comps.len(), 2);
    }

    #[test]
    fn kmeans_splits_a_line_evenly() {
        let cells: Vec<Cell> = (0..30).map(|i| Cell::new(i, 0)).collect();
        let reps = kmeans_representatives(&cells, 3);
        let mut got: Vec<(Cell, usize)> = reps;
        got.sort_by_key(|r| r.0.i);
        assert_eq!(
            got,
            vec![
                (Cell::new(4, 0), 10),
                (Cell::new(14, 0), 10),
                (Cell::new(24, 0), 10)
            ]
        );
    }
}
