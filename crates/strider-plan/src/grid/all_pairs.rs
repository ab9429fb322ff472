//! Cost matrix between a set of sites: one early-exit Dijkstra per site (decision 23), run in
//! parallel with rayon, each worker reusing one [`Dijkstra`]'s buffers for all its sites.
//!
//! Entry `(a, b)` is C(ψ*(site_a, site_b)) of Prágr22 Eq. 2 under the source-cell edge cost of
//! decision 21, so the matrix is **not** symmetric in general. The diagonal is 0. A pair without
//! a path (blocked, or either site outside the grid or inadmissible) is `f64::INFINITY`; nothing
//! here panics on such input.

use super::cost_grid::CostGrid;
use super::dijkstra::Dijkstra;
use rayon::prelude::*;
use std::sync::atomic::{AtomicUsize, Ordering as AtomicOrdering};
use strider_core::Cell;

/// Dense row-major `n × n` matrix of path costs between sites.
#[derive(Clone, Debug, PartialEq)]
pub struct SiteCosts {
    n: usize,
    data: Vec<f64>,
}

impl SiteCosts {
    /// A matrix from its `n × n` row-major entries.
    pub(crate) fn from_rows(n: usize, data: Vec<f64>) -> Self {
        debug_assert_eq!(data.len(), n * n);
        Self { n, data }
    }

    /// Number of sites.
    pub fn len(&self) -> usize {
        self.n
    }

    /// True when there are no sites.
    pub fn is_empty(&self) -> bool {
        self.n == 0
    }

    /// Cost from site `a` to site `b` (`+∞` when unreachable). Panics if an index is `≥ len()`.
    pub fn get(&self, a: usize, b: usize) -> f64 {
        assert!(a < self.n && b < self.n, "site index out of range");
        self.data[a * self.n + b]
    }

    /// Row `a`: costs from site `a` to every site.
    pub fn row(&self, a: usize) -> &[f64] {
        &self.data[a * self.n..(a + 1) * self.n]
    }

    /// Row-major data.
    pub fn as_slice(&self) -> &[f64] {
        &self.data
    }

    /// All ordered pairs `(a, b)`, `a ≠ b`, with no path, in row-major order.
    pub fn unreachable_pairs(&self) -> Vec<(usize, usize)> {
        (0..self.n)
            .flat_map(|a| (0..self.n).map(move |b| (a, b)))
            .filter(|&(a, b)| a != b && !self.data[a * self.n + b].is_finite())
            .collect()
    }
}

/// Costs between all ordered pairs of `sites` on `grid`. One worker per rayon thread takes
/// sites one at a time from a shared counter and runs their searches on its own [`Dijkstra`],
/// so buffers and the grid's move masks are built once per worker, not per site, and the
/// workers finish within about one search of each other (fixed blocks of sites could leave one
/// thread idle for a whole block). The result does not depend on the thread count.
pub fn all_pairs(grid: &CostGrid, sites: &[Cell]) -> SiteCosts {
    let n = sites.len();
    if n == 0 {
        return SiteCosts {
            n,
            data: Vec::new(),
        };
    }
    // The move masks are built once here and copied into each worker's search. Each row
    // depends only on its site, so the result does not depend on the schedule; a worker that
    // starts late (a busy pool) simply finds fewer sites left.
    let workers = rayon::current_num_threads().clamp(1, n);
    let mut proto = Dijkstra::new();
    proto.prepare(grid);
    let next = AtomicUsize::new(0);
    // Per worker: the sites it took, in order, and their rows back to back.
    let parts: Vec<(Vec<usize>, Vec<f64>)> = (0..workers)
        .into_par_iter()
        .map(|_| {
            let mut dj = proto.clone();
            let mut pending = Vec::with_capacity(n);
            let mut row = Vec::with_capacity(n);
            let (mut taken, mut rows) = (Vec::new(), Vec::new());
            loop {
                let a = next.fetch_add(1, AtomicOrdering::Relaxed);
                if a >= n {
                    break;
                }
                if dj
                    .row_into(grid, sites[a], sites, &mut pending, &mut row)
                    .is_err()
                {
                    row.clear();
                    row.resize(n, f64::INFINITY);
                }
                row[a] = 0.0;
                taken.push(a);
                rows.extend_from_slice(&row);
            }
            (taken, rows)
        })
        .collect();
    let mut data = vec![f64::INFINITY; n * n];
    for (taken, rows) in &parts {
        for (&a, row) in taken.iter().zip(rows.chunks_exact(n)) {
            data[a * n..(a + 1) * n].copy_from_slice(row);
        }
    }
    SiteCosts { n, data }
}

#[cfg(test)]
mod tests {
    use super::*;
    use strider_core::CellRect;

    #[test]
    fn bad_sites_are_infinite() {
        let inf = f32::INFINITY;
        let g = CostGrid::new(
            CellRect::new(Cell::new(0, 0), 3, 1),
            1.0,
            vec![1.0, 2.0, inf],
        )
        .unwrap();
        let sites = [
            Cell::new(0, 0),
            Cell::new(1, 0),
            Cell::new(2, 0),
            Cell::new(7, 7),
        ];
        let m = all_pairs(&g, &sites);
        assert_eq!(m.get(0, 1), 1.0);
        assert_eq!(m.get(1, 0), 2.0);
        assert_eq!(m.get(2, 2), 0.0);
        assert_eq!(m.get(0, 2), f64::INFINITY);
        assert_eq!(m.get(3, 0), f64::INFINITY);
        assert_eq!(m.unreachable_pairs().len(), 12 - 2);
        assert!(all_pairs(&g, &[]).is_empty());
    }
}
