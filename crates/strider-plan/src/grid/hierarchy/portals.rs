//! Clusters of the lattice and the portals on their borders.
//!
//! The lattice is cut into square clusters of [`CLUSTER`] × [`CLUSTER`] cells aligned to the
//! global cell coordinates, so a cluster keeps its cells (and its cached distances) while the
//! planning rectangle grows around it. On each border between two side-by-side clusters, every
//! maximal run of rows (or columns) where the cells on both sides are admissible is an
//! *entrance*; its portal is the pair of cells across the border at the middle of the run, one
//! node in each cluster. Runs longer than [`MAX_RUN`] are cut into equal pieces with a portal
//! each, so that a path crossing a long open border is not pulled towards one point.

use super::super::cost_grid::CostGrid;
use strider_core::{Cell, CellRect};

/// Side of a cluster, cells (3.2 m at 0.1 m).
pub const CLUSTER: i32 = 32;

/// Longest stretch of an entrance served by one portal, cells.
pub const MAX_RUN: i32 = 16;

/// A cluster's coordinates: the global cell `(i, j)` lies in cluster `(i div K, j div K)`.
pub type ClusterKey = (i32, i32);

/// The cluster of a cell.
pub fn cluster_of(c: Cell) -> ClusterKey {
    (c.i.div_euclid(CLUSTER), c.j.div_euclid(CLUSTER))
}

/// The cells of cluster `key` inside `rect` (empty when they do not meet).
pub fn cluster_rect(key: ClusterKey, rect: CellRect) -> CellRect {
    let lo = Cell::new(key.0.saturating_mul(CLUSTER), key.1.saturating_mul(CLUSTER));
    intersect(CellRect::new(lo, CLUSTER as u32, CLUSTER as u32), rect)
}

/// The common cells of two rectangles (empty when they do not meet).
pub(super) fn intersect(a: CellRect, b: CellRect) -> CellRect {
    let lo_i = a.min.i.max(b.min.i) as i64;
    let lo_j = a.min.j.max(b.min.j) as i64;
    let hi_i = (a.min.i as i64 + a.width as i64).min(b.min.i as i64 + b.width as i64);
    let hi_j = (a.min.j as i64 + a.height as i64).min(b.min.j as i64 + b.height as i64);
    if hi_i <= lo_i || hi_j <= lo_j {
        return CellRect::new(b.min, 0, 0);
    }
    CellRect::new(
        Cell::new(lo_i as i32, lo_j as i32),
        (hi_i - lo_i) as u32,
        (hi_j - lo_j) as u32,
    )
}

/// Every cluster that meets `rect`, row by row.
pub fn clusters_of(rect: CellRect) -> Vec<ClusterKey> {
    if rect.is_empty() {
        return Vec::new();
    }
    let (lo, hi) = (
        cluster_of(rect.min),
        cluster_of(Cell::new(
            rect.min.i + rect.width as i32 - 1,
            rect.min.j + rect.height as i32 - 1,
        )),
    );
    (lo.1..=hi.1)
        .flat_map(|cy| (lo.0..=hi.0).map(move |cx| (cx, cy)))
        .collect()
}

/// One crossing between two clusters: the cells on either side, in crossing order.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Portal {
    /// The cell on the lower side (left or below).
    pub low: Cell,
    /// The cell on the upper side (right or above).
    pub high: Cell,
}

/// Every portal of `grid`, deterministic: vertical borders first (by cluster row, then column),
/// then horizontal ones.
pub fn portals(grid: &CostGrid) -> Vec<Portal> {
    let rect = grid.rect();
    let mut out = Vec::new();
    let free = |c: Cell| grid.is_admissible(c);
    for (cx, cy) in clusters_of(rect) {
        let span = cluster_rect((cx, cy), rect);
        // The border to the right: columns i and i + 1 over the cluster's rows.
        let i = (cx + 1) * CLUSTER - 1;
        if span.width > 0
            && rect.contains(Cell::new(i + 1, span.min.j))
            && rect.contains(Cell::new(i, span.min.j))
        {
            let rows = span.min.j..span.min.j + span.height as i32;
            entrances(
                rows,
                |j| free(Cell::new(i, j)) && free(Cell::new(i + 1, j)),
                |j| {
                    out.push(Portal {
                        low: Cell::new(i, j),
                        high: Cell::new(i + 1, j),
                    })
                },
            );
        }
        // The border above: rows j and j + 1 over the cluster's columns.
        let j = (cy + 1) * CLUSTER - 1;
        if span.height > 0
            && rect.contains(Cell::new(span.min.i, j + 1))
            && rect.contains(Cell::new(span.min.i, j))
        {
            let cols = span.min.i..span.min.i + span.width as i32;
            entrances(
                cols,
                |i| free(Cell::new(i, j)) && free(Cell::new(i, j + 1)),
                |i| {
                    out.push(Portal {
                        low: Cell::new(i, j),
                        high: Cell::new(i, j + 1),
                    })
                },
            );
        }
    }
    out
}

/// Calls `portal(k)` for the middle of every maximal run of `along` where `open` holds, runs
/// longer than [`MAX_RUN`] cut into equal pieces.
fn entrances(along: std::ops::Range<i32>, open: impl Fn(i32) -> bool, mut portal: impl FnMut(i32)) {
    let mut start = None;
    for k in along.start..=along.end {
        let is_open = k < along.end && open(k);
        match (start, is_open) {
            (None, true) => start = Some(k),
            (Some(s), false) => {
                let len = k - s;
                let pieces = (len + MAX_RUN - 1) / MAX_RUN;
                for p in 0..pieces {
                    let (a, b) = (s + p * len / pieces, s + (p + 1) * len / pieces);
                    portal((a + b - 1) / 2);
                }
                start = None;
            }
            _ => {}
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clusters_follow_global_coordinates() {
        assert_eq!(cluster_of(Cell::new(0, 31)), (0, 0));
        assert_eq!(cluster_of(Cell::new(-1, 32)), (-1, 1));
        let r = CellRect::new(Cell::new(-5, 10), 40, 10);
        assert_eq!(clusters_of(r), vec![(-1, 0), (0, 0), (1, 0)]);
        assert_eq!(
            cluster_rect((0, 0), r),
            CellRect::new(Cell::new(0, 10), 32, 10)
        );
        assert_eq!(cluster_rect((5, 5), r).len(), 0);
    }

    #[test]
    fn runs_get_one_portal_per_piece() {
        let mut got = Vec::new();
        entrances(0..40, |k| !(10..12).contains(&k), |k| got.push(k));
        // Run 0..10 (one piece), run 12..40 (28 cells, two pieces of 14).
        assert_eq!(got, vec![4, 18, 32]);
    }

    #[test]
    fn portals_cross_borders_between_admissible_cells() {
        let rect = CellRect::new(Cell::new(0, 0), 64, 8);
        let g =
            CostGrid::from_fn(rect, 0.1, |c| if c.j == 3 { f32::INFINITY } else { 1.0 }).unwrap();
        let p = portals(&g);
        // One vertical border (columns 31 | 32), rows 0..3 and 4..8: one portal each.
        assert_eq!(
            p,
            vec![
                Portal {
                    low: Cell::new(31, 1),
                    high: Cell::new(32, 1)
                },
                Portal {
                    low: Cell::new(31, 5),
                    high: Cell::new(32, 5)
                },
            ]
        );
    }
}
