//! `001` Alg. 3, clusterEntropyRepresentatives: spatial goals from the cells with non-zero
//! information gain (decision 5).
//!
//! Greedy, in the fixed (row-major) order of the cells: a cell joins the cluster whose nearest
//! member is closer than c_radius (line 7–9), else starts a new cluster (line 11). Clusters with
//! more than c_min_cells members (line 14) yield a representative: the average-coordinate cell
//! (line 15), snapped to the nearest reachable admissible cell inside the exploration bounds.
//! Nearest members are found through a hash grid of c_radius-sized buckets.

use crate::information_gain::InfoGain;
use crate::map::ElevationMap;
use crate::reachability::Reachability;
use crate::rect::{WorldRect, in_bounds};
use std::collections::HashMap;
use strider_core::{Cell, Point2};

/// A spatial exploration goal Γ_P (one representative per kept cluster).
#[derive(Clone, Debug, PartialEq)]
pub struct SpatialGoal {
    /// The representative cell (reachable, admissible).
    pub cell: Cell,
    /// The average coordinate of the members, world frame.
    pub centroid: Point2,
    /// Σ I_model over the members.
    pub information: f64,
    /// Number of member cells.
    pub members: usize,
}

/// Alg. 3 lines 2–11: greedy clustering of `cells` (in the given order) with linkage radius
/// `radius` (cells, strict `<`). Returns the member indices of each cluster, in creation order.
pub fn greedy_clusters(cells: &[Cell], radius: f64) -> Vec<Vec<usize>> {
    let b = radius.ceil().max(1.0) as i32;
    let bucket = |c: Cell| (c.i.div_euclid(b), c.j.div_euclid(b));
    let mut grid: HashMap<(i32, i32), Vec<(usize, usize)>> = HashMap::new();
    let mut clusters: Vec<Vec<usize>> = Vec::new();
    for (k, &c) in cells.iter().enumerate() {
        let (bi, bj) = bucket(c);
        let mut best: Option<(f64, usize)> = None;
        for dj in -1..=1 {
            for di in -1..=1 {
                let Some(members) = grid.get(&(bi + di, bj + dj)) else {
                    continue;
                };
                for &(m, cl) in members {
                    let dist = c.dist_cells(cells[m]);
                    let better = best.is_none_or(|(bd, bc)| dist < bd || (dist == bd && cl < bc));
                    if dist < radius && better {
                        best = Some((dist, cl));
                    }
                }
            }
        }
        let cl = match best {
            Some((_, cl)) => cl,
            None => {
                clusters.push(Vec::new());
                clusters.len() - 1
            }
        };
        clusters[cl].push(k);
        grid.entry((bi, bj)).or_default().push((k, cl));
    }
    clusters
}

/// Alg. 3: spatial goals from the information gain field. Clusters with at most `c_min_cells`
/// members are dropped, as are clusters whose representative cannot be snapped to a reachable
/// admissible cell inside `bounds`.
pub fn cluster_information(
    map: &ElevationMap,
    gain: &InfoGain,
    reach: &Reachability,
    bounds: Option<&WorldRect>,
) -> Vec<SpatialGoal> {
    let p = map.params();
    let d = map.cell_size();
    let cells: Vec<Cell> = gain.cells.iter().map(|&(c, _)| c).collect();
    let clusters = greedy_clusters(&cells, p.c_radius / d);
    let mut goals = Vec::new();
    for members in clusters {
        if members.len() <= p.c_min_cells {
            continue; // line 14: |A_i| > c_min_cells
        }
        let n = members.len() as f64;
        // Average in lattice units (cell centres at i + 0.5), exact for integer sums.
        let (mut x, mut y, mut info) = (0.0, 0.0, 0.0);
        for &k in &members {
            let c = gain.cells[k].0;
            x += c.i as f64 + 0.5;
            y += c.j as f64 + 0.5;
            info += gain.cells[k].1;
        }
        let (x, y) = (x / n, y / n);
        let centroid = Point2::new(x * d, y * d);
        let avg = Cell::new(x.floor() as i32, y.floor() as i32);
        let Some(cell) = reach.nearest_goal_cell(avg, |c| in_bounds(bounds, c, d)) else {
            continue;
        };
        goals.push(SpatialGoal {
            cell,
            centroid,
            information: info,
            members: members.len(),
        });
    }
    goals
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::MapParams;
    use approx::assert_abs_diff_eq;
    use strider_core::Rgb8;

    #[test]
    fn greedy_order_matters_as_in_alg3() {
        // Radius 1.5 cells: (0,0)-(1,0) link, (3,0) is 2 away from (1,0) → new cluster,
        // (2,0) then joins the nearest member's cluster: (1,0) and (3,0) tie at distance 1,
        // the older cluster wins.
        let cells = [
            Cell::new(0, 0),
            Cell::new(1, 0),
            Cell::new(3, 0),
            Cell::new(2, 0),
            Cell::new(10, 10),
        ];
        let cl = greedy_clusters(&cells, 1.5);
        assert_eq!(cl, vec![vec![0, 1, 3], vec![2], vec![4]]);
        // Strict "<": at radius exactly 1 neighbours do not link.
        assert_eq!(greedy_clusters(&cells[..2], 1.0).len(), 2);
    }

    #[test]
    fn goals_from_two_blobs() {
        let params = MapParams {
            cell_size: 0.1,
            c_radius: 0.25,
            c_min_cells: 3,
            r_robot: 0.0,
            ..MapParams::default()
        };
        let mut m = ElevationMap::new(params);
        for j in 0..10 {
            for i in 0..20 {
                m.set_cell(Cell::new(i, j), 0.0, 1e-4, Rgb8::default());
            }
        }
        m.update_passability();
        let reach = Reachability::compute(&m, Cell::new(0, 0));
        // Blob A: 2×3 cells around (2..=3, 1..=3) with gain 1 each; blob B: 3 cells (too small).
        let mut cells = Vec::new();
        for j in 1..=3 {
            for i in 2..=3 {
                cells.push((Cell::new(i, j), 1.0));
            }
        }
        cells.extend([
            (Cell::new(15, 5), 2.0),
            (Cell::new(16, 5), 2.0),
            (Cell::new(17, 5), 2.0),
        ]);
        cells.sort_by_key(|&(c, _)| (c.j, c.i));
        let gain = InfoGain {
            candidates: cells.len(),
            cells,
        };
        let goals = cluster_information(&m, &gain, &reach, None);
        assert_eq!(goals.len(), 1);
        let g = &goals[0];
        assert_eq!(g.members, 6);
        assert_abs_diff_eq!(g.information, 6.0);
        // Average coordinate: x = 0.3 (between columns 2 and 3), y = 0.25 → cell (3, 2).
        assert_abs_diff_eq!(g.centroid.x, 0.3, epsilon = 1e-12);
        assert_abs_diff_eq!(g.centroid.y, 0.25, epsilon = 1e-12);
        assert_eq!(g.cell, Cell::new(3, 2));
        // Bounds excluding the blob's neighbourhood snap the representative elsewhere.
        let b = WorldRect::new(Point2::new(0.0, 0.0), Point2::new(0.2, 1.0));
        let goals = cluster_information(&m, &gain, &reach, Some(&b));
        assert_eq!(goals[0].cell, Cell::new(1, 2));
    }
}
