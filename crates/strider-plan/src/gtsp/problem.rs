//! Internal, solver-friendly form of an instance.
//!
//! Vertices are renumbered so that every set is a contiguous range
//! `set_start[s]..set_start[s + 1]` of "internal" vertices; vertices in no
//! set are dropped. The cost matrix is copied into that numbering (row-major,
//! plus its transpose when asymmetric, so that both "costs out of `u`" and
//! "costs into `v`" over a set are contiguous slices). Restrictions of the
//! parameters are applied here:
//!
//! * `open = Some(s)`: the set of `s` is reduced to `{s}` and every arc into
//!   `s` costs 0, so a closed tour of the internal problem is an open path
//!   from `s` in the original one;
//! * `fixed_start = Some(s)`: the set of `s` is reduced to `{s}`.

use rayon::prelude::*;

use super::instance::{Instance, is_symmetric, transpose};

pub(crate) struct Problem {
    /// Number of sets.
    pub m: usize,
    /// Number of internal vertices.
    pub nv: usize,
    /// Set `s` is `set_start[s]..set_start[s + 1]`.
    pub set_start: Vec<u32>,
    /// Set of each internal vertex.
    pub set_of: Vec<u32>,
    /// Original vertex of each internal vertex.
    pub orig: Vec<usize>,
    /// Row-major costs, `d[u * nv + v]`.
    d: Vec<i64>,
    /// Transposed costs `dt[v * nv + u] = d(u, v)` (empty when symmetric).
    dt: Vec<i64>,
    /// True if the internal matrix is symmetric.
    pub symmetric: bool,
    /// Internal vertex that every tour must contain and is reported first
    /// (open start or fixed start).
    pub anchor: Option<u32>,
    /// Symmetrised set-to-set distance `min over u in A, v in B of
    /// min(d(u,v), d(v,u))`, row-major `m x m`.
    pub set_dist: Vec<i64>,
    /// For each set, the other sets sorted by `set_dist`.
    pub set_nbrs: Vec<Vec<u32>>,
    /// Cheapest arc into each vertex from a vertex of another set.
    pub min_in: Vec<i64>,
    /// Cheapest arc out of each vertex to a vertex of another set.
    pub min_out: Vec<i64>,
    /// For each set, the least `min_in + min_out` of its vertices: no insertion of the set on
    /// an edge of cost `c` costs less than this minus `c`.
    pub set_min_through: Vec<i64>,
}

impl Problem {
    /// Largest number of vertices (one per set) whose tables fit
    /// [`crate::MEMORY_LIMIT_BYTES`]: 28 bytes per vertex pair, see [`Problem::estimate_bytes`].
    pub fn max_vertices() -> u64 {
        (crate::memory::MEMORY_LIMIT_BYTES / 28).isqrt()
    }

    /// Bytes of the tables [`Problem::new`] allocates for `inst` (`None` on overflow): the
    /// renumbered matrix and its transpose (8 bytes per vertex pair each), the set-to-set
    /// distances (8 bytes per set pair) and neighbour lists (4 bytes per set pair).
    pub fn estimate_bytes(inst: &Instance) -> Option<u64> {
        let nv = inst
            .sets
            .iter()
            .try_fold(0u64, |a, s| a.checked_add(s.len() as u64))?;
        let m = inst.sets.len() as u64;
        let vertex_tables = nv.checked_mul(nv)?.checked_mul(16)?;
        let set_tables = m.checked_mul(m)?.checked_mul(12)?;
        vertex_tables.checked_add(set_tables)
    }

    /// Builds the internal problem. `anchor` is the original vertex that is
    /// fixed (its set reduced to it), and `open` zeroes the arcs into it.
    pub fn new(inst: &Instance, anchor: Option<usize>, open: bool) -> Self {
        let m = inst.sets.len();
        let mut set_start = Vec::with_capacity(m + 1);
        let mut set_of = Vec::new();
        let mut orig = Vec::new();
        let owner = anchor.map(|a| inst.sets.iter().position(|s| s.contains(&a)));
        let anchor_set = owner.flatten();
        let mut anchor_int = None;
        for (s, set) in inst.sets.iter().enumerate() {
            set_start.push(orig.len() as u32);
            if Some(s) == anchor_set {
                let a = anchor.unwrap();
                anchor_int = Some(orig.len() as u32);
                orig.push(a);
                set_of.push(s as u32);
            } else {
                for &v in set {
                    orig.push(v);
                    set_of.push(s as u32);
                }
            }
        }
        set_start.push(orig.len() as u32);
        let nv = orig.len();
        let mut d = vec![0i64; nv * nv];
        for (i, &u) in orig.iter().enumerate() {
            let row = inst.dist.row(u);
            for (j, &v) in orig.iter().enumerate() {
                d[i * nv + j] = if i == j { 0 } else { row[v] };
            }
        }
        if open && let Some(a) = anchor_int {
            for i in 0..nv {
                d[i * nv + a as usize] = 0;
            }
        }
        let symmetric = is_symmetric(&d, nv);
        let dt = if symmetric {
            Vec::new()
        } else {
            transpose(&d, nv)
        };
        let mut p = Self {
            m,
            nv,
            set_start,
            set_of,
            orig,
            d,
            dt,
            symmetric,
            anchor: anchor_int,
            set_dist: Vec::new(),
            set_nbrs: Vec::new(),
            min_in: Vec::new(),
            min_out: Vec::new(),
            set_min_through: Vec::new(),
        };
        p.build_set_distances();
        p.build_min_arcs();
        p
    }

    fn build_min_arcs(&mut self) {
        let min_off_set = |costs: &[i64], own: std::ops::Range<usize>| {
            let (before, rest) = costs.split_at(own.start);
            let after = &rest[own.len()..];
            before
                .iter()
                .chain(after)
                .copied()
                .min()
                .unwrap_or(i64::MAX)
        };
        let (mut min_in, mut min_out) = (Vec::with_capacity(self.nv), Vec::with_capacity(self.nv));
        for v in 0..self.nv as u32 {
            let own = self.set_range(self.set_of(v));
            min_in.push(min_off_set(self.col(v), own.clone()));
            min_out.push(min_off_set(self.row(v), own));
        }
        self.set_min_through = (0..self.m)
            .map(|s| {
                self.set_range(s)
                    .map(|v| min_in[v].saturating_add(min_out[v]))
                    .min()
                    .unwrap_or(i64::MAX)
            })
            .collect();
        self.min_in = min_in;
        self.min_out = min_out;
    }

    fn build_set_distances(&mut self) {
        let m = self.m;
        let mut sd = vec![0i64; m * m];
        for a in 0..m {
            for b in a + 1..m {
                let mut best = i64::MAX;
                for u in self.set(a) {
                    let ru = self.row(u);
                    let cu = self.col(u);
                    for v in self.set_range(b) {
                        best = best.min(ru[v].min(cu[v]));
                    }
                }
                sd[a * m + b] = best;
                sd[b * m + a] = best;
            }
        }
        // Keys (distance, set) are distinct, so the unstable sort gives the one order.
        let nbrs = (0..m)
            .into_par_iter()
            .map(|a| {
                let row = &sd[a * m..(a + 1) * m];
                let mut keyed: Vec<(i64, u32)> = (0..m as u32)
                    .filter(|&b| b as usize != a)
                    .map(|b| (row[b as usize], b))
                    .collect();
                keyed.sort_unstable();
                keyed.into_iter().map(|(_, b)| b).collect()
            })
            .collect();
        self.set_dist = sd;
        self.set_nbrs = nbrs;
    }

    /// Cost of the arc `u -> v` (internal vertices).
    #[inline(always)]
    pub fn d(&self, u: u32, v: u32) -> i64 {
        self.d[u as usize * self.nv + v as usize]
    }

    /// Costs of the arcs out of `u`, indexed by internal vertex.
    #[inline(always)]
    pub fn row(&self, u: u32) -> &[i64] {
        let s = u as usize * self.nv;
        &self.d[s..s + self.nv]
    }

    /// Costs of the arcs into `v`, indexed by internal vertex.
    #[inline(always)]
    pub fn col(&self, v: u32) -> &[i64] {
        let s = v as usize * self.nv;
        if self.symmetric {
            &self.d[s..s + self.nv]
        } else {
            &self.dt[s..s + self.nv]
        }
    }

    /// Internal vertices of set `s`.
    #[inline(always)]
    pub fn set(&self, s: usize) -> std::ops::Range<u32> {
        self.set_start[s]..self.set_start[s + 1]
    }

    /// Internal vertices of set `s` as a `usize` range.
    #[inline(always)]
    pub fn set_range(&self, s: usize) -> std::ops::Range<usize> {
        self.set_start[s] as usize..self.set_start[s + 1] as usize
    }

    /// Size of set `s`.
    #[inline(always)]
    pub fn set_size(&self, s: usize) -> usize {
        (self.set_start[s + 1] - self.set_start[s]) as usize
    }

    /// Set of internal vertex `v`.
    #[inline(always)]
    pub fn set_of(&self, v: u32) -> usize {
        self.set_of[v as usize] as usize
    }

    /// Cost of the closed tour.
    pub fn tour_cost(&self, t: &[u32]) -> i64 {
        if t.len() < 2 {
            return 0;
        }
        let mut c = self.d(t[t.len() - 1], t[0]);
        for w in t.windows(2) {
            c += self.d(w[0], w[1]);
        }
        c
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gtsp::CostMatrix;
    use crate::memory;

    #[test]
    fn the_estimate_counts_vertex_and_set_tables_and_is_checked() {
        let n = 30_000usize;
        // Only the sets matter to the estimate; no 30 000² matrix is built.
        let inst = Instance {
            name: "big".into(),
            n,
            sets: (0..n).map(|v| vec![v]).collect(),
            dist: CostMatrix::from_fn(0, |_, _| 0),
            symmetric: true,
        };
        let nn = (n * n) as u64;
        assert_eq!(Problem::estimate_bytes(&inst), Some(nn * 16 + nn * 12));
        let e = memory::check(Problem::estimate_bytes(&inst), "solving", "use fewer").unwrap_err();
        assert_eq!(e.needed, nn * 28);
        assert_eq!(e.limit, memory::MEMORY_LIMIT_BYTES);
    }
}
