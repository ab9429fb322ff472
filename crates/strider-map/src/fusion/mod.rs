//! Elevation fusion: `updateMapByRangeMeasurements` of Prágr22 Alg. 2 (§4.2), decision 2.
//!
//! Per scan, the highest return in each cell is that cell's measurement z (a 2.5D map keeps the
//! top surface). Its variance is σ_z² = σ_d² + (k_d · range²)², range = distance from the sensor
//! origin. Each cell runs a 1-D Kalman filter (Fankhauser et al. 2014):
//!
//! * first measurement: h = z, σ_h² = σ_z²;
//! * Mahalanobis gate: if |z − h| / √(σ_h² + σ_z²) > `mahalanobis_gate`, z is not fused and
//!   σ_h² += `multi_height_noise` (so a changed surface is eventually re-acquired);
//! * otherwise h ← (σ_z² h + σ_h² z) / (σ_h² + σ_z²), σ_h² ← σ_h² σ_z² / (σ_h² + σ_z²).
//!
//! **Mixed-cell rule.** World and map cells are aligned, so returns from a wall's vertical face sit
//! on a cell edge and depth noise pushes about half of them into the lower neighbour, where they
//! would become its highest point. A return within 3σ of a cell edge whose z lies more than 3σ
//! below this scan's maximum in the neighbour across that edge is attributed to the neighbour's
//! face and ignored for its own cell. The rule catches face returns well below the top of the
//! face; those near its top are not below the neighbour's maximum, and for them:
//!
//! **Ray carving** (the visibility clean-up of Fankhauser et al. 2018, restricted to where it
//! matters). A beam physically travelled its path, so no cell it crossed can have a top above
//! the beam there. Each beam is sampled at half-cell steps over the last cell before its
//! trusted end (the final `CARVE_SIGMAS`·σ are not trusted: the true hit may lie anywhere within
//! the range noise before the return), and each crossed cell records the lowest such height in
//! this scan. A return above that bound (+3σ) is not its cell's surface and is dropped; a map
//! estimate above it (by more than the gate) is lowered to it, with a variance that lets the next
//! returns decide. A return never carves its own cell, so a genuinely bumpy cell keeps its
//! highest point.
//!
//! **Face bounds.** A sensor below the top of a wall or box never sees its top surface: the
//! highest return in such a cell comes from the vertical face the beam hit, and it lies below the
//! top by up to the vertical beam spacing times the distance (on `courtyard-large`, 0.5 m walls
//! seen by a 0.5 m high sensor with 1.06° rows: several centimetres from a few metres away).
//! Kalman-averaging those returns over scans from many distances settles well below the top.
//! Such a measurement is a *lower bound* of the top surface, so it is fused as one. A cell's
//! highest kept return is a face bound when it lies within 3σ of a cell edge that faces the
//! sensor and the map (before this scan) already holds a step up from the neighbour across that
//! edge (by more than the gate times both standard deviations): a stray face return spilled into
//! a ground cell is then gated like any outlier instead of lifting the ground. A face bound more
//! than one σ_z above the estimate replaces it — the "a higher return replaces" rule of
//! Fankhauser et al. for points of one scan, applied across scans to bounds only, with a
//! noise-sized margin (the 3σ gate is coarser than the centimetre differences between the bounds
//! seen from near and far; measured on `courtyard-large`, it left the wall error at 0.029 m
//! median, the 1σ margin at 0.016 m with box tops unbiased to 3 mm). A bound at or below the
//! estimate carries no news and is ignored. A top surface that is seen yields returns away from
//! the facing edge, which are fused as usual.
//!
//! Two passes per scan over scratch rasters covering the scan's bounding box; the rasters are
//! reused, so steady-state fusion allocates nothing.
//!
//! **Parallel passes.** A scan of the default camera (19 200 rays, about 12 000 returns in range)
//! costs about 0.5 ms to fuse on one core and about 0.3 ms on two (measured on the default
//! `strider run`), so the per-return passes run over contiguous chunks of the scan, one private
//! set of rasters per chunk, merged in chunk order: a per-cell maximum or minimum does not
//! depend on the order, and the kept return is merged with the same strict `>` as the
//! sequential scan, so the earliest of equally high returns wins. The result is bit-identical
//! whatever the number of chunks (a test checks 1–7 chunks against each other).
//!
//! The parts: `frame` (where a scan lies), `passes` (the per-return passes and their merges),
//! `carving` (ray carving of one beam), `face_bounds` (the floors a face bound must exceed), `kalman` (the per-cell update)
//! and `scratch` (the reused rasters).

mod carving;
mod face_bounds;
mod frame;
mod kalman;
mod passes;
pub(crate) mod scratch;
mod stats;

pub use stats::FuseStats;

use crate::map::ElevationMap;
use frame::{ScanFrame, ScanGrid};
use passes::{Chunks, bounding_box, highest_and_carving, keep_returns};
use strider_core::PointCloud;

/// Fewest returns per chunk. The passes cost about 25 ns per return and each of the three
/// parallel calls a few tens of µs to hand out (measured on the default `strider run`), so a
/// chunk of fewer returns would gain little or lose.
const MIN_RETURNS_PER_CHUNK: usize = 4096;

impl ElevationMap {
    /// Fuses one scan (decision 2, with the mixed-cell rule). Non-finite returns are skipped and
    /// counted, never a panic. Marks changed cells for [`ElevationMap::update_passability`];
    /// use [`ElevationMap::integrate`] to do both.
    pub fn fuse(&mut self, cloud: &PointCloud) -> FuseStats {
        let chunks = rayon::current_num_threads()
            .min(cloud.points.len() / MIN_RETURNS_PER_CHUNK)
            .max(1);
        self.fuse_in_chunks(cloud, chunks)
    }

    /// [`ElevationMap::fuse`] with the per-return passes split into (at most) `chunks`
    /// contiguous chunks of the scan. The result does not depend on `chunks`.
    pub(crate) fn fuse_in_chunks(&mut self, cloud: &PointCloud, chunks: usize) -> FuseStats {
        let mut stats = FuseStats::default();
        let Some(frame) = ScanFrame::new(&self.params, cloud.origin) else {
            stats.skipped_non_finite = cloud.points.len();
            return stats;
        };
        let chunks = Chunks::new(&cloud.points, chunks);
        let bbox = bounding_box(&mut self.scratch, &chunks, &frame, &mut stats);
        self.scans += 1;
        let Some(grid) = ScanGrid::covering(bbox, self.params.cell_size) else {
            return stats;
        };
        let s = &mut self.scratch;
        if highest_and_carving(s, &chunks, &frame, &grid).is_none()
            || keep_returns(s, &chunks, &frame, &grid, &mut stats).is_none()
        {
            return stats;
        }
        self.face_bound_floors(grid.rect);
        self.apply_measurements(grid.rect, &mut stats);
        stats
    }

    /// Fuses a scan and updates passability and admissibility of the affected region
    /// (Prágr22 Alg. 2 lines 2–3).
    pub fn integrate(&mut self, cloud: &PointCloud) -> FuseStats {
        let stats = self.fuse(cloud);
        self.update_passability();
        stats
    }
}

#[cfg(test)]
mod tests;
