//! Any-angle smoothing of 8-connected cell paths (decision 21 extended: how a grid path is
//! driven).
//!
//! A cheapest 8-connected path (Eq. 2) zig-zags between axis and diagonal moves wherever the
//! straight direction is neither, and a robot that follows its cell centres turns by 45° at each
//! switch (turning in place when its controller must). The planner's cost is not the time of
//! that zig-zag: the lattice metric overestimates straight distances by up to 8 %, and the
//! turns cost time the model never sees. So before a path is driven it is shortened by line of
//! sight: from each kept vertex the path jumps to the farthest later path cell whose straight
//! segment
//!
//! * crosses only admissible cells (at an exact lattice-corner crossing, both side cells), and
//! * costs no more than the grid path it replaces, the segment's cost being the continuous
//!   form of Eq. 4, Σ (length inside cell) × c(cell), and the grid path's Eq. 4 with decision 21.
//!
//! So the driven polyline never enters a cell the grid path could not, and its cost on the
//! planning grid never exceeds the grid path's. The scan from each vertex stops after a few
//! consecutive rejected cells (greedy string pulling), which keeps the work near-linear in the
//! path length.

use super::cost_grid::CostGrid;
use std::f64::consts::SQRT_2;
use strider_core::Cell;
use strider_core::grid::CellRay;

/// Consecutive rejected cells after which the scan from a vertex stops.
const LOOKAHEAD: usize = 4;

/// Relative slack of the cost comparison, against rounding.
const COST_SLACK: f64 = 1e-9;

/// The vertices of the smoothed path: a subsequence of `path` that starts and ends with its
/// ends; consecutive vertices are joined by straight segments (see the module docs). Paths of
/// fewer than three cells, and paths with a cell outside `grid` or inadmissible, are returned as
/// they are.
pub fn smooth_path(grid: &CostGrid, path: &[Cell]) -> Vec<Cell> {
    if path.len() < 3 || !path.iter().all(|&c| grid.is_admissible(c)) {
        return path.to_vec();
    }
    let d = grid.cell_size();
    // prefix[k]: Eq. 4 cost of path[0..=k] (source-cell convention).
    let mut prefix = Vec::with_capacity(path.len());
    prefix.push(0.0);
    for w in path.windows(2) {
        let (a, b) = (w[0], w[1]);
        let len = if a.i != b.i && a.j != b.j {
            SQRT_2
        } else {
            1.0
        } * d;
        let c = grid.cost(a).map_or(f64::INFINITY, f64::from);
        prefix.push(prefix[prefix.len() - 1] + len * c);
    }
    let mut out = vec![path[0]];
    let mut scratch = Vec::new();
    let mut i = 0;
    while i + 1 < path.len() {
        let mut best = i + 1;
        let mut misses = 0;
        for j in i + 2..path.len() {
            let budget = prefix[j] - prefix[i];
            match segment_cost(grid, path[i], path[j], &mut scratch) {
                Some(c) if c <= budget * (1.0 + COST_SLACK) => {
                    best = j;
                    misses = 0;
                }
                _ => {
                    misses += 1;
                    if misses >= LOOKAHEAD {
                        break;
                    }
                }
            }
        }
        out.push(path[best]);
        i = best;
    }
    out
}

/// Σ (length inside cell) × c(cell) along the straight segment between the centres of `a` and
/// `b`, or `None` when it touches an inadmissible or outside cell (at a corner crossing, both
/// side cells count as touched). `scratch` holds the traversal.
pub fn segment_cost(
    grid: &CostGrid,
    a: Cell,
    b: Cell,
    scratch: &mut Vec<(Cell, f64)>,
) -> Option<f64> {
    let d = grid.cell_size();
    let (pa, pb) = (a.center(d), b.center(d));
    let len = pa.dist(pb);
    scratch.clear();
    let mut ray = CellRay::new(pa, pb, d);
    while let Some(step) = ray.next_with_exit() {
        scratch.push(step);
    }
    let mut total = 0.0;
    let mut prev_exit = 0.0;
    for (k, &(c, exit)) in scratch.iter().enumerate() {
        let cost = f64::from(grid.cost(c).filter(|v| v.is_finite())?);
        let inside = exit - prev_exit;
        if inside <= 1e-12 && k > 0 && k + 1 < scratch.len() {
            // A corner crossing: the traversal reports one side cell; the other is the corner's
            // fourth cell, diagonal to this one between its neighbours on the ray.
            let (p, n) = (scratch[k - 1].0, scratch[k + 1].0);
            let other = Cell::new(p.i + n.i - c.i, p.j + n.j - c.j);
            if !grid.is_admissible(other) {
                return None;
            }
        }
        total += inside.max(0.0) * len * cost;
        prev_exit = exit;
    }
    Some(total)
}

#[cfg(test)]
mod tests {
    use super::*;
    use strider_core::CellRect;

    fn grid(w: u32, h: u32, blocked: &[(i32, i32)]) -> CostGrid {
        let rect = CellRect::new(Cell::new(0, 0), w, h);
        let cost = rect
            .cells()
            .map(|c| {
                if blocked.contains(&(c.i, c.j)) {
                    f32::INFINITY
                } else {
                    1.0
                }
            })
            .collect();
        CostGrid::new(rect, 0.5, cost).unwrap()
    }

    #[test]
    fn a_zig_zag_in_the_open_becomes_one_segment() {
        let g = grid(10, 10, &[]);
        // Knight-like zig-zag from (0, 0) to (8, 4): diagonal, axis, diagonal, ...
        let path: Vec<Cell> = [
            (0, 0),
            (1, 1),
            (2, 1),
            (3, 2),
            (4, 2),
            (5, 3),
            (6, 3),
            (7, 4),
            (8, 4),
        ]
        .iter()
        .map(|&(i, j)| Cell::new(i, j))
        .collect();
        assert_eq!(
            smooth_path(&g, &path),
            vec![Cell::new(0, 0), Cell::new(8, 4)]
        );
        let straight = segment_cost(&g, path[0], path[8], &mut Vec::new()).unwrap();
        assert!((straight - 0.5 * (64.0f64 + 16.0).sqrt()).abs() < 1e-9);
    }

    #[test]
    fn segments_do_not_cut_a_blocked_corner() {
        // A blocked cell at (2, 1) on the inside of an L-shaped path.
        let g = grid(6, 6, &[(2, 1)]);
        let path: Vec<Cell> = [(0, 0), (1, 0), (2, 0), (3, 0), (3, 1), (3, 2)]
            .iter()
            .map(|&(i, j)| Cell::new(i, j))
            .collect();
        let s = smooth_path(&g, &path);
        assert_eq!(s.first(), Some(&path[0]));
        assert_eq!(s.last(), path.last());
        for w in s.windows(2) {
            assert!(segment_cost(&g, w[0], w[1], &mut Vec::new()).is_some());
        }
        // A 45° ray through the corner of the blocked (1, 0) is refused.
        let g2 = grid(4, 4, &[(1, 0)]);
        assert!(segment_cost(&g2, Cell::new(0, 0), Cell::new(2, 2), &mut Vec::new()).is_none());
    }
}
