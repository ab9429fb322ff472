//! A field of terrain descriptors over a rectangle of the map lattice.
//!
//! The learners are generic over the descriptor: the 9-bin colour histogram ta(ν) of Prágr22
//! §4.2, the 5-D shape + Lab descriptor of Prágr19 Eq. 10, or anything else with a fixed
//! dimension. The map crate computes them as `Raster<Option<[f32; N]>>`; this type keeps them
//! as `f64` (what the GP works on) and refuses non-finite values so nothing downstream ever sees
//! a NaN.
//!
//! **Sparse storage.** The rectangle is the map's known bounds, and on a real building most of
//! it is never seen (a laser maps corridors: 45k described cells in a bounding box of 557k on
//! the ACES3 log). So only described cells hold values; a slot index per cell of the *storage
//! rectangle* finds them, and the described cells are kept in row-major order for the
//! learners that draw from them. The storage rectangle is the rectangle rounded out to
//! multiples of [`STORAGE_ALIGN`] cells: as the known bounds grow cell by cell, it changes
//! only when they cross an alignment line, so per-cell buffers indexed by it (the cost model's
//! class rasters) survive from one learning update to the next.
//!
//! **Incremental refresh.** [`DescriptorField::refresh`] recomputes only the descriptors a map
//! change can have touched: the changed blocks grown by the descriptor's reach, and the cells
//! the rectangle gained. A descriptor depends only on the map around its cell, so the result is
//! the field a full computation gives, value for value.

use std::sync::atomic::{AtomicU64, Ordering as AtomicOrdering};
use strider_core::{Cell, CellRect};
use strider_map::ElevationMap;
use strider_map::descriptors::{Raster, TA_BINS, color_histograms, histogram_reach};
use strider_map::rect;

/// Alignment of the storage rectangle, in cells.
pub const STORAGE_ALIGN: i64 = 64;

const NONE: u32 = u32::MAX;

/// Identity and revision of a [`DescriptorField`]: a fresh identity per field (clones
/// included), and a revision that grows by one with each change
/// ([`refresh`](DescriptorField::refresh), [`set`](DescriptorField::set)). A consumer that
/// saw version `v` reads what changed since from [`DescriptorField::changes_since`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FieldVersion {
    id: u64,
    revision: u64,
}

impl FieldVersion {
    fn fresh() -> Self {
        static NEXT: AtomicU64 = AtomicU64::new(0);
        Self {
            id: NEXT.fetch_add(1, AtomicOrdering::Relaxed),
            revision: 0,
        }
    }
}

impl Clone for DescriptorField {
    /// A copy with its own identity (its changes are not the original's).
    fn clone(&self) -> Self {
        Self {
            version: FieldVersion::fresh(),
            changed_rev: Vec::new(),
            changed: Vec::new(),
            changed_old: Vec::new(),
            log_start: 0,
            added_rev: Vec::new(),
            added: Vec::new(),
            added_start: 0,
            rect: self.rect,
            store: self.store,
            dim: self.dim,
            slot: self.slot.clone(),
            values: self.values.clone(),
            free: self.free.clone(),
            order: self.order.clone(),
            rejected: self.rejected,
        }
    }
}

/// Descriptors over `rect`, `dim` values per described cell.
#[derive(Debug)]
pub struct DescriptorField {
    /// Which field this is and how often it changed (see [`FieldVersion`]).
    version: FieldVersion,
    /// The change log: per entry the revision, the storage index of a cell whose descriptor
    /// that change replaced or removed, and (`dim` per entry) the descriptor it had before.
    /// It holds every such change after revision `log_start`.
    changed_rev: Vec<u64>,
    changed: Vec<u32>,
    changed_old: Vec<f64>,
    log_start: u64,
    /// The newly described cells: per entry the revision and the storage index. It holds every
    /// one after revision `added_start`.
    added_rev: Vec<u64>,
    added: Vec<u32>,
    added_start: u64,
    rect: CellRect,
    store: CellRect,
    dim: usize,
    /// Per cell of `store`: the slot of its descriptor in `values`, or [`NONE`].
    slot: Vec<u32>,
    /// `dim` values per slot.
    values: Vec<f64>,
    /// Slots whose cell lost its descriptor, for reuse.
    free: Vec<u32>,
    /// Storage indices of the described cells, ascending (row-major).
    order: Vec<u32>,
    rejected: usize,
}

impl PartialEq for DescriptorField {
    /// Equal rectangles, dimensions, rejection counts and the same descriptor at every cell
    /// (however the slots are laid out).
    fn eq(&self, other: &Self) -> bool {
        self.rect == other.rect
            && self.dim == other.dim
            && self.rejected == other.rejected
            && self.order.len() == other.order.len()
            && self.described().zip(other.described()).all(|(a, b)| a == b)
    }
}

/// The storage rectangle of `r`: `r` rounded out to multiples of [`STORAGE_ALIGN`] cells
/// (clamped to the lattice), empty for an empty `r`.
pub fn storage_rect(r: CellRect) -> CellRect {
    if r.is_empty() {
        return r;
    }
    let a = STORAGE_ALIGN;
    let lo = |v: i32| (v as i64).div_euclid(a) * a;
    let hi = |v: i64| ((v + a).div_euclid(a) * a - 1).min(i32::MAX as i64);
    let (i0, j0) = (
        lo(r.min.i).max(i32::MIN as i64),
        lo(r.min.j).max(i32::MIN as i64),
    );
    let i1 = hi(r.min.i as i64 + r.width as i64 - 1);
    let j1 = hi(r.min.j as i64 + r.height as i64 - 1);
    CellRect::new(
        Cell::new(i0 as i32, j0 as i32),
        (i1 - i0 + 1) as u32,
        (j1 - j0 + 1) as u32,
    )
}

impl DescriptorField {
    /// An empty field (no cell described) of dimension `dim` over `rect`.
    pub fn empty(rect: CellRect, dim: usize) -> Self {
        let store = storage_rect(rect);
        Self {
            version: FieldVersion::fresh(),
            changed_rev: Vec::new(),
            changed: Vec::new(),
            changed_old: Vec::new(),
            log_start: 0,
            added_rev: Vec::new(),
            added: Vec::new(),
            added_start: 0,
            rect,
            store,
            dim,
            slot: vec![NONE; store.len()],
            values: Vec::new(),
            free: Vec::new(),
            order: Vec::new(),
            rejected: 0,
        }
    }

    /// Flattens a map-crate descriptor raster. Descriptors with a non-finite component are
    /// treated as absent and counted in [`DescriptorField::rejected`].
    pub fn from_raster<const N: usize>(r: &Raster<Option<[f32; N]>>) -> Self {
        let mut f = Self::empty(r.rect, N);
        f.write_raster(r);
        f
    }

    /// The field of ta(ν) colour histograms (Prágr22 §4.2) brought up to date with `map` over
    /// its known bounds: only what the map's changes since revision `*seen` can have touched is
    /// recomputed, and `*seen` becomes the map's revision. Returns the bounds; `None` (and
    /// nothing done) while the map is empty.
    pub fn follow_color_histograms(
        &mut self,
        map: &ElevationMap,
        seen: &mut u64,
    ) -> Option<CellRect> {
        let rect = map.known_bounds()?;
        let r_hist = map.params().r_hist;
        let changed = map.changes().changed_since(*seen);
        let reach = histogram_reach(r_hist, map.cell_size());
        self.refresh::<TA_BINS>(map, rect, &changed, reach, |m, r| {
            color_histograms(m, r, r_hist)
        });
        *seen = map.changes().revision();
        Some(rect)
    }

    /// Brings the field up to date with `map` over `rect` (the map's known bounds):
    /// recomputes, with `compute`, the descriptors within `reach` cells of the map's
    /// `changed` rectangles and those of the cells `rect` gained, and drops the cells it
    /// lost. `compute(map, r)` must give every cell of `r` its descriptor from the map alone,
    /// `reach` being how far a cell's descriptor looks. A field of another dimension is
    /// rebuilt from scratch.
    pub fn refresh<const N: usize>(
        &mut self,
        map: &ElevationMap,
        rect: CellRect,
        changed: &[CellRect],
        reach: u32,
        compute: impl Fn(&ElevationMap, CellRect) -> Raster<Option<[f32; N]>>,
    ) {
        if self.dim != N {
            *self = Self::empty(CellRect::new(rect.min, 0, 0), N);
        }
        self.begin_change();
        let old = self.rect;
        self.resize(rect);
        let mut added = Vec::new();
        for region in stale_regions(old, rect, changed, reach) {
            self.write_cells(&compute(map, region), &mut added);
        }
        self.merge_order(added);
    }

    /// Moves the field to `rect`: cells outside it lose their descriptor; the storage is laid
    /// out again only when the storage rectangle changes.
    fn resize(&mut self, rect: CellRect) {
        let store = storage_rect(rect);
        if store != self.store {
            let mut slot = vec![NONE; store.len()];
            let mut order = Vec::with_capacity(self.order.len());
            for &k in &self.order {
                let c = self.store.cell(k as usize);
                let s = self.slot[k as usize];
                match store.index(c) {
                    Some(n) => {
                        slot[n] = s;
                        order.push(n as u32);
                    }
                    None => self.free.push(s),
                }
            }
            (self.slot, self.order, self.store) = (slot, order, store);
        }
        // Only cells of the old rectangle are described: when the new one holds it (the
        // known bounds grow), none is lost, and the pass over every described cell (millions
        // on a large map, at every learning update) is not needed.
        let keeps_old =
            self.rect.is_empty() || rect::intersection(self.rect, rect) == Some(self.rect);
        if !keeps_old
            && !self
                .order
                .iter()
                .all(|&k| rect.contains(store.cell(k as usize)))
        {
            let gone: Vec<u32> = self
                .order
                .iter()
                .copied()
                .filter(|&k| !rect.contains(store.cell(k as usize)))
                .collect();
            for k in gone {
                self.clear_stored(k as usize);
            }
        }
        self.rect = rect;
    }

    /// Writes every cell of `r` that lies in the rectangle into the field.
    fn write_raster<const N: usize>(&mut self, r: &Raster<Option<[f32; N]>>) {
        let mut added = Vec::new();
        self.write_cells(r, &mut added);
        self.merge_order(added);
    }

    /// [`DescriptorField::write_raster`] without the ordering: the storage indices of the
    /// newly described cells are appended to `added`.
    fn write_cells<const N: usize>(&mut self, r: &Raster<Option<[f32; N]>>, added: &mut Vec<u32>) {
        for (k, v) in r.values.iter().enumerate() {
            let Some(n) = self.store.index(r.rect.cell(k)).filter(|_| {
                // Cells outside the rectangle are never described.
                self.rect.contains(r.rect.cell(k))
            }) else {
                continue;
            };
            match v {
                Some(d) => {
                    let row: [f64; N] = d.map(f64::from);
                    if self.store_row(n, &row) {
                        added.push(n as u32);
                    }
                }
                None => self.clear_stored(n),
            }
        }
    }

    /// Stores the descriptor of storage cell `n`; a non-finite one is rejected, counted, and
    /// leaves the cell undescribed. True when the cell was not described before.
    fn store_row(&mut self, n: usize, d: &[f64]) -> bool {
        if d.len() != self.dim || d.iter().any(|x| !x.is_finite()) {
            self.rejected += 1;
            self.clear_stored(n);
            return false;
        }
        let dim = self.dim;
        if self.slot[n] != NONE {
            let s = self.slot[n] as usize;
            let row = &mut self.values[s * dim..(s + 1) * dim];
            // Bit for bit: a consumer keyed by the values (class medians) must hear of -0 → +0.
            if row.iter().zip(d).any(|(a, b)| a.to_bits() != b.to_bits()) {
                self.changed_rev.push(self.version.revision);
                self.changed.push(n as u32);
                self.changed_old.extend_from_slice(row);
                row.copy_from_slice(d);
            }
            return false;
        }
        let s = match self.free.pop() {
            Some(s) => {
                let s = s as usize;
                self.values[s * dim..(s + 1) * dim].copy_from_slice(d);
                s
            }
            None => {
                self.values.extend_from_slice(d);
                self.values.len() / dim.max(1) - 1
            }
        };
        self.slot[n] = s as u32;
        true
    }

    /// Removes the descriptor of storage cell `n`, if any.
    fn clear_stored(&mut self, n: usize) {
        let s = std::mem::replace(&mut self.slot[n], NONE);
        if s != NONE {
            let dim = self.dim;
            self.changed_rev.push(self.version.revision);
            self.changed.push(n as u32);
            self.changed_old
                .extend_from_slice(&self.values[s as usize * dim..(s as usize + 1) * dim]);
            self.free.push(s);
            if let Ok(p) = self.order.binary_search(&(n as u32)) {
                self.order.remove(p);
            }
        }
    }

    /// Merges newly described storage cells into the row-major order.
    fn merge_order(&mut self, mut added: Vec<u32>) {
        if added.is_empty() {
            return;
        }
        // A cell described in one region and cleared in a later one is not described.
        added.retain(|&n| self.slot[n as usize] != NONE);
        added.sort_unstable();
        added.dedup();
        let old = std::mem::take(&mut self.order);
        let mut out = Vec::with_capacity(old.len() + added.len());
        let (mut i, mut j) = (0, 0);
        while i < old.len() && j < added.len() {
            if old[i] <= added[j] {
                out.push(old[i]);
                i += 1;
            } else {
                out.push(added[j]);
                j += 1;
            }
        }
        out.extend_from_slice(&old[i..]);
        out.extend_from_slice(&added[j..]);
        out.dedup();
        self.order = out;
        self.added_rev
            .extend(std::iter::repeat_n(self.version.revision, added.len()));
        self.added.extend_from_slice(&added);
    }

    /// Sets the descriptor of cell `c`. Returns `false` (and counts a rejection) when `c` is
    /// outside the rectangle, `d` has the wrong length or a non-finite component.
    pub fn set(&mut self, c: Cell, d: &[f64]) -> bool {
        self.begin_change();
        let Some(n) = self.store.index(c).filter(|_| self.rect.contains(c)) else {
            self.rejected += 1;
            return false;
        };
        if self.store_row(n, d) {
            self.merge_order(vec![n as u32]);
        }
        self.slot[n] != NONE
    }

    /// Starts a change: a new revision. The log is dropped when it holds more entries than
    /// there are described cells (a consumer that far behind starts over anyway).
    fn begin_change(&mut self) {
        if self.changed.len() > self.order.len().max(1024) {
            self.changed_rev.clear();
            self.changed.clear();
            self.changed_old.clear();
            self.log_start = self.version.revision;
        }
        if self.added.len() > self.order.len().max(1024) {
            self.added_rev.clear();
            self.added.clear();
            self.added_start = self.version.revision;
        }
        self.version.revision = self.version.revision.wrapping_add(1);
    }

    /// Drops the change logs: a consumer that has seen the current version reads empty logs
    /// from now on, an older one starts over. An owner whose consumers all catch up at once
    /// (the learning update brings every gait's model to the field) calls this after they
    /// did, so that the logs hold one update's changes instead of up to as many entries as
    /// there are described cells (84 bytes each at nine bins).
    pub fn forget_changes(&mut self) {
        self.changed_rev.clear();
        self.changed.clear();
        self.changed_old.clear();
        self.log_start = self.version.revision;
        self.added_rev.clear();
        self.added.clear();
        self.added_start = self.version.revision;
    }

    /// Identity and revision (see [`FieldVersion`]).
    pub fn version(&self) -> FieldVersion {
        self.version
    }

    /// The cells whose descriptor a change after version `seen` replaced with another or
    /// removed, as (storage index, the descriptor before that change), in the order changed;
    /// a cell can appear more than once, its first entry holding its descriptor at `seen`.
    /// Newly described cells are not listed. `None` when `seen` is not a version of this
    /// field or the log no longer reaches back to it. When the storage rectangle
    /// ([`storage`](Self::storage)) moved since, the log does not say where every cell went,
    /// and a consumer starts over.
    pub fn changes_since(
        &self,
        seen: FieldVersion,
    ) -> Option<impl Iterator<Item = (usize, &[f64])> + '_> {
        if seen.id != self.version.id
            || seen.revision < self.log_start
            || seen.revision > self.version.revision
        {
            return None;
        }
        let first = self.changed_rev.partition_point(|&r| r <= seen.revision);
        let dim = self.dim.max(1);
        Some(
            self.changed[first..]
                .iter()
                .zip(self.changed_old[first * dim..].chunks_exact(dim))
                .map(|(&n, old)| (n as usize, old)),
        )
    }

    /// The storage indices of the cells newly described after version `seen` (a cell that
    /// lost its descriptor and got one again is listed again), in the order described; they
    /// may have lost their descriptor since. `None` as for
    /// [`changes_since`](Self::changes_since).
    pub fn added_since(&self, seen: FieldVersion) -> Option<&[u32]> {
        if seen.id != self.version.id
            || seen.revision < self.added_start
            || seen.revision > self.version.revision
        {
            return None;
        }
        let first = self.added_rev.partition_point(|&r| r <= seen.revision);
        Some(&self.added[first..])
    }

    /// The rectangle covered.
    pub fn rect(&self) -> CellRect {
        self.rect
    }

    /// The storage rectangle ([`storage_rect`] of the rectangle): the lattice of the indices
    /// [`DescriptorField::described`] and [`DescriptorField::get_stored`] use.
    pub fn storage(&self) -> CellRect {
        self.store
    }

    /// Descriptor dimension.
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// The descriptor of `c`, `None` when outside the rectangle or not described.
    pub fn get(&self, c: Cell) -> Option<&[f64]> {
        self.get_stored(self.store.index(c)?)
    }

    /// The descriptor of the cell with storage index `n`, if described.
    pub fn get_stored(&self, n: usize) -> Option<&[f64]> {
        let s = *self.slot.get(n)?;
        (s != NONE).then(|| &self.values[s as usize * self.dim..(s as usize + 1) * self.dim])
    }

    /// The described cells as (storage index, descriptor), in row-major order.
    pub fn described(&self) -> impl Iterator<Item = (usize, &[f64])> + '_ {
        self.order.iter().map(move |&n| {
            let s = self.slot[n as usize] as usize;
            (n as usize, &self.values[s * self.dim..(s + 1) * self.dim])
        })
    }

    /// Storage indices of the described cells, ascending.
    pub fn described_indices(&self) -> &[u32] {
        &self.order
    }

    /// Number of described cells.
    pub fn described_count(&self) -> usize {
        self.order.len()
    }

    /// Descriptors refused because of a non-finite component, wrong length or position.
    pub fn rejected(&self) -> usize {
        self.rejected
    }
}

/// The parts of `rect` whose descriptors may differ from the field's over `old`: each changed
/// rectangle grown by `reach`, and the cells of `rect` outside `old` (cut into at most four
/// bands), all clipped to `rect`.
fn stale_regions(old: CellRect, rect: CellRect, changed: &[CellRect], reach: u32) -> Vec<CellRect> {
    let mut out: Vec<CellRect> = changed
        .iter()
        .filter_map(|&r| rect::intersection(rect::expand(r, reach), rect))
        .collect();
    match rect::intersection(old, rect) {
        None => out = vec![rect],
        Some(kept) if kept != rect => out.extend(bands_outside(rect, kept)),
        Some(_) => {}
    }
    out.retain(|r| !r.is_empty());
    out
}

/// `outer` minus `inner` (which lies inside it) as up to four rectangles: full-width bands
/// below and above `inner`, and the parts left and right of it.
fn bands_outside(outer: CellRect, inner: CellRect) -> Vec<CellRect> {
    let (oi1, oj1) = rect::max_corner(outer);
    let (ii1, ij1) = rect::max_corner(inner);
    let mut out = Vec::new();
    let mut push = |i0: i32, j0: i32, i1: i32, j1: i32| {
        if i0 <= i1 && j0 <= j1 {
            out.push(rect::from_corners(Cell::new(i0, j0), Cell::new(i1, j1)));
        }
    };
    if inner.min.j > outer.min.j {
        push(outer.min.i, outer.min.j, oi1, inner.min.j - 1);
    }
    if ij1 < oj1 {
        push(outer.min.i, ij1 + 1, oi1, oj1);
    }
    if inner.min.i > outer.min.i {
        push(outer.min.i, inner.min.j, inner.min.i - 1, ij1);
    }
    if ii1 < oi1 {
        push(ii1 + 1, inner.min.j, oi1, ij1);
    }
    out
}

#[cfg(test)]
mod tests;
