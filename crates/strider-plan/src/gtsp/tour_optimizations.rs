//! Local improvement of a g-tour.
//!
//! A tour is a cyclic sequence of internal vertices, one per set. Two kinds
//! of improvement are combined:
//!
//! * **Cluster optimisation** ([`ClusterOpt`]): for the fixed cyclic order
//!   of the sets, choose the optimal vertex of every set. This is a shortest
//!   path through the set-layered graph (Fischetti, Salazar González & Toth
//!   1997; "re-opt" in GLNS, Smith & Imeson 2017; "CO" in Karapetyan & Gutin
//!   2011). The smallest set is used as the first layer and one shortest
//!   path is run per vertex of it: `O(|S_min| · Σ |S_i|·|S_{i+1}|)`.
//! * **Set-order local search** ([`LocalSearch`]), driven by a queue of
//!   "dirty" sets (don't-look bits, Bentley 1992): for a dirty set `X`
//!   1. *move-opt*: remove `X` and re-insert it at its best position with its
//!      best vertex (the vertex choice is re-optimised, GLNS's "moveopt");
//!   2. *2-opt* on the two tour edges at `X` against every other edge;
//!   3. *or-opt*: move the segments of 2 and 3 sets that start or end at
//!      `X` elsewhere, forward or reversed.
//!
//!   All gains are exact for asymmetric costs: what reversing a segment adds
//!   is read from a prefix sum of backward minus forward arc costs along the
//!   tour. A candidate that a lower bound rules out (each vertex's cheapest
//!   arcs to and from other sets, [`Problem::min_in`]) is not read, which
//!   changes no choice. Endpoints of changed edges become dirty again.
//!
//! The two are alternated until cluster optimisation finds nothing.

use std::time::Instant;

use super::problem::Problem;

/// Shortest-path cluster optimisation with reusable buffers.
#[derive(Default)]
pub(crate) struct ClusterOpt {
    dp: Vec<i64>,
    parent: Vec<u32>,
    best_parent: Vec<u32>,
    sets: Vec<usize>,
}

impl ClusterOpt {
    /// Re-chooses the vertices of `tour` optimally for its set order.
    /// Returns the new cost (never worse than the old one).
    pub fn run(&mut self, p: &Problem, tour: &mut [u32]) -> i64 {
        let m = tour.len();
        if m < 2 {
            return p.tour_cost(tour);
        }
        self.dp.resize(p.nv, 0);
        self.parent.resize(p.nv, 0);
        self.best_parent.resize(p.nv, 0);
        self.sets.clear();
        self.sets.extend(tour.iter().map(|&v| p.set_of(v)));
        // First layer: the smallest set.
        let r = (0..m).min_by_key(|&i| p.set_size(self.sets[i])).unwrap();
        let layer = |i: usize| self.sets[wrap(r + i, m)];
        let mut best = (i64::MAX, 0u32, 0usize);
        for a in p.set(layer(0)) {
            // Layer 1.
            let s1 = layer(1);
            let ra = p.row(a);
            for w in p.set_range(s1) {
                self.dp[w] = ra[w];
                self.parent[w] = a;
            }
            for i in 2..m {
                let prev = p.set_range(layer(i - 1));
                for w in p.set(layer(i)) {
                    let cw = &p.col(w)[prev.clone()];
                    let dp = &self.dp[prev.clone()];
                    let mut bv = i64::MAX;
                    let mut bp = 0usize;
                    for (k, (x, y)) in dp.iter().zip(cw).enumerate() {
                        let c = x + y;
                        if c < bv {
                            bv = c;
                            bp = k;
                        }
                    }
                    self.dp[w as usize] = bv;
                    self.parent[w as usize] = (prev.start + bp) as u32;
                }
            }
            let last = p.set_range(layer(m - 1));
            let ca = p.col(a);
            let mut total = i64::MAX;
            let mut end = 0usize;
            for v in last {
                let c = self.dp[v] + ca[v];
                if c < total {
                    total = c;
                    end = v;
                }
            }
            if total < best.0 {
                best = (total, a, end);
                std::mem::swap(&mut self.parent, &mut self.best_parent);
            }
        }
        let (total, a, end) = best;
        let mut v = end as u32;
        for i in (1..m).rev() {
            tour[(r + i) % m] = v;
            v = self.best_parent[v as usize];
        }
        tour[r] = a;
        total
    }
}

/// A set's place in the tour: its position, its vertex, the vertices before and after it and
/// the costs of the arcs from and to them. The moves try the two tour edges at each of a set's
/// neighbour sets; one record per neighbour holds all they read of the tour.
#[derive(Clone, Copy, Default)]
struct Link {
    pos: u32,
    pred: u32,
    vert: u32,
    succ: u32,
    /// `d(pred, vert)`.
    ein: i64,
    /// `d(vert, succ)`.
    eout: i64,
    /// `d(succ, vert)`.
    eback: i64,
}

/// Dirty-set driven local search over the set order (see module docs).
#[derive(Default)]
pub(crate) struct LocalSearch {
    /// Place of each set in the tour.
    link: Vec<Link>,
    /// What reversing costs, as prefix sums over the tour's arcs (the last one closes it):
    /// `rev[k] = Σ_{x<k} d(t[x+1], t[x]) − d(t[x], t[x+1])`, `k ≤ m`.
    rev: Vec<i64>,
    /// Cost of tour edge `k`: `edge[k] = d(t[k], t[k+1 mod m])`, read in the moves' inner loops
    /// instead of a scattered matrix entry.
    edge: Vec<i64>,
    /// Incremented whenever the tour changes ([`Self::refresh`]).
    version: u64,
    /// `or_failed[2·s + len − 2] == version`: the or-opt move of the segment of `len` sets
    /// starting at set `s` found nothing on this very tour. Both end sets of a segment try it,
    /// and neighbouring sets are often dirty together, so the second try is skipped.
    or_failed: Vec<u64>,
    queue: Vec<u32>,
    queued: Vec<bool>,
    scratch: Vec<u32>,
    pub co: ClusterOpt,
    /// Enable or-opt moves.
    pub or_opt: bool,
    /// Enable 2-opt moves.
    pub two_opt: bool,
    /// Neighbour-list length (number of nearest sets tried per move).
    pub nn: usize,
    /// The run's deadline: the set-order moves stop there (the tour stays feasible), so that a
    /// first local search on a large random tour cannot outlast the time limit.
    pub stop_at: Option<Instant>,
}

/// `x mod m` for `x < 2m`: tour indices step by at most one lap, and a division in the inner
/// loops of the moves costs more than their memory reads.
#[inline(always)]
fn wrap(x: usize, m: usize) -> usize {
    debug_assert!(x < 2 * m);
    if x >= m { x - m } else { x }
}

/// An or-opt candidate: (insertion cost, position q, the edge is q − 1 rather than q, reversed).
type Best = (i64, usize, bool, bool);

/// Queue pops between two looks at the clock.
const CLOCK_EVERY: usize = 256;

impl LocalSearch {
    pub fn new(m: usize) -> Self {
        Self {
            link: vec![Link::default(); m],
            queued: vec![false; m],
            or_opt: true,
            two_opt: true,
            nn: 10,
            ..Default::default()
        }
    }

    /// Positions, records and prefix sums of tour `t`. A set whose vertex and successor are
    /// those of its previous record keeps that record's arc costs: a move changes a few arcs,
    /// and the matrix reads of all the others would be scattered.
    fn refresh(&mut self, p: &Problem, t: &[u32]) {
        let m = t.len();
        self.version += 1;
        self.rev.resize(m + 1, 0);
        self.edge.resize(m, 0);
        let (rev, edge) = (&mut self.rev[..m + 1], &mut self.edge[..m]);
        let mut r = 0i64;
        let mut pred = t[m - 1];
        let arcs = |old: &Link, v: u32, w: u32| {
            if old.vert == v && old.succ == w {
                (old.eout, old.eback)
            } else {
                (p.d(v, w), p.d(w, v))
            }
        };
        // The set at position m − 1 is read here and rewritten last.
        let (mut ein, _) = arcs(&self.link[p.set_of(pred)], pred, t[0]);
        for i in 0..m {
            let v = t[i];
            let w = if i + 1 < m { t[i + 1] } else { t[0] };
            let link = &mut self.link[p.set_of(v)];
            let (e, back) = arcs(link, v, w);
            rev[i] = r;
            edge[i] = e;
            *link = Link {
                pos: i as u32,
                pred,
                vert: v,
                succ: w,
                ein,
                eout: e,
                eback: back,
            };
            r += back - e;
            pred = v;
            ein = e;
        }
        rev[m] = r;
    }

    fn push(&mut self, s: usize) {
        if !self.queued[s] {
            self.queued[s] = true;
            self.queue.push(s as u32);
        }
    }

    /// Improves `tour` (cost `cost`) starting from the given dirty sets;
    /// with `dirty = None` every set is dirty. Cluster optimisation is
    /// skipped when the cost after the set-order moves exceeds `co_above`.
    /// Returns the new cost.
    pub fn run(
        &mut self,
        p: &Problem,
        tour: &mut Vec<u32>,
        mut cost: i64,
        dirty: Option<&[u32]>,
        co_above: i64,
    ) -> i64 {
        let m = tour.len();
        if m < 3 {
            return self.co.run(p, tour);
        }
        self.link.resize(p.m, Link::default());
        self.queued.resize(p.m, false);
        // Version 0 marks no segment: entries of an earlier run are below the current version.
        self.or_failed.resize(2 * p.m, 0);
        match dirty {
            Some(ds) => {
                for &s in ds {
                    self.push(s as usize);
                }
            }
            None => {
                for i in (0..m).rev() {
                    self.push(p.set_of(tour[i]));
                }
            }
        }
        let mut rounds = 0;
        let mut pops = 0usize;
        loop {
            self.refresh(p, tour);
            while let Some(s) = self.queue.pop() {
                self.queued[s as usize] = false;
                pops += 1;
                if pops.is_multiple_of(CLOCK_EVERY) && self.out_of_time() {
                    for s in self.queue.drain(..) {
                        self.queued[s as usize] = false;
                    }
                    return cost;
                }
                let i = self.link[s as usize].pos as usize;
                if let Some(delta) = self.improve_at(p, tour, i) {
                    debug_assert!(delta < 0);
                    cost += delta;
                    self.refresh(p, tour);
                    debug_assert_eq!(cost, p.tour_cost(tour));
                }
            }
            if cost > co_above {
                return cost;
            }
            self.scratch.clear();
            self.scratch.extend_from_slice(tour);
            let c = self.co.run(p, tour);
            rounds += 1;
            if c >= cost || rounds >= 8 {
                if c > cost {
                    tour.copy_from_slice(&self.scratch);
                }
                return c.min(cost);
            }
            cost = c;
            // Re-examine the sets whose vertex changed, and their neighbours.
            for i in 0..m {
                if tour[i] != self.scratch[i] {
                    self.push(p.set_of(tour[(i + m - 1) % m]));
                    self.push(p.set_of(tour[i]));
                    self.push(p.set_of(tour[(i + 1) % m]));
                }
            }
        }
    }

    fn out_of_time(&self) -> bool {
        self.stop_at.is_some_and(|t| Instant::now() >= t)
    }

    /// Tries the moves at position `i`; applies the first improving one.
    fn improve_at(&mut self, p: &Problem, t: &mut Vec<u32>, i: usize) -> Option<i64> {
        if let Some(d) = self.move_opt(p, t, i) {
            return Some(d);
        }
        if self.two_opt {
            let m = t.len();
            if let Some(d) = self.two_opt_edge(p, t, wrap(i + m - 1, m), false) {
                return Some(d);
            }
            if let Some(d) = self.two_opt_edge(p, t, i, true) {
                return Some(d);
            }
        }
        if self.or_opt {
            let m = t.len();
            for len in [2usize, 3] {
                if len + 2 > m {
                    break;
                }
                for start in [i, (i + m + 1 - len) % m] {
                    let key = 2 * p.set_of(t[start]) + len - 2;
                    if self.or_failed[key] == self.version {
                        continue;
                    }
                    if let Some(d) = self.or_move(p, t, start, len) {
                        return Some(d);
                    }
                    self.or_failed[key] = self.version;
                }
            }
        }
        None
    }

    /// Marks the sets at positions `idx` (mod m) dirty.
    fn dirty_positions(&mut self, p: &Problem, t: &[u32], idx: &[usize]) {
        let m = t.len();
        for &k in idx {
            let s = p.set_of(t[wrap(k, m)]);
            self.push(s);
        }
    }

    /// Remove the set at position `i` and re-insert it with its best vertex
    /// at its best position. Candidate positions are the edges next to the
    /// `nn` nearest sets (all edges when `nn >= m - 1`), plus the gap left
    /// by the removal.
    fn move_opt(&mut self, p: &Problem, t: &mut Vec<u32>, i: usize) -> Option<i64> {
        let m = t.len();
        let v = t[i];
        let im1 = wrap(i + m - 1, m);
        let prev = t[im1];
        let next = t[wrap(i + 1, m)];
        let s = p.set_of(v);
        let gain = p.d(prev, v) + p.d(v, next) - p.d(prev, next);
        let range = p.set_range(s);
        let mut best = (gain, usize::MAX, 0u32); // (insert cost, after-position, vertex)
        // Inserting on edge j = (a, b) of cost `base` of the tour without position i (j == i is
        // (prev, next)).
        let through = p.set_min_through[s];
        let min_out = &p.min_out[range.clone()];
        let eval = |a: u32, b: u32, base: i64, j: usize, best: &mut (i64, usize, u32)| {
            // No vertex of the set costs less than `through - base` here, nor less than its
            // arc from `a` and its cheapest arc out: the arcs into `b` are read only if needed.
            if through - base >= best.0 {
                return;
            }
            let ra = &p.row(a)[range.clone()];
            let least = ra.iter().zip(min_out).map(|(x, o)| x + o).min();
            if least.is_none_or(|l| l - base >= best.0) {
                return;
            }
            let cb = &p.col(b)[range.clone()];
            for (k, (x, y)) in ra.iter().zip(cb).enumerate() {
                let c = x + y - base;
                if c < best.0 {
                    *best = (c, j, range.start as u32 + k as u32);
                }
            }
        };
        let gap = p.d(prev, next);
        if self.nn + 1 >= m {
            for j in 0..m {
                if j == i {
                    eval(prev, next, gap, j, &mut best);
                } else if j != im1 {
                    eval(t[j], t[wrap(j + 1, m)], self.edge[j], j, &mut best);
                }
            }
        } else {
            eval(prev, next, gap, i, &mut best);
            let (sp, sn) = (p.set_of(prev) as u32, p.set_of(next) as u32);
            for &y in &p.set_nbrs[s][..self.nn] {
                let l = &self.link[y as usize];
                let q = l.pos as usize;
                // Edge q − 1 = (pred(y), y) is edge i when y is the next set, and edge
                // q = (y, succ(y)) is the removed edge (prev, X) when y is the previous set.
                if y != sn {
                    eval(l.pred, l.vert, l.ein, wrap(q + m - 1, m), &mut best);
                }
                if y != sp {
                    eval(l.vert, l.succ, l.eout, q, &mut best);
                }
            }
        }
        if best.1 == usize::MAX {
            return None;
        }
        let (c, j, w) = best;
        let delta = c - gain;
        if j == i {
            t[i] = w;
            self.dirty_positions(p, t, &[i + m - 1, i, i + 1]);
        } else {
            t.remove(i);
            // After removal, the edge (t[j], t[j+1]) of the old tour starts
            // at index j if j < i, else at j - 1.
            let jj = if j < i { j } else { j - 1 };
            t.insert(jj + 1, w);
            self.dirty_positions(p, t, &[jj, jj + 1, jj + 2]);
            self.push(p.set_of(prev));
            self.push(p.set_of(next));
        }
        Some(delta)
    }

    /// What reversing `t[lo..=hi]` adds to its internal cost (`lo <= hi < m`).
    #[inline]
    fn rev_extra(&self, lo: usize, hi: usize) -> i64 {
        self.rev[hi] - self.rev[lo]
    }

    /// The 2-opt move on tour edges `k` and `j`, each given as (position, tail, head, cost):
    /// reversing `t[lo+1..=hi]` for `lo < hi` the two positions; kept in `best` as
    /// `(delta, lo, hi)` when it improves on it.
    #[inline(always)]
    fn two_opt_try(
        &self,
        p: &Problem,
        (k, tk, tk1, ek): (usize, u32, u32, i64),
        (j, a, b, ej): (usize, u32, u32, i64),
        best: &mut (i64, usize, usize),
    ) {
        let (lo, hi) = if j < k { (j, k) } else { (k, j) };
        if hi < lo + 2 {
            return;
        }
        let (a, b, c, e) = if j < k {
            (a, b, tk, tk1)
        } else {
            (tk, tk1, a, b)
        };
        let delta = self.rev_extra(lo + 1, hi) - ej - ek;
        // The new arcs a → c and b → e cost at least the cheapest arcs out of a and b.
        if delta + p.min_out[a as usize] + p.min_out[b as usize] >= best.0 {
            return;
        }
        let delta = delta + p.d(a, c) + p.d(b, e);
        if delta < best.0 {
            *best = (delta, lo, hi);
        }
    }

    /// Best 2-opt move between edge `k` = (t[k], t[k+1]) and another edge.
    /// With neighbour lists, `x` is the vertex of the dirty set (`t[k]` if
    /// `x_first`, else `t[k+1]`) and only moves creating an edge between `x`
    /// and one of its neighbour sets are tried.
    fn two_opt_edge(&mut self, p: &Problem, t: &mut [u32], k: usize, x_first: bool) -> Option<i64> {
        let m = t.len();
        let mut best = (0i64, usize::MAX, usize::MAX);
        let (tk, tk1) = (t[k], t[wrap(k + 1, m)]);
        let edge_k = (k, tk, tk1, self.edge[k]);
        if self.nn + 1 >= m {
            for j in 0..m {
                let edge_j = (j, t[j], t[wrap(j + 1, m)], self.edge[j]);
                self.two_opt_try(p, edge_k, edge_j, &mut best);
            }
        } else {
            let x = if x_first { tk } else { tk1 };
            for &y in &p.set_nbrs[p.set_of(x)][..self.nn] {
                let l = &self.link[y as usize];
                let q = l.pos as usize;
                // x = t[k]: edge pair (k, q) creates (x, t[q]);
                // x = t[k+1]: edge pair (k, q-1) creates (x, t[q]).
                let edge_j = if x_first {
                    (q, l.vert, l.succ, l.eout)
                } else {
                    (wrap(q + m - 1, m), l.pred, l.vert, l.ein)
                };
                self.two_opt_try(p, edge_k, edge_j, &mut best);
            }
        }
        if best.1 == usize::MAX {
            return None;
        }
        let (delta, lo, hi) = best;
        t[lo + 1..=hi].reverse();
        self.dirty_positions(p, t, &[lo, lo + 1, hi, hi + 1]);
        Some(delta)
    }

    /// Best or-opt move of the segment of `len` sets starting at `start`.
    fn or_move(&mut self, p: &Problem, t: &mut [u32], start: usize, len: usize) -> Option<i64> {
        let m = t.len();
        let at = |x: usize| t[wrap(x, m)];
        let s1 = at(start);
        let sl = at(start + len - 1);
        let prev = at(start + m - 1);
        let next = at(start + len);
        let last = start + len - 1;
        let remove_gain =
            self.edge[wrap(start + m - 1, m)] + self.edge[wrap(last, m)] - p.d(prev, next);
        let rev_extra = if last < m {
            self.rev_extra(start, last)
        } else {
            self.rev[m] - self.rev[start] + self.rev[last - m]
        };
        let mut best: Best = (remove_gain, usize::MAX, false, false);
        // The arcs into and out of the segment's ends as rows and columns: four of the five
        // costs of a candidate edge come from these short slices instead of scattered rows.
        let (into_s1, into_sl) = (p.col(s1), p.col(sl));
        let (from_s1, from_sl) = (p.row(s1), p.row(sl));
        // Lower bounds of the forward and reversed insertion costs plus the edge's cost, from
        // the ends' cheapest arcs: an orientation whose bound is not below the best so far is
        // not read.
        let (out_s1, out_sl) = (p.min_out[s1 as usize], p.min_out[sl as usize]);
        let kf = p.min_in[s1 as usize] + out_sl;
        let kr = p.min_in[sl as usize] + out_s1 + rev_extra;
        let k_least = kf.min(kr);
        // Inserting on edge (c, e) of cost `base`, edge q − 1 if `before` else q: the position
        // is worked out only for the chosen one.
        let eval = |c: u32, e: u32, base: i64, q: usize, before: bool, best: &mut Best| {
            let (c, e) = (c as usize, e as usize);
            // Most edges leave room for neither orientation.
            if k_least - base >= best.0 {
                return;
            }
            if kf - base < best.0 {
                let f = into_s1[c] - base;
                if f + out_sl < best.0 {
                    let f = f + from_sl[e];
                    if f < best.0 {
                        *best = (f, q, before, false);
                    }
                }
            }
            if kr - base < best.0 {
                let r = into_sl[c] - base + rev_extra;
                if r + out_s1 < best.0 {
                    let r = r + from_s1[e];
                    if r < best.0 {
                        *best = (r, q, before, true);
                    }
                }
            }
        };
        if self.nn + 1 >= m {
            // Candidate edges (t[j], t[j+1]) of the rest: j from start+len to start+m-2.
            for off in len..m - 1 {
                let j = wrap(start + off, m);
                eval(t[j], t[wrap(j + 1, m)], self.edge[j], j, false, &mut best);
            }
        } else {
            for end in [s1, sl] {
                for &y in &p.set_nbrs[p.set_of(end)][..self.nn] {
                    let l = &self.link[y as usize];
                    let q = l.pos as usize;
                    // Edges touching the segment are at offsets m − 1 and 0..len from its
                    // start; edge q − 1 = (pred(y), y) is at offset off − 1, edge q at off.
                    let off = wrap(q + m - start, m);
                    if off > len {
                        eval(l.pred, l.vert, l.ein, q, true, &mut best);
                    }
                    // len <= off < m − 1
                    if off.wrapping_sub(len) < m - 1 - len {
                        eval(l.vert, l.succ, l.eout, q, false, &mut best);
                    }
                }
            }
        }
        if best.1 == usize::MAX {
            return None;
        }
        let (ins, q, before, rev) = best;
        let j = if before { wrap(q + m - 1, m) } else { q };
        let delta = ins - remove_gain;
        // Build the new tour: rest from next ... up to t[j], segment, rest after.
        self.scratch.clear();
        let mut seg: Vec<u32> = (0..len).map(|x| at(start + x)).collect();
        if rev {
            seg.reverse();
        }
        let mut x = (start + len) % m;
        loop {
            self.scratch.push(t[x]);
            if x == j {
                self.scratch.extend_from_slice(&seg);
            }
            x = (x + 1) % m;
            if x == start {
                break;
            }
        }
        t.copy_from_slice(&self.scratch);
        // Dirty: old neighbours and new neighbours of the segment.
        let sp = p.set_of(prev);
        let sn = p.set_of(next);
        self.push(sp);
        self.push(sn);
        for &v in &seg {
            self.push(p.set_of(v));
        }
        self.push(
            p.set_of(t[(self.scratch.iter().position(|&v| v == seg[0]).unwrap() + m - 1) % m]),
        );
        self.push(
            p.set_of(
                t[(self
                    .scratch
                    .iter()
                    .position(|&v| v == seg[len - 1])
                    .unwrap()
                    + 1)
                    % m],
            ),
        );
        Some(delta)
    }
}
