//! Destroy and repair operators of the large neighbourhood search.
//!
//! **Removal** (destroy) takes `k` sets out of the tour:
//! * `Random`: uniformly random sets;
//! * `Segment`: `k` consecutive sets of the tour;
//! * `Related`: a seed set, then repeatedly a set close (by set-to-set
//!   distance) to an already removed one, picked with a randomised rank
//!   (Shaw 1998, "relatedness" removal);
//! * `Worst`: sets whose removal saves most, picked with a randomised rank
//!   (Ropke & Pisinger 2006).
//!
//! **Insertion** (repair) re-inserts the removed sets one at a time, each at
//! its cheapest position with its cheapest vertex (`O(|S|·L)` per set with
//! contiguous row/column slices). The order of the sets is one of
//! * `Random`;
//! * `Nearest` / `Farthest`: the set closest to / farthest from the partial
//!   tour first, as in GLNS's nearest/farthest insertion (the distance of a
//!   set to the tour is the precomputed set-to-set distance to the nearest
//!   set in the tour, maintained in `O(1)` per set and insertion);
//! * `Cheapest`: globally cheapest insertion first; every pending set caches
//!   its best insertion, which stays valid unless its edge was the one just
//!   split, so an insertion costs `O(k·|S|)` plus rare full re-evaluations.
//!
//! `noise > 0` perturbs every candidate insertion cost by a relative
//! uniform factor in `[0, noise)` of the tour's mean edge length
//! (randomised insertion, as in GLNS's insertion randomisation).

use rand::RngExt;
use rand::rngs::ChaCha8Rng;

use super::problem::Problem;

/// Removal operators.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Removal {
    Random,
    Segment,
    Related,
    Worst,
}

impl Removal {
    pub const ALL: [Removal; 4] = [
        Removal::Random,
        Removal::Segment,
        Removal::Related,
        Removal::Worst,
    ];
}

/// Insertion orders.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum InsertOrder {
    Random,
    Nearest,
    Farthest,
    Cheapest,
}

impl InsertOrder {
    pub const ALL: [InsertOrder; 4] = [
        InsertOrder::Random,
        InsertOrder::Nearest,
        InsertOrder::Farthest,
        InsertOrder::Cheapest,
    ];
}

/// Randomised rank in `0..len`, biased towards 0 by `power` (`power = 1`
/// is uniform).
#[inline]
fn biased_rank(rng: &mut ChaCha8Rng, len: usize, power: i32) -> usize {
    let u: f64 = rng.random();
    ((u.powi(power) * len as f64) as usize).min(len - 1)
}

/// Reusable buffers for the operators.
#[derive(Default)]
pub(crate) struct Operators {
    in_tour: Vec<bool>,
    gains: Vec<(i64, u32)>,
    mind: Vec<i64>,
    cache: Vec<(i64, u32, u32, u32)>,
    tmp: Vec<u32>,
    tpos: Vec<u32>,
    /// Neighbour-list length for insertion positions (0 = all positions).
    pub insert_nn: usize,
}

/// Cheap uniform noise in `[0, scale)` (xorshift64*), seeded from the
/// solver's generator so runs stay deterministic.
pub(crate) struct Noise {
    state: u64,
    scale: u64,
}

impl Noise {
    fn new(scale: i64, seed: u64) -> Self {
        Self {
            state: seed | 1,
            scale: scale.max(0) as u64,
        }
    }

    #[inline(always)]
    fn next(&mut self) -> i64 {
        if self.scale == 0 {
            return 0;
        }
        self.state ^= self.state >> 12;
        self.state ^= self.state << 25;
        self.state ^= self.state >> 27;
        let r = self.state.wrapping_mul(0x2545_f491_4f6c_dd1d);
        (((r >> 32) * self.scale) >> 32) as i64
    }

    /// Draws `n` values unseen: the state moves on exactly as `n` calls of `next` move it.
    #[inline]
    fn skip(&mut self, n: usize) {
        if self.scale == 0 {
            return;
        }
        for _ in 0..n {
            self.state ^= self.state >> 12;
            self.state ^= self.state << 25;
            self.state ^= self.state >> 27;
        }
    }
}

impl Operators {
    /// Removes `k` sets from `tour` with operator `op`; their ids go to
    /// `removed`.
    pub fn remove(
        &mut self,
        p: &Problem,
        tour: &mut Vec<u32>,
        k: usize,
        op: Removal,
        rng: &mut ChaCha8Rng,
        removed: &mut Vec<u32>,
    ) {
        let m = tour.len();
        let k = k.min(m.saturating_sub(1));
        removed.clear();
        if k == 0 {
            return;
        }
        self.in_tour.clear();
        self.in_tour.resize(p.m, false);
        for &v in tour.iter() {
            self.in_tour[p.set_of(v)] = true;
        }
        match op {
            Removal::Random => {
                self.tmp.clear();
                self.tmp.extend(tour.iter().map(|&v| p.set_of(v) as u32));
                for x in 0..k {
                    let y = rng.random_range(x..m);
                    self.tmp.swap(x, y);
                    removed.push(self.tmp[x]);
                }
            }
            Removal::Segment => {
                let start = rng.random_range(0..m);
                for x in 0..k {
                    removed.push(p.set_of(tour[(start + x) % m]) as u32);
                }
            }
            Removal::Related => {
                let seed = p.set_of(tour[rng.random_range(0..m)]);
                removed.push(seed as u32);
                self.in_tour[seed] = false;
                while removed.len() < k {
                    let r = removed[rng.random_range(0..removed.len())] as usize;
                    let nb = &p.set_nbrs[r];
                    let start = biased_rank(rng, nb.len(), 4);
                    let mut found = None;
                    for x in 0..nb.len() {
                        let s = nb[(start + x) % nb.len()] as usize;
                        if self.in_tour[s] {
                            found = Some(s);
                            break;
                        }
                    }
                    let s = found.expect("k < number of sets in the tour");
                    self.in_tour[s] = false;
                    removed.push(s as u32);
                }
            }
            Removal::Worst => {
                self.gains.clear();
                for i in 0..m {
                    let prev = tour[(i + m - 1) % m];
                    let v = tour[i];
                    let next = tour[(i + 1) % m];
                    let g = p.d(prev, v) + p.d(v, next) - p.d(prev, next);
                    self.gains.push((-g, p.set_of(v) as u32));
                }
                self.gains.sort_unstable();
                for _ in 0..k {
                    let r = biased_rank(rng, self.gains.len(), 3);
                    removed.push(self.gains.remove(r).1);
                }
            }
        }
        for &s in removed.iter() {
            self.in_tour[s as usize] = false;
        }
        let in_tour = &self.in_tour;
        tour.retain(|&v| in_tour[p.set_of(v)]);
    }

    /// Cheapest insertion of set `s` into `tour`: `(cost, after, vertex)`,
    /// meaning "insert `vertex` after position `after`". With `nn > 0` and a
    /// long tour, only the edges next to the `nn` nearest sets present in
    /// the tour are tried (`tpos` = position of each set, `u32::MAX` if
    /// absent).
    #[inline]
    fn best_insertion(
        p: &Problem,
        tour: &[u32],
        tpos: &[u32],
        nn: usize,
        s: usize,
        noise: &mut Noise,
    ) -> (i64, usize, u32) {
        let l = tour.len();
        let range = p.set_range(s);
        let mut best = (i64::MAX, 0usize, range.start as u32);
        if l == 0 {
            return (0, 0, range.start as u32);
        }
        let mut eval = |j: usize, best: &mut (i64, usize, u32)| {
            let a = tour[j];
            let b = tour[if j + 1 == l { 0 } else { j + 1 }];
            if let Some((c, w)) = cheapest_on_edge(p, a, b, s, best.0, noise) {
                *best = (c, j, w);
            }
        };
        if nn > 0 && l > 3 * nn {
            let mut found = 0;
            for &y in &p.set_nbrs[s] {
                let q = tpos[y as usize];
                if q != u32::MAX {
                    let q = q as usize;
                    eval(if q == 0 { l - 1 } else { q - 1 }, &mut best);
                    eval(q, &mut best);
                    found += 1;
                    if found == nn {
                        break;
                    }
                }
            }
            if found > 0 {
                return best;
            }
        }
        for j in 0..l {
            eval(j, &mut best);
        }
        best
    }

    /// Inserts `w` after position `j` and updates `tpos`.
    fn insert_at(&mut self, p: &Problem, tour: &mut Vec<u32>, j: usize, w: u32) {
        tour.insert(j + 1, w);
        for (idx, &v) in tour.iter().enumerate().skip(j + 1) {
            self.tpos[p.set_of(v)] = idx as u32;
        }
    }

    /// Inserts the sets `pending` into `tour` in the order given by `op`.
    pub fn insert(
        &mut self,
        p: &Problem,
        tour: &mut Vec<u32>,
        pending: &mut Vec<u32>,
        op: InsertOrder,
        noise: i64,
        rng: &mut ChaCha8Rng,
    ) {
        if pending.is_empty() {
            return;
        }
        let mut noise = Noise::new(noise, rng.random());
        self.tpos.clear();
        self.tpos.resize(p.m, u32::MAX);
        for (i, &v) in tour.iter().enumerate() {
            self.tpos[p.set_of(v)] = i as u32;
        }
        if tour.is_empty() {
            let x = rng.random_range(0..pending.len());
            let s = pending.swap_remove(x) as usize;
            let r = p.set_range(s);
            tour.push(rng.random_range(r.start..r.end) as u32);
            self.tpos[s] = 0;
        }
        match op {
            InsertOrder::Random => self.insert_random(p, tour, pending, rng, &mut noise),
            InsertOrder::Nearest | InsertOrder::Farthest => {
                self.insert_by_distance(p, tour, pending, op == InsertOrder::Nearest, &mut noise)
            }
            InsertOrder::Cheapest => self.insert_cheapest(p, tour, pending, &mut noise),
        }
    }

    /// The pending sets in random order, each at its cheapest place.
    fn insert_random(
        &mut self,
        p: &Problem,
        tour: &mut Vec<u32>,
        pending: &mut Vec<u32>,
        rng: &mut ChaCha8Rng,
        noise: &mut Noise,
    ) {
        let nn = self.insert_nn;
        while !pending.is_empty() {
            let x = rng.random_range(0..pending.len());
            let s = pending.swap_remove(x) as usize;
            let (_, j, w) = Self::best_insertion(p, tour, &self.tpos, nn, s, noise);
            self.insert_at(p, tour, j, w);
        }
    }

    /// The pending set nearest to (`nearest`) or farthest from the partial
    /// tour first. The distance of a set to the tour is approximated by the
    /// set-to-set distance to the nearest set in the tour.
    fn insert_by_distance(
        &mut self,
        p: &Problem,
        tour: &mut Vec<u32>,
        pending: &mut Vec<u32>,
        nearest: bool,
        noise: &mut Noise,
    ) {
        let nn = self.insert_nn;
        self.mind.clear();
        for &s in pending.iter() {
            let s = s as usize;
            let d = p.set_nbrs[s]
                .iter()
                .find(|&&y| self.tpos[y as usize] != u32::MAX)
                .map_or(0, |&y| p.set_dist[s * p.m + y as usize]);
            self.mind.push(d);
        }
        while !pending.is_empty() {
            let mut pick = 0;
            for x in 1..pending.len() {
                let better = if nearest {
                    self.mind[x] < self.mind[pick]
                } else {
                    self.mind[x] > self.mind[pick]
                };
                if better {
                    pick = x;
                }
            }
            let s = pending.swap_remove(pick) as usize;
            self.mind.swap_remove(pick);
            let (_, j, w) = Self::best_insertion(p, tour, &self.tpos, nn, s, noise);
            self.insert_at(p, tour, j, w);
            let row = &p.set_dist[s * p.m..(s + 1) * p.m];
            for (x, &r) in pending.iter().enumerate() {
                self.mind[x] = self.mind[x].min(row[r as usize]);
            }
        }
    }

    /// Globally cheapest insertion first. Every pending set caches its best
    /// insertion `(cost, vertex, a, b)` on edge `a → b`; after an insertion
    /// splits edge `a → b` only the sets cached on it are re-evaluated in
    /// full, the others try just the two new edges.
    fn insert_cheapest(
        &mut self,
        p: &Problem,
        tour: &mut Vec<u32>,
        pending: &mut Vec<u32>,
        noise: &mut Noise,
    ) {
        let nn = self.insert_nn;
        self.cache.clear();
        for &s in pending.iter() {
            let (c, j, w) = Self::best_insertion(p, tour, &self.tpos, nn, s as usize, noise);
            let a = tour[j];
            let b = tour[(j + 1) % tour.len()];
            self.cache.push((c, w, a, b));
        }
        while !pending.is_empty() {
            let mut pick = 0;
            for x in 1..pending.len() {
                if self.cache[x].0 < self.cache[pick].0 {
                    pick = x;
                }
            }
            pending.swap_remove(pick);
            let (_, w, a, b) = self.cache.swap_remove(pick);
            let j = self.tpos[p.set_of(a)] as usize;
            self.insert_at(p, tour, j, w);
            for (x, &s) in pending.iter().enumerate() {
                let s = s as usize;
                let e = self.cache[x];
                self.cache[x] = if e.2 == a && e.3 == b {
                    let (c, j, w2) = Self::best_insertion(p, tour, &self.tpos, nn, s, noise);
                    (c, w2, tour[j], tour[(j + 1) % tour.len()])
                } else {
                    let mut best = e;
                    for (ea, eb) in [(a, w), (w, b)] {
                        if let Some((c, v)) = cheapest_on_edge(p, ea, eb, s, best.0, noise) {
                            best = (c, v, ea, eb);
                        }
                    }
                    best
                };
            }
        }
    }
}

/// The cheapest vertex of set `s` to insert on edge `a → b` when it costs
/// less than `bound`: `(cost, vertex)`; the first such vertex on ties. Every
/// vertex of the set draws one noise value.
#[inline]
fn cheapest_on_edge(
    p: &Problem,
    a: u32,
    b: u32,
    s: usize,
    bound: i64,
    noise: &mut Noise,
) -> Option<(i64, u32)> {
    let range = p.set_range(s);
    let base = p.d(a, b);
    // Noise is never negative, so no vertex costs less than this here; the set's draws are
    // still made, so that the noise of later candidates stays the same.
    if p.set_min_through[s] - base >= bound {
        noise.skip(range.len());
        return None;
    }
    let ra = &p.row(a)[range.clone()];
    let cb = &p.col(b)[range.clone()];
    let mut best = None;
    let mut bound = bound;
    for (x, (ca, cbv)) in ra.iter().zip(cb).enumerate() {
        let c = ca + cbv - base + noise.next();
        if c < bound {
            bound = c;
            best = Some((c, range.start as u32 + x as u32));
        }
    }
    best
}
