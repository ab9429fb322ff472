//! Elevation fusion: `updateMapByRangeMeasurements` of `001` Alg. 2 (§4.2), decision 2.
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
//! took about 0.5 ms to fuse on one core while the other sat idle; the per-return passes now
//! take about 0.3 ms on two (default `strider run`, temporary instrumentation). They run over contiguous chunks of the scan, one private set of rasters per
//! chunk, merged in chunk order: a per-cell maximum or minimum does not depend on the order, and
//! the kept return is merged with the same strict `>` as the sequential scan, so the earliest of
//! equally high returns wins. The result is bit-identical whatever the number of chunks (a test
//! checks 1–7 chunks against each other).

use crate::map::ElevationMap;
use crate::params::ColorMode;
use rayon::prelude::*;
use strider_core::{Cell, CellRect, PointCloud};

/// What one call to [`ElevationMap::fuse`] did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FuseStats {
    /// Finite returns within `max_point_range` that entered their cell's per-scan maximum.
    pub fused_points: usize,
    /// Returns with a non-finite coordinate (or a scan with a non-finite origin).
    pub skipped_non_finite: usize,
    /// Returns farther than `max_point_range` from the sensor origin.
    pub skipped_out_of_range: usize,
    /// Returns attributed to a neighbour's vertical face by the mixed-cell rule.
    pub face_points: usize,
    /// Cells that received a measurement this scan (initialised, fused or gated).
    pub cells_updated: usize,
    /// Cells whose measurement was rejected by the Mahalanobis gate.
    pub cells_gated: usize,
    /// Returns dropped because a beam of the same scan crossed their cell's column below them.
    pub carved_points: usize,
    /// Cells whose estimate a beam contradicted and lowered (ray carving).
    pub cells_carved: usize,
    /// Cells whose measurement was a face bound that raised the estimate.
    pub face_bounds_raised: usize,
    /// Cells whose measurement was a face bound at or below the estimate (not fused).
    pub face_bounds_ignored: usize,
}

/// Per-scan scratch rasters over the scan's bounding box, reused between scans.
#[derive(Clone, Debug, Default)]
pub(crate) struct FusionScratch {
    /// Highest return per cell (pass 1), −∞ where none.
    max_z: Vec<f32>,
    /// Per return, where pass 1 located it (reused by pass 2); `ci == u32::MAX` when skipped.
    located: Vec<Located>,
    /// The private rasters of each chunk of returns (see "Parallel passes"); chunk 0's are
    /// swapped with the merged ones above.
    chunks: Vec<ChunkScratch>,
    /// Carving bound per cell: the lowest height at which a beam of this scan crossed the cell's
    /// column (pass 2), +∞ where none.
    carve_z: Vec<f32>,
    /// Highest return kept per cell (pass 2), −∞ where none.
    best_z: Vec<f32>,
    /// σ_z² of the kept return.
    best_var: Vec<f32>,
    /// Colour of the kept return.
    best_rgb: Vec<[u8; 3]>,
    /// Bit f set: the kept return sits on the cell edge towards neighbour `FACING[f]`, and that
    /// edge faces the sensor.
    facing: Vec<u8>,
    /// For a kept return on a facing edge: the facing neighbour's map elevation plus the gate
    /// times its standard deviation, the height the cell must exceed for the return to be a face
    /// bound; +∞ when the neighbour is unobserved.
    bound_floor: Vec<f32>,
}

/// One chunk's share of the per-return passes: its own rasters over the scan rectangle (same
/// meaning as in [`FusionScratch`]), its bounding box and its counts.
#[derive(Clone, Debug, Default)]
pub(crate) struct ChunkScratch {
    max_z: Vec<f32>,
    carve_z: Vec<f32>,
    best_z: Vec<f32>,
    best_var: Vec<f32>,
    best_rgb: Vec<[u8; 3]>,
    facing: Vec<u8>,
    /// Bounding box of the chunk's usable returns: (x0, y0, x1, y1).
    bbox: (f32, f32, f32, f32),
    stats: FuseStats,
}

/// Fewest returns per chunk. The passes cost about 25 ns per return and each of the three
/// parallel calls a few tens of µs to hand out (default `strider run`, temporary
/// instrumentation), so a chunk of fewer returns would gain little or lose.
const MIN_RETURNS_PER_CHUNK: usize = 4096;

/// Where a return lies: cell column/row in the scan rectangle, position inside the cell (cell
/// units) and its measurement variance σ².
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Located {
    ci: u32,
    cj: u32,
    u: f32,
    v: f32,
    var: f32,
}

/// A return's squared range from the origin when it is usable: `Ok(range²)`, or
/// `Err(true)` for non-finite and `Err(false)` for out of range.
#[inline(always)]
fn classify_point(p: &strider_core::ColoredPoint, o: [f32; 3], max_r2: f32) -> Result<f32, bool> {
    if !(p.x.is_finite() && p.y.is_finite() && p.z.is_finite()) {
        return Err(true);
    }
    let (dx, dy, dz) = (p.x - o[0], p.y - o[1], p.z - o[2]);
    let r2 = dx * dx + dy * dy + dz * dz;
    if r2 <= max_r2 { Ok(r2) } else { Err(false) }
}

/// `v.floor()` for |v| < 2⁶², without a libm call on baseline x86-64 (no SSE4.1 `roundsd`).
#[inline(always)]
fn fast_floor(v: f64) -> f64 {
    let t = v as i64 as f64;
    if t > v { t - 1.0 } else { t }
}

/// Carving samples each beam at half-cell steps from its trusted end back over this many
/// steps (one cell). The trusted end of a beam that hit a face lies at most about 1σ in front
/// of it, so one cell back reaches the cell in front of the face, where spilled face returns
/// sit; looking no further keeps carving at three samples per return. A sample's height is
/// one the beam really had inside that cell, so the bound is sound (only slightly weaker than
/// the beam's minimum over the cell).
const CARVE_SAMPLES: usize = 2;
/// Carving uses every `CARVE_EVERY`-th beam of a scan (in scan order, so deterministic). A cell in
/// front of a face is crossed by many face beams; a subset finds it as surely (measured on
/// courtyard-large: the same elevation error with every beam and with every fourth) at a quarter
/// of the cost.
const CARVE_EVERY: usize = 4;
/// The last `CARVE_SIGMAS`·σ of each beam are not trusted to have been travelled.
const CARVE_SIGMAS: f32 = 4.0;
/// Neighbour offsets across the cell edges a return can face the sensor on: −x, +x, −y, +y.
const FACING: [(i32, i32); 4] = [(-1, 0), (1, 0), (0, -1), (0, 1)];

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
        let o = cloud.origin;
        if !(o.x.is_finite() && o.y.is_finite() && o.z.is_finite()) {
            stats.skipped_non_finite = cloud.points.len();
            return stats;
        }
        let d = self.params.cell_size;
        let o = [o.x as f32, o.y as f32, o.z as f32];
        let max_r = self.params.max_point_range.min(1e6) as f32;
        let max_r2 = max_r * max_r;
        let sd2 = (self.params.sigma_d * self.params.sigma_d) as f32;
        let kd = self.params.k_d as f32;
        let inv_d = (1.0 / d) as f32;
        let pts = &cloud.points[..];
        let cl = pts.len().div_ceil(chunks.max(1)).max(1);
        let nch = pts.len().div_ceil(cl);
        let s = &mut self.scratch;
        if s.chunks.len() < nch {
            s.chunks.resize_with(nch, ChunkScratch::default);
        }

        // Pass 0: bounding box and counts.
        s.chunks[..nch]
            .par_iter_mut()
            .zip(pts.par_chunks(cl))
            .for_each(|(c, pts)| {
                let mut st = FuseStats::default();
                let (mut x0, mut y0, mut x1, mut y1) = (f32::MAX, f32::MAX, f32::MIN, f32::MIN);
                for p in pts {
                    match classify_point(p, o, max_r2) {
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
        for c in &s.chunks[..nch] {
            x0 = x0.min(c.bbox.0);
            y0 = y0.min(c.bbox.1);
            x1 = x1.max(c.bbox.2);
            y1 = y1.max(c.bbox.3);
            stats.skipped_non_finite += c.stats.skipped_non_finite;
            stats.skipped_out_of_range += c.stats.skipped_out_of_range;
        }
        self.scans += 1;
        let (Some(lo), Some(hi)) = (
            Cell::containing(x0 as f64, y0 as f64, d),
            Cell::containing(x1 as f64, y1 as f64, d),
        ) else {
            return stats;
        };
        let rect = crate::rect::from_corners(lo, hi);
        let w = rect.width as usize;
        let hgt = rect.height as usize;
        let n = rect.len();
        let (mi, mj) = (rect.min.i as f64, rect.min.j as f64);
        // Cell coordinates relative to the rect, computed exactly like `Cell::containing`.
        let locate = |p: &strider_core::ColoredPoint| -> (usize, usize, f32, f32) {
            let fx = p.x as f64 / d;
            let fy = p.y as f64 / d;
            let (cx, cy) = (fast_floor(fx), fast_floor(fy));
            (
                (cx - mi) as usize,
                (cy - mj) as usize,
                (fx - cx) as f32,
                (fy - cy) as f32,
            )
        };

        // Pass 1: highest return per cell, and ray carving over the last stretch of each beam.
        let (wf, hf) = (w as f32, rect.height as f32);
        s.located.clear();
        s.located.resize(pts.len(), Located::default());
        s.chunks[..nch]
            .par_iter_mut()
            .zip(pts.par_chunks(cl))
            .zip(s.located.par_chunks_mut(cl))
            .enumerate()
            .for_each(|(chunk, ((c, pts), located))| {
                c.max_z.clear();
                c.max_z.resize(n, f32::NEG_INFINITY);
                c.carve_z.clear();
                c.carve_z.resize(n, f32::INFINITY);
                for (j, (p, l)) in pts.iter().zip(located.iter_mut()).enumerate() {
                    let Ok(r2) = classify_point(p, o, max_r2) else {
                        l.ci = u32::MAX;
                        continue;
                    };
                    let (ci, cj, u, v) = locate(p);
                    let k = cj * w + ci;
                    let m = &mut c.max_z[k];
                    *m = m.max(p.z);
                    let kr = kd * r2;
                    let var = sd2 + kr * kr;
                    *l = Located {
                        ci: ci as u32,
                        cj: cj as u32,
                        u,
                        v,
                        var,
                    };
                    if !(chunk * cl + j).is_multiple_of(CARVE_EVERY) {
                        continue;
                    }

                    // Beam geometry in cell units relative to the rect. Trust the beam up to
                    // CARVE_SIGMAS·σ short of the return: the true hit may lie anywhere within
                    // the range noise before it.
                    let back = CARVE_SIGMAS * var.sqrt();
                    let (vx, vy, vz) = (p.x - o[0], p.y - o[1], p.z - o[2]);
                    let lh = (vx * vx + vy * vy).sqrt() * inv_d; // horizontal beam length, cells
                    let r = r2.sqrt();
                    if lh < 1e-3 || back >= r {
                        continue;
                    }
                    // Unit horizontal direction (cells) and height change per cell travelled.
                    let inv_lh = 1.0 / lh;
                    let (hx, hy, dzc) = (vx * inv_d * inv_lh, vy * inv_d * inv_lh, vz * inv_lh);
                    let back_c = lh * back / r; // trusted-end offset, horizontal cells
                    let (ex, ey) = (ci as f32 + u - hx * back_c, cj as f32 + v - hy * back_c);
                    let ez = p.z - dzc * back_c;
                    let reach = lh - back_c; // horizontal cells from the origin to the trusted end
                    for step in 0..=CARVE_SAMPLES {
                        let b = 0.5 * step as f32;
                        if b > reach {
                            break;
                        }
                        let (x, y) = (ex - hx * b, ey - hy * b);
                        if !(x >= 0.0 && y >= 0.0 && x < wf && y < hf) {
                            continue;
                        }
                        let (xi, yi) = (x as usize, y as usize);
                        if (xi, yi) == (ci, cj) {
                            continue; // a return never carves its own cell
                        }
                        let cz = &mut c.carve_z[yi * w + xi];
                        *cz = cz.min(ez - dzc * b);
                    }
                }
            });
        // Merge: per-cell maximum and minimum, independent of the order.
        let Some((first, rest)) = s.chunks[..nch].split_first_mut() else {
            return stats;
        };
        std::mem::swap(&mut s.max_z, &mut first.max_z);
        std::mem::swap(&mut s.carve_z, &mut first.carve_z);
        for c in rest.iter() {
            for (a, b) in s.max_z.iter_mut().zip(&c.max_z) {
                *a = a.max(*b);
            }
            for (a, b) in s.carve_z.iter_mut().zip(&c.carve_z) {
                *a = a.min(*b);
            }
        }

        // Pass 2: mixed-cell rule and carving bound, then the highest kept return per cell is
        // the measurement.
        let (max_z, carve_z) = (&s.max_z, &s.carve_z);
        s.chunks[..nch]
            .par_iter_mut()
            .zip(pts.par_chunks(cl))
            .zip(s.located.par_chunks(cl))
            .for_each(|((c, pts), located)| {
                c.best_z.clear();
                c.best_z.resize(n, f32::NEG_INFINITY);
                c.best_var.clear();
                c.best_var.resize(n, 0.0);
                c.best_rgb.clear();
                c.best_rgb.resize(n, [0; 3]);
                c.facing.clear();
                c.facing.resize(n, 0);
                let mut st = FuseStats::default();
                for (p, l) in pts.iter().zip(located) {
                    if l.ci == u32::MAX {
                        continue;
                    }
                    let (ci, cj, u, v, var) = (l.ci as usize, l.cj as usize, l.u, l.v, l.var);
                    let k = cj * w + ci;
                    let sigma3 = 3.0 * var.sqrt();
                    let edge = sigma3 * inv_d; // 3σ in cell units
                    let below = |nk: usize| p.z < max_z[nk] - sigma3;
                    let face = (u < edge && ci > 0 && below(k - 1))
                        || (u > 1.0 - edge && ci + 1 < w && below(k + 1))
                        || (v < edge && cj > 0 && below(k - w))
                        || (v > 1.0 - edge && cj + 1 < hgt && below(k + w));
                    if face {
                        st.face_points += 1;
                        continue;
                    }
                    if p.z > carve_z[k] + sigma3 {
                        // A beam of this scan crossed this cell's column below this return.
                        st.carved_points += 1;
                        continue;
                    }
                    st.fused_points += 1;
                    if p.z > c.best_z[k] {
                        // Face bound: on the edge facing the sensor, with a neighbour across
                        // it that was seen in this scan and lies wholly > 3σ lower (see the
                        // module docs).
                        c.best_z[k] = p.z;
                        c.best_var[k] = var;
                        c.best_rgb[k] = p.rgb;
                        // Near a corner both edges may face the sensor; either may be the one
                        // hit.
                        c.facing[k] = (u < edge && o[0] < p.x) as u8
                            | ((u > 1.0 - edge && o[0] > p.x) as u8) << 1
                            | ((v < edge && o[1] < p.y) as u8) << 2
                            | ((v > 1.0 - edge && o[1] > p.y) as u8) << 3;
                    }
                }
                c.stats = st;
            });
        // Merge in chunk order with the same strict `>`: the earliest highest return wins, as
        // in one sequential pass.
        for c in &s.chunks[..nch] {
            stats.face_points += c.stats.face_points;
            stats.carved_points += c.stats.carved_points;
            stats.fused_points += c.stats.fused_points;
        }
        let Some((first, rest)) = s.chunks[..nch].split_first_mut() else {
            return stats;
        };
        std::mem::swap(&mut s.best_z, &mut first.best_z);
        std::mem::swap(&mut s.best_var, &mut first.best_var);
        std::mem::swap(&mut s.best_rgb, &mut first.best_rgb);
        std::mem::swap(&mut s.facing, &mut first.facing);
        for c in rest.iter() {
            for k in 0..n {
                if c.best_z[k] > s.best_z[k] {
                    s.best_z[k] = c.best_z[k];
                    s.best_var[k] = c.best_var[k];
                    s.best_rgb[k] = c.best_rgb[k];
                    s.facing[k] = c.facing[k];
                }
            }
        }
        self.face_bound_floors(rect);
        self.apply_measurements(rect, &mut stats);
        stats
    }

    /// Fills `bound_floor` for every cell whose kept return sits on its sensor-facing edge, from
    /// the map as it was before this scan (so the spilled face returns of this scan in the
    /// neighbour, which ray carving is yet to remove, do not hide the step).
    fn face_bound_floors(&mut self, rect: CellRect) {
        let gate = self.params.mahalanobis_gate as f32;
        let s = &mut self.scratch;
        s.bound_floor.clear();
        s.bound_floor.resize(rect.len(), f32::INFINITY);
        for (k, &bits) in s.facing.iter().enumerate() {
            if bits == 0 || s.best_z[k] == f32::NEG_INFINITY {
                continue;
            }
            let c = rect.cell(k);
            for (f, (di, dj)) in FACING.iter().enumerate() {
                let nb = Cell::new(c.i + di, c.j + dj);
                if bits & (1 << f) == 0 || !self.observed.get(nb).unwrap_or(false) {
                    continue;
                }
                if let (Some(z), Some(var)) = (self.elevation.get(nb), self.variance.get(nb)) {
                    let floor = &mut s.bound_floor[k];
                    *floor = floor.min(z + gate * var.max(0.0).sqrt());
                }
            }
        }
    }

    /// Kalman update of every cell with a measurement in the scratch rasters, tile by tile (one
    /// lookup per tile and layer).
    fn apply_measurements(&mut self, rect: CellRect, stats: &mut FuseStats) {
        let ElevationMap {
            params,
            elevation,
            variance,
            color,
            hits,
            observed,
            passability,
            admissible,
            known_bounds,
            observed_count,
            dirty,
            scratch: s,
            ..
        } = self;
        let gate = params.mahalanobis_gate;
        let noise = params.multi_height_noise as f32;
        let first_seen = params.color_mode == ColorMode::FirstSeen;
        let ts = elevation.tile_size() as i32;
        let w = rect.width as usize;
        let (mut lo, mut hi) = ((i32::MAX, i32::MAX), (i32::MIN, i32::MIN));
        let (mut klo, mut khi) = ((i32::MAX, i32::MAX), (i32::MIN, i32::MIN));
        let (ri1, rj1) = crate::rect::max_corner(rect);
        for tj in rect.min.j.div_euclid(ts)..=rj1.div_euclid(ts) {
            for ti in rect.min.i.div_euclid(ts)..=ri1.div_euclid(ts) {
                let key = crate::tiles::TileKey { ti, tj };
                let Some(ov) = crate::rect::intersection(rect, elevation.tile_rect(key)) else {
                    continue;
                };
                let rk = |c: Cell| (c.j - rect.min.j) as usize * w + (c.i - rect.min.i) as usize;
                if !ov.cells().any(|c| {
                    s.best_z[rk(c)] > f32::NEG_INFINITY || s.carve_z[rk(c)] < f32::INFINITY
                }) {
                    continue;
                }
                let el = elevation.tile_or_insert(key);
                let va = variance.tile_or_insert(key);
                let co = color.tile_or_insert(key);
                let hi_t = hits.tile_or_insert(key);
                let ob = observed.tile_or_insert(key);
                passability.tile_or_insert(key);
                admissible.tile_or_insert(key);
                for c in ov.cells() {
                    let k = rk(c);
                    let t = ((c.j - tj * ts) * ts + (c.i - ti * ts)) as usize;
                    let cz = s.carve_z[k];
                    if cz < el[t] && ob[t] && (el[t] - cz) as f64 > gate * (va[t] as f64).sqrt() {
                        // A beam crossed this column below the estimate: the top is at most
                        // there. Lower it and make it uncertain so the next returns decide.
                        let excess = (el[t] - cz) as f64 / gate;
                        el[t] = cz;
                        va[t] = va[t].max((excess * excess) as f32);
                        stats.cells_carved += 1;
                        lo = (lo.0.min(c.i), lo.1.min(c.j));
                        hi = (hi.0.max(c.i), hi.1.max(c.j));
                    }
                    let z = s.best_z[k];
                    if z == f32::NEG_INFINITY {
                        continue;
                    }
                    stats.cells_updated += 1;
                    let r = s.best_var[k];
                    let rgb = s.best_rgb[k].map(f32::from);
                    if !ob[t] {
                        ob[t] = true;
                        *observed_count += 1;
                        el[t] = z;
                        va[t] = r;
                        co[t] = rgb;
                        hi_t[t] = 1;
                        klo = (klo.0.min(c.i), klo.1.min(c.j));
                        khi = (khi.0.max(c.i), khi.1.max(c.j));
                    } else {
                        let (h, p) = (el[t] as f64, va[t] as f64);
                        let (zf, rf) = (z as f64, r as f64);
                        let sum = p + rf;
                        // A face bound counts only where the map already holds a step up from
                        // the facing neighbour: a stray face return spilled into a ground cell
                        // is then gated like any outlier instead of lifting the ground.
                        if h - s.bound_floor[k] as f64 > gate * p.sqrt() {
                            // A lower bound of the top: news only when more than σ_z above it.
                            if zf - h > rf.sqrt() {
                                el[t] = z;
                                va[t] = r;
                                stats.face_bounds_raised += 1;
                                lo = (lo.0.min(c.i), lo.1.min(c.j));
                                hi = (hi.0.max(c.i), hi.1.max(c.j));
                            } else {
                                stats.face_bounds_ignored += 1;
                            }
                            continue;
                        }
                        if (zf - h).abs() > gate * sum.sqrt() {
                            va[t] += noise;
                            stats.cells_gated += 1;
                            continue;
                        }
                        el[t] = ((rf * h + p * zf) / sum) as f32;
                        va[t] = (p * rf / sum) as f32;
                        hi_t[t] = hi_t[t].saturating_add(1);
                        if !first_seen {
                            let inv = 1.0 / hi_t[t] as f32;
                            for ch in 0..3 {
                                co[t][ch] += (rgb[ch] - co[t][ch]) * inv;
                            }
                        }
                    }
                    lo = (lo.0.min(c.i), lo.1.min(c.j));
                    hi = (hi.0.max(c.i), hi.1.max(c.j));
                }
            }
        }
        if lo.0 <= hi.0 {
            let r = crate::rect::from_corners(Cell::new(lo.0, lo.1), Cell::new(hi.0, hi.1));
            *dirty = Some(dirty.map_or(r, |d| crate::rect::union(d, r)));
        }
        if klo.0 <= khi.0 {
            let r = crate::rect::from_corners(Cell::new(klo.0, klo.1), Cell::new(khi.0, khi.1));
            *known_bounds = Some(known_bounds.map_or(r, |b| crate::rect::union(b, r)));
        }
    }

    /// Fuses a scan and updates passability and admissibility of the affected region
    /// (`001` Alg. 2 lines 2–3).
    pub fn integrate(&mut self, cloud: &PointCloud) -> FuseStats {
        let stats = self.fuse(cloud);
        self.update_passability();
        stats
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::MapParams;
    use approx::assert_abs_diff_eq;
    use strider_core::{ColoredPoint, Point3, Rgb8};

    fn cloud(origin: Point3, pts: &[(f32, f32, f32)]) -> PointCloud {
        PointCloud {
            stamp: 0.0,
            sensor: 0,
            origin,
            points: pts
                .iter()
                .map(|&(x, y, z)| ColoredPoint {
                    x,
                    y,
                    z,
                    rgb: [100, 150, 200],
                })
                .collect(),
        }
    }

    fn params() -> MapParams {
        MapParams {
            cell_size: 0.1,
            tile_size: 8,
            ..MapParams::default()
        }
    }

    /// A wall cell (5, 5) with top 0.5 m, seen from −x by a sensor at 0.5 m: every return on its
    /// face lies below the top, lower from farther away. The ground cell (4, 5) in front is seen
    /// at 0.
    fn face_scan(distance: f32, face_z: f32) -> PointCloud {
        let x_face = 0.5f32;
        cloud(
            Point3::new((x_face - distance) as f64, 0.55, 0.5),
            &[
                (0.45, 0.55, 0.0),
                (0.45, 0.52, 0.0),
                (x_face + 0.001, 0.55, face_z),
            ],
        )
    }

    #[test]
    fn face_bounds_raise_a_wall_top_and_lower_ones_do_not_pull_it_down() {
        let mut m = ElevationMap::new(params());
        let wall = Cell::new(5, 5);
        // First sight from far: the estimate starts low.
        m.fuse(&face_scan(2.0, 0.40));
        m.fuse(&face_scan(2.0, 0.40));
        assert_abs_diff_eq!(m.elevation(wall).unwrap(), 0.40, epsilon = 1e-6);
        // A nearer view sees the face higher up: the bound replaces the estimate.
        let s = m.fuse(&face_scan(0.8, 0.49));
        assert_eq!(s.face_bounds_raised, 1);
        assert_abs_diff_eq!(m.elevation(wall).unwrap(), 0.49, epsilon = 1e-6);
        // Far views again: their lower bounds are ignored, not averaged in.
        for _ in 0..5 {
            let s = m.fuse(&face_scan(2.0, 0.40));
            assert_eq!(s.face_bounds_ignored, 1);
        }
        assert_abs_diff_eq!(m.elevation(wall).unwrap(), 0.49, epsilon = 1e-6);
        // A bound within σ_z of the estimate is no news either.
        let s = m.fuse(&face_scan(0.8, 0.4905));
        assert_eq!((s.face_bounds_raised, s.face_bounds_ignored), (0, 1));
    }

    #[test]
    fn a_face_return_on_the_edge_of_flat_ground_is_not_a_bound() {
        // Two ground cells at 0; a stray high return on the facing edge of the second is an
        // outlier (no step in the map), so it is gated, never lifting the ground.
        let mut m = ElevationMap::new(params());
        let o = Point3::new(-1.0, 0.55, 0.5);
        for _ in 0..3 {
            m.fuse(&cloud(o, &[(0.45, 0.55, 0.0), (0.55, 0.55, 0.0)]));
        }
        let s = m.fuse(&cloud(o, &[(0.45, 0.55, 0.0), (0.501, 0.55, 0.3)]));
        assert_eq!((s.face_bounds_raised, s.cells_gated), (0, 1));
        assert_abs_diff_eq!(m.elevation(Cell::new(5, 5)).unwrap(), 0.0, epsilon = 1e-6);
    }

    #[test]
    fn kalman_matches_closed_form() {
        let p = MapParams {
            mahalanobis_gate: 1e9,
            ..params()
        };
        let mut m = ElevationMap::new(p.clone());
        // The cell (5, 5) centre at (0.55, 0.55); sensors at different heights give different
        // ranges, hence different σ_z².
        let zs = [0.10f32, 0.12, 0.09, 0.115, 0.101];
        let mut num = 0.0;
        let mut den = 0.0;
        for (k, &z) in zs.iter().enumerate() {
            let origin = Point3::new(0.55, 0.55, 0.5 + k as f64);
            let c = cloud(origin, &[(0.55, 0.55, z)]);
            let s = m.fuse(&c);
            assert_eq!(s.cells_updated, 1);
            let r2 = (origin.z - z as f64).powi(2);
            let var = p.sigma_d.powi(2) + (p.k_d * r2).powi(2);
            num += z as f64 / var;
            den += 1.0 / var;
        }
        let c = Cell::new(5, 5);
        assert_abs_diff_eq!(m.elevation(c).unwrap() as f64, num / den, epsilon = 1e-6);
        let rel = (m.variance(c).unwrap() as f64 - 1.0 / den).abs() / (1.0 / den);
        assert!(rel < 1e-4, "variance rel. error {rel}");
        assert_eq!(m.hits(c), 5);
    }

    #[test]
    fn highest_point_per_cell_and_gate() {
        let mut m = ElevationMap::new(params());
        let o = Point3::new(0.0, 0.0, 1.0);
        let s = m.fuse(&cloud(
            o,
            &[(0.25, 0.25, 0.1), (0.22, 0.28, 0.3), (0.27, 0.21, 0.2)],
        ));
        assert_eq!(s.fused_points, 3);
        assert_eq!(s.cells_updated, 1);
        assert_eq!(m.elevation(Cell::new(2, 2)), Some(0.3));
        // A far outlier is gated: elevation unchanged, variance inflated.
        let v0 = m.variance(Cell::new(2, 2)).unwrap();
        let s = m.fuse(&cloud(o, &[(0.25, 0.25, 0.8)]));
        assert_eq!(s.cells_gated, 1);
        assert_eq!(m.elevation(Cell::new(2, 2)), Some(0.3));
        assert_abs_diff_eq!(
            m.variance(Cell::new(2, 2)).unwrap(),
            v0 + 1e-5,
            epsilon = 1e-9
        );
    }

    /// A wall (x ≥ 1.0, 0.5 m) seen from (0.05, 0.05, 0.5): its face returns straddle the edge
    /// x = 1.0. Those pushed into cell (9, 0) near the top of the face are not below the wall's
    /// scan maximum, so only ray carving can tell they are not the floor of (9, 0): beams to the
    /// lower face returns cross (9, 0) close to the floor.
    fn wall_scan(o: Point3) -> PointCloud {
        let mut pts = vec![(0.95, 0.05, 0.0), (0.93, 0.07, 0.001)];
        for k in 1..=9 {
            let z = 0.05 * k as f32;
            pts.push((1.004, 0.05, z));
            pts.push((0.997, 0.05, z + 0.002));
        }
        cloud(o, &pts)
    }

    #[test]
    fn ray_carving_removes_face_returns_in_front_of_a_wall() {
        let mut m = ElevationMap::new(params());
        let s = m.fuse(&wall_scan(Point3::new(0.05, 0.05, 0.5)));
        assert!(s.carved_points > 0, "{s:?}");
        let floor = m.elevation(Cell::new(9, 0)).unwrap();
        assert!(floor.abs() < 0.01, "floor in front of the wall at {floor}");
        assert!(m.elevation(Cell::new(10, 0)).unwrap() > 0.4);
    }

    #[test]
    fn ray_carving_lowers_a_contradicted_estimate() {
        let mut m = ElevationMap::new(params());
        // A wrong estimate from an earlier scan, confident.
        m.set_cell(Cell::new(9, 0), 0.4, 1e-6, Rgb8::new(0, 0, 0));
        let s = m.fuse(&wall_scan(Point3::new(0.05, 0.05, 0.5)));
        assert!(s.cells_carved >= 1, "{s:?}");
        let z = m.elevation(Cell::new(9, 0)).unwrap();
        assert!(z < 0.06, "carved to the lowest beam crossing, got {z}");
        // Carving never touches a cell no beam crossed below its top.
        assert!(m.elevation(Cell::new(10, 0)).unwrap() > 0.4);
    }

    #[test]
    fn non_finite_points_are_skipped_and_counted() {
        let mut m = ElevationMap::new(params());
        let o = Point3::new(0.0, 0.0, 1.0);
        let s = m.fuse(&cloud(
            o,
            &[
                (f32::NAN, 0.0, 0.0),
                (0.0, f32::INFINITY, 0.0),
                (0.0, 0.0, f32::NEG_INFINITY),
                (0.05, 0.05, 0.0),
                (1e30, 0.0, 0.0),
            ],
        ));
        assert_eq!(s.skipped_non_finite, 3);
        assert_eq!(s.skipped_out_of_range, 1);
        assert_eq!(s.fused_points, 1);
        let s = m.fuse(&cloud(Point3::new(f64::NAN, 0.0, 0.0), &[(0.0, 0.0, 0.0)]));
        assert_eq!(s.skipped_non_finite, 1);
        let s = m.fuse(&cloud(o, &[]));
        assert_eq!(s, FuseStats::default());
        assert_eq!(m.observed_count(), 1);
    }

    #[test]
    fn mixed_cell_rule_ignores_wall_face_returns() {
        // A wall occupies cells i ≥ 10 (x ≥ 1.0) with top at 0.5 m; the floor (z = 0) lies at
        // x < 1.0. The sensor at x = 0 sees the floor, the wall's face at x = 1.0 (noisy in x)
        // and the wall top.
        let mut m = ElevationMap::new(params());
        let o = Point3::new(0.0, 0.55, 0.8);
        let mut pts = Vec::new();
        let mut rng = 12345u64;
        let mut noise = || {
            rng = rng
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((rng >> 33) as f32 / (1u64 << 31) as f32 - 0.5) * 0.004 // ±2 mm
        };
        for k in 0..10 {
            let y = 0.51 + 0.008 * k as f32;
            for a in 0..10 {
                pts.push((0.9 + 0.01 * a as f32 + 0.005, y, noise())); // floor cell 9
                pts.push((1.0 + noise(), y, 0.05 * a as f32)); // face at x = 1.0
                pts.push((1.005 + 0.01 * a as f32, y, 0.5 + noise())); // wall top cell 10
            }
        }
        let s = m.fuse(&cloud(o, &pts));
        assert!(s.face_points > 0);
        let floor = m.elevation(Cell::new(9, 5)).unwrap();
        assert!(floor.abs() < 0.01, "floor cell corrupted: {floor}");
        let top = m.elevation(Cell::new(10, 5)).unwrap();
        assert!((top - 0.5).abs() < 0.01, "wall top {top}");
    }

    /// A scan of a floor, a wall and its face with coarse heights (so that equally high returns
    /// with different colours share cells), a few unusable returns, from `origin`.
    fn tied_scan(origin: Point3, seed: u64, n: usize) -> PointCloud {
        let mut rng = seed.wrapping_mul(0x9e37_79b9_7f4a_7c15) | 1;
        let mut next = move || {
            rng ^= rng << 13;
            rng ^= rng >> 7;
            rng ^= rng << 17;
            (rng >> 40) as f32 / (1u64 << 24) as f32
        };
        let points = (0..n)
            .map(|k| {
                let (x, y) = (next() * 3.0 - 1.0, next() * 3.0 - 1.0);
                let z = match k % 7 {
                    // Face returns on the wall's edge at x = 1.5, noisy in x.
                    0 => {
                        return ColoredPoint {
                            x: 1.5 + (next() - 0.5) * 0.01,
                            y,
                            z: (next() * 11.0).floor() * 0.05,
                            rgb: [k as u8, 7, 9],
                        };
                    }
                    _ if x >= 1.5 => 0.5,
                    _ => 0.0,
                } + (next() * 3.0).floor() * 0.002;
                let bad = k % 997 == 0;
                ColoredPoint {
                    x: if bad { f32::NAN } else { x },
                    y,
                    z,
                    rgb: [(k % 251) as u8, (k / 251 % 251) as u8, 40],
                }
            })
            .collect();
        PointCloud {
            stamp: 0.0,
            sensor: 0,
            origin,
            points,
        }
    }

    #[test]
    fn fusion_does_not_depend_on_the_number_of_chunks() {
        let scans: Vec<PointCloud> = (0..4)
            .map(|s| tied_scan(Point3::new(0.1 * s as f64, 0.2, 0.6), s, 3000))
            .collect();
        let run = |chunks: usize| {
            let mut m = ElevationMap::new(params());
            let stats: Vec<FuseStats> = scans.iter().map(|c| m.fuse_in_chunks(c, chunks)).collect();
            m.update_passability();
            (m, stats)
        };
        let (one, one_stats) = run(1);
        let rect = one.known_bounds().expect("cells observed");
        assert!(
            one_stats
                .iter()
                .any(|s| s.face_points > 0 && s.carved_points > 0)
        );
        assert!(one_stats.iter().all(|s| s.skipped_non_finite > 0));
        for chunks in [2, 3, 7] {
            let (m, stats) = run(chunks);
            assert_eq!(stats, one_stats, "{chunks} chunks");
            assert_eq!(m.known_bounds(), Some(rect));
            for c in rect.cells() {
                let (a, b) = (m.elevation(c), one.elevation(c));
                assert_eq!(
                    a.map(f32::to_bits),
                    b.map(f32::to_bits),
                    "{chunks} chunks, {c:?}"
                );
                let (a, b) = (m.variance(c), one.variance(c));
                assert_eq!(
                    a.map(f32::to_bits),
                    b.map(f32::to_bits),
                    "{chunks} chunks, {c:?}"
                );
                assert_eq!(m.color(c), one.color(c), "{chunks} chunks, {c:?}");
                assert_eq!(m.hits(c), one.hits(c), "{chunks} chunks, {c:?}");
                assert_eq!(
                    m.passability(c),
                    one.passability(c),
                    "{chunks} chunks, {c:?}"
                );
            }
        }
    }

    #[test]
    fn running_mean_and_first_seen_colour() {
        let o = Point3::new(0.0, 0.0, 1.0);
        let mk = |rgb: [u8; 3]| PointCloud {
            stamp: 0.0,
            sensor: 0,
            origin: o,
            points: vec![ColoredPoint {
                x: 0.05,
                y: 0.05,
                z: 0.0,
                rgb,
            }],
        };
        let mut m = ElevationMap::new(params());
        m.fuse(&mk([100, 0, 0]));
        m.fuse(&mk([200, 50, 0]));
        assert_eq!(
            m.color(Cell::new(0, 0)),
            Some(strider_core::Rgb8::new(150, 25, 0))
        );
        let mut m = ElevationMap::new(MapParams {
            color_mode: ColorMode::FirstSeen,
            ..params()
        });
        m.fuse(&mk([100, 0, 0]));
        m.fuse(&mk([200, 50, 0]));
        assert_eq!(
            m.color(Cell::new(0, 0)),
            Some(strider_core::Rgb8::new(100, 0, 0))
        );
    }

    #[test]
    fn map_grows_into_negative_coordinates() {
        let mut m = ElevationMap::new(params());
        let o = Point3::new(0.0, 0.0, 1.0);
        m.fuse(&cloud(o, &[(-3.05, -2.05, 0.1), (2.05, 1.05, 0.2)]));
        assert_eq!(m.elevation_at(-3.05, -2.05), Some(0.1));
        assert_eq!(m.elevation(Cell::new(20, 10)), Some(0.2));
        assert_eq!(
            m.known_bounds(),
            Some(CellRect::new(Cell::new(-31, -21), 52, 32))
        );
        assert_eq!(m.elevation_layer().tile_count(), 2);
    }
}
