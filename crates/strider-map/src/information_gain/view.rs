//! The dense view of the map that Eq. 10–11 are evaluated on, and Eq. 11 afresh at one
//! candidate.

use super::bits::set_bit;
use super::disc::{ANGLE_BINS, DiscTable, HALF_DIAG};
use super::sight::Sight;
use crate::map::ElevationMap;
use crate::rect::{WorldRect, in_bounds};
use strider_core::grid::NEIGHBOURS8;
use strider_core::{Cell, CellRect};

/// Per-thread scratch space of Eq. 11.
#[derive(Default)]
pub(super) struct Scratch {
    /// Unknown targets of the disc: (entry index, 9·I_cell).
    targets: Vec<(u32, u8)>,
    /// Disc entries already visited by a delta update (== `stamp`).
    pub(super) seen: Vec<u32>,
    pub(super) stamp: u32,
}

impl Scratch {
    /// Starts a new visit over a disc of `n` entries.
    pub(super) fn next_stamp(&mut self, n: usize) {
        if self.seen.len() != n || self.stamp == u32::MAX {
            self.seen.clear();
            self.seen.resize(n, 0);
            self.stamp = 0;
        }
        self.stamp += 1;
    }

    /// Whether entry `k` was visited in this visit; marks it visited.
    #[inline]
    pub(super) fn visit(&mut self, k: usize) -> bool {
        let seen = self.seen[k] == self.stamp;
        self.seen[k] = self.stamp;
        seen
    }
}

/// Side of the blocks over which a [`GainView`] counts its unknown cells, cells.
const UNKNOWN_BLOCK: usize = 16;

/// A dense view of the map for Eq. 10–11: elevations (NaN = unknown), 9·I_cell of every
/// unknown cell (k + 1 ∈ 1..=9; 0 for known cells and cells outside the bounds) and the
/// number of unknown cells per block. I_cell is kept as the integer k + 1 so that sums are
/// exact and a delta update gives bit-for-bit the sum a fresh evaluation gives.
pub(super) struct GainView {
    pub(super) rect: CellRect,
    pub(super) elev: Vec<f32>,
    pub(super) icount: Vec<u8>,
    /// Unknown cells (I_cell > 0) per [`UNKNOWN_BLOCK`]² block of the view, row-major: a
    /// candidate with no unknown cell in the blocks its disc touches has no gain. Unlike a
    /// summed-area table, a change updates only the blocks it touches.
    unknown_blocks: Vec<u32>,
}

/// Per direction bin, what the raised cells of a disc can do to its targets (see
/// [`GainView::mark_shadows`]).
struct ShadowMask {
    /// The hull of the shadow intervals of the cells that subtend the bin.
    shadow: [(f32, f32); ANGLE_BINS],
    /// The distance beyond which a cell higher than the sensor certainly hides the target.
    hidden_from: [f32; ANGLE_BINS],
    /// Whether any cell can block at all.
    any_tall: bool,
}

impl GainView {
    /// The view of `map` over `rect`.
    pub(super) fn new(map: &ElevationMap, rect: CellRect, bounds: Option<&WorldRect>) -> Self {
        Self::from_elevations(rect, map.elevation_raster(rect), bounds, map.cell_size())
    }

    /// The view of the elevations `elev` over `rect` (NaN = unknown).
    pub(super) fn from_elevations(
        rect: CellRect,
        elev: Vec<f32>,
        bounds: Option<&WorldRect>,
        d: f64,
    ) -> Self {
        let mut v = Self {
            rect,
            elev,
            icount: Vec::new(),
            unknown_blocks: Vec::new(),
        };
        v.derive(bounds, d);
        v
    }

    /// This view moved into the larger `rect`; cells new to the view are unknown.
    pub(super) fn grown(&self, rect: CellRect, bounds: Option<&WorldRect>, d: f64) -> Self {
        let mut elev = vec![f32::NAN; rect.len()];
        for (k, c) in self.rect.cells().enumerate() {
            if let Some(nk) = rect.index(c) {
                elev[nk] = self.elev[k];
            }
        }
        Self::from_elevations(rect, elev, bounds, d)
    }

    /// Recomputes 9·I_cell (Eq. 10) and the unknown counts from the elevations.
    pub(super) fn derive(&mut self, bounds: Option<&WorldRect>, d: f64) {
        self.icount.clear();
        self.icount.resize(self.rect.len(), 0);
        let (bw, bh) = self.block_dims();
        self.unknown_blocks.clear();
        self.unknown_blocks.resize(bw * bh, 0);
        self.derive_in(self.rect, bounds, d);
    }

    /// Recomputes 9·I_cell over `region` (clipped to the view) and the unknown counts of the
    /// blocks it touches. Every other cell keeps its value, so `region` must hold every cell
    /// whose own or 8-neighbours' elevation went from or to unknown.
    pub(super) fn derive_in(&mut self, region: CellRect, bounds: Option<&WorldRect>, d: f64) {
        let Some(region) = crate::rect::intersection(region, self.rect) else {
            return;
        };
        let rect = self.rect;
        let (w, h) = (rect.width as i64, rect.height as i64);
        let (x0, y0) = (
            (region.min.i - rect.min.i) as i64,
            (region.min.j - rect.min.j) as i64,
        );
        let (rw, rh) = (region.width as i64, region.height as i64);
        // The unknown mask over the region and a ring of one cell around it; outside the
        // view nothing is known either.
        let (mw, mh) = (rw + 2, rh + 2);
        let mut unknown = vec![false; (mw * mh) as usize];
        for my in 0..mh {
            for mx in 0..mw {
                let (x, y) = (x0 - 1 + mx, y0 - 1 + my);
                let c = rect.min.offset(x as i32, y as i32);
                let inside = x >= 0 && y >= 0 && x < w && y < h;
                unknown[(my * mw + mx) as usize] = in_bounds(bounds, c, d)
                    && (!inside || self.elev[(y * w + x) as usize].is_nan());
            }
        }
        for ry in 0..rh {
            for rx in 0..rw {
                let m = (ry + 1) * mw + rx + 1;
                let k = ((y0 + ry) * w + x0 + rx) as usize;
                self.icount[k] = if unknown[m as usize] {
                    // k(ν'): unknown 8-neighbours.
                    let n = NEIGHBOURS8
                        .iter()
                        .filter(|&&(di, dj)| unknown[(m + dj as i64 * mw + di as i64) as usize])
                        .count();
                    n as u8 + 1 // Eq. 10, times 9
                } else {
                    0
                };
            }
        }
        self.count_unknown_blocks(x0 as usize, y0 as usize, rw as usize, rh as usize);
    }

    /// Blocks per row and per column of the view.
    fn block_dims(&self) -> (usize, usize) {
        (
            (self.rect.width as usize).div_ceil(UNKNOWN_BLOCK),
            (self.rect.height as usize).div_ceil(UNKNOWN_BLOCK),
        )
    }

    /// Recounts the unknown cells of the blocks that meet the `rw` × `rh` cells at view
    /// offset (`x0`, `y0`).
    fn count_unknown_blocks(&mut self, x0: usize, y0: usize, rw: usize, rh: usize) {
        if rw == 0 || rh == 0 {
            return;
        }
        let (w, h) = (self.rect.width as usize, self.rect.height as usize);
        let (bw, _) = self.block_dims();
        for by in y0 / UNKNOWN_BLOCK..=(y0 + rh - 1) / UNKNOWN_BLOCK {
            for bx in x0 / UNKNOWN_BLOCK..=(x0 + rw - 1) / UNKNOWN_BLOCK {
                let (xs, ys) = (bx * UNKNOWN_BLOCK, by * UNKNOWN_BLOCK);
                let (xe, ye) = ((xs + UNKNOWN_BLOCK).min(w), (ys + UNKNOWN_BLOCK).min(h));
                let n: usize = (ys..ye)
                    .map(|y| {
                        self.icount[y * w + xs..y * w + xe]
                            .iter()
                            .filter(|&&g| g > 0)
                            .count()
                    })
                    .sum();
                self.unknown_blocks[by * bw + bx] = n as u32;
            }
        }
    }

    /// Elevation of `c`, `None` when unknown or outside the view.
    #[inline]
    pub(super) fn elevation(&self, c: Cell) -> Option<f32> {
        self.rect
            .index(c)
            .map(|k| self.elev[k])
            .filter(|e| !e.is_nan())
    }

    /// The sight lines from candidate `c` with the sensor `h` above it, on cells of size `d`;
    /// `None` when `c` is unknown.
    #[inline]
    pub(super) fn sight(&self, c: Cell, h: f64, d: f64) -> Option<Sight> {
        Some(Sight::new(c, self.elevation(c)?, h, d))
    }

    /// Whether the sight line from `s` to `t` is clear in this view.
    #[inline]
    pub(super) fn clear(&self, s: &Sight, t: Cell) -> bool {
        s.clear_in(&self.elev, self.rect, t)
    }

    /// Whether the square of half-size `n` around `c` (clipped to the view) may hold an
    /// unknown cell: false only when every block it meets has none.
    fn may_see_unknown(&self, c: Cell, n: u32) -> bool {
        let (w, h) = (self.rect.width as i64, self.rect.height as i64);
        let (x, y) = (
            (c.i - self.rect.min.i) as i64,
            (c.j - self.rect.min.j) as i64,
        );
        let n = n as i64;
        let (x0, x1) = ((x - n).clamp(0, w), (x + n + 1).clamp(0, w));
        let (y0, y1) = ((y - n).clamp(0, h), (y + n + 1).clamp(0, h));
        if x0 >= x1 || y0 >= y1 {
            return false;
        }
        let b = UNKNOWN_BLOCK as i64;
        let (bw, _) = self.block_dims();
        (y0 / b..=(y1 - 1) / b).any(|by| {
            (x0 / b..=(x1 - 1) / b)
                .any(|bx| self.unknown_blocks[by as usize * bw + bx as usize] > 0)
        })
    }

    /// 9·I_model(ν) (Eq. 11).
    pub(super) fn model_count(&self, c: Cell, disc: &DiscTable, h: f64, d: f64) -> u32 {
        self.model_count_with(c, disc, h, d, &mut Scratch::default(), None)
    }

    /// [`GainView::model_count`] with reusable scratch space; fills `vis` (when given) with
    /// the visibility of each unknown target.
    ///
    /// The targets (unknown cells of the disc) are gathered first. When casting a ray to each
    /// of them costs less than a pass over the disc (few targets, late in exploration), each is
    /// cast directly; otherwise raised cells mark shadow intervals first and only targets inside
    /// one are cast. Both give the exact Eq. 11 sum.
    pub(super) fn model_count_with(
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
        let Some(sight) = self.sight(c, h, d) else {
            return 0;
        };
        if !self.may_see_unknown(c, disc.reach) {
            return 0;
        }
        let ray_work = self.gather_targets(c, disc, &mut scratch.targets);
        let targets = &scratch.targets;
        if targets.is_empty() {
            return 0;
        }
        if ray_work < disc.entries.len() {
            return self.sum_casting_each(&sight, disc, targets, vis);
        }
        let mut mask = ShadowMask {
            shadow: [(f32::INFINITY, f32::NEG_INFINITY); ANGLE_BINS],
            hidden_from: [f32::INFINITY; ANGLE_BINS],
            any_tall: false,
        };
        self.mark_shadows(&sight, disc, &mut mask);
        self.sum_outside_shadows(&sight, disc, targets, &mask, vis)
    }

    /// Gathers the unknown targets of the disc around `c` into `targets` with their 9·I_cell;
    /// returns the cost of casting a ray to each (cells traversed).
    fn gather_targets(&self, c: Cell, disc: &DiscTable, targets: &mut Vec<(u32, u8)>) -> usize {
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
        ray_work
    }

    /// The Eq. 11 sum by casting a ray to every target.
    fn sum_casting_each(
        &self,
        sight: &Sight,
        disc: &DiscTable,
        targets: &[(u32, u8)],
        mut vis: Option<&mut [u64]>,
    ) -> u32 {
        let mut sum = 0u32;
        for &(k, g) in targets {
            let e = disc.entries[k as usize];
            if self.clear(sight, sight.target(&e)) {
                sum += g as u32;
                if let Some(v) = vis.as_deref_mut() {
                    set_bit(v, k as usize);
                }
            }
        }
        sum
    }

    /// Marks the shadows of the raised cells of the disc.
    ///
    /// Only known cells above min(sensor, target) = ef can block a ray to an unknown
    /// target, and only over their shadow interval of target distances. Each such cell
    /// marks the direction bins it subtends with that interval (kept as the hull per bin);
    /// targets outside every interval of their direction are clear without casting (exact:
    /// a ray meets a cell only within its angular extent, and a slightly raised cell
    /// shadows only the targets just behind it).
    fn mark_shadows(&self, sight: &Sight, disc: &DiscTable, mask: &mut ShadowMask) {
        for e in &disc.entries[..] {
            if e.is_centre() {
                continue;
            }
            let Some(idx) = self.rect.index(sight.target(e)) else {
                continue;
            };
            // Unknown (NaN) cells are transparent; cells not above ef cannot block.
            let Some(z) = sight.blocking(self.elev[idx]) else {
                continue;
            };
            let (start, end) = sight.shadow(e.r, z);
            for &(a, b) in e.spans() {
                for m in &mut mask.shadow[a as usize..=b as usize] {
                    m.0 = m.0.min(start);
                    m.1 = m.1.max(end);
                }
            }
            // A cell higher than the sensor certainly hides the targets beyond it whose sight
            // line crosses its interior (inner bins): the line never rises above the sensor,
            // so it runs below the cell's top there.
            if sight.above_sensor(z) && e.inner.0 <= e.inner.1 {
                let far = e.r + HALF_DIAG;
                for m in &mut mask.hidden_from[e.inner.0 as usize..=e.inner.1 as usize] {
                    *m = m.min(far);
                }
            }
            mask.any_tall = true;
        }
    }

    /// The Eq. 11 sum casting only the targets inside a shadow.
    fn sum_outside_shadows(
        &self,
        sight: &Sight,
        disc: &DiscTable,
        targets: &[(u32, u8)],
        mask: &ShadowMask,
        mut vis: Option<&mut [u64]>,
    ) -> u32 {
        let mut sum = 0u32;
        for &(k, g) in targets {
            let e = disc.entries[k as usize];
            let maybe_blocked = mask.any_tall && {
                let (lo, hi) = mask.shadow[e.bin as usize];
                e.r >= lo && e.r <= hi
            };
            if maybe_blocked && e.r >= mask.hidden_from[e.bin as usize] {
                continue;
            }
            if !maybe_blocked || self.clear(sight, sight.target(&e)) {
                sum += g as u32;
                if let Some(v) = vis.as_deref_mut() {
                    set_bit(v, k as usize);
                }
            }
        }
        sum
    }
}

/// Summed-area table ((w + 1) × (h + 1)) of a row-major mask.
pub(super) fn summed_area(mask: &[bool], w: usize, h: usize) -> Vec<u32> {
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
pub(super) fn square_count(sat: &[u32], rect: CellRect, c: Cell, n: u32) -> u32 {
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
