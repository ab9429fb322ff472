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
        Self {
            candidates: candidates.len(),
            cells: candidates
                .into_iter()
                .zip(counts)
                .filter(|&(_, n)| n > 0)
                .map(|(c, n)| (c, n as f64 / 9.0))
                .collect(),
        }
    }
}

/// The candidate cells of Eq. 11: reachable goal cells on the `info_gain_stride` lattice inside
/// `bounds`, in row-major order. Only the lattice's rows and columns are visited: a mission asks
/// for these every few seconds, and a pass over every reachable cell grew with the explored
/// area (stride² times the work).
pub(super) fn candidates(
    map: &ElevationMap,
    reach: &Reachability,
    bounds: Option<&WorldRect>,
) -> Vec<Cell> {
    let stride = map.params().info_gain_stride.max(1) as i32;
    let d = map.cell_size();
    lattice_cells(reach.rect(), stride)
        .filter(|&c| reach.is_goal_cell(c) && in_bounds(bounds, c, d))
        .collect()
}

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

/// The view rectangle: the known area grown by the sensor reach plus the neighbourhood of
/// Eq. 10.
pub(super) fn view_rect(map: &ElevationMap, around: CellRect) -> CellRect {
    let reach = disc_reach(map.params().r_sensor, map.cell_size());
    rect::expand(around, reach + 2)
}

#[cfg(test)]
mod tests {
    use super::*;

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
    }
}
