//! Eq. 11 kept up to date between calls ([`GainCache`]).

use super::candidates::{InfoGain, candidates, view_rect};
use super::delta::OldView;
use super::disc::DiscTable;
use super::view::{GainView, Scratch, square_count, summed_area};
use crate::map::ElevationMap;
use crate::reachability::Reachability;
use crate::rect::{self, WorldRect};
use rayon::prelude::*;
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
    /// Cached 9·I_model per view cell ([`NOT_CACHED`] = none).
    counts: Vec<u32>,
    /// Per cached view cell, the visibility of each disc target unknown at the last
    /// evaluation (one bit per disc entry); empty when not cached.
    vis: Vec<Vec<u64>>,
    bounds: Option<WorldRect>,
}

/// What changed in the view since the last call, and the cached candidates to update for it.
struct Changes {
    /// The cells that changed.
    cells: Vec<Cell>,
    /// Their (new, old) elevations, NaN when unknown.
    z: Vec<(f32, f32)>,
    /// I_cell before the changes, when it changed (else the current one serves).
    old_icount: Option<Vec<u8>>,
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
            ..
        } = &mut self.cached
        else {
            return InfoGain::default();
        };
        let todo: Vec<(usize, Cell)> = candidates
            .iter()
            .filter_map(|&c| view.rect.index(c).map(|k| (k, c)))
            .filter(|&(k, _)| counts[k] == NOT_CACHED)
            .collect();
        let fresh = evaluate(view, &todo, disc, h, d);
        let updated = changes.map_or(0, |ch| update(view, counts, vis, &ch, disc, h, d));
        self.last = (todo.len(), updated);
        for (&(k, _), (n, v)) in todo.iter().zip(fresh) {
            counts[k] = n;
            vis[k] = v;
        }
        let counts = candidates
            .iter()
            .map(|&c| view.rect.index(c).map_or(0, |k| counts[k]))
            .collect();
        InfoGain::from_counts(candidates, counts)
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
                self.view = Some(GainView::new(map, rect, bounds));
                self.counts = vec![NOT_CACHED; rect.len()];
                self.vis = vec![Vec::new(); rect.len()];
                self.bounds = bounds.copied();
                return None;
            }
        };
        if rect::intersection(view.rect, needed) != Some(needed) {
            // The known area outgrew the view: grow it with a margin (so that a slowly
            // growing map grows it rarely) and carry the cache over. Every cached candidate's
            // disc lies in the old view, outside which nothing was known; the new cells enter
            // as changes below like any other.
            let rect = rect::expand(rect::union(view.rect, needed), disc.reach);
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
        let mut vis = vec![Vec::new(); rect.len()];
        for (k, c) in old.rect.cells().enumerate() {
            if let Some(nk) = rect.index(c) {
                counts[nk] = self.counts[k];
                vis[nk] = std::mem::take(&mut self.vis[k]);
            }
        }
        self.view = Some(old.grown(rect, bounds, d));
        self.counts = counts;
        self.vis = vis;
    }

    /// Follows the map: copies the cells that became observed or moved by more than `dz` into
    /// the view and returns them (with no deltas yet).
    fn take_changes(
        &mut self,
        map: &ElevationMap,
        bounds: Option<&WorldRect>,
        d: f64,
        dz: f32,
    ) -> Option<Changes> {
        let v = self.view.as_mut()?;
        let fresh = map.elevation_raster(v.rect);
        let mut changes = Changes {
            cells: Vec::new(),
            z: Vec::new(),
            old_icount: None,
            deltas: Vec::new(),
        };
        let mut known_changed = false;
        for (k, (&new, cur)) in fresh.iter().zip(v.elev.iter_mut()).enumerate() {
            let differs = if new.is_nan() || cur.is_nan() {
                new.is_nan() != cur.is_nan()
            } else {
                (new - *cur).abs() > dz
            };
            if differs {
                known_changed |= new.is_nan() != cur.is_nan();
                changes.z.push((new, *cur));
                *cur = new;
                changes.cells.push(v.rect.cell(k));
            }
        }
        changes.old_icount = known_changed.then(|| {
            let o = v.icount.clone();
            v.derive(bounds, d);
            o
        });
        Some(changes)
    }

    /// The cached candidates near the `changed` cells to update; drops from the cache those
    /// that changed themselves, saw too many changes or are no longer candidates.
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
        if changed.is_empty() {
            return deltas;
        }
        let mask = |cells: &[Cell]| {
            let mut m = vec![false; v.rect.len()];
            for &c in cells {
                if let Some(k) = v.rect.index(c) {
                    m[k] = true;
                }
            }
            m
        };
        let changed_mask = mask(changed);
        let is_candidate = mask(candidates);
        let (w, h) = (v.rect.width as usize, v.rect.height as usize);
        let sat = summed_area(&changed_mask, w, h);
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
            if changed_mask[k] || near > max_changes || !is_candidate[k] {
                *n = NOT_CACHED;
                self.vis[k] = Vec::new();
            } else {
                deltas.push((k, c));
            }
        }
        deltas
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
            (n, vis)
        })
        .collect()
}

/// Updates the cached counts and bits of the candidates `changes.deltas` from the changes;
/// returns how many were updated.
fn update(
    view: &GainView,
    counts: &mut [u32],
    vis: &mut [Vec<u64>],
    changes: &Changes,
    disc: &DiscTable,
    h: f64,
    d: f64,
) -> usize {
    let old = OldView {
        icount: changes.old_icount.as_deref().unwrap_or(&view.icount),
        changed: &changes.cells,
        changed_z: &changes.z,
    };
    let mut work: Vec<(usize, Cell, Vec<u64>, i64)> = changes
        .deltas
        .iter()
        .map(|&(k, c)| (k, c, std::mem::take(&mut vis[k]), 0))
        .collect();
    work.par_iter_mut()
        .for_each_init(Scratch::default, |s, (_, c, bits, dn)| {
            *dn = view.delta_count(&old, *c, disc, h, d, s, bits);
        });
    for (k, _, bits, dn) in work {
        let n = counts[k] as i64 + dn;
        debug_assert!(n >= 0, "negative Eq. 11 count");
        counts[k] = n.max(0) as u32;
        vis[k] = bits;
    }
    changes.deltas.len()
}
