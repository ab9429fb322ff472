//! Prágr22 Alg. 3, clusterEntropyRepresentatives: spatial goals from the cells with non-zero
//! information gain (decision 5).
//!
//! Greedy, in the fixed (row-major) order of the cells: a cell joins the cluster whose centre
//! (the running average coordinate of its members) is closer than c_radius (line 7–9), else
//! starts a new cluster (line 11). Clusters with more than c_min_cells members (line 14) yield
//! a representative: the average-coordinate cell (line 15), snapped to the nearest reachable
//! admissible cell inside the exploration bounds.
//!
//! "distanceToClosestCluster" is read as the distance to the cluster's centre. Reading it as
//! the distance to the nearest member (single linkage, our first choice) chains every
//! informative cell of a connected region into one cluster, because the candidate lattice is
//! denser than c_radius: the robot then gets a single spatial goal at the centroid of the whole
//! frontier band, often in the middle of mapped space, and exploration stops once that spot was
//! visited (observed on `courtyard-large`, where a 10 m sensor makes most of the known area
//! informative). Centre distance bounds each cluster to a c_radius ball, so the goals cover
//! the informative area at c_radius spacing: "a limited number of spatial entropy
//! representants" (Prágr22 §4.2) rather than one.

use crate::information_gain::InfoGain;
use crate::map::ElevationMap;
use crate::reachability::Reachability;
use crate::rect::{WorldRect, in_bounds};
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

/// Alg. 3 lines 2–11: greedy clustering of `cells` (in the given order) with radius `radius`
/// (cells, strict `<`) around each cluster's running centre; ties go to the older cluster.
/// Returns the member indices of each cluster, in creation order.
///
/// A long frontier makes hundreds of clusters, so the centres are kept in square buckets of
/// side a little over `radius`: a centre closer than `radius` to a cell lies in the 3 × 3
/// buckets around the cell's, and the relative margin of 1e-6 on the side is far above the
/// rounding of a bucket index (about 1e-11 of a bucket at a million cells from the origin). The
/// result is that of comparing every centre.
pub fn greedy_clusters(cells: &[Cell], radius: f64) -> Vec<Vec<usize>> {
    let (of, sums) = greedy_cluster_ids(cells, radius);
    let mut clusters: Vec<Vec<usize>> = sums
        .iter()
        .map(|s| Vec::with_capacity(s.2 as usize))
        .collect();
    for (k, &cl) in of.iter().enumerate() {
        clusters[cl as usize].push(k);
    }
    clusters
}

/// [`greedy_clusters`] as each cell's cluster id, with each cluster's (Σi, Σj, n) in lattice
/// units: a large map's frontier has hundreds of thousands of informative cells, and member
/// lists grown one cell at a time cost more in the allocator than the clustering itself.
fn greedy_cluster_ids(cells: &[Cell], radius: f64) -> (Vec<u32>, Vec<(f64, f64, f64)>) {
    // Per cluster: Σi, Σj, n (centres in lattice units; exact for integer sums).
    let mut sums: Vec<(f64, f64, f64)> = Vec::new();
    let mut of = Vec::with_capacity(cells.len());
    let mut buckets = CentreBuckets::new(radius, cells);
    let r2 = radius * radius;
    for &c in cells {
        let (x, y) = (c.i as f64, c.j as f64);
        let mut best: Option<(f64, usize)> = None;
        buckets.for_each_near(x, y, |cl, (cx, cy)| {
            let (dx, dy) = (x - cx, y - cy);
            let d2 = dx * dx + dy * dy;
            if d2 < r2 && best.is_none_or(|(bd, bc)| d2 < bd || (d2 == bd && cl < bc)) {
                best = Some((d2, cl));
            }
        });
        let cl = match best {
            Some((_, cl)) => {
                let (sx, sy, n) = sums[cl];
                let s = (sx + x, sy + y, n + 1.0);
                sums[cl] = s;
                buckets.moved(cl, (sx / n, sy / n), (s.0 / s.2, s.1 / s.2));
                cl
            }
            None => {
                sums.push((x, y, 1.0));
                buckets.insert(sums.len() - 1, x, y);
                sums.len() - 1
            }
        };
        of.push(cl as u32);
    }
    (of, sums)
}

/// Cluster centres by square bucket, in a dense grid over the cells' bounding box (a centre
/// is a mean of cells, so it lies inside it). A bucket is a little wider than `radius` (see
/// [`greedy_clusters`]), wider still when the grid would otherwise hold many more buckets than
/// there are cells.
/// Relative margin of a bucket's side over the clustering radius.
const BUCKET_MARGIN: f64 = 1e-6;

struct CentreBuckets {
    side: f64,
    origin: (f64, f64),
    dims: (i64, i64),
    /// Per bucket: the clusters whose centre lies in it, with the centre (kept here, so that
    /// a look-up reads it next to the id instead of dividing the cluster's sums).
    buckets: Vec<Vec<(usize, (f64, f64))>>,
}

impl CentreBuckets {
    fn new(radius: f64, cells: &[Cell]) -> Self {
        let lo = cells
            .iter()
            .fold((i32::MAX, i32::MAX), |a, c| (a.0.min(c.i), a.1.min(c.j)));
        let hi = cells
            .iter()
            .fold((i32::MIN, i32::MIN), |a, c| (a.0.max(c.i), a.1.max(c.j)));
        let extent = if cells.is_empty() {
            (1.0, 1.0)
        } else {
            (
                f64::from(hi.0) - f64::from(lo.0) + 1.0,
                f64::from(hi.1) - f64::from(lo.1) + 1.0,
            )
        };
        let most = 4.0 * cells.len() as f64 + 1024.0;
        let least = (extent.0 * extent.1 / most).sqrt();
        let side = if radius.is_finite() && radius > 0.0 {
            radius.max(least) * (1.0 + BUCKET_MARGIN)
        } else {
            f64::MAX
        };
        let dims = (
            (extent.0 / side).ceil().max(1.0) as i64,
            (extent.1 / side).ceil().max(1.0) as i64,
        );
        Self {
            side,
            origin: (f64::from(lo.0.min(hi.0)), f64::from(lo.1.min(hi.1))),
            dims,
            buckets: vec![Vec::new(); (dims.0 * dims.1) as usize],
        }
    }

    /// The bucket (column, row) of (x, y), clamped to the grid. Truncation stands in for
    /// `floor` (a library call on the baseline target): the two differ only below zero, where
    /// the clamp makes both 0.
    fn key(&self, x: f64, y: f64) -> (i64, i64) {
        let f = |v: f64, o: f64, n: i64| (((v - o) / self.side) as i64).clamp(0, n - 1);
        (
            f(x, self.origin.0, self.dims.0),
            f(y, self.origin.1, self.dims.1),
        )
    }

    fn at(&mut self, (bx, by): (i64, i64)) -> &mut Vec<(usize, (f64, f64))> {
        &mut self.buckets[(by * self.dims.0 + bx) as usize]
    }

    fn insert(&mut self, cl: usize, x: f64, y: f64) {
        let k = self.key(x, y);
        self.at(k).push((cl, (x, y)));
    }

    /// Cluster `cl`'s centre moved from `from` to `to`: updated in place when it stays in its
    /// bucket (the usual case: one more member moves a centre by a fraction of a cell).
    fn moved(&mut self, cl: usize, from: (f64, f64), to: (f64, f64)) {
        let (was, now) = (self.key(from.0, from.1), self.key(to.0, to.1));
        let bucket = self.at(was);
        if was == now {
            if let Some(e) = bucket.iter_mut().find(|e| e.0 == cl) {
                e.1 = to;
            }
        } else {
            bucket.retain(|&(c, _)| c != cl);
            self.insert(cl, to.0, to.1);
        }
    }

    /// Calls `visit` with every cluster whose centre lies in (x, y)'s bucket or a neighbour,
    /// and its centre.
    fn for_each_near(&self, x: f64, y: f64, mut visit: impl FnMut(usize, (f64, f64))) {
        let (bx, by) = self.key(x, y);
        for ny in (by - 1).max(0)..=(by + 1).min(self.dims.1 - 1) {
            for nx in (bx - 1).max(0)..=(bx + 1).min(self.dims.0 - 1) {
                for &(cl, centre) in &self.buckets[(ny * self.dims.0 + nx) as usize] {
                    visit(cl, centre);
                }
            }
        }
    }
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
    let (of, sums) = greedy_cluster_ids(&cells, p.c_radius / d);
    // Per cluster, Σ(i + 0.5), Σ(j + 0.5) (cell centres, lattice units: exact for integer
    // sums) and Σ gain, each summed over the members in their order.
    let mut totals = vec![(0.0, 0.0, 0.0); sums.len()];
    for (&cl, &(c, g)) in of.iter().zip(&gain.cells) {
        let t = &mut totals[cl as usize];
        *t = (t.0 + (c.i as f64 + 0.5), t.1 + (c.j as f64 + 0.5), t.2 + g);
    }
    let mut goals = Vec::new();
    for (&(_, _, n), &(x, y, info)) in sums.iter().zip(&totals) {
        let members = n as usize;
        if members <= p.c_min_cells {
            continue; // line 14: |A_i| > c_min_cells
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
            members,
        });
    }
    goals
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::MapParams;
    use crate::testing::{block, flat};
    use approx::assert_abs_diff_eq;

    #[test]
    fn greedy_order_matters_as_in_alg3() {
        // Radius 1.5 cells: (1,0) joins (0,0) (centre now (0.5, 0)); (3,0) is 2.5 from it →
        // new cluster; (2,0) is 1.5 from the first centre (not < 1.5) and 1 from the second.
        let cells = [
            Cell::new(0, 0),
            Cell::new(1, 0),
            Cell::new(3, 0),
            Cell::new(2, 0),
            Cell::new(10, 10),
        ];
        let cl = greedy_clusters(&cells, 1.5);
        assert_eq!(cl, vec![vec![0, 1], vec![2, 3], vec![4]]);
        // Strict "<": at radius exactly 1 neighbours do not link.
        assert_eq!(greedy_clusters(&cells[..2], 1.0).len(), 2);
    }

    /// Alg. 3's clustering comparing every centre, the reference of the bucketed one.
    fn clusters_by_scanning(cells: &[Cell], radius: f64) -> Vec<Vec<usize>> {
        let mut sums: Vec<(f64, f64, f64)> = Vec::new();
        let mut clusters: Vec<Vec<usize>> = Vec::new();
        for (k, &c) in cells.iter().enumerate() {
            let (x, y) = (c.i as f64, c.j as f64);
            let mut best: Option<(f64, usize)> = None;
            for (cl, &(sx, sy, n)) in sums.iter().enumerate() {
                let d2 = (x - sx / n).powi(2) + (y - sy / n).powi(2);
                if d2 < radius * radius && best.is_none_or(|(bd, _)| d2 < bd) {
                    best = Some((d2, cl));
                }
            }
            let cl = best.map_or_else(
                || {
                    sums.push((0.0, 0.0, 0.0));
                    clusters.push(Vec::new());
                    clusters.len() - 1
                },
                |(_, cl)| cl,
            );
            let s = &mut sums[cl];
            *s = (s.0 + x, s.1 + y, s.2 + 1.0);
            clusters[cl].push(k);
        }
        clusters
    }

    proptest::proptest! {
        #[test]
        fn bucketed_clustering_equals_scanning_every_centre(
            pts in proptest::collection::vec((-60i32..60, -60i32..60), 0..300),
            // Whole radii put centres exactly on bucket edges.
            radius in proptest::prop_oneof![
                0.5f64..20.0,
                proptest::strategy::Just(2.0),
                proptest::strategy::Just(5.0),
                proptest::strategy::Just(8.0),
            ],
        ) {
            let cells: Vec<Cell> = pts.iter().map(|&(i, j)| Cell::new(i, j)).collect();
            proptest::prop_assert_eq!(
                greedy_clusters(&cells, radius),
                clusters_by_scanning(&cells, radius)
            );
        }
    }

    /// Alg. 3's goals from the member lists of [`greedy_clusters`], summed member by member:
    /// the reference of the per-cluster totals of [`cluster_information`].
    fn goals_from_member_lists(
        map: &ElevationMap,
        gain: &InfoGain,
        reach: &Reachability,
    ) -> Vec<SpatialGoal> {
        let p = map.params();
        let d = map.cell_size();
        let cells: Vec<Cell> = gain.cells.iter().map(|&(c, _)| c).collect();
        let mut goals = Vec::new();
        for members in greedy_clusters(&cells, p.c_radius / d) {
            if members.len() <= p.c_min_cells {
                continue;
            }
            let n = members.len() as f64;
            let (mut x, mut y, mut info) = (0.0, 0.0, 0.0);
            for &k in &members {
                let c = gain.cells[k].0;
                x += c.i as f64 + 0.5;
                y += c.j as f64 + 0.5;
                info += gain.cells[k].1;
            }
            let (x, y) = (x / n, y / n);
            let avg = Cell::new(x.floor() as i32, y.floor() as i32);
            if let Some(cell) = reach.nearest_goal_cell(avg, |_| true) {
                goals.push(SpatialGoal {
                    cell,
                    centroid: Point2::new(x * d, y * d),
                    information: info,
                    members: members.len(),
                });
            }
        }
        goals
    }

    proptest::proptest! {
        #[test]
        fn goals_equal_those_summed_from_member_lists(
            pts in proptest::collection::vec((0i32..60, 0i32..40, 1u32..90), 0..250),
            c_radius in 0.15f64..1.5,
            c_min_cells in 0usize..6,
        ) {
            let params = MapParams {
                cell_size: 0.1,
                c_radius,
                c_min_cells,
                r_robot: 0.0,
                ..MapParams::default()
            };
            let mut m = ElevationMap::new(params);
            flat(&mut m, block(0, 0, 60, 40));
            let reach = Reachability::compute(&m, Cell::new(0, 0));
            let mut cells: Vec<(Cell, f64)> =
                pts.iter().map(|&(i, j, g)| (Cell::new(i, j), g as f64 / 9.0)).collect();
            cells.sort_by_key(|&(c, _)| (c.j, c.i));
            cells.dedup_by_key(|&mut (c, _)| c);
            let gain = InfoGain { candidates: cells.len(), cells };
            proptest::prop_assert_eq!(
                cluster_information(&m, &gain, &reach, None),
                goals_from_member_lists(&m, &gain, &reach)
            );
        }
    }

    #[test]
    fn a_long_band_splits_into_radius_sized_clusters() {
        // A 1-cell-wide band of 40 cells with radius 5: single linkage would make one cluster;
        // centre linkage makes clusters of at most 2·5 − 1 = 9 consecutive cells.
        let cells: Vec<Cell> = (0..40).map(|i| Cell::new(i, 0)).collect();
        let cl = greedy_clusters(&cells, 5.0);
        assert!(cl.len() >= 4, "{}", cl.len());
        for c in &cl {
            let (lo, hi) = (c[0], c[c.len() - 1]);
            assert!(hi - lo < 10, "{lo}..{hi}");
            assert_eq!(c.len(), hi - lo + 1, "contiguous");
        }
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
        flat(&mut m, block(0, 0, 20, 10));
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
