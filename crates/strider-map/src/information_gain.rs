//! Spatial information gain of `001` §4.2 (decision 5).
//!
//! * Eq. 10: I_cell(ν') = (k(ν') + 1) / 9 for an unknown cell ν', k = number of unknown cells in
//!   its 8-neighbourhood.
//! * Eq. 11: I_model(ν) = Σ over unknown ν' in δ(r_sensor, ν) with observable(ν, ν') of
//!   I_cell(ν').
//!
//! Eq. 11 is evaluated only on candidate cells: observed, admissible, reachable from the robot,
//! on the `info_gain_stride` lattice, and with an unknown cell within r_sensor (a summed-area
//! table of the unknown mask rejects the others in O(1)). "Unknown" means unobserved *and*
//! inside the exploration bounds (when given); candidates outside the bounds are dropped. All
//! work runs on a dense view of the known area grown by r_sensor, in parallel over candidates.

use crate::map::ElevationMap;
use crate::observability::{box_interval, ray_clear_in, target_height};
use crate::passability::disc_reach;
use crate::reachability::Reachability;
use crate::rect::{self, WorldRect, in_bounds};
use rayon::prelude::*;
use strider_core::grid::{NEIGHBOURS8, disc_offsets};
use strider_core::{Cell, CellRect, Point2};

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
}

/// The sensor disc δ(r_sensor) with what Eq. 11 needs per offset, computed once: the distance,
/// the shadow-mask direction bin of a target there and the bins a raised cell there subtends,
/// plus two indexes (offset → entry, direction bin → entries by distance).
struct DiscTable {
    entries: Vec<DiscEntry>,
    /// Chebyshev radius of the disc, cells.
    reach: u32,
    /// Entry index per offset of the (2·reach + 1)² square, `u32::MAX` outside the disc.
    lookup: Vec<u32>,
    /// `by_bin[by_bin_start[b]..by_bin_start[b + 1]]`: the entries (centre excluded) whose
    /// direction bin is b, by increasing distance.
    by_bin_start: Vec<u32>,
    by_bin: Vec<u32>,
    /// The centre distance of each entry of `by_bin`, alongside: the delta update's wedge
    /// scans search and walk these contiguously instead of loading each entry.
    by_bin_r: Vec<f32>,
    /// `near[near_start[k]..near_start[k + 1]]`: the entries a cell at entry k can shadow
    /// when its shadow interval ends within [`NEAR_SHADOW`] of its centre distance (the
    /// entries of its direction bins with r ∈ [r_k − ½√2, r_k + NEAR_SHADOW]), by increasing
    /// distance. The delta update scans this instead of searching each bin.
    near_start: Vec<u32>,
    near: Vec<u32>,
}

#[derive(Clone, Copy)]
struct DiscEntry {
    di: i32,
    dj: i32,
    /// Centre distance, cells.
    r: f32,
    /// Direction bin of a target at this offset.
    bin: u16,
    /// Bins subtended by a cell at this offset (its four corners, one bin of margin on each
    /// side against rounding), as up to two inclusive ranges (two when they wrap around the
    /// +x axis); none for the centre.
    spans: [(u16, u16); 2],
    n_spans: u8,
    /// Bins strictly inside the cell's angular extent, one bin away from its corner
    /// directions (inclusive; `lo > hi` when none, or when the cell straddles the +x axis):
    /// a sight line in such a bin crosses the cell's interior.
    inner: (u16, u16),
}

impl DiscEntry {
    fn spans(&self) -> &[(u16, u16)] {
        &self.spans[..self.n_spans as usize]
    }
}

impl DiscTable {
    fn new(r_sensor: f64, d: f64) -> Self {
        let offsets = disc_offsets(r_sensor, d);
        let reach = offsets
            .iter()
            .map(|&(di, dj)| di.unsigned_abs().max(dj.unsigned_abs()))
            .max()
            .unwrap_or(0);
        let mut entries: Vec<DiscEntry> = offsets
            .into_iter()
            .map(|(di, dj)| Self::entry(di, dj))
            .collect();
        // Entries in (direction bin, distance) order: the delta update walks a bin's entries
        // outwards, so its per-entry state (visit stamps, visibility bits, the entries
        // themselves) is then read sequentially instead of scattered over the disc.
        entries.sort_by(|a, b| {
            a.bin
                .cmp(&b.bin)
                .then(a.r.total_cmp(&b.r))
                .then((a.dj, a.di).cmp(&(b.dj, b.di)))
        });
        let side = 2 * reach as usize + 1;
        let mut lookup = vec![u32::MAX; side * side];
        for (k, e) in entries.iter().enumerate() {
            let idx = (e.dj + reach as i32) as usize * side + (e.di + reach as i32) as usize;
            lookup[idx] = k as u32;
        }
        let mut order: Vec<u32> = (0..entries.len() as u32)
            .filter(|&k| entries[k as usize].n_spans > 0)
            .collect();
        order.sort_by(|&a, &b| {
            let (ea, eb) = (&entries[a as usize], &entries[b as usize]);
            ea.bin.cmp(&eb.bin).then(ea.r.total_cmp(&eb.r))
        });
        let mut by_bin_start = vec![0u32; ANGLE_BINS + 1];
        for &k in &order {
            by_bin_start[entries[k as usize].bin as usize + 1] += 1;
        }
        for b in 0..ANGLE_BINS {
            by_bin_start[b + 1] += by_bin_start[b];
        }
        let mut near_start = Vec::with_capacity(entries.len() + 1);
        let mut near = Vec::new();
        near_start.push(0u32);
        for x in &entries {
            let from = near.len();
            let (lo, hi) = (x.r - HALF_DIAG, x.r + NEAR_SHADOW);
            for &(a, b) in x.spans() {
                for bin in a as usize..=b as usize {
                    let group = &order[by_bin_start[bin] as usize..by_bin_start[bin + 1] as usize];
                    let start = group.partition_point(|&k| entries[k as usize].r < lo);
                    near.extend(
                        group[start..]
                            .iter()
                            .take_while(|&&k| entries[k as usize].r <= hi),
                    );
                }
            }
            near[from..].sort_by(|&a, &b| entries[a as usize].r.total_cmp(&entries[b as usize].r));
            near_start.push(near.len() as u32);
        }
        let by_bin_r = order.iter().map(|&k| entries[k as usize].r).collect();
        Self {
            entries,
            reach,
            lookup,
            by_bin_start,
            by_bin: order,
            by_bin_r,
            near_start,
            near,
        }
    }

    /// The entries a cell at entry `k` can shadow within [`NEAR_SHADOW`] of its centre
    /// distance, by increasing distance (see `DiscTable::near`).
    #[inline]
    fn near_shadow(&self, k: usize) -> &[u32] {
        &self.near[self.near_start[k] as usize..self.near_start[k + 1] as usize]
    }

    fn entry(di: i32, dj: i32) -> DiscEntry {
        let (x, y) = (di as f64, dj as f64);
        let mut e = DiscEntry {
            di,
            dj,
            r: ((di * di + dj * dj) as f64).sqrt() as f32,
            bin: 0,
            spans: [(0, 0); 2],
            n_spans: 0,
            inner: (1, 0),
        };
        if (di, dj) == (0, 0) {
            return e;
        }
        e.bin = angle_bin(x, y) as u16;
        let n = ANGLE_BINS as i64;
        let bins = [(-0.5, -0.5), (0.5, -0.5), (-0.5, 0.5), (0.5, 0.5)]
            .map(|(ox, oy)| angle_bin(x + ox, y + oy) as i64);
        let lo = bins.iter().copied().min().unwrap_or(0);
        let hi = bins.iter().copied().max().unwrap_or(0);
        if hi - lo <= n / 2 && hi - lo >= 2 {
            e.inner = ((lo + 1) as u16, (hi - 1) as u16);
        }
        if hi - lo > n / 2 {
            // The cell straddles direction 0 (the +x axis): the bins just below n and just
            // above 0, each with its margin (lo_w − 1 ≥ n/2 − 1, hi_w + 1 ≤ n/2).
            let lo_w = bins
                .iter()
                .copied()
                .filter(|&b| b >= n / 2)
                .min()
                .unwrap_or(n);
            let hi_w = bins
                .iter()
                .copied()
                .filter(|&b| b < n / 2)
                .max()
                .unwrap_or(0);
            e.spans = [((lo_w - 1) as u16, (n - 1) as u16), (0, (hi_w + 1) as u16)];
            e.n_spans = 2;
        } else {
            // One bin of margin on each side, wrapping around direction 0.
            let (a, b) = (lo - 1, hi + 1);
            (e.spans, e.n_spans) = if a < 0 {
                ([(0, b as u16), ((a + n) as u16, (n - 1) as u16)], 2)
            } else if b >= n {
                ([(a as u16, (n - 1) as u16), (0, (b - n) as u16)], 2)
            } else {
                ([(a as u16, b as u16), (0, 0)], 1)
            };
        }
        e
    }

    /// The entry at offset `(di, dj)`, if it lies in the disc.
    #[inline]
    fn entry_of(&self, di: i32, dj: i32) -> Option<usize> {
        let r = self.reach as i32;
        if di.abs() > r || dj.abs() > r {
            return None;
        }
        let side = 2 * r + 1;
        let k = self.lookup[((dj + r) * side + di + r) as usize];
        (k != u32::MAX).then_some(k as usize)
    }
}

/// Reach (cells beyond a cell's centre distance) of the shadows [`DiscTable::near_shadow`]
/// lists: a floor cell a centimetre or two above the sensor's ground, seen from half a metre,
/// shadows about that far.
const NEAR_SHADOW: f32 = 3.0;

/// Half the diagonal of a cell, in cells.
const HALF_DIAG: f32 = std::f32::consts::FRAC_1_SQRT_2;

/// The target distances (cells) a known cell of elevation `e` at centre distance `r` can shadow
/// from a sensor at `zs` looking at unknown targets at `zt` (< zs): the sight line to a target
/// at distance R passes the cell no lower than zs − (zs − zt)·(r + ½√2)/R, so only targets with
/// R < (zs − zt)·(r + ½√2)/(zs − e) can be hidden, and none nearer than the cell's near side.
#[inline]
fn shadow_interval(r: f32, e: f32, zs: f64, zt: f64) -> (f32, f32) {
    let start = r - HALF_DIAG;
    let end = if (e as f64) < zs {
        ((zs - zt) * ((r + HALF_DIAG) as f64) / (zs - e as f64)) as f32
    } else {
        f32::INFINITY
    };
    (start, end)
}

/// Elevation of `c` in a dense raster over `rect` (NaN = unknown).
#[inline]
fn elevation_in(elev: &[f32], rect: CellRect, c: Cell) -> Option<f32> {
    rect.index(c).map(|k| elev[k]).filter(|e| !e.is_nan())
}

/// Per-thread scratch space of Eq. 11.
#[derive(Default)]
struct Scratch {
    /// Unknown targets of the disc: (entry index, 9·I_cell).
    targets: Vec<(u32, u8)>,
    /// Disc entries already visited by a delta update (== `stamp`).
    seen: Vec<u32>,
    stamp: u32,
}

impl Scratch {
    fn next_stamp(&mut self, n: usize) {
        if self.seen.len() != n || self.stamp == u32::MAX {
            self.seen.clear();
            self.seen.resize(n, 0);
            self.stamp = 0;
        }
        self.stamp += 1;
    }
}

/// A dense view of the map for Eq. 10–11: elevations (NaN = unknown), 9·I_cell of every
/// unknown cell (k + 1 ∈ 1..=9; 0 for known cells and cells outside the bounds) and a
/// summed-area table of the unknown mask. I_cell is kept as the integer k + 1 so that sums are
/// exact and a delta update gives bit-for-bit the sum a fresh evaluation gives.
struct GainView {
    rect: CellRect,
    elev: Vec<f32>,
    icount: Vec<u8>,
    sat: Vec<u32>,
}

impl GainView {
    fn new(map: &ElevationMap, rect: CellRect, bounds: Option<&WorldRect>) -> Self {
        let mut v = Self {
            rect,
            elev: map.elevation_raster(rect),
            icount: Vec::new(),
            sat: Vec::new(),
        };
        v.derive(bounds, map.cell_size());
        v
    }

    /// Recomputes 9·I_cell (Eq. 10) and the summed-area table from the elevations.
    fn derive(&mut self, bounds: Option<&WorldRect>, d: f64) {
        let rect = self.rect;
        let (w, h) = (rect.width as usize, rect.height as usize);
        let unknown: Vec<bool> = rect
            .cells()
            .zip(&self.elev)
            .map(|(c, e)| e.is_nan() && in_bounds(bounds, c, d))
            .collect();
        self.icount.clear();
        self.icount.resize(rect.len(), 0);
        for y in 0..h {
            for x in 0..w {
                if !unknown[y * w + x] {
                    continue;
                }
                // k(ν'): unknown 8-neighbours; outside the view nothing is known either.
                let k = NEIGHBOURS8
                    .iter()
                    .filter(|&&(di, dj)| {
                        let (nx, ny) = (x as i64 + di as i64, y as i64 + dj as i64);
                        if nx < 0 || ny < 0 || nx >= w as i64 || ny >= h as i64 {
                            in_bounds(bounds, rect.cell(y * w + x).offset(di, dj), d)
                        } else {
                            unknown[ny as usize * w + nx as usize]
                        }
                    })
                    .count();
                self.icount[y * w + x] = k as u8 + 1; // Eq. 10, times 9
            }
        }
        self.sat = summed_area(&unknown, w, h);
    }

    #[inline]
    fn elevation(&self, c: Cell) -> Option<f32> {
        elevation_in(&self.elev, self.rect, c)
    }

    /// Number of unknown cells in the square of half-size `n` around `c` (clipped to the view).
    fn unknown_in_square(&self, c: Cell, n: u32) -> u32 {
        square_count(&self.sat, self.rect, c, n)
    }

    /// 9·I_model(ν) (Eq. 11).
    fn model_count(&self, c: Cell, disc: &DiscTable, h: f64, d: f64) -> u32 {
        self.model_count_with(c, disc, h, d, &mut Scratch::default(), None)
    }

    /// [`GainView::model_count`] with reusable scratch space.
    ///
    /// The targets (unknown cells of the disc) are gathered first. When casting a ray to each
    /// of them costs less than a pass over the disc (few targets, late in exploration), each is
    /// cast directly; otherwise raised cells mark shadow intervals first and only targets inside
    /// one are cast. Both give the exact Eq. 11 sum.
    fn model_count_with(
        &self,
        c: Cell,
        disc: &DiscTable,
        h: f64,
        d: f64,
        scratch: &mut Scratch,
        mut vis: Option<&mut [u64]>,
    ) -> u32 {
        if let Some(v) = vis.as_deref_mut() {
            v.fill(0);
        }
        let Some(ef) = self.elevation(c) else {
            return 0;
        };
        if self.unknown_in_square(c, disc.reach) == 0 {
            return 0;
        }
        let zs = ef as f64 + h;
        let zt = target_height(None, ef);
        let targets = &mut scratch.targets;
        targets.clear();
        let mut ray_work = 0usize;
        for (k, e) in disc.entries.iter().enumerate() {
            let Some(idx) = self.rect.index(c.offset(e.di, e.dj)) else {
                continue;
            };
            let g = self.icount[idx];
            if g > 0 {
                targets.push((k as u32, g));
                ray_work += (e.di.unsigned_abs().max(e.dj.unsigned_abs()) + 1) as usize;
            }
        }
        if targets.is_empty() {
            return 0;
        }
        let clear = |t: Cell| ray_clear_in(&self.elev, self.rect, c, t, zs, zt, d);
        if ray_work < disc.entries.len() {
            let mut sum = 0u32;
            for &(k, g) in targets.iter() {
                let e = disc.entries[k as usize];
                if clear(c.offset(e.di, e.dj)) {
                    sum += g as u32;
                    if let Some(v) = vis.as_deref_mut() {
                        set_bit(v, k as usize);
                    }
                }
            }
            return sum;
        }
        // Only known cells above min(sensor, target) = ef can block a ray to an unknown
        // target, and only over their shadow interval of target distances. Each such cell
        // marks the direction bins it subtends with that interval (kept as the hull per bin);
        // targets outside every interval of their direction are clear without casting (exact:
        // a ray meets a cell only within its angular extent, and a slightly raised cell
        // shadows only the targets just behind it).
        let mut shadow = [(f32::INFINITY, f32::NEG_INFINITY); ANGLE_BINS];
        // Per bin, the distance beyond which a cell higher than the sensor certainly hides the
        // target: the sight line crosses that cell's interior (inner bins) and never rises
        // above the sensor, so it runs below the cell's top there.
        let mut hidden_from = [f32::INFINITY; ANGLE_BINS];
        let mut any_tall = false;
        for e in &disc.entries[..] {
            if e.n_spans == 0 {
                continue;
            }
            let Some(idx) = self.rect.index(c.offset(e.di, e.dj)) else {
                continue;
            };
            let z = self.elev[idx];
            // Unknown (NaN) cells are transparent; cells not above ef cannot block.
            if z.is_nan() || z <= ef {
                continue;
            }
            let (start, end) = shadow_interval(e.r, z, zs, zt);
            for &(a, b) in e.spans() {
                for m in &mut shadow[a as usize..=b as usize] {
                    m.0 = m.0.min(start);
                    m.1 = m.1.max(end);
                }
            }
            if z as f64 > zs && e.inner.0 <= e.inner.1 {
                let far = e.r + HALF_DIAG;
                for m in &mut hidden_from[e.inner.0 as usize..=e.inner.1 as usize] {
                    *m = m.min(far);
                }
            }
            any_tall = true;
        }
        let mut sum = 0u32;
        for &(k, g) in targets.iter() {
            let e = disc.entries[k as usize];
            let maybe_blocked = any_tall && {
                let (lo, hi) = shadow[e.bin as usize];
                e.r >= lo && e.r <= hi
            };
            if maybe_blocked && e.r >= hidden_from[e.bin as usize] {
                continue;
            }
            if !maybe_blocked || clear(c.offset(e.di, e.dj)) {
                sum += g as u32;
                if let Some(v) = vis.as_deref_mut() {
                    set_bit(v, k as usize);
                }
            }
        }
        sum
    }

    /// The change of 9·I_model at candidate `c` from the view `old` (same rectangle) to this
    /// one, given the cells that differ between them (`changed`; `c` not among them) with
    /// their (new, old) elevations (`changed_z`, NaN for unknown) and the visibility of every
    /// target that was unknown in `old` (`vis`, one bit per disc entry), which it brings up to
    /// date.
    ///
    /// A target's term I_cell(t)·observable(c, t) can change only if (a) I_cell(t) changed,
    /// i.e. t is a changed cell or one of its 8-neighbours, or (b) a changed cell on the ray
    /// could block in either view, i.e. rises above ef in one of them; the targets it can
    /// shadow lie in its direction bins within its shadow interval (computed with the higher
    /// of its two elevations, which covers both views). Targets of (b) are cast again in the
    /// new view; for the others of (a) the sight line is unchanged and the stored bit serves.
    ///
    /// Two safe per-cell tests (conservative, with margins against rounding) spare most of
    /// (b)'s casts: a target whose sight line the changed cell does not reach in either view
    /// ([`touches_sight_line`]) is left to the other changed cells, and one whose line it now
    /// crosses below its top ([`crosses_below`]) is blocked without a cast. On
    /// `courtyard-large` they cut the delta updates' time roughly in half.
    #[allow(clippy::too_many_arguments)]
    fn delta_count(
        &self,
        old: &OldView,
        c: Cell,
        changed: &[Cell],
        changed_z: &[(f32, f32)],
        disc: &DiscTable,
        h: f64,
        d: f64,
        scratch: &mut Scratch,
        vis: &mut [u64],
    ) -> i64 {
        let Some(ef) = self.elevation(c) else {
            return 0;
        };
        let zs = ef as f64 + h;
        let zt = target_height(None, ef);
        scratch.next_stamp(disc.entries.len());
        let reach = disc.reach as i32 + 1;
        let mut delta = 0i64;
        let in_range = |x: Cell| {
            let (dx, dy) = (x.i - c.i, x.j - c.j);
            (dx.abs() <= reach && dy.abs() <= reach).then_some((dx, dy))
        };
        // (b) first: sight lines that may have changed are cast again.
        for (&x, &(zn, zo)) in changed.iter().zip(changed_z) {
            // Elevations above ef only (NaN, unknown, compares false).
            let (e_new, e_old) = ((zn > ef).then_some(zn), (zo > ef).then_some(zo));
            if e_new.is_none() && e_old.is_none() {
                continue;
            }
            let Some((dx, dy)) = in_range(x) else {
                continue;
            };
            let Some(kx) = disc.entry_of(dx, dy) else {
                continue;
            };
            let ex = disc.entries[kx];
            let Some(z) = e_new.into_iter().chain(e_old).reduce(f32::max) else {
                continue;
            };
            let (start, end) = shadow_interval(ex.r, z, zs, zt);
            // Targets x now certainly hides (see `model_count_with`).
            let hides = e_new.is_some_and(|z| z as f64 > zs) && ex.inner.0 <= ex.inner.1;
            let far = ex.r + HALF_DIAG;
            // A cell that could not block in the old view (unknown then, which is transparent,
            // or not above ef) can only hide targets now: a target not visible before stays
            // hidden by whatever hid it (a changed blocker recasts it in its own turn), so only
            // the targets visible before need a look. Most of a wedge is known ground.
            let only_hides = e_old.is_none();
            let mut visit = |k: usize| {
                if scratch.seen[k] == scratch.stamp || (only_hides && !get_bit(vis, k)) {
                    return;
                }
                let e = disc.entries[k];
                let t = c.offset(e.di, e.dj);
                let Some(idx) = self.rect.index(t) else {
                    return;
                };
                let (g1, g0) = (self.icount[idx], old.icount[idx]);
                let was = g0 > 0 && get_bit(vis, k);
                if g1 == 0 && !was {
                    // Not visible unknown before, not unknown now: the term stays 0.
                    return;
                }
                // The interval test is coarse: skip the targets whose sight line x does not
                // reach in either view (another changed cell on the same line recasts it; if
                // none does, the line is unchanged).
                if !touches_sight_line(ex.di, ex.dj, e.di, e.dj, z as f64, zs, zt) {
                    return;
                }
                scratch.seen[k] = scratch.stamp;
                let hidden = hides && e.r >= far && (ex.inner.0..=ex.inner.1).contains(&e.bin);
                let now = g1 > 0
                    && !hidden
                    && !e_new.is_some_and(|zn| {
                        k != kx && crosses_below(ex.di, ex.dj, e.di, e.dj, zn as f64, zs, zt)
                    })
                    && ray_clear_in(&self.elev, self.rect, c, t, zs, zt, d);
                delta += if now { g1 as i64 } else { 0 } - if was { g0 as i64 } else { 0 };
                put_bit(vis, k, now);
            };
            if end <= ex.r + NEAR_SHADOW {
                // Short shadow (x barely above the sensor's ground): its precomputed list.
                for &k in disc.near_shadow(kx) {
                    if disc.entries[k as usize].r > end {
                        break;
                    }
                    visit(k as usize);
                }
            } else {
                for &(a, b) in ex.spans() {
                    for bin in a as usize..=b as usize {
                        let range =
                            disc.by_bin_start[bin] as usize..disc.by_bin_start[bin + 1] as usize;
                        let (group, rs) = (&disc.by_bin[range.clone()], &disc.by_bin_r[range]);
                        let from = rs.partition_point(|&r| r < start);
                        for (&k, &r) in group[from..].iter().zip(&rs[from..]) {
                            if r > end {
                                break;
                            }
                            visit(k as usize);
                        }
                    }
                }
            }
        }
        // (a) the rest: I_cell changed, the sight line did not.
        for &x in changed {
            let Some((dx, dy)) = in_range(x) else {
                continue;
            };
            for oy in -1..=1 {
                for ox in -1..=1 {
                    let Some(k) = disc.entry_of(dx + ox, dy + oy) else {
                        continue;
                    };
                    if scratch.seen[k] == scratch.stamp {
                        continue;
                    }
                    scratch.seen[k] = scratch.stamp;
                    let e = disc.entries[k];
                    let t = c.offset(e.di, e.dj);
                    let Some(idx) = self.rect.index(t) else {
                        continue;
                    };
                    let (g1, g0) = (self.icount[idx], old.icount[idx]);
                    if g1 == g0 {
                        continue;
                    }
                    let clear = if g0 > 0 {
                        get_bit(vis, k)
                    } else {
                        // Unknown again (not in practice): no stored bit to trust.
                        ray_clear_in(&self.elev, self.rect, c, t, zs, zt, d)
                    };
                    if clear {
                        delta += g1 as i64 - g0 as i64;
                    }
                    put_bit(vis, k, clear && g1 > 0);
                }
            }
        }
        delta
    }
}

/// Whether a cell of height `z` at offset `(xi, xj)` from the sensor cell can take part in
/// blocking the sight line to the target at offset `(ti, tj)` (sensor at `zs`, target at
/// `zt`, both above cell centres): the closed cell meets the segment where the segment is
/// below `z`. This is the condition under which [`ray_clear_in`] looks at a cell (as a
/// traversed cell or as the other side of a corner crossing), widened by 1e-6 cell and 1e-9 m
/// against rounding, so a `false` is safe: the cell cannot change that sight line.
#[inline]
fn touches_sight_line(xi: i32, xj: i32, ti: i32, tj: i32, z: f64, zs: f64, zt: f64) -> bool {
    let (t0, t1) = cell_span(xi, xj, ti, tj, 1e-6);
    t0 <= t1 && z > lowest_on(t0, t1, zs, zt) - 1e-9
}

/// Whether a cell of height `z` at offset `(xi, xj)` from the sensor cell certainly blocks the
/// sight line to the target at offset `(ti, tj)` (see [`touches_sight_line`]): the segment
/// crosses the cell's interior over more than 1e-6 of its length and dips more than 1e-9 m
/// below `z` there. [`ray_clear_in`] then reports the line blocked, whatever the rounding of
/// its traversal. The cell must be neither the sensor's nor the target's.
#[inline]
fn crosses_below(xi: i32, xj: i32, ti: i32, tj: i32, z: f64, zs: f64, zt: f64) -> bool {
    let (t0, t1) = cell_span(xi, xj, ti, tj, 0.0);
    t1 - t0 > 1e-6 && z > lowest_on(t0, t1, zs, zt) + 1e-9
}

/// The parameter interval `[t0, t1]` ⊂ [0, 1] of the segment from the sensor cell's centre
/// (0, 0) to the target's centre `(ti, tj)` (cell units) inside the cell at `(xi, xj)` grown by
/// `grow` cells on every side; `t0 > t1` when they do not meet.
#[inline]
fn cell_span(xi: i32, xj: i32, ti: i32, tj: i32, grow: f64) -> (f64, f64) {
    let h = 0.5 + grow;
    let (x, y) = (xi as f64, xj as f64);
    box_interval(
        Point2::new(0.0, 0.0),
        ti as f64,
        tj as f64,
        Point2::new(x - h, y - h),
        Point2::new(x + h, y + h),
    )
}

/// The segment's lowest height over `[t0, t1]` (heights `zs` at 0 and `zt` at 1): linear, so
/// at an end of the interval.
#[inline]
fn lowest_on(t0: f64, t1: f64, zs: f64, zt: f64) -> f64 {
    zs + (zt - zs) * if zt < zs { t1 } else { t0 }
}

#[inline]
fn set_bit(v: &mut [u64], k: usize) {
    v[k / 64] |= 1 << (k % 64);
}

#[inline]
fn get_bit(v: &[u64], k: usize) -> bool {
    v[k / 64] >> (k % 64) & 1 == 1
}

#[inline]
fn put_bit(v: &mut [u64], k: usize, on: bool) {
    if on {
        set_bit(v, k);
    } else {
        v[k / 64] &= !(1 << (k % 64));
    }
}

/// The previous state of a [`GainView`] during an incremental update (the previous elevations
/// of the changed cells travel with them).
struct OldView<'a> {
    icount: &'a [u8],
}

/// Summed-area table ((w + 1) × (h + 1)) of a row-major mask.
fn summed_area(mask: &[bool], w: usize, h: usize) -> Vec<u32> {
    let mut sat = vec![0u32; (w + 1) * (h + 1)];
    for y in 0..h {
        let mut row = 0;
        for x in 0..w {
            row += mask[y * w + x] as u32;
            sat[(y + 1) * (w + 1) + x + 1] = sat[y * (w + 1) + x + 1] + row;
        }
    }
    sat
}

/// Number of set cells of the mask behind `sat` (over `rect`) in the square of half-size `n`
/// around `c`, clipped to `rect`.
fn square_count(sat: &[u32], rect: CellRect, c: Cell, n: u32) -> u32 {
    let w = rect.width as i64;
    let h = rect.height as i64;
    let (x, y) = ((c.i - rect.min.i) as i64, (c.j - rect.min.j) as i64);
    let (x0, y0) = ((x - n as i64).clamp(0, w), (y - n as i64).clamp(0, h));
    let (x1, y1) = (
        (x + n as i64 + 1).clamp(0, w),
        (y + n as i64 + 1).clamp(0, h),
    );
    let at = |xx: i64, yy: i64| sat[(yy * (w + 1) + xx) as usize];
    at(x1, y1) + at(x0, y0) - at(x0, y1) - at(x1, y0)
}

/// Direction bins of the shadow mask in [`GainView::model_count`].
const ANGLE_BINS: usize = 2048;

/// Pseudo-angle of the direction (x, y) ≠ 0 in [0, 4): monotone in atan2, no trigonometry.
#[inline]
fn pseudo_angle(x: f64, y: f64) -> f64 {
    if y >= 0.0 {
        if x >= 0.0 {
            y / (x + y)
        } else {
            1.0 - x / (-x + y)
        }
    } else if x < 0.0 {
        2.0 - y / (-x - y)
    } else {
        3.0 + x / (x - y)
    }
}

#[inline]
fn angle_bin(x: f64, y: f64) -> usize {
    ((pseudo_angle(x, y) * (ANGLE_BINS as f64 / 4.0)) as usize).min(ANGLE_BINS - 1)
}

/// The view rectangle: the known area grown by the sensor reach plus the neighbourhood of
/// Eq. 10.
fn view_rect(map: &ElevationMap, around: CellRect) -> CellRect {
    let reach = disc_reach(map.params().r_sensor, map.cell_size());
    rect::expand(around, reach + 2)
}

/// Moves the view, the cached counts and visibility bits into the larger `rect`; cells
/// new to the view are unknown (as they were to the old view), so its I_cell values are
/// unchanged where a cached candidate reads them.
fn grow_view(
    view: &mut Option<GainView>,
    counts: &mut Vec<u32>,
    vis: &mut Vec<Vec<u64>>,
    rect: CellRect,
    bounds: Option<&WorldRect>,
    d: f64,
) {
    let Some(old) = view.take() else {
        return;
    };
    let mut elev = vec![f32::NAN; rect.len()];
    let mut new_counts = vec![NOT_CACHED; rect.len()];
    let mut new_vis = vec![Vec::new(); rect.len()];
    for (k, c) in old.rect.cells().enumerate() {
        if let Some(nk) = rect.index(c) {
            elev[nk] = old.elev[k];
            new_counts[nk] = counts[k];
            new_vis[nk] = std::mem::take(&mut vis[k]);
        }
    }
    let mut v = GainView {
        rect,
        elev,
        icount: Vec::new(),
        sat: Vec::new(),
    };
    v.derive(bounds, d);
    *view = Some(v);
    *counts = new_counts;
    *vis = new_vis;
}

/// I_cell(ν') (Eq. 10): (k + 1) / 9 for an unknown cell inside `bounds`, 0 otherwise.
pub fn cell_information(map: &ElevationMap, c: Cell, bounds: Option<&WorldRect>) -> f64 {
    let v = GainView::new(map, rect::expand(CellRect::new(c, 1, 1), 1), bounds);
    v.icount[v.rect.index(c).unwrap_or(0)] as f64 / 9.0
}

/// I_model(ν) (Eq. 11) at one observed cell, without the candidate filter. 0 for an unknown
/// cell.
pub fn model_information(map: &ElevationMap, c: Cell, bounds: Option<&WorldRect>) -> f64 {
    let p = map.params();
    let d = map.cell_size();
    let view = GainView::new(map, view_rect(map, CellRect::new(c, 1, 1)), bounds);
    view.model_count(c, &DiscTable::new(p.r_sensor, d), p.sensor_height, d) as f64 / 9.0
}

/// The candidate cells of Eq. 11: reachable goal cells on the `info_gain_stride` lattice inside
/// `bounds`.
fn candidates(map: &ElevationMap, reach: &Reachability, bounds: Option<&WorldRect>) -> Vec<Cell> {
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

/// I_model (Eq. 11) on every candidate cell: observed, admissible, reachable (`reach`), on the
/// `info_gain_stride` lattice, inside `bounds`, with an unknown cell within r_sensor. Runs in
/// parallel over candidates; the result is deterministic. [`GainCache`] gives the same result
/// incrementally.
pub fn information_gain(
    map: &ElevationMap,
    reach: &Reachability,
    bounds: Option<&WorldRect>,
) -> InfoGain {
    let Some(known) = map.known_bounds() else {
        return InfoGain::default();
    };
    let p = map.params();
    let d = map.cell_size();
    let candidates = candidates(map, reach, bounds);
    let view = GainView::new(map, view_rect(map, known), bounds);
    let disc = DiscTable::new(p.r_sensor, d);
    let counts: Vec<u32> = candidates
        .par_iter()
        .map_init(Scratch::default, |s, &c| {
            view.model_count_with(c, &disc, p.sensor_height, d, s, None)
        })
        .collect();
    collect_gains(candidates, counts)
}

fn collect_gains(candidates: Vec<Cell>, counts: Vec<u32>) -> InfoGain {
    InfoGain {
        candidates: candidates.len(),
        cells: candidates
            .into_iter()
            .zip(counts)
            .filter(|&(_, n)| n > 0)
            .map(|(c, n)| (c, n as f64 / 9.0))
            .collect(),
    }
}

/// Above disc size / this many changed cells within r_sensor + 1 of a cached candidate, its
/// Eq. 11 sum is evaluated afresh instead of updated. An update looks up ~9 stored visibility
/// bits per changed cell and casts only the sight lines in the shadow of changed cells that
/// rise above the candidate (most of them settled by per-cell tests, see
/// `GainView::delta_count`); a fresh evaluation makes about two passes over the disc and casts
/// its maybe-blocked targets. Measured worst spatial update on courtyard-large (whole mission):
/// /2 108 ms, /8 128 ms, /32 295 ms; on courtyard-small /2 9–10 ms against 23–30 ms for /32.
/// (Before the per-cell tests, /32 beat /160 on courtyard-small: 33–47 against 87 ms.)
const DELTA_CHANGES_PER_DISC: usize = 2;

/// Sentinel of [`GainCache`]: no cached value.
const NOT_CACHED: u32 = u32::MAX;

/// Eq. 11 kept up to date between calls: a mission asks for the gain every few seconds while
/// the map changes only where the sensor looks. A cached candidate near cells that changed
/// since the last call gets its sum *updated* from the targets those changes can affect
/// (`GainView::delta_count`); only candidates that are new, changed themselves, or saw many
/// changes are evaluated afresh. Sums are kept as integers (9·I_model), so updates are exact.
///
/// "Changed" means the cell became observed, or its elevation moved by more than `dz` from
/// the value the cache last used; the cache evaluates Eq. 11 on its own copy of the
/// elevations, which follows the map with that hysteresis. With `dz = 0` the result equals
/// [`information_gain`] exactly; a small `dz` (the mission uses 1 cm, the order of the depth
/// noise) stops the Kalman refinement of ground already seen, which moves elevations by
/// millimetres with every scan, from touching every candidate near the sensor footprint. Such
/// a change can flip a sight line only where it grazes a cell within `dz`.
#[derive(Default)]
pub struct GainCache {
    view: Option<GainView>,
    /// Cached 9·I_model per view cell ([`NOT_CACHED`] = none).
    counts: Vec<u32>,
    /// Per cached view cell, the visibility of each disc target unknown at the last
    /// evaluation (one bit per disc entry); empty when not cached.
    vis: Vec<Vec<u64>>,
    bounds: Option<WorldRect>,
    disc: Option<(f64, f64, DiscTable)>,
    dz: f32,
    /// (fresh evaluations, delta updates) in the last call.
    last: (usize, usize),
}

impl GainCache {
    /// An empty cache with elevation hysteresis `dz` (metres, ≥ 0; NaN or negative counts as 0).
    pub fn new(dz: f64) -> Self {
        Self {
            dz: if dz > 0.0 { dz as f32 } else { 0.0 },
            ..Self::default()
        }
    }

    /// Candidates whose Eq. 11 sum was evaluated afresh in the last call.
    pub fn last_evaluated(&self) -> usize {
        self.last.0
    }

    /// Candidates whose cached Eq. 11 sum was updated from nearby changes in the last call.
    pub fn last_updated(&self) -> usize {
        self.last.1
    }

    /// [`information_gain`] on the current map, re-evaluating only what changed since the
    /// last call.
    pub fn compute(
        &mut self,
        map: &ElevationMap,
        reach: &Reachability,
        bounds: Option<&WorldRect>,
    ) -> InfoGain {
        self.last = (0, 0);
        let Some(known) = map.known_bounds() else {
            return InfoGain::default();
        };
        let p = map.params();
        let d = map.cell_size();
        if self
            .disc
            .as_ref()
            .is_none_or(|(r, dd, _)| *r != p.r_sensor || *dd != d)
        {
            self.disc = Some((p.r_sensor, d, DiscTable::new(p.r_sensor, d)));
            self.view = None;
        }
        let Some((_, _, disc)) = self.disc.as_ref() else {
            return InfoGain::default();
        };
        let h = p.sensor_height;
        let needed = view_rect(map, known);
        let fits = self
            .view
            .as_ref()
            .is_some_and(|v| rect::intersection(v.rect, needed) == Some(needed));
        let candidates = candidates(map, reach, bounds);
        let mut deltas: Vec<(usize, Cell)> = Vec::new();
        let mut changed_cells: Vec<Cell> = Vec::new();
        // Their (new, old) elevations, NaN when unknown.
        let mut changed_z: Vec<(f32, f32)> = Vec::new();
        // The view before this call's changes: I_cell when it changed (else the current one
        // serves).
        let mut old: Option<Option<Vec<u8>>> = None;
        let rebuild = self.view.is_none() || self.bounds != bounds.copied();
        if rebuild {
            let rect = rect::expand(needed, disc.reach);
            self.view = Some(GainView::new(map, rect, bounds));
            self.counts = vec![NOT_CACHED; rect.len()];
            self.vis = vec![Vec::new(); rect.len()];
            self.bounds = bounds.copied();
        } else if !fits {
            // The known area outgrew the view: grow it with a margin (so that a slowly
            // growing map grows it rarely) and carry the cache over. Every cached candidate's
            // disc lies in the old view, outside which nothing was known; the new cells enter
            // as changes below like any other.
            let grown = self
                .view
                .as_ref()
                .map_or(needed, |v| rect::union(v.rect, needed));
            let rect = rect::expand(grown, disc.reach);
            let (view, counts, vis) = (&mut self.view, &mut self.counts, &mut self.vis);
            grow_view(view, counts, vis, rect, bounds, d);
        }
        if !rebuild && let Some(v) = self.view.as_mut() {
            // Follow the map: cells that became observed or moved by more than dz.
            let fresh = map.elevation_raster(v.rect);
            let mut changed = vec![false; fresh.len()];
            let mut known_changed = false;
            for (k, (&new, cur)) in fresh.iter().zip(v.elev.iter_mut()).enumerate() {
                let differs = if new.is_nan() || cur.is_nan() {
                    new.is_nan() != cur.is_nan()
                } else {
                    (new - *cur).abs() > self.dz
                };
                if differs {
                    known_changed |= new.is_nan() != cur.is_nan();
                    changed_z.push((new, *cur));
                    *cur = new;
                    changed[k] = true;
                    changed_cells.push(v.rect.cell(k));
                }
            }
            let old_icount = known_changed.then(|| {
                let o = v.icount.clone();
                v.derive(bounds, d);
                o
            });
            if !changed_cells.is_empty() {
                let (w, hh) = (v.rect.width as usize, v.rect.height as usize);
                let sat = summed_area(&changed, w, hh);
                let is_candidate = {
                    let mut m = vec![false; v.rect.len()];
                    for &c in &candidates {
                        if let Some(k) = v.rect.index(c) {
                            m[k] = true;
                        }
                    }
                    m
                };
                let max_changes = (disc.entries.len() / DELTA_CHANGES_PER_DISC).max(16) as u32;
                for (k, n) in self.counts.iter_mut().enumerate() {
                    if *n == NOT_CACHED {
                        continue;
                    }
                    let c = v.rect.cell(k);
                    let near = square_count(&sat, v.rect, c, disc.reach + 1);
                    if near == 0 {
                        continue;
                    }
                    if changed[k] || near > max_changes || !is_candidate[k] {
                        *n = NOT_CACHED;
                        self.vis[k] = Vec::new();
                    } else {
                        deltas.push((k, c));
                    }
                }
            }
            old = Some(old_icount);
        }
        let Some(view) = self.view.as_ref() else {
            return InfoGain::default();
        };
        let todo: Vec<(usize, Cell)> = candidates
            .iter()
            .filter_map(|&c| view.rect.index(c).map(|k| (k, c)))
            .filter(|&(k, _)| self.counts[k] == NOT_CACHED)
            .collect();
        let words = disc.entries.len().div_ceil(64);
        let fresh: Vec<(u32, Vec<u64>)> = todo
            .par_iter()
            .map_init(Scratch::default, |s, &(_, c)| {
                let mut vis = vec![0u64; words];
                let n = view.model_count_with(c, disc, h, d, s, Some(&mut vis));
                (n, vis)
            })
            .collect();
        if let Some(old_icount) = &old {
            let ov = OldView {
                icount: old_icount.as_deref().unwrap_or(&view.icount),
            };
            let (changed, changed_z) = (&changed_cells, &changed_z);
            let mut work: Vec<(usize, Cell, Vec<u64>, i64)> = deltas
                .iter()
                .map(|&(k, c)| (k, c, std::mem::take(&mut self.vis[k]), 0))
                .collect();
            work.par_iter_mut()
                .for_each_init(Scratch::default, |s, (_, c, vis, dn)| {
                    *dn = view.delta_count(&ov, *c, changed, changed_z, disc, h, d, s, vis);
                });
            for (k, _, vis, dn) in work {
                let n = self.counts[k] as i64 + dn;
                debug_assert!(n >= 0, "negative Eq. 11 count");
                self.counts[k] = n.max(0) as u32;
                self.vis[k] = vis;
            }
        }
        self.last = (todo.len(), deltas.len());
        for (&(k, _), (n, vis)) in todo.iter().zip(fresh) {
            self.counts[k] = n;
            self.vis[k] = vis;
        }
        let counts = candidates
            .iter()
            .map(|&c| view.rect.index(c).map_or(0, |k| self.counts[k]))
            .collect();
        collect_gains(candidates, counts)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::observability::ray_clear;
    use crate::params::MapParams;
    use approx::assert_abs_diff_eq;
    use strider_core::{Point2, Rgb8};

    fn params() -> MapParams {
        MapParams {
            cell_size: 0.1,
            tile_size: 8,
            r_sensor: 0.2, // disc of 13 cells
            r_robot: 0.0,
            sensor_height: 0.3,
            ..MapParams::default()
        }
    }

    fn flat(m: &mut ElevationMap, cells: impl IntoIterator<Item = Cell>) {
        for c in cells {
            m.set_cell(c, 0.0, 1e-4, Rgb8::default());
        }
        m.update_passability();
    }

    #[test]
    fn cell_information_counts_unknown_neighbours() {
        let mut m = ElevationMap::new(params());
        assert_abs_diff_eq!(
            cell_information(&m, Cell::new(0, 0), None),
            1.0,
            epsilon = 1e-6
        );
        flat(&mut m, [Cell::new(1, 0), Cell::new(1, 1)]);
        assert_abs_diff_eq!(
            cell_information(&m, Cell::new(0, 0), None),
            7.0 / 9.0,
            epsilon = 1e-6
        );
        assert_abs_diff_eq!(
            cell_information(&m, Cell::new(1, 0), None),
            0.0,
            epsilon = 1e-6
        );
        // Bounds: the cell itself outside gives nothing; neighbours outside do not count.
        let b = WorldRect::new(Point2::new(-0.1, -0.1), Point2::new(0.1, 1.0));
        assert_abs_diff_eq!(
            cell_information(&m, Cell::new(0, 0), Some(&b)),
            6.0 / 9.0,
            epsilon = 1e-6
        );
        assert_abs_diff_eq!(
            cell_information(&m, Cell::new(2, 0), Some(&b)),
            0.0,
            epsilon = 1e-6
        );
    }

    #[test]
    fn model_information_on_a_strip() {
        // A known 1-cell-wide strip j = 0, i ∈ [-5, 5]; the disc of radius 2 cells around (0, 0)
        // holds 13 cells: 5 known (the strip), 8 unknown. Unknown (0, ±1), (±1, ±1): neighbours
        // include 3 known strip cells → k = 5, I = 6/9; (0, ±2): k = 8 → 1; and (±1, ±1) → k = 5.
        let mut m = ElevationMap::new(params());
        flat(&mut m, (-5..=5).map(|i| Cell::new(i, 0)));
        let expected = 2.0 * (6.0 / 9.0 * 3.0) + 2.0 * 1.0;
        assert_abs_diff_eq!(
            model_information(&m, Cell::new(0, 0), None),
            expected,
            epsilon = 1e-6
        );
        // A tall known wall cell between the robot and (0, 2) hides it.
        m.set_cell(Cell::new(0, 1), 2.0, 1e-4, Rgb8::default());
        let hidden = expected - 6.0 / 9.0 - 1.0 - 2.0 * (1.0 / 9.0);
        // (0,1) became known: it no longer counts, (0,2) is hidden behind it and the unknown
        // cells (±1, 1) lost one unknown neighbour each.
        assert_abs_diff_eq!(
            model_information(&m, Cell::new(0, 0), None),
            hidden,
            epsilon = 1e-6
        );
    }

    #[test]
    fn information_gain_on_candidates() {
        let mut m = ElevationMap::new(params());
        // Known 11 × 11 square: interior cells see no unknown cell within 2 cells.
        flat(
            &mut m,
            (-5..=5).flat_map(|j| (-5..=5).map(move |i| Cell::new(i, j))),
        );
        let reach = Reachability::compute(&m, Cell::new(0, 0));
        let g = information_gain(&m, &reach, None);
        // Candidates: every cell except the border ring (no known neighbour on all sides is
        // fine; the border ring is passable too) → 121 evaluated.
        assert_eq!(g.candidates, 121);
        // Cells with an unknown cell within 2 cells: the outer two rings (121 − 7·7).
        assert_eq!(g.cells.len(), 121 - 49);
        let corner = g
            .cells
            .iter()
            .find(|&&(c, _)| c == Cell::new(5, 5))
            .unwrap()
            .1;
        assert_abs_diff_eq!(corner, model_information(&m, Cell::new(5, 5), None));
        // With a stride of 2 only even lattice cells are evaluated.
        let mut m2 = m.clone();
        m2.set_info_gain_stride(2);
        let g2 = information_gain(&m2, &reach, None);
        assert_eq!(g2.candidates, 25);
        // Bounds that exclude everything beyond the square leave nothing to gain.
        let b = WorldRect::new(Point2::new(-0.5, -0.5), Point2::new(0.6, 0.6));
        assert!(information_gain(&m, &reach, Some(&b)).cells.is_empty());
    }

    /// Applies `edits` (never to the robot's cell (0, 0)), then evaluates Eq. 11 through the
    /// cache and afresh.
    fn edit_and_evaluate(
        m: &mut ElevationMap,
        cache: &mut GainCache,
        edits: &[(i32, i32, f32)],
    ) -> (InfoGain, InfoGain) {
        for &(i, j, z) in edits {
            if (i, j) != (0, 0) {
                m.set_cell(Cell::new(i, j), z, 1e-4, Rgb8::default());
            }
        }
        m.update_passability();
        let reach = Reachability::compute(m, Cell::new(0, 0));
        (
            cache.compute(m, &reach, None),
            information_gain(m, &reach, None),
        )
    }

    #[test]
    fn cache_reuses_unchanged_candidates_and_follows_changes() {
        let mut m = ElevationMap::new(MapParams {
            r_sensor: 0.3,
            ..params()
        });
        flat(
            &mut m,
            (-10..=10).flat_map(|j| (-10..=10).map(move |i| Cell::new(i, j))),
        );
        let reach = Reachability::compute(&m, Cell::new(0, 0));
        let mut cache = GainCache::new(0.01);
        let first = cache.compute(&m, &reach, None);
        assert_eq!(first.cells, information_gain(&m, &reach, None).cells);
        assert!(cache.last_evaluated() > 0);
        // Nothing changed: everything comes from the cache.
        let again = cache.compute(&m, &reach, None);
        assert_eq!(again.cells, first.cells);
        assert_eq!(cache.last_evaluated(), 0);
        // A change below the hysteresis is ignored; above it only nearby candidates are
        // re-evaluated and the result is exact again.
        m.set_cell(Cell::new(9, 9), 0.005, 1e-4, Rgb8::default());
        m.update_passability();
        cache.compute(&m, &reach, None);
        assert_eq!(cache.last_evaluated(), 0);
        m.set_cell(Cell::new(9, 9), 0.2, 1e-4, Rgb8::default());
        m.set_cell(Cell::new(11, 9), 0.0, 1e-4, Rgb8::default());
        m.update_passability();
        let reach = Reachability::compute(&m, Cell::new(0, 0));
        let after = cache.compute(&m, &reach, None);
        let (evaluated, updated) = (cache.last_evaluated(), cache.last_updated());
        assert!(
            updated > 0,
            "nearby candidates are updated, not re-evaluated"
        );
        assert!(
            evaluated + updated < after.candidates,
            "{evaluated} {updated}"
        );
        assert_eq!(after.cells, information_gain(&m, &reach, None).cells);
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(48))]
        /// Delta updates are exact: on a fixed-size patchy map with walls, random edits
        /// (unknown cells becoming known, known cells rising or sinking) leave the cache equal
        /// to a fresh evaluation.
        #[test]
        fn cache_updates_equal_fresh_evaluation(
            init in proptest::collection::vec((proptest::bool::weighted(0.6), 0.0f32..0.6), 625),
            steps in proptest::collection::vec(
                proptest::collection::vec((-12..=12i32, -12..=12i32, 0.0f32..0.6), 1..12),
                1..6,
            ),
            dz in proptest::prop_oneof![proptest::strategy::Just(0.0f64), 0.0f64..0.05],
        ) {
            let mut m = ElevationMap::new(MapParams { r_sensor: 0.6, ..params() });
            for (k, &(known, z)) in init.iter().enumerate() {
                let c = Cell::new(k as i32 % 25 - 12, k as i32 / 25 - 12);
                // Corners pin the known bounds so the view never grows.
                let corner = c.i.abs() == 12 && c.j.abs() == 12;
                if known || corner || c == Cell::new(0, 0) {
                    let z = if c == Cell::new(0, 0) { 0.0 } else { z };
                    m.set_cell(c, z, 1e-4, Rgb8::default());
                }
            }
            m.update_passability();
            let mut cache = GainCache::new(dz);
            let reach = Reachability::compute(&m, Cell::new(0, 0));
            let first = cache.compute(&m, &reach, None);
            proptest::prop_assert_eq!(first.cells, information_gain(&m, &reach, None).cells);
            for edits in steps {
                let (cached, fresh) = edit_and_evaluate(&mut m, &mut cache, &edits);
                if dz == 0.0 {
                    proptest::prop_assert_eq!(cached.candidates, fresh.candidates);
                    proptest::prop_assert_eq!(cached.cells, fresh.cells);
                }
            }
        }
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(32))]
        /// With dz = 0 the cache equals a fresh evaluation after every step of a random
        /// sequence of map edits (new cells, raised cells, the map growing).
        #[test]
        fn cache_equals_fresh_evaluation(
            steps in proptest::collection::vec(
                proptest::collection::vec((-12..12i32, -12..12i32, 0.0f32..0.5), 1..30),
                1..6,
            ),
        ) {
            let mut m = ElevationMap::new(MapParams { r_sensor: 0.4, ..params() });
            flat(&mut m, (-2..=2).flat_map(|j| (-2..=2).map(move |i| Cell::new(i, j))));
            let mut cache = GainCache::new(0.0);
            for edits in steps {
                let (cached, fresh) = edit_and_evaluate(&mut m, &mut cache, &edits);
                proptest::prop_assert_eq!(cached.candidates, fresh.candidates);
                proptest::prop_assert_eq!(cached.cells, fresh.cells);
            }
        }
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(64))]
        /// The shadow-direction shortcut is exact: I_model equals the sum over every unknown
        /// target of I_cell when its ray (cast unconditionally) is clear.
        #[test]
        fn shadow_pruning_is_exact(
            heights in proptest::collection::vec(0.0f32..0.6, 144),
            known in proptest::collection::vec(proptest::bool::weighted(0.6), 144),
            ci in 0..12i32, cj in 0..12i32,
        ) {
            let mut m = ElevationMap::new(MapParams { r_sensor: 0.5, ..params() });
            for k in 0..144 {
                if known[k] || k == (cj * 12 + ci) as usize {
                    m.set_cell(Cell::new(k as i32 % 12, k as i32 / 12), heights[k], 1e-4, Rgb8::default());
                }
            }
            let c = Cell::new(ci, cj);
            let ef = m.elevation(c).unwrap();
            let mut brute = 0.0;
            for (di, dj) in disc_offsets(0.5, 0.1) {
                let t = c.offset(di, dj);
                if m.is_observed(t) {
                    continue;
                }
                let clear = ray_clear(c, t, ef as f64 + 0.3, ef as f64, 0.1, |x| m.elevation(x));
                if clear {
                    brute += cell_information(&m, t, None);
                }
            }
            let fast = model_information(&m, c, None);
            proptest::prop_assert!((fast - brute).abs() < 1e-4, "fast {fast} brute {brute}");
        }
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(2000))]
        /// The two per-cell tests of the delta update agree with the sight-line test itself,
        /// on heights placed within centimetres of the sight line (the near-tangent cases):
        /// a cell that `crosses_below` blocks the line whatever else the raster holds, and a
        /// cell that does not `touches_sight_line` leaves the line's result unchanged when it
        /// is made unknown.
        #[test]
        fn delta_cell_tests_agree_with_the_sight_line(
            known in proptest::collection::vec(proptest::bool::weighted(0.2), 441),
            noise in proptest::collection::vec(-0.03f32..0.01, 441),
            ti in -10..=10i32, tj in -10..=10i32,
            (si, sj) in (-1..=1i32, -1..=1i32),
            diagonal in proptest::bool::ANY,
            along in 0.0f64..1.0, dz in -0.03f64..0.03,
            h in 0.05f64..0.8,
        ) {
            let rect = CellRect::new(Cell::new(-10, -10), 21, 21);
            let c = Cell::new(0, 0);
            let (ti, tj) = if diagonal { (ti, if tj < 0 { -ti } else { ti }) } else { (ti, tj) };
            let t = Cell::new(ti, tj);
            let (zs, zt) = (h, 0.0);
            let line_z = |p: Cell| {
                // Height of the segment where it passes closest to p's centre.
                let (dx, dy) = (ti as f64, tj as f64);
                let len2 = dx * dx + dy * dy;
                let u = if len2 > 0.0 { ((p.i as f64 * dx + p.j as f64 * dy) / len2).clamp(0.0, 1.0) } else { 0.0 };
                zs + (zt - zs) * u
            };
            // Every known cell sits near the line; x near the point `along` of it.
            let mut raster: Vec<f32> = rect
                .cells()
                .zip(known.iter().zip(&noise))
                .map(|(p, (&k, &n))| if k { (line_z(p) + n as f64) as f32 } else { f32::NAN })
                .collect();
            raster[rect.index(c).unwrap()] = 0.0;
            // x on the line at `along`, or a neighbour of that cell.
            let x = Cell::new(
                (ti as f64 * along).round() as i32 + si,
                (tj as f64 * along).round() as i32 + sj,
            );
            proptest::prop_assume!(x != c && x != t);
            let z = (line_z(x) + dz) as f32;
            let Some(kx) = rect.index(x) else {
                return Ok(());
            };
            raster[kx] = z;
            let with_x = ray_clear_in(&raster, rect, c, t, zs, zt, 0.1);
            if crosses_below(x.i, x.j, ti, tj, z as f64, zs, zt) {
                proptest::prop_assert!(!with_x, "crosses_below but the line is clear");
            }
            if !touches_sight_line(x.i, x.j, ti, tj, z as f64, zs, zt) {
                raster[kx] = f32::NAN;
                let without_x = ray_clear_in(&raster, rect, c, t, zs, zt, 0.1);
                proptest::prop_assert_eq!(with_x, without_x, "x does not touch the line but changes it");
            }
        }
    }
}
