//! Cheapest 8-connected paths on a [`CostGrid`] (Prágr22 Eq. 1–4).
//!
//! * Eq. 1: a path is a sequence of admissible cells, each in the 8-neighbourhood of the previous.
//! * Eq. 2: the optimal path minimises the path cost C(ψ) over all such paths.
//! * Eq. 3–4: the cost is additive, C(ψ) = Σ ‖ν_i, ν_{i+1}‖ · c(ν_i, ν_{i+1}), with ‖·,·‖ = d or
//!   √2·d and, per decision 21, c(ν_a, ν_b) = c(ν_a), the per-metre cost of the *source* cell.
//!   Consequently C(ν → ν') ≠ C(ν' → ν) in general.
//!
//! **Corner rule.** A diagonal move from `a` to `a + (di, dj)` is forbidden when *both* side cells
//! `a + (di, 0)` and `a + (0, dj)` are inadmissible (cells outside the grid count as
//! inadmissible); with at least one admissible side cell it is allowed. Both end cells must be
//! admissible for any move.
//!
//! [`Dijkstra`] keeps its queues, arrays and per-grid move masks between calls, so repeated
//! searches on grids of the same size allocate nothing. Dijkstra runs on an exact bucket queue
//! (bucket width just below the smallest edge cost; see `BucketQueue`), falling back to a binary
//! heap for extreme cost ratios; A* uses a binary heap ordered by (key, cell index). The search
//! order is a fixed function of the input, so every result is deterministic.

use super::cost_grid::CostGrid;
use std::cmp::Ordering;
use std::collections::BinaryHeap;
use std::f64::consts::SQRT_2;
use strider_core::Cell;
use thiserror::Error;

/// Marker for "no predecessor" in [`Dijkstra::predecessors`].
pub const NO_PRED: u32 = u32::MAX;

/// Why a search could not start.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Error)]
pub enum SearchError {
    /// The source cell lies outside the grid.
    #[error("source cell {0:?} is outside the grid")]
    SourceOutside(Cell),
    /// The source cell is not admissible (infinite cost).
    #[error("source cell {0:?} is not admissible")]
    SourceInadmissible(Cell),
    /// The grid has more cells than a `u32` index can address.
    #[error("grid too large for u32 cell indices")]
    GridTooLarge,
}

/// Priority-queue entry: min-ordered by key, ties by cell index (for determinism).
#[derive(Clone, Copy, Debug)]
pub(super) struct Entry {
    pub(super) key: f64,
    pub(super) idx: u32,
}

impl PartialEq for Entry {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}
impl Eq for Entry {}
impl PartialOrd for Entry {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Entry {
    fn cmp(&self, other: &Self) -> Ordering {
        // Reversed: BinaryHeap is a max-heap.
        other
            .key
            .total_cmp(&self.key)
            .then_with(|| other.idx.cmp(&self.idx))
    }
}

/// A min-priority queue of cell indices; the search skips already settled cells, so a queue may
/// hold stale duplicates.
trait Queue {
    fn push(&mut self, key: f64, idx: u32);
    fn pop(&mut self) -> Option<u32>;
}

impl Queue for BinaryHeap<Entry> {
    #[inline]
    fn push(&mut self, key: f64, idx: u32) {
        BinaryHeap::push(self, Entry { key, idx });
    }
    #[inline]
    fn pop(&mut self) -> Option<u32> {
        BinaryHeap::pop(self).map(|e| e.idx)
    }
}

/// Exact bucket queue for Dijkstra (Dinitz's refinement of Dial's algorithm): bucket width δ is
/// just below the smallest edge cost d·min c. Relaxing a cell whose key lies in the current
/// bucket `[kδ, (k+1)δ)` adds at least one edge cost > δ, so it can only feed buckets `> k`; hence
/// no cell of the current bucket can improve another, and all of them are final in any order.
/// Live keys span fewer than `√2·max c / min c + 3` buckets, so a ring of that many (rounded up
/// to a power of two) is enough.
#[derive(Clone, Debug, Default)]
struct BucketQueue {
    inv_width: f64,
    buckets: Vec<Vec<u32>>,
}

impl BucketQueue {
    /// Largest ring the bucket queue may use; beyond it (extreme cost ratios) the binary heap is
    /// used instead.
    const MAX_RING: usize = 1 << 16;

    /// Prepares for `grid`; false when its cost ratio needs too large a ring.
    fn reset(&mut self, grid: &CostGrid) -> bool {
        let (lo, hi) = (grid.min_cost() as f64, grid.max_cost() as f64);
        // Margin 1e-6 keeps "edge > δ" true despite rounding of keys up to ~1e9·δ.
        let width = grid.cell_size() * lo * (1.0 - 1e-6);
        let ring = (SQRT_2 * hi / (lo * (1.0 - 1e-6))).ceil() + 3.0;
        if !(width > 0.0 && ring.is_finite() && ring <= Self::MAX_RING as f64) {
            return false;
        }
        // A power of two, so the ring index is a mask, not a division.
        let ring = (ring as usize).next_power_of_two();
        for b in &mut self.buckets {
            b.clear();
        }
        if self.buckets.len() < ring {
            self.buckets.resize_with(ring, Vec::new);
        }
        self.buckets.truncate(ring);
        self.inv_width = 1.0 / width;
        true
    }
}

/// Moves in bit order of the move masks: the lattice's 8-neighbourhood (axis moves first, then
/// diagonals), so bit `b` is `NEIGHBOURS8[b]`.
const MOVES: [(i32, i32); 8] = strider_core::grid::NEIGHBOURS8;

/// Per-cell bit mask of the allowed moves (Eq. 1 plus the corner rule), built once per grid.
///
/// Admissibility is first copied into a mask with a border of inadmissible cells, so the
/// neighbour tests need no bounds checks: the hierarchical site costs build these masks for
/// every cluster they search again, and the checked version cost about as much as the search.
fn build_moves(grid: &CostGrid, out: &mut Vec<u8>) {
    let rect = grid.rect();
    let (w, h) = (rect.width as usize, rect.height as usize);
    let cost = grid.costs();
    let pw = w + 2;
    let mut free = vec![false; pw * (h + 2)];
    for (j, row) in cost.chunks_exact(w.max(1)).take(h).enumerate() {
        let at = (j + 1) * pw + 1;
        for (f, c) in free[at..at + w].iter_mut().zip(row) {
            *f = c.is_finite();
        }
    }
    // Per move: the offset of its end cell and of its two side cells in the padded mask.
    let off = |di: i32, dj: i32| di as isize + dj as isize * pw as isize;
    let ends: [isize; 8] = MOVES.map(|(di, dj)| off(di, dj));
    let sides: [(isize, isize); 8] = MOVES.map(|(di, dj)| (off(di, 0), off(0, dj)));
    let diagonal: [bool; 8] = MOVES.map(|(di, dj)| di != 0 && dj != 0);
    out.clear();
    out.reserve(cost.len());
    for j in 0..h {
        for i in 0..w {
            let p = ((j + 1) * pw + i + 1) as isize;
            if !free[p as usize] {
                out.push(0);
                continue;
            }
            let at = |o: isize| free[(p + o) as usize];
            let mut m = 0u8;
            for b in 0..8 {
                let ok = at(ends[b]) && (!diagonal[b] || at(sides[b].0) || at(sides[b].1));
                m |= (ok as u8) << b;
            }
            out.push(m);
        }
    }
}

/// The index of a search's source cell, or why a search cannot start from it.
fn source_index(grid: &CostGrid, source: Cell) -> Result<usize, SearchError> {
    if grid.len() >= NO_PRED as usize {
        return Err(SearchError::GridTooLarge);
    }
    let s = grid
        .index(source)
        .ok_or(SearchError::SourceOutside(source))?;
    if !grid.costs()[s].is_finite() {
        return Err(SearchError::SourceInadmissible(source));
    }
    Ok(s)
}

/// Octile distance in cells between row-major indices (for the A* heuristic).
#[inline]
fn octile(a: usize, b: usize, w: usize) -> f64 {
    let (ai, aj) = ((a % w) as i64, (a / w) as i64);
    let (bi, bj) = ((b % w) as i64, (b / w) as i64);
    let (dx, dy) = ((ai - bi).abs() as f64, (aj - bj).abs() as f64);
    let (lo, hi) = if dx < dy { (dx, dy) } else { (dy, dx) };
    (hi - lo) + SQRT_2 * lo
}

/// Reusable single-source search state: distance field, predecessor field, priority queues and
/// the move masks of the last grid searched.
///
/// After [`run`](Self::run) every reachable cell is settled. After
/// [`run_to_targets`](Self::run_to_targets) or [`astar`](Self::astar) the search stops early:
/// distances and predecessors are exact for settled cells (every reachable target among them),
/// the others hold upper bounds or `+∞`.
#[derive(Clone, Debug, Default)]
pub struct Dijkstra {
    dist: Vec<f64>,
    pred: Vec<u32>,
    settled: Vec<bool>,
    target: Vec<bool>,
    moves: Vec<u8>,
    moves_of: Option<u64>,
    heap: BinaryHeap<Entry>,
    buckets: BucketQueue,
    rect: Option<strider_core::CellRect>,
    source: Option<usize>,
    /// The cells an A* search gave a distance (see [`astar`](Self::astar)).
    touched: Vec<u32>,
    /// True when the fields hold their reset values everywhere but at `touched`: the next A*
    /// then resets only those cells. A* on a large view reaches a small part of it, and a full
    /// reset would cost more than the search.
    touched_only: bool,
}

impl Dijkstra {
    /// Empty search state; buffers grow on first use.
    pub fn new() -> Self {
        Self::default()
    }

    fn reset(&mut self, grid: &CostGrid, source: Cell) -> Result<usize, SearchError> {
        self.reset_with(grid, source, true)
    }

    /// Builds (or reuses) the move masks of `grid`.
    pub(crate) fn prepare(&mut self, grid: &CostGrid) {
        // Grids are immutable and carry a unique id (shared by clones, which are equal), so
        // the move masks are rebuilt only for a different grid.
        if self.moves_of != Some(grid.id()) {
            build_moves(grid, &mut self.moves);
            self.moves_of = Some(grid.id());
        }
    }

    /// As `reset`; without `full` the predecessor and settled fields are left as they are
    /// (for [`row_into`](Self::row_into), which reads neither).
    fn reset_with(
        &mut self,
        grid: &CostGrid,
        source: Cell,
        full: bool,
    ) -> Result<usize, SearchError> {
        let n = grid.len();
        let s = source_index(grid, source)?;
        self.prepare(grid);
        // Only A* uses the touched list, but every heap search records into it.
        self.touched_only = false;
        self.touched.clear();
        self.dist.clear();
        self.dist.resize(n, f64::INFINITY);
        if full {
            self.pred.clear();
            self.pred.resize(n, NO_PRED);
            self.settled.clear();
            self.settled.resize(n, false);
        }
        self.heap.clear();
        self.rect = Some(grid.rect());
        self.source = Some(s);
        self.dist[s] = 0.0;
        Ok(s)
    }

    /// Core loop over queue `q`; stops when `stop(p)` returns true for a newly settled cell `p`.
    /// Keys are `dist + h`; moves follow Eq. 4 with decision 21 (length × source-cell cost).
    fn search<Q: Queue>(
        &mut self,
        queue: &mut Q,
        grid: &CostGrid,
        s: usize,
        h: impl Fn(usize) -> f64,
        mut stop: impl FnMut(usize) -> bool,
    ) {
        let cost = grid.costs();
        let w = grid.rect().width as isize;
        let delta: [isize; 8] = MOVES.map(|(di, dj)| di as isize + dj as isize * w);
        let d = grid.cell_size();
        queue.push(h(s), s as u32);
        while let Some(idx) = queue.pop() {
            let p = idx as usize;
            // The first pop of a cell is final (Dijkstra, or A* with a consistent heuristic);
            // later pops are stale duplicates.
            if self.settled[p] {
                continue;
            }
            let dp = self.dist[p];
            self.settled[p] = true;
            if stop(p) {
                return;
            }
            // Eq. 4, decision 21: ‖ν_a, ν_b‖ (d or √2·d) × c(ν_a).
            let axis = cost[p] as f64 * d;
            let step = [axis, axis * SQRT_2];
            let mut m = self.moves[p];
            while m != 0 {
                let b = m.trailing_zeros() as usize;
                m &= m - 1;
                let q = (p as isize + delta[b]) as usize;
                let nd = dp + step[b >> 2];
                // A settled q already holds its final (≤ nd) distance, so no settled check.
                if nd < self.dist[q] {
                    if self.dist[q] == f64::INFINITY {
                        self.touched.push(q as u32);
                    }
                    self.dist[q] = nd;
                    self.pred[q] = idx;
                    queue.push(nd + h(q), q as u32);
                }
            }
        }
    }

    /// Dijkstra on the bucket queue. While it runs, a settled cell is marked by the sign bit of
    /// its distance (`-0.0` for the source), which keeps the hot loop on one array: a relaxation
    /// `nd < dist[q]` then also fails for every settled `q`. A cell is pushed on every
    /// improvement. Each bucket is taken as a whole: by the argument of `BucketQueue` all its
    /// cells are final, and it receives no pushes while it is scanned. So it is processed in
    /// two passes: the first, without branches, settles its cells and compacts the list to the
    /// first copy of each (stale copies, whose distance is already negative, drop out); the
    /// second relaxes the settled cells in push order. (One pass that skipped stale copies
    /// with a branch was about 10 % slower on random cost grids: the branch mispredicts and
    /// serialises the loads.)
    ///
    /// `stop(p)` is asked before each settled cell is relaxed, `bucket_done(dist)` after each
    /// bucket; either ends the search (a stop leaves the rest of the bucket settled, with final
    /// distances and predecessors, but not relaxed). With `PUBLIC` predecessors are recorded
    /// and on return the distances are made positive again and `settled` is filled; without it
    /// (all-pairs rows) neither happens, and settled cells keep negative distances.
    fn bucket_search<const PUBLIC: bool>(
        &mut self,
        bq: &mut BucketQueue,
        grid: &CostGrid,
        s: usize,
        mut stop: impl FnMut(usize) -> bool,
        mut bucket_done: impl FnMut(&[f64]) -> bool,
    ) {
        let cost = grid.costs();
        let n = cost.len();
        let w = grid.rect().width as isize;
        let delta: [isize; 8] = MOVES.map(|(di, dj)| di as isize + dj as isize * w);
        let d = grid.cell_size();
        let inv = bq.inv_width;
        let mask = bq.buckets.len() - 1;
        let moves = &self.moves[..n];
        let dist = &mut self.dist[..n];
        let pred = &mut self.pred[..];
        let buckets = &mut bq.buckets;
        // Keys are finite and far below 2^63 buckets here; `as i64` converts more cheaply.
        let bucket_of = |k: f64| (k * inv) as i64 as usize;
        let mut cur = bucket_of(dist[s]);
        buckets[cur & mask].push(s as u32);
        let mut len = 1usize;
        'outer: while len > 0 {
            let slot = cur & mask;
            // Pushes during this bucket only go to later buckets (see `BucketQueue`; enforced
            // below), so its list is fixed while it is scanned.
            let mut list = std::mem::take(&mut buckets[slot]);
            len -= list.len();
            // Settle the bucket first, without branches: keep the first copy of each cell
            // whose distance is not yet negative (stale copies and repeats drop out), mark it.
            let mut live = 0;
            for k in 0..list.len() {
                let idx = list[k];
                let p = idx as usize;
                let dp = dist[p];
                list[live] = idx;
                live += !dp.is_sign_negative() as usize;
                dist[p] = -dp.abs();
            }
            for &idx in &list[..live] {
                let p = idx as usize;
                let dp = -dist[p];
                if stop(p) {
                    buckets[slot] = list;
                    break 'outer;
                }
                // Eq. 4, decision 21: ‖ν_a, ν_b‖ (d or √2·d) × c(ν_a).
                let axis = cost[p] as f64 * d;
                let nds = [dp + axis, dp + axis * SQRT_2];
                debug_assert!(bucket_of(nds[0]) > cur && bucket_of(nds[1]) > cur);
                debug_assert!(bucket_of(nds[1]) - cur < buckets.len());
                let bs = [
                    bucket_of(nds[0]).max(cur + 1),
                    bucket_of(nds[1]).max(cur + 1),
                ];
                // Two phases: first, without branches, the mask of the moves that improve
                // their target (a forbidden move reads `p` itself, whose negative, settled
                // distance no `nd` beats; so does every settled neighbour); then the updates.
                let m = moves[p];
                let mut olds = [0.0f64; 8];
                let mut better = 0u32;
                for k in 0..8 {
                    let q = if (m >> k) & 1 != 0 {
                        (p as isize + delta[k]) as usize
                    } else {
                        p
                    };
                    olds[k] = dist[q];
                    better |= ((nds[k >> 2] < olds[k]) as u32) << k;
                }
                while better != 0 {
                    let k = better.trailing_zeros() as usize;
                    better &= better - 1;
                    let q = (p as isize + delta[k]) as usize;
                    dist[q] = nds[k >> 2];
                    if PUBLIC {
                        pred[q] = idx;
                    }
                    buckets[bs[k >> 2] & mask].push(q as u32);
                    len += 1;
                }
            }
            list.clear();
            buckets[slot] = list;
            cur += 1;
            if bucket_done(dist) {
                break;
            }
        }
        if PUBLIC {
            for (dk, sk) in dist.iter_mut().zip(&mut self.settled[..n]) {
                if dk.is_sign_negative() {
                    *dk = -*dk;
                    *sk = true;
                }
            }
        }
    }

    fn dijkstra(&mut self, grid: &CostGrid, s: usize, stop: impl FnMut(usize) -> bool) {
        let mut buckets = std::mem::take(&mut self.buckets);
        if buckets.reset(grid) {
            self.bucket_search::<true>(&mut buckets, grid, s, stop, |_| false);
        } else {
            let mut heap = std::mem::take(&mut self.heap);
            self.search(&mut heap, grid, s, |_| 0.0, stop);
            self.heap = heap;
        }
        self.buckets = buckets;
    }

    /// One-to-all search from `source`: afterwards [`distances`](Self::distances) holds C(ψ*) of
    /// Eq. 2 for every cell (`+∞` when unreachable or inadmissible).
    pub fn run(&mut self, grid: &CostGrid, source: Cell) -> Result<(), SearchError> {
        let s = self.reset(grid, source)?;
        self.dijkstra(grid, s, |_| false);
        Ok(())
    }

    /// One-to-many search: stops as soon as every target that is reachable has been settled.
    /// Returns the distance to each target, in order (`+∞` for unreachable, inadmissible or
    /// outside targets).
    pub fn run_to_targets(
        &mut self,
        grid: &CostGrid,
        source: Cell,
        targets: &[Cell],
    ) -> Result<Vec<f64>, SearchError> {
        let mut out = Vec::with_capacity(targets.len());
        self.run_to_targets_into(grid, source, targets, &mut out)?;
        Ok(out)
    }

    /// As [`run_to_targets`](Self::run_to_targets), writing into `out` (cleared first) so that
    /// repeated calls allocate nothing.
    pub fn run_to_targets_into(
        &mut self,
        grid: &CostGrid,
        source: Cell,
        targets: &[Cell],
        out: &mut Vec<f64>,
    ) -> Result<(), SearchError> {
        let s = self.reset(grid, source)?;
        self.target.clear();
        self.target.resize(grid.len(), false);
        let mut remaining = 0usize;
        for &t in targets {
            if let Some(k) = grid.index(t)
                && grid.costs()[k].is_finite()
                && !self.target[k]
            {
                self.target[k] = true;
                remaining += 1;
            }
        }
        let mut target = std::mem::take(&mut self.target);
        if remaining > 0 {
            self.dijkstra(grid, s, |p| {
                if target[p] {
                    target[p] = false;
                    remaining -= 1;
                }
                remaining == 0
            });
        }
        self.target = target;
        out.clear();
        out.extend(targets.iter().map(|&t| self.distance(t)));
        Ok(())
    }

    /// Costs from `source` to each of `targets` (`+∞` when unreachable, inadmissible or
    /// outside), as [`run_to_targets_into`](Self::run_to_targets_into) returns them, but
    /// without recording predecessors: for the all-pairs matrix. Afterwards the search state
    /// is unspecified until the next search; `pending` is scratch space.
    pub(crate) fn row_into(
        &mut self,
        grid: &CostGrid,
        source: Cell,
        targets: &[Cell],
        pending: &mut Vec<usize>,
        out: &mut Vec<f64>,
    ) -> Result<(), SearchError> {
        let s = self.reset_with(grid, source, false)?;
        let mut buckets = std::mem::take(&mut self.buckets);
        if !buckets.reset(grid) {
            self.buckets = buckets;
            return self.run_to_targets_into(grid, source, targets, out);
        }
        // Targets still to settle; checked after each bucket from the back, so the search
        // ends with the bucket that settles the last reachable target.
        pending.clear();
        pending.extend(
            targets
                .iter()
                .rev()
                .filter_map(|&t| grid.index(t))
                .filter(|&k| grid.costs()[k].is_finite()),
        );
        if !pending.is_empty() {
            self.bucket_search::<false>(
                &mut buckets,
                grid,
                s,
                |_| false,
                |dist| {
                    while let Some(&k) = pending.last() {
                        if !dist[k].is_sign_negative() {
                            return false;
                        }
                        pending.pop();
                    }
                    true
                },
            );
        }
        self.buckets = buckets;
        let rect = grid.rect();
        out.clear();
        out.extend(targets.iter().map(|&t| match rect.index(t) {
            // Settled cells carry their distance negated (see `bucket_search`).
            Some(k) if self.dist[k].is_sign_negative() => -self.dist[k],
            _ => f64::INFINITY,
        }));
        Ok(())
    }

    /// A* from `source` to `target` with the octile heuristic h(ν) = octile(ν, target) · d ·
    /// min c, which never overestimates because every move of length ℓ costs at least ℓ · min c.
    /// Returns the optimal cost (equal to Dijkstra's), or `+∞` when the target is unreachable,
    /// inadmissible or outside the grid.
    pub fn astar(
        &mut self,
        grid: &CostGrid,
        source: Cell,
        target: Cell,
    ) -> Result<f64, SearchError> {
        let s = self.reset_touched(grid, source)?;
        let Some(t) = grid.index(target) else {
            return Ok(f64::INFINITY);
        };
        if !grid.costs()[t].is_finite() {
            return Ok(f64::INFINITY);
        }
        let w = grid.rect().width as usize;
        // Shrunk by 1e-9 relative so rounding can never make the heuristic inadmissible or
        // inconsistent (each move costs ≥ its octile length · d · min c).
        let scale = grid.cell_size() * grid.min_cost() as f64 * (1.0 - 1e-9);
        let mut heap = std::mem::take(&mut self.heap);
        self.search(&mut heap, grid, s, |q| octile(q, t, w) * scale, |p| p == t);
        self.heap = heap;
        Ok(self.dist_settled(t))
    }

    /// As [`reset`](Self::reset), but after an A* on a grid of the same size only the cells
    /// that search touched are reset; the search records the cells it touches from here on.
    fn reset_touched(&mut self, grid: &CostGrid, source: Cell) -> Result<usize, SearchError> {
        let n = grid.len();
        if !(self.touched_only && self.dist.len() == n && self.rect == Some(grid.rect())) {
            self.touched_only = false;
            self.touched.clear();
            let s = self.reset(grid, source)?;
            self.touched.push(s as u32);
            self.touched_only = true;
            return Ok(s);
        }
        for &k in &self.touched {
            let k = k as usize;
            self.dist[k] = f64::INFINITY;
            self.pred[k] = NO_PRED;
            self.settled[k] = false;
        }
        self.touched.clear();
        // The same checks and state as `reset_with`, without touching the fields.
        let s = source_index(grid, source)?;
        self.prepare(grid);
        self.heap.clear();
        self.source = Some(s);
        self.dist[s] = 0.0;
        self.touched.push(s as u32);
        Ok(s)
    }

    #[inline]
    fn dist_settled(&self, k: usize) -> f64 {
        if self.settled[k] {
            self.dist[k]
        } else {
            f64::INFINITY
        }
    }

    /// Exact cost of the cheapest path from the last source to `c`; `+∞` when `c` is outside,
    /// unreachable, or not settled by an early-exit search.
    pub fn distance(&self, c: Cell) -> f64 {
        match self.rect.and_then(|r| r.index(c)) {
            Some(k) if k < self.settled.len() => self.dist_settled(k),
            _ => f64::INFINITY,
        }
    }

    /// Row-major distance field of the last search (see the type docs for early-exit searches).
    pub fn distances(&self) -> &[f64] {
        &self.dist
    }

    /// Row-major predecessor field of the last search: index of the previous cell on the
    /// cheapest path, [`NO_PRED`] for the source and for unreached cells.
    pub fn predecessors(&self) -> &[u32] {
        &self.pred
    }

    /// True when `c` was settled (its distance is final) by the last search.
    pub fn is_settled(&self, c: Cell) -> bool {
        self.rect
            .and_then(|r| r.index(c))
            .is_some_and(|k| k < self.settled.len() && self.settled[k])
    }

    /// The cheapest path from the last source to `c` (both included), or `None` when `c` was not
    /// settled by the last search.
    pub fn path_to(&self, c: Cell) -> Option<Vec<Cell>> {
        let rect = self.rect?;
        let k = rect.index(c)?;
        if !self.settled.get(k).copied().unwrap_or(false) {
            return None;
        }
        let mut path = vec![c];
        let mut k = k;
        while self.pred[k] != NO_PRED {
            k = self.pred[k] as usize;
            path.push(rect.cell(k));
        }
        debug_assert_eq!(Some(k), self.source);
        path.reverse();
        Some(path)
    }
}

/// Cost of a cell path per Eq. 4 with decision 21 (length × cost of the source cell); `None`
/// when the path leaves the grid, uses an inadmissible cell, makes a non-8-neighbour step or
/// cuts a corner between two inadmissible cells.
pub fn path_cost(grid: &CostGrid, path: &[Cell]) -> Option<f64> {
    let d = grid.cell_size();
    let mut total = 0.0;
    for c in path {
        if !grid.is_admissible(*c) {
            return None;
        }
    }
    for w in path.windows(2) {
        let (a, b) = (w[0], w[1]);
        let (di, dj) = (b.i - a.i, b.j - a.j);
        if di.abs() > 1 || dj.abs() > 1 || (di == 0 && dj == 0) {
            return None;
        }
        let c = grid.cost(a)? as f64;
        if di != 0 && dj != 0 {
            if !grid.is_admissible(a.offset(di, 0)) && !grid.is_admissible(a.offset(0, dj)) {
                return None;
            }
            total += c * d * SQRT_2;
        } else {
            total += c * d;
        }
    }
    Some(total)
}

#[cfg(test)]
mod tests {
    use super::*;
    use strider_core::CellRect;

    /// The move masks by their definition: a move needs both end cells admissible, and a
    /// diagonal one an admissible side cell; outside the grid is inadmissible.
    fn moves_by_definition(grid: &CostGrid) -> Vec<u8> {
        let rect = grid.rect();
        let (w, h) = (rect.width as i64, rect.height as i64);
        let cost = grid.costs();
        let free = |i: i64, j: i64| {
            i >= 0 && j >= 0 && i < w && j < h && cost[(j * w + i) as usize].is_finite()
        };
        (0..cost.len())
            .map(|k| {
                let (i, j) = (k as i64 % w, k as i64 / w);
                if !free(i, j) {
                    return 0;
                }
                let mut m = 0u8;
                for (b, &(di, dj)) in MOVES.iter().enumerate() {
                    let (di, dj) = (di as i64, dj as i64);
                    let side = di == 0 || dj == 0 || free(i + di, j) || free(i, j + dj);
                    if free(i + di, j + dj) && side {
                        m |= 1 << b;
                    }
                }
                m
            })
            .collect()
    }

    proptest::proptest! {
        #[test]
        fn move_masks_follow_their_definition(
            w in 1u32..12, h in 1u32..12,
            blocked in proptest::collection::vec(proptest::bool::weighted(0.35), 144),
        ) {
            let costs: Vec<f32> = (0..(w * h) as usize)
                .map(|k| if blocked[k] { f32::INFINITY } else { 1.0 + (k % 3) as f32 })
                .collect();
            let g = CostGrid::new(CellRect::new(Cell::new(-3, 5), w, h), 0.1, costs).unwrap();
            let mut got = Vec::new();
            build_moves(&g, &mut got);
            proptest::prop_assert_eq!(got, moves_by_definition(&g));
        }
    }

    #[test]
    fn uniform_grid_octile() {
        let g = CostGrid::filled(CellRect::new(Cell::new(0, 0), 5, 4), 0.5, 2.0).unwrap();
        let mut dj = Dijkstra::new();
        dj.run(&g, Cell::new(0, 0)).unwrap();
        let d = dj.distance(Cell::new(4, 2));
        assert!((d - 2.0 * 0.5 * (2.0 + 2.0 * SQRT_2)).abs() < 1e-12);
        let p = dj.path_to(Cell::new(4, 2)).unwrap();
        assert_eq!(p.first(), Some(&Cell::new(0, 0)));
        assert_eq!(p.last(), Some(&Cell::new(4, 2)));
        assert!((path_cost(&g, &p).unwrap() - d).abs() < 1e-12);
        assert_eq!(dj.astar(&g, Cell::new(0, 0), Cell::new(4, 2)).unwrap(), d);
    }

    #[test]
    fn corner_rule_and_errors() {
        // 2×2: (1,0) and (0,1) blocked: (0,0) → (1,1) must be unreachable.
        let inf = f32::INFINITY;
        let g = CostGrid::new(
            CellRect::new(Cell::new(0, 0), 2, 2),
            1.0,
            vec![1.0, inf, inf, 1.0],
        )
        .unwrap();
        let mut dj = Dijkstra::new();
        dj.run(&g, Cell::new(0, 0)).unwrap();
        assert_eq!(dj.distance(Cell::new(1, 1)), f64::INFINITY);
        assert!(dj.path_to(Cell::new(1, 1)).is_none());
        assert_eq!(
            dj.run(&g, Cell::new(1, 0)),
            Err(SearchError::SourceInadmissible(Cell::new(1, 0)))
        );
        assert_eq!(
            dj.run(&g, Cell::new(5, 0)),
            Err(SearchError::SourceOutside(Cell::new(5, 0)))
        );
        // One side open: diagonal allowed.
        let g = CostGrid::new(
            CellRect::new(Cell::new(0, 0), 2, 2),
            1.0,
            vec![1.0, 1.0, inf, 1.0],
        )
        .unwrap();
        dj.run(&g, Cell::new(0, 0)).unwrap();
        assert!((dj.distance(Cell::new(1, 1)) - SQRT_2).abs() < 1e-12);
    }

    #[test]
    fn source_cell_cost_asymmetry() {
        // a (cost 1) — b (cost 3): C(a→b) = d·1, C(b→a) = d·3.
        let g = CostGrid::new(CellRect::new(Cell::new(0, 0), 2, 1), 0.1, vec![1.0, 3.0]).unwrap();
        let mut dj = Dijkstra::new();
        dj.run(&g, Cell::new(0, 0)).unwrap();
        assert!((dj.distance(Cell::new(1, 0)) - 0.1).abs() < 1e-12);
        dj.run(&g, Cell::new(1, 0)).unwrap();
        assert!((dj.distance(Cell::new(0, 0)) - 0.3).abs() < 1e-6);
    }

    /// The bucket-queue kernel (full runs and all-pairs rows) against the binary-heap search on
    /// a grid large enough for many buckets, ring wrap-arounds and stale queue entries.
    #[test]
    fn bucket_kernel_matches_heap_search() {
        let (w, h) = (47u32, 31u32);
        let mut x = 0x2545_f491_4f6c_dd1du64;
        let costs: Vec<f32> = (0..w * h)
            .map(|_| {
                x ^= x << 13;
                x ^= x >> 7;
                x ^= x << 17;
                if x.is_multiple_of(5) {
                    f32::INFINITY
                } else {
                    1.0 + (x >> 40) as f32 / (1u64 << 24) as f32 * 6.0
                }
            })
            .collect();
        let g = CostGrid::new(CellRect::new(Cell::new(-7, 3), w, h), 0.3, costs).unwrap();
        let cells: Vec<Cell> = g.rect().cells().filter(|&c| g.is_admissible(c)).collect();
        let sites: Vec<Cell> = cells.iter().copied().step_by(97).collect();
        let close = |a: f64, b: f64| a == b || (a - b).abs() <= 1e-9 * a.abs().max(b.abs());
        let (mut fast, mut slow) = (Dijkstra::new(), Dijkstra::new());
        let (mut pending, mut row) = (Vec::new(), Vec::new());
        for &src in &sites {
            fast.run(&g, src).unwrap();
            let s = slow.reset(&g, src).unwrap();
            let mut heap = BinaryHeap::new();
            slow.search(&mut heap, &g, s, |_| 0.0, |_| false);
            for &c in &cells {
                let (a, b) = (fast.distance(c), slow.distance(c));
                assert!(close(a, b), "{src:?} → {c:?}: {a} vs {b}");
                if let Some(p) = fast.path_to(c) {
                    assert!(close(path_cost(&g, &p).unwrap(), a));
                }
            }
            let r = fast.run_to_targets(&g, src, &sites).unwrap();
            fast.row_into(&g, src, &sites, &mut pending, &mut row)
                .unwrap();
            for (k, &t) in sites.iter().enumerate() {
                assert!(close(r[k], slow.distance(t)));
                assert!(close(row[k], slow.distance(t)));
            }
        }
    }

    #[test]
    fn early_exit_targets() {
        let g = CostGrid::filled(CellRect::new(Cell::new(0, 0), 30, 30), 1.0, 1.0).unwrap();
        let mut dj = Dijkstra::new();
        let r = dj
            .run_to_targets(&g, Cell::new(0, 0), &[Cell::new(1, 0), Cell::new(99, 0)])
            .unwrap();
        assert_eq!(r, vec![1.0, f64::INFINITY]);
        assert!(!dj.is_settled(Cell::new(29, 29)));
    }
}
