//! Exact solver for small instances: Held–Karp dynamic programming over sets.
//!
//! Held & Karp, "A dynamic programming approach to sequencing problems",
//! J. SIAM 10(1), 1962, generalised to sets (as in Noon & Bean 1991): fix
//! the smallest set `S0` as the start; for every start vertex `a ∈ S0`,
//! `f[M][v]` is the cheapest path from `a` through exactly the sets of the
//! mask `M` (over the other `m - 1` sets) ending at vertex `v` of a set in
//! `M`. The answer is `min_a min_v f[all][v] + d(v, a)`.
//! Time `O(|S0| · 2^(m-1) · |V|²)`, memory `O(2^(m-1) · |V|)`.

use super::problem::Problem;

/// Estimated number of inner-loop operations of [`solve`].
pub(crate) fn work(p: &Problem) -> f64 {
    if p.m < 2 {
        return 0.0;
    }
    let smin = (0..p.m).map(|s| p.set_size(s)).min().unwrap_or(1);
    smin as f64 * 2f64.powi(p.m as i32 - 1) * (p.nv as f64) * (p.nv as f64)
}

/// Optimal closed tour (internal vertices) and its cost. Requires
/// `m <= 25` (practically much less: see [`work`]).
pub(crate) fn solve(p: &Problem) -> (Vec<u32>, i64) {
    let m = p.m;
    if m == 0 {
        return (Vec::new(), 0);
    }
    if m == 1 {
        return (vec![p.set_start[0]], 0);
    }
    assert!(m <= 25, "exact solver is limited to 25 sets");
    let s0 = (0..m).min_by_key(|&s| (p.set_size(s), s)).unwrap();
    // Other sets, re-indexed 0..m-1 as bits.
    let others: Vec<usize> = (0..m).filter(|&s| s != s0).collect();
    let k = others.len();
    let full = (1usize << k) - 1;
    // Local vertex index: vertices of the other sets, contiguous per bit.
    let mut verts: Vec<u32> = Vec::new();
    let mut bit_range = Vec::with_capacity(k);
    for &s in &others {
        let lo = verts.len();
        verts.extend(p.set(s));
        bit_range.push(lo..verts.len());
    }
    let nl = verts.len();
    let mut f = vec![i64::MAX; (full + 1) * nl];
    let mut best = (i64::MAX, 0u32, Vec::new());
    for a in p.set(s0) {
        f.fill(i64::MAX);
        for (b, r) in bit_range.iter().enumerate() {
            for li in r.clone() {
                f[(1 << b) * nl + li] = p.d(a, verts[li]);
            }
        }
        for mask in 1..=full {
            let base = mask * nl;
            for (b, r) in bit_range.iter().enumerate() {
                if mask & (1 << b) == 0 {
                    continue;
                }
                for li in r.clone() {
                    let cur = f[base + li];
                    if cur == i64::MAX {
                        continue;
                    }
                    let row = p.row(verts[li]);
                    for (b2, r2) in bit_range.iter().enumerate() {
                        if mask & (1 << b2) != 0 {
                            continue;
                        }
                        let nb = (mask | (1 << b2)) * nl;
                        for lj in r2.clone() {
                            let c = cur + row[verts[lj] as usize];
                            if c < f[nb + lj] {
                                f[nb + lj] = c;
                            }
                        }
                    }
                }
            }
        }
        let mut best_end = (i64::MAX, 0);
        for li in 0..nl {
            let c = f[full * nl + li];
            if c != i64::MAX {
                let t = c + p.d(verts[li], a);
                if t < best_end.0 {
                    best_end = (t, li);
                }
            }
        }
        if best_end.0 < best.0 {
            // Reconstruct backwards.
            let mut tour = Vec::with_capacity(m);
            let mut mask = full;
            let mut li = best_end.1;
            loop {
                tour.push(verts[li]);
                let b = bit_range.iter().position(|r| r.contains(&li)).unwrap();
                let prev_mask = mask & !(1 << b);
                if prev_mask == 0 {
                    break;
                }
                let target = f[mask * nl + li];
                let v = verts[li];
                let mut found = None;
                'outer: for (b2, r2) in bit_range.iter().enumerate() {
                    if prev_mask & (1 << b2) == 0 {
                        continue;
                    }
                    for lj in r2.clone() {
                        let c = f[prev_mask * nl + lj];
                        if c != i64::MAX && c + p.d(verts[lj], v) == target {
                            found = Some(lj);
                            break 'outer;
                        }
                    }
                }
                li = found.expect("Held-Karp predecessor");
                mask = prev_mask;
            }
            tour.push(a);
            tour.reverse();
            best = (best_end.0, a, tour);
        }
    }
    (best.2, best.0)
}
