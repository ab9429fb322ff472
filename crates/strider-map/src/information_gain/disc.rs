//! The sensor disc δ(r_sensor) with what Eq. 11 needs per offset, computed once, and the
//! shadow geometry of a raised cell in it.

use strider_core::grid::disc_offsets;

/// Direction bins of the shadow mask in `GainView::model_count`.
pub(super) const ANGLE_BINS: usize = 2048;

/// Reach (cells beyond a cell's centre distance) of the shadows [`DiscTable::near_shadow`]
/// lists: a floor cell a centimetre or two above the sensor's ground, seen from half a metre,
/// shadows about that far.
pub(super) const NEAR_SHADOW: f32 = 3.0;

/// Half the diagonal of a cell, in cells.
pub(super) const HALF_DIAG: f32 = std::f32::consts::FRAC_1_SQRT_2;

/// The sensor disc δ(r_sensor) with what Eq. 11 needs per offset: the distance, the
/// shadow-mask direction bin of a target there and the bins a raised cell there subtends,
/// plus two indexes (offset → entry, direction bin → entries by distance).
pub(super) struct DiscTable {
    pub(super) entries: Vec<DiscEntry>,
    /// Chebyshev radius of the disc, cells.
    pub(super) reach: u32,
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
    /// The centre distance of each entry of `near`, alongside (as `by_bin_r`).
    near_r: Vec<f32>,
}

/// One offset of the disc.
#[derive(Clone, Copy)]
pub(super) struct DiscEntry {
    pub(super) di: i32,
    pub(super) dj: i32,
    /// Centre distance, cells.
    pub(super) r: f32,
    /// Direction bin of a target at this offset.
    pub(super) bin: u16,
    /// Bins subtended by a cell at this offset (its four corners, one bin of margin on each
    /// side against rounding), as up to two inclusive ranges (two when they wrap around the
    /// +x axis); none for the centre.
    spans: [(u16, u16); 2],
    n_spans: u8,
    /// Bins strictly inside the cell's angular extent, one bin away from its corner
    /// directions (inclusive; `lo > hi` when none, or when the cell straddles the +x axis):
    /// a sight line in such a bin crosses the cell's interior.
    pub(super) inner: (u16, u16),
}

impl DiscEntry {
    /// The offset's entry (see the fields).
    fn new(di: i32, dj: i32) -> DiscEntry {
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
        (e.spans, e.n_spans) = if hi - lo > n / 2 {
            straddling_spans(&bins)
        } else {
            margin_spans(lo, hi)
        };
        e
    }

    /// The direction bins a cell at this offset subtends (none for the centre).
    pub(super) fn spans(&self) -> &[(u16, u16)] {
        &self.spans[..self.n_spans as usize]
    }

    /// Whether this is the centre (it subtends no direction).
    pub(super) fn is_centre(&self) -> bool {
        self.n_spans == 0
    }
}

/// The spans of a cell that straddles direction 0 (the +x axis), given its corners' bins: the
/// bins just below n and just above 0, each with its margin (lo_w − 1 ≥ n/2 − 1,
/// hi_w + 1 ≤ n/2).
fn straddling_spans(bins: &[i64; 4]) -> ([(u16, u16); 2], u8) {
    let n = ANGLE_BINS as i64;
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
    (
        [((lo_w - 1) as u16, (n - 1) as u16), (0, (hi_w + 1) as u16)],
        2,
    )
}

/// The spans of a cell whose corners' bins run from `lo` to `hi`: one bin of margin on each
/// side, wrapping around direction 0.
fn margin_spans(lo: i64, hi: i64) -> ([(u16, u16); 2], u8) {
    let n = ANGLE_BINS as i64;
    let (a, b) = (lo - 1, hi + 1);
    if a < 0 {
        ([(0, b as u16), ((a + n) as u16, (n - 1) as u16)], 2)
    } else if b >= n {
        ([(a as u16, (n - 1) as u16), (0, (b - n) as u16)], 2)
    } else {
        ([(a as u16, b as u16), (0, 0)], 1)
    }
}

impl DiscTable {
    /// The disc of radius `r_sensor` on cells of size `d`.
    pub(super) fn new(r_sensor: f64, d: f64) -> Self {
        let offsets = disc_offsets(r_sensor, d);
        let reach = offsets
            .iter()
            .map(|&(di, dj)| di.unsigned_abs().max(dj.unsigned_abs()))
            .max()
            .unwrap_or(0);
        let mut entries: Vec<DiscEntry> = offsets
            .into_iter()
            .map(|(di, dj)| DiscEntry::new(di, dj))
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
        let lookup = offset_lookup(&entries, reach);
        let (by_bin_start, by_bin) = bin_index(&entries);
        let (near_start, near) = near_shadow_lists(&entries, &by_bin_start, &by_bin);
        let by_bin_r = by_bin.iter().map(|&k| entries[k as usize].r).collect();
        let near_r = near.iter().map(|&k| entries[k as usize].r).collect();
        Self {
            entries,
            reach,
            lookup,
            by_bin_start,
            by_bin,
            by_bin_r,
            near_start,
            near,
            near_r,
        }
    }

    /// The entries a cell at entry `k` can shadow within [`NEAR_SHADOW`] of its centre
    /// distance, by increasing distance (see `DiscTable::near`), with their distances.
    #[inline]
    pub(super) fn near_shadow(&self, k: usize) -> (&[u32], &[f32]) {
        let range = self.near_start[k] as usize..self.near_start[k + 1] as usize;
        (&self.near[range.clone()], &self.near_r[range])
    }

    /// The entries (centre excluded) of direction bin `bin` by increasing distance, with their
    /// distances alongside.
    #[inline]
    pub(super) fn in_bin(&self, bin: usize) -> (&[u32], &[f32]) {
        let range = self.by_bin_start[bin] as usize..self.by_bin_start[bin + 1] as usize;
        (&self.by_bin[range.clone()], &self.by_bin_r[range])
    }

    /// The entry at offset `(di, dj)`, if it lies in the disc.
    #[inline]
    pub(super) fn entry_of(&self, di: i32, dj: i32) -> Option<usize> {
        let r = self.reach as i32;
        if di.abs() > r || dj.abs() > r {
            return None;
        }
        let side = 2 * r + 1;
        let k = self.lookup[((dj + r) * side + di + r) as usize];
        (k != u32::MAX).then_some(k as usize)
    }
}

/// Entry index per offset of the (2·reach + 1)² square, `u32::MAX` outside the disc.
fn offset_lookup(entries: &[DiscEntry], reach: u32) -> Vec<u32> {
    let side = 2 * reach as usize + 1;
    let mut lookup = vec![u32::MAX; side * side];
    for (k, e) in entries.iter().enumerate() {
        let idx = (e.dj + reach as i32) as usize * side + (e.di + reach as i32) as usize;
        lookup[idx] = k as u32;
    }
    lookup
}

/// The entries other than the centre by (direction bin, distance), and where each bin's run
/// starts (`ANGLE_BINS + 1` offsets).
fn bin_index(entries: &[DiscEntry]) -> (Vec<u32>, Vec<u32>) {
    let mut order: Vec<u32> = (0..entries.len() as u32)
        .filter(|&k| !entries[k as usize].is_centre())
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
    (by_bin_start, order)
}

/// Per entry, the entries of its direction bins within [`NEAR_SHADOW`] beyond it (see
/// `DiscTable::near`), as (starts, lists).
fn near_shadow_lists(
    entries: &[DiscEntry],
    by_bin_start: &[u32],
    order: &[u32],
) -> (Vec<u32>, Vec<u32>) {
    let mut near_start = Vec::with_capacity(entries.len() + 1);
    let mut near = Vec::new();
    near_start.push(0u32);
    for x in entries {
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
    (near_start, near)
}

/// The target distances (cells) a known cell of elevation `e` at centre distance `r` can shadow
/// from a sensor at `zs` looking at unknown targets at `zt` (< zs): the sight line to a target
/// at distance R passes the cell no lower than zs − (zs − zt)·(r + ½√2)/R, so only targets with
/// R < (zs − zt)·(r + ½√2)/(zs − e) can be hidden, and none nearer than the cell's near side.
#[inline]
pub(super) fn shadow_interval(r: f32, e: f32, zs: f64, zt: f64) -> (f32, f32) {
    let start = r - HALF_DIAG;
    let end = if (e as f64) < zs {
        ((zs - zt) * ((r + HALF_DIAG) as f64) / (zs - e as f64)) as f32
    } else {
        f32::INFINITY
    };
    (start, end)
}

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

/// The direction bin of (x, y) ≠ 0.
#[inline]
fn angle_bin(x: f64, y: f64) -> usize {
    ((pseudo_angle(x, y) * (ANGLE_BINS as f64 / 4.0)) as usize).min(ANGLE_BINS - 1)
}
