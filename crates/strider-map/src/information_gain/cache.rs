//! Eq. 11 kept up to date between calls ([`GainCache`]).

use super::candidates::{InfoGain, candidates, view_rect};
use super::delta::OldView;
use super::disc::DiscTable;
use super::view::{GainView, Scratch, square_count, summed_area};
use crate::map::ElevationMap;
use crate::reachability::Reachability;
use crate::rect::{self, WorldRect};
use rayon::prelude::*;
use std::collections::HashMap;
use strider_core::{Cell, CellRect};

/// Above disc size / this many changed cells within r_sensor + 1 of a cached candidate, its
/// Eq. 11 sum is evaluated afresh instead of updated. An update looks up ~9 stored visibility
/// bits per changed cell and casts only the sight lines in the shadow of changed cells that
/// rise above the candidate (most of them settled by per-cell tests, see
/// `GainView::delta_count`); a fresh evaluation makes about two passes over the disc and casts
/// its maybe-blocked targets. Measured worst spatial update on courtyard-large (whole mission):
/// /2 108 ms, /8 128 ms, /32 295 ms; on courtyard-small /2 9–10 ms against 23–30 ms for /32.
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
/// [`information_gain`](super::information_gain) exactly; a small `dz` (the mission uses
/// 1 cm, the order of the depth noise) stops the Kalman refinement of ground already seen,
/// which moves elevations by millimetres with every scan, from touching every candidate near
/// the sensor footprint. Such a change can flip a sight line only where it grazes a cell
/// within `dz`.
#[derive(Default)]
pub struct GainCache {
    cached: Cached,
    disc: Option<(f64, f64, DiscTable)>,
    dz: f32,
    /// (fresh evaluations, delta updates) in the last call.
    last: (usize, usize),
}

/// The cache proper: the view and what is known per view cell.
#[derive(Default)]
struct Cached {
    view: Option<GainView>,
    /// The map's change-log revision the view has followed up to.
    revision: u64,
    /// 9·I_cell before the last change of the view: equal to the view's except over
    /// `icount_dirty`, where the last call recomputed it.
    prev_icount: Vec<u8>,
    icount_dirty: Option<CellRect>,
    /// Cached 9·I_model per view cell ([`NOT_CACHED`] = none).
    counts: Vec<u32>,
    /// Per cached view cell, the visibility of each disc target unknown at the last
    /// evaluation (one bit per disc entry); absent when not cached or when no bit is set.
    vis: VisBits,
    bounds: Option<WorldRect>,
}

/// What changed in the view since the last call, and the cached candidates to update for it.
struct Changes {
    /// The cells that changed.
    cells: Vec<Cell>,
    /// Their (new, old) elevations, NaN when unknown.
    z: Vec<(f32, f32)>,
    /// Whether I_cell changed (its old values are then [`Cached::prev_icount`]).
    icount_changed: bool,
    /// The cached candidates to update: (view index, cell).
    deltas: Vec<(usize, Cell)>,
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

    /// [`information_gain`](super::information_gain) on the current map, re-evaluating only
    /// what changed since the last call.
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
        self.use_disc(p.r_sensor, d);
        let Some((_, _, disc)) = self.disc.as_ref() else {
            return InfoGain::default();
        };
        let h = p.sensor_height;
        let candidates = candidates(map, reach, bounds);
        let needed = view_rect(map, known);
        let changes = self
            .cached
            .follow(map, needed, disc, bounds, self.dz, &candidates);
        let Cached {
            view: Some(view),
            counts,
            vis,
            prev_icount,
            ..
        } = &mut self.cached
        else {
            return InfoGain::default();
        };
        let view: &GainView = view;
        let todo: Vec<(usize, Cell)> = candidates
            .iter()
            .filter_map(|&c| view.rect.index(c).map(|k| (k, c)))
            .filter(|&(k, _)| counts[k] == NOT_CACHED)
            .collect();
        let fresh = evaluate(view, &todo, disc, h, d);
        let updated = changes.map_or(0, |ch| {
            let old_icount = if ch.icount_changed {
                prev_icount.as_slice()
            } else {
                &view.icount
            };
            update(view, old_icount, counts, vis, &ch, disc, h, d)
        });
        self.last = (todo.len(), updated);
        for (&(k, _), (n, v)) in todo.iter().zip(fresh) {
            counts[k] = n;
            vis.put(k, v);
        }
        InfoGain::from_count_of(&candidates, |c| view.rect.index(c).map_or(0, |k| counts[k]))
    }

    /// Makes the disc that of radius `r_sensor` on cells of size `d`, dropping the view when
    /// that changes it.
    fn use_disc(&mut self, r_sensor: f64, d: f64) {
        if self
            .disc
            .as_ref()
            .is_none_or(|(r, dd, _)| *r != r_sensor || *dd != d)
        {
            self.disc = Some((r_sensor, d, DiscTable::new(r_sensor, d)));
            self.cached.view = None;
        }
    }
}

impl Cached {
    /// Brings the view up to `map` over (at least) `needed`: afresh when there is none or the
    /// bounds changed (`None`), else by following the changes (returned).
    fn follow(
        &mut self,
        map: &ElevationMap,
        needed: CellRect,
        disc: &DiscTable,
        bounds: Option<&WorldRect>,
        dz: f32,
        candidates: &[Cell],
    ) -> Option<Changes> {
        let d = map.cell_size();
        let view = match &self.view {
            Some(v) if self.bounds == bounds.copied() => v,
            _ => {
                let rect = rect::expand(needed, disc.reach);
                let view = GainView::new(map, rect, bounds);
                self.prev_icount = view.icount.clone();
                self.icount_dirty = None;
                self.view = Some(view);
                self.revision = map.changes().revision();
                self.counts = vec![NOT_CACHED; rect.len()];
                self.vis = VisBits::default();
                self.bounds = bounds.copied();
                return None;
            }
        };
        if rect::intersection(view.rect, needed) != Some(needed) {
            // The known area outgrew the view: grow it with a margin (so that a slowly
            // growing map grows it rarely) on the sides it outgrew, and carry the cache over.
            // Every cached candidate's disc lies in the old view, outside which nothing was
            // known; the new cells enter as changes below like any other.
            let rect = rect::grown_to_cover(view.rect, needed, disc.reach);
            self.grow(rect, bounds, d);
        }
        let mut changes = self.take_changes(map, bounds, d, dz)?;
        changes.deltas = self.schedule(&changes.cells, disc, candidates);
        Some(changes)
    }

    /// Moves the view, the cached counts and visibility bits into the larger `rect`; cells
    /// new to the view are unknown (as they were to the old view), so its I_cell values are
    /// unchanged where a cached candidate reads them.
    fn grow(&mut self, rect: CellRect, bounds: Option<&WorldRect>, d: f64) {
        let Some(old) = self.view.take() else {
            return;
        };
        let mut counts = vec![NOT_CACHED; rect.len()];
        for (k, c) in old.rect.cells().enumerate() {
            if let Some(nk) = rect.index(c) {
                counts[nk] = self.counts[k];
            }
        }
        let vis = std::mem::take(&mut self.vis).moved(old.rect, rect);
        let view = old.grown(rect, bounds, d);
        self.prev_icount = view.icount.clone();
        self.icount_dirty = None;
        self.view = Some(view);
        self.counts = counts;
        self.vis = vis;
    }

    /// Follows the map: copies the cells that became observed or moved by more than `dz` into
    /// the view and returns them in the view's row-major order (with no deltas yet). Only the
    /// blocks the map changed since the last call are read, so the work follows the sensor's
    /// footprint, not the map.
    fn take_changes(
        &mut self,
        map: &ElevationMap,
        bounds: Option<&WorldRect>,
        d: f64,
        dz: f32,
    ) -> Option<Changes> {
        let v = self.view.as_mut()?;
        // `prev_icount` equals the view's I_cell again before this call's changes.
        if let Some(r) = self.icount_dirty.take() {
            copy_rect(&v.icount, &mut self.prev_icount, v.rect, r);
        }
        let blocks = map.changes().changed_since(self.revision);
        self.revision = map.changes().revision();
        let mut found: Vec<(usize, f32, f32)> = Vec::new();
        let mut known_hull: Option<CellRect> = None;
        for r in blocks.iter().filter_map(|&b| rect::intersection(b, v.rect)) {
            let fresh = map.elevation_raster(r);
            for (c, new) in r.cells().zip(fresh) {
                let Some(k) = v.rect.index(c) else {
                    continue;
                };
                let cur = v.elev[k];
                let differs = if new.is_nan() || cur.is_nan() {
                    new.is_nan() != cur.is_nan()
                } else {
                    (new - cur).abs() > dz
                };
                if differs {
                    if new.is_nan() != cur.is_nan() {
                        known_hull = Some(rect::include(known_hull, c));
                    }
                    v.elev[k] = new;
                    found.push((k, new, cur));
                }
            }
        }
        found.sort_unstable_by_key(|f| f.0);
        let icount_changed = known_hull.is_some();
        if let Some(hull) = known_hull {
            // I_cell changes within one cell of a cell that became known.
            let region = rect::expand(hull, 1);
            v.derive_in(region, bounds, d);
            self.icount_dirty = rect::intersection(region, v.rect);
        }
        Some(Changes {
            cells: found.iter().map(|f| v.rect.cell(f.0)).collect(),
            z: found.iter().map(|f| (f.1, f.2)).collect(),
            icount_changed,
            deltas: Vec::new(),
        })
    }

    /// The cached candidates near the `changed` cells to update; drops from the cache those
    /// that changed themselves, saw too many changes or are no longer candidates. Only the
    /// area within reach of the changes is looked at.
    fn schedule(
        &mut self,
        changed: &[Cell],
        disc: &DiscTable,
        candidates: &[Cell],
    ) -> Vec<(usize, Cell)> {
        let mut deltas = Vec::new();
        let Some(v) = self.view.as_ref() else {
            return deltas;
        };
        let Some(hull) = changed.iter().fold(None, |r, &c| Some(rect::include(r, c))) else {
            return deltas;
        };
        let n = disc.reach + 1;
        let Some(area) = rect::intersection(rect::expand(hull, n), v.rect) else {
            return deltas;
        };
        let mask = |cells: &[Cell]| {
            let mut m = vec![false; area.len()];
            for &c in cells {
                if let Some(k) = area.index(c) {
                    m[k] = true;
                }
            }
            m
        };
        let changed_mask = mask(changed);
        let is_candidate = mask(candidates);
        // Every change lies in `area`, so counts clipped to it are those clipped to the view.
        let sat = summed_area(&changed_mask, area.width as usize, area.height as usize);
        let max_changes = (disc.entries.len() / DELTA_CHANGES_PER_DISC).max(16) as u32;
        for (a, c) in area.cells().enumerate() {
            let Some(k) = v.rect.index(c) else {
                continue;
            };
            if self.counts[k] == NOT_CACHED {
                continue;
            }
            let near = square_count(&sat, area, c, n);
            if near == 0 {
                continue;
            }
            if changed_mask[a] || near > max_changes || !is_candidate[a] {
                self.counts[k] = NOT_CACHED;
                self.vis.take(k);
            } else {
                deltas.push((k, c));
            }
        }
        deltas
    }
}

/// Copies the cells of `region` (clipped to `rect`) from `src` to `dst`, both over `rect`.
fn copy_rect(src: &[u8], dst: &mut [u8], rect: CellRect, region: CellRect) {
    let Some(r) = rect::intersection(region, rect) else {
        return;
    };
    for j in r.min.j..r.min.j + r.height as i32 {
        if let Some(a) = rect.index(Cell::new(r.min.i, j)) {
            let b = a + r.width as usize;
            dst[a..b].copy_from_slice(&src[a..b]);
        }
    }
}

/// Eq. 11 afresh at the candidates `todo` (view index, cell), with the visibility bits.
fn evaluate(
    view: &GainView,
    todo: &[(usize, Cell)],
    disc: &DiscTable,
    h: f64,
    d: f64,
) -> Vec<(u32, Vec<u64>)> {
    let words = disc.entries.len().div_ceil(64);
    todo.par_iter()
        .map_init(Scratch::default, |s, &(_, c)| {
            let mut vis = vec![0u64; words];
            let n = view.model_count_with(c, disc, h, d, s, Some(&mut vis));
            (n, compact(vis))
        })
        .collect()
}

/// The stored visibility bits of the cached candidates, by view index. Only candidates with a
/// visible unknown target have any, a few along the frontier, so they are kept by index rather
/// than in a slot per view cell (24 bytes per cell, 100 MB over `campus`).
#[derive(Default)]
struct VisBits(HashMap<usize, Vec<u64>>);

impl VisBits {
    /// Takes the bits of view index `k` (empty when none are stored).
    fn take(&mut self, k: usize) -> Vec<u64> {
        self.0.remove(&k).unwrap_or_default()
    }

    /// Stores the bits of view index `k` (nothing when `bits` is empty).
    fn put(&mut self, k: usize, bits: Vec<u64>) {
        if bits.is_empty() {
            self.0.remove(&k);
        } else {
            self.0.insert(k, bits);
        }
    }

    /// The same bits indexed in `to`, a rectangle that contains `from`.
    fn moved(self, from: CellRect, to: CellRect) -> Self {
        Self(
            self.0
                .into_iter()
                .filter_map(|(k, bits)| to.index(from.cell(k)).map(|nk| (nk, bits)))
                .collect(),
        )
    }
}

/// Visibility bits as stored: none at all when no target is visible, which is the case of
/// every candidate without unknown cells in sight (most of an explored map), so that memory
/// follows the frontier rather than the explored area.
fn compact(bits: Vec<u64>) -> Vec<u64> {
    if bits.iter().all(|&w| w == 0) {
        Vec::new()
    } else {
        bits
    }
}

/// Stored visibility bits of a disc of `words` words, expanded for an update.
fn expand(bits: Vec<u64>, words: usize) -> Vec<u64> {
    if bits.is_empty() {
        vec![0; words]
    } else {
        bits
    }
}

/// Updates the cached counts and bits of the candidates `changes.deltas` from the changes;
/// returns how many were updated.
#[allow(clippy::too_many_arguments)]
fn update(
    view: &GainView,
    old_icount: &[u8],
    counts: &mut [u32],
    vis: &mut VisBits,
    changes: &Changes,
    disc: &DiscTable,
    h: f64,
    d: f64,
) -> usize {
    let old = OldView::prepare(view, old_icount, &changes.cells, &changes.z);
    let words = disc.entries.len().div_ceil(64);
    let mut work: Vec<(usize, Cell, Vec<u64>, i64)> = changes
        .deltas
        .iter()
        .map(|&(k, c)| (k, c, expand(vis.take(k), words), 0))
        .collect();
    work.par_iter_mut()
        .for_each_init(Scratch::default, |s, (_, c, bits, dn)| {
            *dn = view.delta_count(&old, *c, disc, h, d, s, bits);
        });
    for (k, _, bits, dn) in work {
        let n = counts[k] as i64 + dn;
        debug_assert!(n >= 0, "negative Eq. 11 count");
        counts[k] = n.max(0) as u32;
        vis.put(k, compact(bits));
    }
    changes.deltas.len()
}
