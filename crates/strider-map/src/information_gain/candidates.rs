//! The cells Eq. 11 is evaluated on, the view rectangle they need and the result.

use crate::map::ElevationMap;
use crate::passability::disc_reach;
use crate::reachability::Reachability;
use crate::rect::{self, WorldRect, in_bounds};
use strider_core::{Cell, CellRect};

/// I_model (Eq. 11) of the candidate cells with non-zero gain.
#[derive(Clone, Debug, Default)]
pub struct InfoGain {
    /// Candidates with I_model > 0 and their gain, in row-major order (the fixed order of
    /// Alg. 3).
    pub cells: Vec<(Cell, f64)>,
    /// Number of candidate cells evaluated.
    pub candidates: usize,
}

impl InfoGain {
    /// The gains as a dense raster over `rect` (0 elsewhere), for rendering.
    pub fn raster(&self, rect: CellRect) -> Vec<f32> {
        let mut out = vec![0.0; rect.len()];
        for &(c, g) in &self.cells {
            if let Some(k) = rect.index(c) {
                out[k] = g as f32;
            }
        }
        out
    }

    /// Total gain over all cells.
    pub fn total(&self) -> f64 {
        self.cells.iter().map(|&(_, g)| g).sum()
    }

    /// The gains from the candidates and their 9·I_model counts (in the same order).
    pub(super) fn from_counts(candidates: Vec<Cell>, counts: Vec<u32>) -> Self {
        let mut counts = counts.into_iter();
        Self::from_count_of(&candidates, |_| counts.next().unwrap_or(0))
    }

    /// The gains from the candidates and `count`, their 9·I_model counts, read in order: most
    /// candidates of a large explored map count 0, so no count vector is built.
    pub(super) fn from_count_of(candidates: &[Cell], mut count: impl FnMut(Cell) -> u32) -> Self {
        let mut cells = Vec::new();
        for &c in candidates {
            let n = count(c);
            if n > 0 {
                cells.push((c, n as f64 / 9.0));
            }
        }
        Self {
            candidates: candidates.len(),
            cells,
        }
    }
}

/// The candidate cells of Eq. 11: reachable goal cells on the `info_gain_stride` lattice inside
/// `bounds`, in row-major order. Only the lattice's rows and columns are visited: a mission asks
/// for these every few seconds, and a pass over every reachable cell grew with the explored
/// area (stride² times the work). Each lattice row is a strided walk over the row's slices of
/// the two bitmaps: a large map has about a million lattice points.
pub(super) fn candidates(
    map: &ElevationMap,
    reach: &Reachability,
    bounds: Option<&WorldRect>,
) -> Vec<Cell> {
    let stride = map.params().info_gain_stride.max(1) as usize;
    let d = map.cell_size();
    let rect = reach.rect();
    let (reachable, admissible) = (reach.bitmap(), reach.admissible_bitmap());
    let s = stride as i64;
    let first = |lo: i64| lo + (-lo).rem_euclid(s);
    let (i_lo, j_lo) = (rect.min.i as i64, rect.min.j as i64);
    let (i0, j_end) = (first(i_lo), j_lo + rect.height as i64);
    let w = rect.width as usize;
    let skip = (i0 - i_lo) as usize;
    let mut out = Vec::new();
    for j in (first(j_lo)..j_end).step_by(stride) {
        let row = (j - j_lo) as usize * w;
        let cols = reachable[row..row + w]
            .iter()
            .zip(&admissible[row..row + w]);
        for (n, (&r, &a)) in cols.skip(skip).step_by(stride).enumerate() {
            if r && a {
                let c = Cell::new((i0 + n as i64 * s) as i32, j as i32);
                if in_bounds(bounds, c, d) {
                    out.push(c);
                }
            }
        }
    }
    out
}

/// The view rectangle: the known area grown by the sensor reach plus the neighbourhood of
/// Eq. 10.
pub(super) fn view_rect(map: &ElevationMap, around: CellRect) -> CellRect {
    let reach = disc_reach(map.params().r_sensor, map.cell_size());
    rect::expand(around, reach + 2)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::{block, flat, lattice_map};

    /// The cells of `rect` whose coordinates are both multiples of `stride` (≥ 1), row-major.
    fn lattice_cells(rect: CellRect, stride: i32) -> impl Iterator<Item = Cell> {
        let first = |lo: i32| lo + (-lo).rem_euclid(stride);
        let (i0, j0) = (first(rect.min.i), first(rect.min.j));
        let i_end = rect.min.i as i64 + rect.width as i64;
        let j_end = rect.min.j as i64 + rect.height as i64;
        let step = stride as usize;
        (j0 as i64..j_end).step_by(step).flat_map(move |j| {
            (i0 as i64..i_end)
                .step_by(step)
                .map(move |i| Cell::new(i as i32, j as i32))
        })
    }

    proptest::proptest! {
        /// The lattice walk visits exactly the cells of the rectangle on the lattice, in
        /// row-major order, wherever the rectangle lies (negative coordinates included).
        #[test]
        fn lattice_cells_are_the_rectangles_cells_on_the_lattice(
            i in -40..40i32, j in -40..40i32, w in 0..30u32, h in 0..30u32, stride in 1..7i32,
        ) {
            let rect = CellRect::new(Cell::new(i, j), w, h);
            let want: Vec<Cell> = rect
                .cells()
                .filter(|c| c.i.rem_euclid(stride) == 0 && c.j.rem_euclid(stride) == 0)
                .collect();
            let got: Vec<Cell> = lattice_cells(rect, stride).collect();
            proptest::prop_assert_eq!(got, want);
        }

        /// The strided walk over the bitmaps gives the lattice cells that are reachable goal
        /// cells inside the bounds, in row-major order, wherever the map lies.
        #[test]
        fn candidates_are_the_reachable_goal_cells_on_the_lattice(
            i in -30..30i32, j in -30..30i32, w in 1..25i32, h in 1..25i32,
            holes in proptest::collection::vec((0..25i32, 0..25i32), 0..40),
            stride in 1..5u32,
            bounded in proptest::bool::ANY,
            (bx, by) in (-2.0f64..2.0, -2.0f64..2.0),
        ) {
            let mut m = lattice_map(0.1, 8);
            flat(&mut m, block(i, j, w, h).filter(|c| {
                !holes.contains(&(c.i - i, c.j - j)) || (c.i, c.j) == (i, j)
            }));
            m.set_info_gain_stride(stride);
            let reach = Reachability::compute(&m, Cell::new(i, j));
            let bounds = WorldRect::new(
                strider_core::Point2::new(bx, by),
                strider_core::Point2::new(bx + 1.2, by + 0.9),
            );
            let bounds = bounded.then_some(&bounds);
            let want: Vec<Cell> = lattice_cells(reach.rect(), stride as i32)
                .filter(|&c| reach.is_goal_cell(c) && in_bounds(bounds, c, 0.1))
                .collect();
            proptest::prop_assert_eq!(candidates(&m, &reach, bounds), want);
        }
    }
}
