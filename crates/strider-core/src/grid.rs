//! The global cell lattice and the shape iterators shared by every grid algorithm.
//!
//! Cells are addressed by integer coordinates on one global lattice anchored at the world origin:
//! cell `(i, j)` covers `[i·d, (i+1)·d) × [j·d, (j+1)·d)` for cell size `d` (Prágr22 §3, d_ν). Every
//! grid in Strider (the robot's map, the simulator's world, cost layers) uses this lattice, so a
//! cell index means the same place everywhere and no resampling is needed between layers of the
//! same resolution.

use crate::geom::Point2;
use serde::{Deserialize, Serialize};

/// A cell of the global lattice.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize,
)]
pub struct Cell {
    /// Column (x) index.
    pub i: i32,
    /// Row (y) index.
    pub j: i32,
}

impl Cell {
    /// A cell from its indices.
    pub const fn new(i: i32, j: i32) -> Self {
        Self { i, j }
    }
    /// The cell containing world point `(x, y)` for cell size `d`; `None` for non-finite input or
    /// coordinates outside the i32 lattice.
    #[inline]
    pub fn containing(x: f64, y: f64, d: f64) -> Option<Cell> {
        let fi = (x / d).floor();
        let fj = (y / d).floor();
        if fi.is_finite() && fj.is_finite() && fi.abs() < 1e9 && fj.abs() < 1e9 {
            Some(Cell::new(fi as i32, fj as i32))
        } else {
            None
        }
    }
    /// The centre of this cell for cell size `d`.
    #[inline]
    pub fn center(self, d: f64) -> Point2 {
        Point2::new((self.i as f64 + 0.5) * d, (self.j as f64 + 0.5) * d)
    }
    /// This cell shifted by `(di, dj)`.
    #[inline]
    pub const fn offset(self, di: i32, dj: i32) -> Cell {
        Cell::new(self.i + di, self.j + dj)
    }
    /// The 8-neighbourhood 8nb(ν) (Prágr22 Eq. 1), in a fixed order.
    pub fn neighbours8(self) -> impl Iterator<Item = Cell> {
        NEIGHBOURS8.iter().map(move |&(di, dj)| self.offset(di, dj))
    }
    /// Euclidean distance between cell centres, in cells.
    pub fn dist_cells(self, other: Cell) -> f64 {
        ((self.i - other.i) as f64).hypot((self.j - other.j) as f64)
    }
}

/// Offsets of the 8-neighbourhood, axis neighbours first.
pub const NEIGHBOURS8: [(i32, i32); 8] = [
    (1, 0),
    (0, 1),
    (-1, 0),
    (0, -1),
    (1, 1),
    (-1, 1),
    (-1, -1),
    (1, -1),
];

/// An axis-aligned rectangle of cells, `min` inclusive, `min + size` exclusive.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct CellRect {
    /// Lowest cell (inclusive).
    pub min: Cell,
    /// Number of columns.
    pub width: u32,
    /// Number of rows.
    pub height: u32,
}

impl CellRect {
    /// A rectangle from its lowest cell and size.
    pub const fn new(min: Cell, width: u32, height: u32) -> Self {
        Self { min, width, height }
    }
    /// Number of cells.
    pub fn len(&self) -> usize {
        self.width as usize * self.height as usize
    }
    /// True when the rectangle holds no cell.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// True when `c` lies inside.
    #[inline]
    pub fn contains(&self, c: Cell) -> bool {
        let (di, dj) = (
            c.i as i64 - self.min.i as i64,
            c.j as i64 - self.min.j as i64,
        );
        di >= 0 && dj >= 0 && di < self.width as i64 && dj < self.height as i64
    }
    /// Row-major index of `c` (row = j), or `None` outside.
    #[inline]
    pub fn index(&self, c: Cell) -> Option<usize> {
        if self.contains(c) {
            Some((c.j - self.min.j) as usize * self.width as usize + (c.i - self.min.i) as usize)
        } else {
            None
        }
    }
    /// The cell at row-major index `k` (must be `< len()`).
    #[inline]
    pub fn cell(&self, k: usize) -> Cell {
        let w = self.width as usize;
        Cell::new(self.min.i + (k % w) as i32, self.min.j + (k / w) as i32)
    }
    /// All cells in row-major order.
    pub fn cells(&self) -> impl Iterator<Item = Cell> + '_ {
        (0..self.len()).map(|k| self.cell(k))
    }
}

/// Largest radius, in cells, of a disc that [`disc_offsets`] builds: 2048 cells give 13.2 M
/// offsets (105 MB). The parameters that become discs are validated far below it where they
/// enter (the map's radii at most 1000 cells, footprints 200); the cap only keeps a radius that
/// escaped validation from allocating and looping without bound.
pub const MAX_DISC_RADIUS_CELLS: i32 = 2048;

/// Cell offsets of a disc of radius `r` (same unit as `d`), centre included: every cell whose
/// centre lies within `r` of the centre cell's centre. Used for footprints δ(r, ν) (Prágr22 Eq. 12)
/// and descriptor neighbourhoods. Sorted by distance, then row, then column. A radius beyond
/// [`MAX_DISC_RADIUS_CELLS`] cells is cut to it.
pub fn disc_offsets(r: f64, d: f64) -> Vec<(i32, i32)> {
    if !(r.is_finite() && d.is_finite() && d > 0.0 && r >= 0.0) {
        return vec![(0, 0)];
    }
    let rc = (r / d).min(MAX_DISC_RADIUS_CELLS as f64);
    let n = rc.floor() as i32;
    let mut v: Vec<(i32, i32)> = Vec::with_capacity(((2 * n + 1) * (2 * n + 1)) as usize);
    for dj in -n..=n {
        for di in -n..=n {
            if ((di * di + dj * dj) as f64) <= rc * rc + 1e-9 {
                v.push((di, dj));
            }
        }
    }
    v.sort_by_key(|&(di, dj)| (di * di + dj * dj, dj, di));
    v
}

/// The cells a straight 2-D segment passes through, in order from its start (Amanatides–Woo
/// traversal). Every cell whose interior the segment crosses is yielded exactly once; a segment
/// through a cell corner steps through one of the two side cells.
#[derive(Clone, Debug)]
pub struct CellRay {
    cell: Cell,
    end: Cell,
    step_i: i32,
    step_j: i32,
    t_max_x: f64,
    t_max_y: f64,
    t_delta_x: f64,
    t_delta_y: f64,
    remaining: u32,
}

impl CellRay {
    /// The traversal from `a` to `b` (world coordinates) with cell size `d`. Non-finite input
    /// yields an empty traversal.
    pub fn new(a: Point2, b: Point2, d: f64) -> Self {
        let (Some(start), Some(end)) =
            (Cell::containing(a.x, a.y, d), Cell::containing(b.x, b.y, d))
        else {
            return Self::empty();
        };
        let (dx, dy) = (b.x - a.x, b.y - a.y);
        let step_i = if dx > 0.0 {
            1
        } else if dx < 0.0 {
            -1
        } else {
            0
        };
        let step_j = if dy > 0.0 {
            1
        } else if dy < 0.0 {
            -1
        } else {
            0
        };
        let next_x = if step_i > 0 {
            (start.i + 1) as f64 * d
        } else {
            start.i as f64 * d
        };
        let next_y = if step_j > 0 {
            (start.j + 1) as f64 * d
        } else {
            start.j as f64 * d
        };
        let t_max_x = if step_i != 0 {
            (next_x - a.x) / dx
        } else {
            f64::INFINITY
        };
        let t_max_y = if step_j != 0 {
            (next_y - a.y) / dy
        } else {
            f64::INFINITY
        };
        let t_delta_x = if step_i != 0 {
            d / dx.abs()
        } else {
            f64::INFINITY
        };
        let t_delta_y = if step_j != 0 {
            d / dy.abs()
        } else {
            f64::INFINITY
        };
        let remaining = ((end.i - start.i).unsigned_abs() + (end.j - start.j).unsigned_abs()) + 1;
        Self {
            cell: start,
            end,
            step_i,
            step_j,
            t_max_x,
            t_max_y,
            t_delta_x,
            t_delta_y,
            remaining,
        }
    }

    fn empty() -> Self {
        Self {
            cell: Cell::default(),
            end: Cell::default(),
            step_i: 0,
            step_j: 0,
            t_max_x: f64::INFINITY,
            t_max_y: f64::INFINITY,
            t_delta_x: f64::INFINITY,
            t_delta_y: f64::INFINITY,
            remaining: 0,
        }
    }

    /// The last cell of the traversal (the cell containing the end point).
    pub fn end(&self) -> Cell {
        self.end
    }

    /// The next cell and where the segment leaves it, as a fraction t ∈ [0, 1] of the segment
    /// (1 for the last cell). The part of the segment inside the cell runs from the previous
    /// cell's exit (0 for the first) to this one, so lengths along the segment are exact.
    #[inline]
    pub fn next_with_exit(&mut self) -> Option<(Cell, f64)> {
        if self.remaining == 0 {
            return None;
        }
        let out = self.cell;
        self.remaining -= 1;
        let exit;
        if out == self.end {
            self.remaining = 0;
            exit = 1.0;
        } else if self.t_max_x < self.t_max_y {
            exit = self.t_max_x.min(1.0);
            self.cell.i += self.step_i;
            self.t_max_x += self.t_delta_x;
        } else {
            exit = self.t_max_y.min(1.0);
            self.cell.j += self.step_j;
            self.t_max_y += self.t_delta_y;
        }
        Some((out, exit))
    }
}

impl Iterator for CellRay {
    type Item = Cell;
    #[inline]
    fn next(&mut self) -> Option<Cell> {
        self.next_with_exit().map(|(c, _)| c)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn containing_handles_negative_coordinates() {
        assert_eq!(Cell::containing(-0.01, 0.0, 0.05), Some(Cell::new(-1, 0)));
        assert_eq!(
            Cell::containing(0.049, -0.051, 0.05),
            Some(Cell::new(0, -2))
        );
        assert_eq!(Cell::containing(f64::NAN, 0.0, 0.05), None);
    }

    #[test]
    fn disc_counts() {
        assert_eq!(disc_offsets(0.0, 0.05), vec![(0, 0)]);
        assert_eq!(disc_offsets(0.05, 0.05).len(), 5);
        assert_eq!(disc_offsets(0.25, 0.05).len(), 81);
    }

    #[test]
    fn huge_discs_are_capped() {
        // 1e9 m at 5 cm: 2e10 cells, beyond i32; the disc stops at the cap.
        let v = disc_offsets(1e9, 0.05);
        let n = MAX_DISC_RADIUS_CELLS;
        assert!(v.iter().all(|&(i, j)| i.abs() <= n && j.abs() <= n));
        assert!(v.contains(&(n, 0)) && !v.contains(&(n, 1)));
        assert_eq!(disc_offsets(f64::INFINITY, 0.05), vec![(0, 0)]);
        assert_eq!(disc_offsets(1.0, 0.0), vec![(0, 0)]);
    }

    #[test]
    fn rect_index_round_trip() {
        let r = CellRect::new(Cell::new(-3, 5), 7, 4);
        for k in 0..r.len() {
            assert_eq!(r.index(r.cell(k)), Some(k));
        }
        assert_eq!(r.index(Cell::new(4, 5)), None);
    }

    #[test]
    fn exits_split_the_segment_into_the_lengths_inside_each_cell() {
        // From (0.05, 0.05) to (0.35, 0.15) with d = 0.1: x crosses 0.1, 0.2, 0.3 at t = 1/6,
        // 1/2, 5/6 and y crosses 0.1 at t = 1/2 (a corner: one side cell with zero length).
        let mut r = CellRay::new(Point2::new(0.05, 0.05), Point2::new(0.35, 0.15), 0.1);
        let mut seen = Vec::new();
        while let Some(x) = r.next_with_exit() {
            seen.push(x);
        }
        let exits: Vec<f64> = seen.iter().map(|x| x.1).collect();
        assert_eq!(seen.first().map(|x| x.0), Some(Cell::new(0, 0)));
        assert_eq!(seen.last().map(|x| x.0), Some(Cell::new(3, 1)));
        assert!(exits.windows(2).all(|w| w[0] <= w[1] + 1e-12), "{exits:?}");
        assert!((exits[0] - 1.0 / 6.0).abs() < 1e-12);
        assert_eq!(*exits.last().unwrap(), 1.0);
    }

    proptest! {
        #[test]
        fn ray_is_connected_and_ends_at_end(ax in -5.0..5.0f64, ay in -5.0..5.0f64, bx in -5.0..5.0f64, by in -5.0..5.0f64) {
            let d = 0.1;
            let cells: Vec<Cell> = CellRay::new(Point2::new(ax, ay), Point2::new(bx, by), d).collect();
            prop_assert_eq!(cells[0], Cell::containing(ax, ay, d).unwrap());
            prop_assert_eq!(*cells.last().unwrap(), Cell::containing(bx, by, d).unwrap());
            for w in cells.windows(2) {
                let (di, dj) = ((w[1].i - w[0].i).abs(), (w[1].j - w[0].j).abs());
                prop_assert_eq!(di + dj, 1, "4-connected step");
            }
        }

        #[test]
        fn ray_visits_cells_the_segment_crosses(ax in -2.0..2.0f64, ay in -2.0..2.0f64, bx in -2.0..2.0f64, by in -2.0..2.0f64) {
            let d = 0.1;
            let cells: std::collections::HashSet<Cell> = CellRay::new(Point2::new(ax, ay), Point2::new(bx, by), d).collect();
            for k in 0..=200 {
                let t = k as f64 / 200.0;
                let c = Cell::containing(ax + t * (bx - ax), ay + t * (by - ay), d).unwrap();
                // Points exactly on a cell corner may belong to either side cell.
                let near_corner = {
                    let (x, y) = (ax + t * (bx - ax), ay + t * (by - ay));
                    let fx = (x / d - (x / d).round()).abs();
                    let fy = (y / d - (y / d).round()).abs();
                    fx < 1e-6 || fy < 1e-6
                };
                prop_assert!(cells.contains(&c) || near_corner, "sample {:?} missing", c);
            }
        }
    }
}
