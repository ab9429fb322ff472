//! The per-return passes of fusion over contiguous chunks of a scan (see "Parallel passes" in
//! the module docs of `fusion`): the bounding box, the highest return and the carving bound
//! per cell, then the mixed-cell rule and the highest kept return per cell. Each chunk writes
//! its own rasters; they are merged in chunk order.

use super::carving::{CARVE_EVERY, carve_beam};
use super::frame::{ScanFrame, ScanGrid};
use super::scratch::{ChunkScratch, Columns, FusionScratch, Kept, Located, refill};
use super::stats::FuseStats;
use rayon::prelude::*;
use strider_core::ColoredPoint;

/// The scan's returns in chunks of `len`, each with its own rasters.
pub(super) struct Chunks<'a> {
    pub(super) points: &'a [ColoredPoint],
    pub(super) len: usize,
    pub(super) count: usize,
}

impl<'a> Chunks<'a> {
    /// `points` in (at most) `chunks` contiguous chunks.
    pub(super) fn new(points: &'a [ColoredPoint], chunks: usize) -> Self {
        let len = points.len().div_ceil(chunks.max(1)).max(1);
        Self {
            points,
            len,
            count: points.len().div_ceil(len),
        }
    }
}

/// Pass 0: the bounding box of the usable returns; counts the others into `stats`.
pub(super) fn bounding_box(
    s: &mut FusionScratch,
    chunks: &Chunks,
    frame: &ScanFrame,
    stats: &mut FuseStats,
) -> (f32, f32, f32, f32) {
    if s.chunks.len() < chunks.count {
        s.chunks.resize_with(chunks.count, ChunkScratch::default);
    }
    s.chunks[..chunks.count]
        .par_iter_mut()
        .zip(chunks.points.par_chunks(chunks.len))
        .for_each(|(c, pts)| {
            let mut st = FuseStats::default();
            let (mut x0, mut y0, mut x1, mut y1) = (f32::MAX, f32::MAX, f32::MIN, f32::MIN);
            for p in pts {
                match frame.classify(p) {
                    Ok(_) => {
                        x0 = x0.min(p.x);
                        x1 = x1.max(p.x);
                        y0 = y0.min(p.y);
                        y1 = y1.max(p.y);
                    }
                    Err(true) => st.skipped_non_finite += 1,
                    Err(false) => st.skipped_out_of_range += 1,
                }
            }
            c.bbox = (x0, y0, x1, y1);
            c.stats = st;
        });
    let (mut x0, mut y0, mut x1, mut y1) = (f32::MAX, f32::MAX, f32::MIN, f32::MIN);
    for c in &s.chunks[..chunks.count] {
        x0 = x0.min(c.bbox.0);
        y0 = y0.min(c.bbox.1);
        x1 = x1.max(c.bbox.2);
        y1 = y1.max(c.bbox.3);
        stats.skipped_non_finite += c.stats.skipped_non_finite;
        stats.skipped_out_of_range += c.stats.skipped_out_of_range;
    }
    (x0, y0, x1, y1)
}

/// Pass 1: the highest return per cell and ray carving over the last stretch of each beam,
/// merged into `s.columns`; locates every return. `None` when there is no
/// chunk.
pub(super) fn highest_and_carving(
    s: &mut FusionScratch,
    chunks: &Chunks,
    frame: &ScanFrame,
    grid: &ScanGrid,
) -> Option<()> {
    let n = grid.rect.len();
    let cl = chunks.len;
    refill(&mut s.located, chunks.points.len(), Located::default());
    s.chunks[..chunks.count]
        .par_iter_mut()
        .zip(chunks.points.par_chunks(cl))
        .zip(s.located.par_chunks_mut(cl))
        .enumerate()
        .for_each(|(chunk, ((c, pts), located))| {
            c.columns.reset(n);
            for (j, (p, l)) in pts.iter().zip(located.iter_mut()).enumerate() {
                let Ok(r2) = frame.classify(p) else {
                    l.ci = u32::MAX;
                    continue;
                };
                *l = Located {
                    var: frame.variance(r2),
                    ..grid.locate(p, frame.d)
                };
                let m = &mut c.columns.max_z[grid.index(l.ci as usize, l.cj as usize)];
                *m = m.max(p.z);
                if (chunk * cl + j).is_multiple_of(CARVE_EVERY) {
                    carve_beam(&mut c.columns.carve_z, p, r2, l, frame, grid);
                }
            }
        });
    let (first, rest) = s.chunks[..chunks.count].split_first_mut()?;
    std::mem::swap(&mut s.columns, &mut first.columns);
    for c in rest.iter() {
        s.columns.merge(&c.columns);
    }
    Some(())
}

/// Pass 2: the mixed-cell rule and the carving bound, then the highest kept return per cell is
/// the measurement, merged into `s.kept` in chunk order with the same strict `>` (the earliest
/// highest return wins, as in one sequential pass); counts into `stats`. `None` when there is
/// no chunk.
pub(super) fn keep_returns(
    s: &mut FusionScratch,
    chunks: &Chunks,
    frame: &ScanFrame,
    grid: &ScanGrid,
    stats: &mut FuseStats,
) -> Option<()> {
    let n = grid.rect.len();
    let cl = chunks.len;
    let rule = KeepRule {
        columns: &s.columns,
        frame,
        grid,
    };
    s.chunks[..chunks.count]
        .par_iter_mut()
        .zip(chunks.points.par_chunks(cl))
        .zip(s.located.par_chunks(cl))
        .for_each(|((c, pts), located)| {
            c.kept.reset(n);
            let mut st = FuseStats::default();
            for (p, l) in pts.iter().zip(located) {
                if l.ci != u32::MAX {
                    rule.apply(&mut c.kept, &mut st, p, l);
                }
            }
            c.stats = st;
        });
    for c in &s.chunks[..chunks.count] {
        stats.face_points += c.stats.face_points;
        stats.carved_points += c.stats.carved_points;
        stats.fused_points += c.stats.fused_points;
    }
    let (first, rest) = s.chunks[..chunks.count].split_first_mut()?;
    std::mem::swap(&mut s.kept, &mut first.kept);
    for c in rest.iter() {
        s.kept.merge(&c.kept);
    }
    Some(())
}

/// What pass 2 decides a return by: this scan's merged column bounds.
struct KeepRule<'a> {
    columns: &'a Columns,
    frame: &'a ScanFrame,
    grid: &'a ScanGrid,
}

impl KeepRule<'_> {
    /// One located return: dropped as a neighbour's face (mixed-cell rule) or as carved, else
    /// kept when it is the highest of its cell so far.
    #[inline(always)]
    fn apply(&self, kept: &mut Kept, st: &mut FuseStats, p: &ColoredPoint, l: &Located) {
        let (w, o) = (self.grid.w, self.frame.origin);
        let (ci, cj, u, v, var) = (l.ci as usize, l.cj as usize, l.u, l.v, l.var);
        let k = self.grid.index(ci, cj);
        let sigma3 = 3.0 * var.sqrt();
        let edge = sigma3 * self.frame.inv_d; // 3σ in cell units
        let below = |nk: usize| p.z < self.columns.max_z[nk] - sigma3;
        let face = (u < edge && ci > 0 && below(k - 1))
            || (u > 1.0 - edge && ci + 1 < w && below(k + 1))
            || (v < edge && cj > 0 && below(k - w))
            || (v > 1.0 - edge && cj + 1 < self.grid.h && below(k + w));
        if face {
            st.face_points += 1;
            return;
        }
        if p.z > self.columns.carve_z[k] + sigma3 {
            // A beam of this scan crossed this cell's column below this return.
            st.carved_points += 1;
            return;
        }
        st.fused_points += 1;
        if p.z > kept.z[k] {
            kept.z[k] = p.z;
            kept.var[k] = var;
            kept.rgb[k] = p.rgb;
            // The edges that face the sensor, for the face bounds. Near a corner both edges
            // may face the sensor; either may be the one hit.
            kept.facing[k] = (u < edge && o[0] < p.x) as u8
                | ((u > 1.0 - edge && o[0] > p.x) as u8) << 1
                | ((v < edge && o[1] < p.y) as u8) << 2
                | ((v > 1.0 - edge && o[1] > p.y) as u8) << 3;
        }
    }
}
