//! Cost matrix between a set of sites: one early-exit Dijkstra per site (decision 23), run in
//! parallel with rayon, each block of sites reusing one [`Dijkstra`]'s buffers.
//!
//! Entry `(a, b)` is C(ψ*(site_a, site_b)) of `001` Eq. 2 under the source-cell edge cost of
//! decision 21, so the matrix is **not** symmetric in general. The diagonal is 0. A pair without
//! a path (blocked, or either site outside the grid or inadmissible) is `f64::INFINITY`; nothing
//! here panics on such input.

use super::cost_grid::CostGrid;
use super::dijkstra::Dijkstra;
use rayon::prelude::*;
use strider_core::Cell;

/// Dense row-major `n × n` matrix of path costs between sites.
#[derive(Clone, Debug, PartialEq)]
pub struct SiteCosts {
    n: usize,
    data: Vec<f64>,
}

impl SiteCosts {
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

/// Costs between all ordered pairs of `sites` on `grid`. Sites are split into a few contiguous
/// blocks per rayon thread; each block runs its searches on one [`Dijkstra`], so its buffers and
/// the grid's move masks are built once per block, not per site. The result does not depend on
/// the thread count.
pub fn all_pairs(grid: &CostGrid, sites: &[Cell]) -> SiteCosts {
    let n = sites.len();
    if n == 0 {
        return SiteCosts {
            n,
            data: Vec::new(),
        };
    }
    let blocks = rayon::current_num_threads().max(1) * 4;
    let chunk = n.div_ceil(blocks).max(1);
    // The grid's move masks are built once and copied into each block's search.
    let mut proto = Dijkstra::new();
    proto.prepare(grid);
    let parts: Vec<Vec<f64>> = sites
        .par_chunks(chunk)
        .enumerate()
        .map(|(ci, block)| {
            let mut dj = proto.clone();
            let mut out = Vec::with_capacity(block.len() * n);
            let mut row = Vec::with_capacity(n);
            let mut pending = Vec::with_capacity(n);
            for (k, &s) in block.iter().enumerate() {
                if dj.row_into(grid, s, sites, &mut pending, &mut row).is_err() {
                    row.clear();
                    row.resize(n, f64::INFINITY);
                }
                row[ci * chunk + k] = 0.0;
                out.extend_from_slice(&row);
            }
            out
        })
        .collect();
    SiteCosts {
        n,
        data: parts.concat(),
    }
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
