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
//!
//! [`smooth_between`] does the same for a robot driven between exact points: the robot's
//! position and the goal point replace the centres of their own cells, so a straight cheapest
//! route runs from the robot to the goal point itself, not through the cell centres beside it.

use super::cost_grid::CostGrid;
use std::f64::consts::SQRT_2;
use strider_core::grid::CellRay;
use strider_core::{Cell, Point2};

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
    let pts: Vec<Point2> = path.iter().map(|c| c.center(d)).collect();
    let legs: Vec<f64> = path
        .windows(2)
        .map(|w| step_cost(grid, w[0], w[1]))
        .collect();
    pull(grid, &pts, &legs)
        .into_iter()
        .map(|k| path[k])
        .collect()
}

/// [`smooth_path`] for a robot driven from the exact point `from` to the exact point `to`
/// along the cell path `path` (typically: `from` in its first cell, `to` in its last). The
/// result is a polyline from `from` to `to` through a subsequence of the path's cell centres.
///
/// A path cell's centre is left out when the end point lying in that cell replaces it: a robot
/// standing in the first cell does not walk to its centre first, and a goal point in the last
/// cell is driven to directly. Shortcuts then start at `from` and end at `to` themselves, so a
/// path whose cheapest route is the straight segment `from`–`to` is driven exactly along it,
/// not through the cell centres next to it. The guarantees of [`smooth_path`] hold for every
/// shortcut; the legs from `from` and to `to` are costed by [`segment_cost_between`], and one
/// that touches an inadmissible cell (an end point outside the admissible grid) is driven as it
/// is, never cut across to a later vertex unless that shortcut is itself admissible.
pub fn smooth_between(grid: &CostGrid, from: Point2, path: &[Cell], to: Point2) -> Vec<Point2> {
    let d = grid.cell_size();
    let (Some(&first), Some(&last)) = (path.first(), path.last()) else {
        return vec![from, to];
    };
    let inside = |p: Point2, c: Cell| Cell::containing(p.x, p.y, d) == Some(c);
    let lo = usize::from(inside(from, first));
    let hi = path.len() - usize::from(inside(to, last));
    // Vertices: `from`, the kept cell centres path[lo..hi], `to`.
    let cells = &path[lo.min(hi)..hi];
    let mut pts = Vec::with_capacity(cells.len() + 2);
    pts.push(from);
    pts.extend(cells.iter().map(|c| c.center(d)));
    pts.push(to);
    let mut scratch = Vec::new();
    let mut end_leg = |a: Point2, b: Point2| {
        segment_cost_between(grid, a, b, &mut scratch).unwrap_or(f64::INFINITY)
    };
    let mut legs = Vec::with_capacity(pts.len() - 1);
    legs.push(end_leg(pts[0], pts[1]));
    legs.extend(cells.windows(2).map(|w| step_cost(grid, w[0], w[1])));
    if pts.len() > 2 {
        legs.push(end_leg(pts[pts.len() - 2], pts[pts.len() - 1]));
    }
    pull(grid, &pts, &legs)
        .into_iter()
        .map(|k| pts[k])
        .collect()
}

/// Eq. 4 with decision 21 for one move of a cell path: d or √2·d times the source cell's cost
/// (`+∞` outside the grid).
fn step_cost(grid: &CostGrid, a: Cell, b: Cell) -> f64 {
    let len = if a.i != b.i && a.j != b.j {
        SQRT_2
    } else {
        1.0
    } * grid.cell_size();
    grid.cost(a).map_or(f64::INFINITY, |c| len * f64::from(c))
}

/// Greedy string pulling over the polyline `pts`, where `legs[k]` is the cost of driving from
/// `pts[k]` to `pts[k + 1]` as planned (`+∞` for a leg that may not be cut short from either
/// side unless the shortcut is admissible). Returns the indices of the kept vertices, first and
/// last included.
fn pull(grid: &CostGrid, pts: &[Point2], legs: &[f64]) -> Vec<usize> {
    debug_assert_eq!(legs.len() + 1, pts.len());
    // Prefix sums of the finite legs, and counts of the infinite ones: the budget of a shortcut
    // over an infinite leg is unbounded (no ∞ − ∞).
    let mut prefix = Vec::with_capacity(pts.len());
    let mut infinite = Vec::with_capacity(pts.len());
    prefix.push(0.0);
    infinite.push(0usize);
    for &l in legs {
        let (p, n) = (prefix[prefix.len() - 1], infinite[infinite.len() - 1]);
        if l.is_finite() {
            prefix.push(p + l);
            infinite.push(n);
        } else {
            prefix.push(p);
            infinite.push(n + 1);
        }
    }
    let mut out = vec![0];
    let mut scratch = Vec::new();
    let mut i = 0;
    while i + 1 < pts.len() {
        let mut best = i + 1;
        let mut misses = 0;
        for j in i + 2..pts.len() {
            let unbounded = infinite[j] > infinite[i];
            let budget = prefix[j] - prefix[i];
            match segment_cost_between(grid, pts[i], pts[j], &mut scratch) {
                Some(c) if unbounded || c <= budget * (1.0 + COST_SLACK) => {
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
        out.push(best);
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
    segment_cost_between(grid, a.center(d), b.center(d), scratch)
}

/// [`segment_cost`] between two points.
pub fn segment_cost_between(
    grid: &CostGrid,
    pa: Point2,
    pb: Point2,
    scratch: &mut Vec<(Cell, f64)>,
) -> Option<f64> {
    let d = grid.cell_size();
    let len = pa.dist(pb);
    scratch.clear();
    let mut ray = CellRay::new(pa, pb, d);
    while let Some(step) = ray.next_with_exit() {
        scratch.push(step);
    }
    if scratch.is_empty() {
        return None;
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
