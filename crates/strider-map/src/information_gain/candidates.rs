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
/// `bounds`.
pub(super) fn candidates(
    map: &ElevationMap,
    reach: &Reachability,
    bounds: Option<&WorldRect>,
) -> Vec<Cell> {
    let stride = map.params().info_gain_stride.max(1) as i32;
    let d = map.cell_size();
    reach
        .cells()
        .filter(|&c| {
            c.i.rem_euclid(stride) == 0
                && c.j.rem_euclid(stride) == 0
                && reach.is_goal_cell(c)
                && in_bounds(bounds, c, d)
        })
        .collect()
}

/// The view rectangle: the known area grown by the sensor reach plus the neighbourhood of
/// Eq. 10.
pub(super) fn view_rect(map: &ElevationMap, around: CellRect) -> CellRect {
    let reach = disc_reach(map.params().r_sensor, map.cell_size());
    rect::expand(around, reach + 2)
}
