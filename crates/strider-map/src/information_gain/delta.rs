//! The delta update of Eq. 11: the change of a cached candidate's sum from the cells that
//! changed since it was computed.

use super::bits::{get_bit, put_bit};
use super::disc::{DiscEntry, DiscTable, HALF_DIAG, NEAR_SHADOW};
use super::sight::Sight;
use super::view::{GainView, Scratch};
use strider_core::Cell;

/// The previous state of a [`GainView`] during an incremental update: its I_cell values, and
/// what changed since, prepared once for every candidate ([`OldView::prepare`]).
pub(super) struct OldView<'a> {
    pub(super) icount: &'a [u8],
    /// The changed cells known in either view, with their (new, old) elevations (NaN for
    /// unknown), highest first (by the higher of the two): a candidate reads them only down to
    /// its own ground, below which none can block.
    pub(super) by_height: Vec<(Cell, f32, f32)>,
    /// `by_height` by tile of the map, so that a candidate reads only the changed cells
    /// within its reach.
    tiles: ChangeTiles,
    /// The cells whose I_cell differs between the views: the changed cells and their
    /// 8-neighbours (I_cell depends on nothing else) where the values differ, once each.
    pub(super) icell_changed: Vec<Cell>,
    /// `icell_changed` by tile, for the same reason as `tiles`.
    icell_tiles: ChangeTiles,
}

impl<'a> OldView<'a> {
    /// The old view `icount` of `view`, given the cells that changed and their (new, old)
    /// elevations.
    pub(super) fn prepare(
        view: &GainView,
        icount: &'a [u8],
        changed: &[Cell],
        changed_z: &[(f32, f32)],
    ) -> Self {
        let mut by_height: Vec<(Cell, f32, f32)> = changed
            .iter()
            .zip(changed_z)
            .filter(|(_, (zn, zo))| !(zn.is_nan() && zo.is_nan()))
            .map(|(&x, &(zn, zo))| (x, zn, zo))
            .collect();
        // Stable, so equal heights keep the changes' order.
        by_height.sort_by(|a, b| higher(b.1, b.2).total_cmp(&higher(a.1, a.2)));
        let mut idx: Vec<usize> = Vec::new();
        for &x in changed {
            for (ox, oy) in NEIGHBOURHOOD {
                let t = Cell::new(x.i + ox, x.j + oy);
                if let Some(k) = view.rect.index(t)
                    && view.icount[k] != icount[k]
                {
                    idx.push(k);
                }
            }
        }
        idx.sort_unstable();
        idx.dedup();
        let icell_changed: Vec<Cell> = idx.into_iter().map(|k| view.rect.cell(k)).collect();
        let tiles = ChangeTiles::new(&by_height, |&(c, _, _)| c);
        let icell_tiles = ChangeTiles::new(&icell_changed, |&c| c);
        Self {
            icount,
            by_height,
            tiles,
            icell_changed,
            icell_tiles,
        }
    }
}

/// Side of the tiles of [`ChangeTiles`], cells.
const TILE: i32 = 16;

/// Indices into a list of cells, ascending, per tile of [`TILE`] cells over the cells'
/// bounding box.
struct ChangeTiles {
    /// Tile (0, 0)'s tile coordinates.
    min: (i32, i32),
    cols: i32,
    rows: i32,
    lists: Vec<Vec<u32>>,
}

impl ChangeTiles {
    /// The tiles of `items`, each at cell `cell_of(item)`.
    fn new<T>(items: &[T], cell_of: impl Fn(&T) -> Cell) -> Self {
        let tile = |c: Cell| (c.i.div_euclid(TILE), c.j.div_euclid(TILE));
        let (lo, hi) = items.iter().fold(
            ((i32::MAX, i32::MAX), (i32::MIN, i32::MIN)),
            |(lo, hi), x| {
                let t = tile(cell_of(x));
                (
                    (lo.0.min(t.0), lo.1.min(t.1)),
                    (hi.0.max(t.0), hi.1.max(t.1)),
                )
            },
        );
        if items.is_empty() {
            return Self {
                min: (0, 0),
                cols: 0,
                rows: 0,
                lists: Vec::new(),
            };
        }
        let (cols, rows) = (hi.0 - lo.0 + 1, hi.1 - lo.1 + 1);
        let mut lists = vec![Vec::new(); cols as usize * rows as usize];
        for (n, x) in items.iter().enumerate() {
            let t = tile(cell_of(x));
            lists[((t.1 - lo.1) * cols + (t.0 - lo.0)) as usize].push(n as u32);
        }
        Self {
            min: lo,
            cols,
            rows,
            lists,
        }
    }

    /// The lists of the tiles that meet the square of Chebyshev radius `reach` around `c`.
    fn near(&self, c: Cell, reach: i32) -> impl Iterator<Item = &[u32]> {
        let span = |lo: i32, hi: i32, min: i32, n: i32| {
            let a = (lo.div_euclid(TILE) - min).max(0);
            let b = (hi.div_euclid(TILE) - min).min(n - 1);
            a..=b
        };
        let xs = span(
            c.i.saturating_sub(reach),
            c.i.saturating_add(reach),
            self.min.0,
            self.cols,
        );
        let ys = span(
            c.j.saturating_sub(reach),
            c.j.saturating_add(reach),
            self.min.1,
            self.rows,
        );
        ys.flat_map(move |ty| {
            xs.clone()
                .map(move |tx| self.lists[(ty * self.cols + tx) as usize].as_slice())
        })
    }
}

/// The higher of a changed cell's two elevations, NaN ones ignored.
#[inline]
fn higher(zn: f32, zo: f32) -> f32 {
    zn.max(zo)
}

/// A cell and its 8-neighbours, as offsets.
const NEIGHBOURHOOD: [(i32, i32); 9] = [
    (-1, -1),
    (0, -1),
    (1, -1),
    (-1, 0),
    (0, 0),
    (1, 0),
    (-1, 1),
    (0, 1),
    (1, 1),
];

/// A changed cell that rises above the candidate in the old view or the new one, so that it
/// may block sight lines in either.
struct Blocker {
    /// Its disc entry.
    kx: usize,
    ex: DiscEntry,
    /// The higher of its two elevations (covers both views).
    z: f32,
    /// Its new elevation, when above the candidate.
    e_new: Option<f32>,
    /// Its shadow interval of target distances (computed with `z`).
    start: f32,
    end: f32,
    /// It is higher than the sensor now and crosses some sight lines' interior: the targets
    /// beyond `far` in its inner bins are certainly hidden.
    hides: bool,
    far: f32,
    /// It could not block in the old view (unknown then, which is transparent, or not above
    /// the candidate), so it can only hide targets now: a target not visible before stays
    /// hidden by whatever hid it (a changed blocker recasts it in its own turn), so only the
    /// targets visible before need a look. Most of a wedge is known ground.
    only_hides: bool,
}

/// One candidate's delta update.
struct Delta<'a> {
    view: &'a GainView,
    old: &'a [u8],
    disc: &'a DiscTable,
    sight: Sight,
    /// Chebyshev reach of a change that can matter, cells.
    reach: i32,
}

impl GainView {
    /// The change of 9·I_model at candidate `c` from the view `old` (same rectangle) to this
    /// one, given the cells that differ between them (`c` not among them) and the visibility
    /// of every target that was unknown in `old` (`vis`, one bit per disc entry), which it
    /// brings up to date.
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
    /// (`touches_sight_line`) is left to the other changed cells, and one whose line it now
    /// crosses below its top (`crosses_below`) is blocked without a cast. On
    /// `courtyard-large` they cut the delta updates' time roughly in half.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn delta_count(
        &self,
        old: &OldView,
        c: Cell,
        disc: &DiscTable,
        h: f64,
        d: f64,
        scratch: &mut Scratch,
        vis: &mut [u64],
    ) -> i64 {
        let Some(sight) = self.sight(c, h, d) else {
            return 0;
        };
        scratch.next_stamp(disc.entries.len());
        let update = Delta {
            view: self,
            old: old.icount,
            disc,
            sight,
            reach: disc.reach as i32 + 1,
        };
        let mut delta = 0i64;
        // (b) first: sight lines that may have changed are cast again, from the changed cells
        // within reach, tile by tile. Only cells above the candidate's ground can block; the
        // rest of a tile's list is lower still. The order of the blockers does not matter:
        // each target is recast once, by the first blocker that may have changed its line,
        // and a recast finds its visibility in the new view whichever blocker asked.
        for list in old.tiles.near(c, update.reach) {
            for &n in list {
                let (x, zn, zo) = old.by_height[n as usize];
                if update.sight.blocking(higher(zn, zo)).is_none() {
                    break;
                }
                let Some(b) = update.blocker(x, zn, zo) else {
                    continue;
                };
                update.for_each_shadowed(&b, |k| delta += update.recast(&b, k, scratch, vis));
            }
        }
        // (a) the rest: I_cell changed, the sight line did not. Each target is its own term,
        // so the order does not matter either.
        for list in old.icell_tiles.near(c, update.reach) {
            for &n in list {
                delta += update.follow_icell(old.icell_changed[n as usize], scratch, vis);
            }
        }
        delta
    }
}

impl Delta<'_> {
    /// The offset of `x` from the candidate when a change there can matter.
    #[inline]
    fn offset(&self, x: Cell) -> Option<(i32, i32)> {
        let c = self.sight.cell();
        let (dx, dy) = (x.i - c.i, x.j - c.j);
        (dx.abs() <= self.reach && dy.abs() <= self.reach).then_some((dx, dy))
    }

    /// The changed cell `x` with (new, old) elevations `(zn, zo)` as a blocker, if it rises
    /// above the candidate in either view and lies in the disc.
    fn blocker(&self, x: Cell, zn: f32, zo: f32) -> Option<Blocker> {
        // Elevations above the candidate only.
        let (e_new, e_old) = (self.sight.blocking(zn), self.sight.blocking(zo));
        if e_new.is_none() && e_old.is_none() {
            return None;
        }
        let (dx, dy) = self.offset(x)?;
        let kx = self.disc.entry_of(dx, dy)?;
        let ex = self.disc.entries[kx];
        let z = e_new.into_iter().chain(e_old).reduce(f32::max)?;
        let (start, end) = self.sight.shadow(ex.r, z);
        Some(Blocker {
            kx,
            ex,
            z,
            e_new,
            start,
            end,
            hides: e_new.is_some_and(|z| self.sight.above_sensor(z)) && ex.inner.0 <= ex.inner.1,
            far: ex.r + HALF_DIAG,
            only_hides: e_old.is_none(),
        })
    }

    /// Calls `visit` with the disc entries in the shadow interval of `b`, by increasing
    /// distance per direction bin.
    fn for_each_shadowed(&self, b: &Blocker, mut visit: impl FnMut(usize)) {
        let disc = self.disc;
        if b.end <= b.ex.r + NEAR_SHADOW {
            // Short shadow (barely above the sensor's ground): its precomputed list.
            let (group, rs) = disc.near_shadow(b.kx);
            for (&k, &r) in group.iter().zip(rs) {
                if r > b.end {
                    break;
                }
                visit(k as usize);
            }
            return;
        }
        for &(lo, hi) in b.ex.spans() {
            for bin in lo as usize..=hi as usize {
                let (group, rs) = disc.in_bin(bin);
                let from = rs.partition_point(|&r| r < b.start);
                for (&k, &r) in group[from..].iter().zip(&rs[from..]) {
                    if r > b.end {
                        break;
                    }
                    visit(k as usize);
                }
            }
        }
    }

    /// Casts the sight line to the target at entry `k` again in the new view if `b` can have
    /// changed it; returns the change of its term and brings its bit up to date.
    fn recast(&self, b: &Blocker, k: usize, scratch: &mut Scratch, vis: &mut [u64]) -> i64 {
        if scratch.seen[k] == scratch.stamp || (b.only_hides && !get_bit(vis, k)) {
            return 0;
        }
        let e = self.disc.entries[k];
        let t = self.sight.target(&e);
        let Some(idx) = self.view.rect.index(t) else {
            return 0;
        };
        let (g1, g0) = (self.view.icount[idx], self.old[idx]);
        let was = g0 > 0 && get_bit(vis, k);
        if g1 == 0 && !was {
            // Not visible unknown before, not unknown now: the term stays 0.
            return 0;
        }
        let ex = b.ex;
        // The interval test is coarse: skip the targets whose sight line x does not reach in
        // either view (another changed cell on the same line recasts it; if none does, the
        // line is unchanged).
        if !self.sight.touched_by(&ex, &e, b.z) {
            return 0;
        }
        scratch.seen[k] = scratch.stamp;
        let hidden = b.hides && e.r >= b.far && (ex.inner.0..=ex.inner.1).contains(&e.bin);
        let now = g1 > 0
            && !hidden
            && !b
                .e_new
                .is_some_and(|zn| k != b.kx && self.sight.blocked_by(&ex, &e, zn))
            && self.view.clear(&self.sight, t);
        put_bit(vis, k, now);
        let gained = if now { g1 as i64 } else { 0 };
        let lost = if was { g0 as i64 } else { 0 };
        gained - lost
    }

    /// The change of the term of target `t`, whose I_cell changed, unless its sight line was
    /// cast again; brings its bit up to date.
    fn follow_icell(&self, t: Cell, scratch: &mut Scratch, vis: &mut [u64]) -> i64 {
        let c = self.sight.cell();
        let Some(k) = self.disc.entry_of(t.i - c.i, t.j - c.j) else {
            return 0;
        };
        if scratch.visit(k) {
            return 0;
        }
        let Some(idx) = self.view.rect.index(t) else {
            return 0;
        };
        let (g1, g0) = (self.view.icount[idx], self.old[idx]);
        let clear = if g0 > 0 {
            get_bit(vis, k)
        } else {
            // Unknown again (not in practice): no stored bit to trust.
            self.view.clear(&self.sight, t)
        };
        put_bit(vis, k, clear && g1 > 0);
        if clear { g1 as i64 - g0 as i64 } else { 0 }
    }
}
