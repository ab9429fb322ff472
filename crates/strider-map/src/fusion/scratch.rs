//! The per-scan scratch rasters of fusion, reused between scans so that steady-state fusion
//! allocates nothing.

use super::stats::FuseStats;

/// Per-scan scratch rasters over the scan's bounding box, reused between scans.
#[derive(Clone, Debug, Default)]
pub(crate) struct FusionScratch {
    /// The merged column bounds per cell (pass 1).
    pub(super) columns: Columns,
    /// Per return, where pass 1 located it (reused by pass 2); `ci == u32::MAX` when skipped.
    pub(super) located: Vec<Located>,
    /// The private rasters of each chunk of returns (see "Parallel passes" in the module docs
    /// of `fusion`); chunk 0's are swapped with the merged ones above.
    pub(super) chunks: Vec<ChunkScratch>,
    /// The kept returns per cell (pass 2).
    pub(super) kept: Kept,
    /// For a kept return on a facing edge: the facing neighbour's map elevation plus the gate
    /// times its standard deviation, the height the cell must exceed for the return to be a face
    /// bound; +∞ when the neighbour is unobserved.
    pub(super) bound_floor: Vec<f32>,
}

/// What pass 1 learns of each cell's column.
#[derive(Clone, Debug, Default)]
pub(super) struct Columns {
    /// The highest return, −∞ where none.
    pub(super) max_z: Vec<f32>,
    /// The carving bound: the lowest height at which a beam of this scan crossed the column,
    /// +∞ where none.
    pub(super) carve_z: Vec<f32>,
}

impl Columns {
    /// Empties the rasters for `n` cells.
    pub(super) fn reset(&mut self, n: usize) {
        refill(&mut self.max_z, n, f32::NEG_INFINITY);
        refill(&mut self.carve_z, n, f32::INFINITY);
    }

    /// Merges `other` in: per-cell maximum and minimum, independent of the order.
    pub(super) fn merge(&mut self, other: &Columns) {
        for (a, b) in self.max_z.iter_mut().zip(&other.max_z) {
            *a = a.max(*b);
        }
        for (a, b) in self.carve_z.iter_mut().zip(&other.carve_z) {
            *a = a.min(*b);
        }
    }
}

/// The highest return kept per cell (pass 2), with what the Kalman update needs of it.
#[derive(Clone, Debug, Default)]
pub(super) struct Kept {
    /// Its height, −∞ where none.
    pub(super) z: Vec<f32>,
    /// Its σ_z².
    pub(super) var: Vec<f32>,
    /// Its colour.
    pub(super) rgb: Vec<[u8; 3]>,
    /// Bit f set: it sits on the cell edge towards neighbour `FACING[f]`, and that edge faces
    /// the sensor.
    pub(super) facing: Vec<u8>,
}

impl Kept {
    /// Empties the rasters for `n` cells.
    pub(super) fn reset(&mut self, n: usize) {
        refill(&mut self.z, n, f32::NEG_INFINITY);
        refill(&mut self.var, n, 0.0);
        refill(&mut self.rgb, n, [0; 3]);
        refill(&mut self.facing, n, 0);
    }

    /// Takes over `other`'s return in every cell where it is strictly higher.
    pub(super) fn merge(&mut self, other: &Kept) {
        for k in 0..self.z.len() {
            if other.z[k] > self.z[k] {
                self.z[k] = other.z[k];
                self.var[k] = other.var[k];
                self.rgb[k] = other.rgb[k];
                self.facing[k] = other.facing[k];
            }
        }
    }
}

/// One chunk's share of the per-return passes: its own rasters over the scan rectangle (same
/// meaning as in [`FusionScratch`]), its bounding box and its counts.
#[derive(Clone, Debug, Default)]
pub(super) struct ChunkScratch {
    pub(super) columns: Columns,
    pub(super) kept: Kept,
    /// Bounding box of the chunk's usable returns: (x0, y0, x1, y1).
    pub(super) bbox: (f32, f32, f32, f32),
    pub(super) stats: FuseStats,
}

/// Where a return lies: cell column/row in the scan rectangle, position inside the cell (cell
/// units) and its measurement variance σ².
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Located {
    pub(super) ci: u32,
    pub(super) cj: u32,
    pub(super) u: f32,
    pub(super) v: f32,
    pub(super) var: f32,
}

/// Makes `v` hold `n` copies of `value`, reusing its allocation.
pub(super) fn refill<T: Clone>(v: &mut Vec<T>, n: usize, value: T) {
    v.clear();
    v.resize(n, value);
}
