//! Dijkstra with the symmetric edge cost of Prágr19 Eq. 14, on a [`CostGrid`] of predicted
//! traversal costs (the cost map Mcost of the `rbcm-greedy` explorer).
//!
//! Eq. 14: c(ν_i, ν_j) = ‖ν_i, ν_j‖ · (μ(ν_i) + μ(ν_j)) / 2, so unlike the source-cell cost of
//! decision 21 ([`super::Dijkstra`]) a move costs the same both ways. Moves follow Eq. 1 of Prágr22
//! and the same corner rule as [`super::Dijkstra`]: a diagonal move is forbidden when both side
//! cells are inadmissible. Mcost is small (about a thousand 10 cm cells on `lab-track`), so a plain
//! binary heap is enough; the buffers are kept between searches so repeated plans allocate
//! nothing once warm. Ties are broken by cell index, so results are deterministic.

use super::cost_grid::CostGrid;
use super::dijkstra::{Entry, NO_PRED, SearchError};
use std::collections::BinaryHeap;
use strider_core::Cell;
use strider_core::grid::NEIGHBOURS8;

/// Reusable single-source search under the Eq. 14 edge cost. After [`run`](Self::run) every
/// cell reachable from the source is settled with its exact cost.
#[derive(Clone, Debug, Default)]
pub struct MeanEdgeDijkstra {
    dist: Vec<f64>,
    pred: Vec<u32>,
    heap: BinaryHeap<Entry>,
    grid_id: Option<u64>,
    width: usize,
    rect_origin: Cell,
}

impl MeanEdgeDijkstra {
    /// An empty search.
    pub fn new() -> Self {
        Self::default()
    }

    /// Cheapest costs from `source` to every cell of `grid` under Eq. 14.
    pub fn run(&mut self, grid: &CostGrid, source: Cell) -> Result<(), SearchError> {
        let rect = grid.rect();
        let Some(s) = rect.index(source) else {
            return Err(SearchError::SourceOutside(source));
        };
        if grid.len() >= u32::MAX as usize {
            return Err(SearchError::GridTooLarge);
        }
        let cost = grid.costs();
        if !cost[s].is_finite() {
            return Err(SearchError::SourceInadmissible(source));
        }
        let (w, h) = (rect.width as i64, rect.height as i64);
        self.width = rect.width as usize;
        self.rect_origin = rect.cell(0);
        self.grid_id = Some(grid.id());
        self.dist.clear();
        self.dist.resize(cost.len(), f64::INFINITY);
        self.pred.clear();
        self.pred.resize(cost.len(), NO_PRED);
        self.heap.clear();
        let d = grid.cell_size();
        let free = |i: i64, j: i64| {
            i >= 0 && j >= 0 && i < w && j < h && cost[(j * w + i) as usize].is_finite()
        };
        self.dist[s] = 0.0;
        self.heap.push(Entry {
            key: 0.0,
            idx: s as u32,
        });
        while let Some(Entry { key, idx }) = self.heap.pop() {
            let k = idx as usize;
            if key > self.dist[k] {
                continue; // stale duplicate
            }
            let (i, j) = ((k % self.width) as i64, (k / self.width) as i64);
            let ck = cost[k] as f64;
            for &(di, dj) in &NEIGHBOURS8 {
                let (di, dj) = (di as i64, dj as i64);
                let (ni, nj) = (i + di, j + dj);
                if !free(ni, nj) {
                    continue;
                }
                let diagonal = di != 0 && dj != 0;
                if diagonal && !free(i + di, j) && !free(i, j + dj) {
                    continue; // corner rule
                }
                let n = (nj * w + ni) as usize;
                let len = if diagonal {
                    d * std::f64::consts::SQRT_2
                } else {
                    d
                };
                let nd = key + len * 0.5 * (ck + cost[n] as f64); // Eq. 14
                if nd < self.dist[n] {
                    self.dist[n] = nd;
                    self.pred[n] = idx;
                    self.heap.push(Entry {
                        key: nd,
                        idx: n as u32,
                    });
                }
            }
        }
        Ok(())
    }

    /// The cost of the cheapest path from the last source to `c`; `None` when `c` is outside
    /// the grid of the last search or unreachable.
    pub fn cost(&self, c: Cell) -> Option<f64> {
        let k = self.index(c)?;
        let v = self.dist[k];
        v.is_finite().then_some(v)
    }

    /// The cheapest path from the last source to `goal`, source first; `None` when unreachable.
    pub fn path_to(&self, goal: Cell) -> Option<Vec<Cell>> {
        let mut k = self.index(goal)?;
        if !self.dist[k].is_finite() {
            return None;
        }
        let mut out = vec![goal];
        while self.pred[k] != NO_PRED {
            k = self.pred[k] as usize;
            out.push(self.cell(k));
        }
        out.reverse();
        Some(out)
    }

    fn index(&self, c: Cell) -> Option<usize> {
        self.grid_id?;
        let (i, j) = (c.i - self.rect_origin.i, c.j - self.rect_origin.j);
        if i < 0 || j < 0 || i as usize >= self.width {
            return None;
        }
        let k = j as usize * self.width + i as usize;
        (k < self.dist.len()).then_some(k)
    }

    fn cell(&self, k: usize) -> Cell {
        Cell::new(
            self.rect_origin.i + (k % self.width) as i32,
            self.rect_origin.j + (k / self.width) as i32,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use strider_core::CellRect;

    fn grid(w: u32, h: u32, cost: Vec<f32>) -> CostGrid {
        CostGrid::new(CellRect::new(Cell::new(0, 0), w, h), 0.1, cost).unwrap()
    }

    #[test]
    fn uniform_grid_costs_are_octile_lengths() {
        let g = grid(5, 5, vec![2.0; 25]);
        let mut s = MeanEdgeDijkstra::new();
        s.run(&g, Cell::new(0, 0)).unwrap();
        let c = s.cost(Cell::new(4, 2)).unwrap();
        let expect = 2.0 * 0.1 * (2.0 + 2.0 * std::f64::consts::SQRT_2);
        assert!((c - expect).abs() < 1e-9, "{c} vs {expect}");
        let p = s.path_to(Cell::new(4, 2)).unwrap();
        assert_eq!(p.first(), Some(&Cell::new(0, 0)));
        assert_eq!(p.last(), Some(&Cell::new(4, 2)));
    }

    #[test]
    fn edge_cost_is_symmetric() {
        // A 1-D strip with rising costs: cost a→b equals b→a under Eq. 14.
        let g = grid(6, 1, vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0]);
        let mut s = MeanEdgeDijkstra::new();
        s.run(&g, Cell::new(0, 0)).unwrap();
        let ab = s.cost(Cell::new(5, 0)).unwrap();
        s.run(&g, Cell::new(5, 0)).unwrap();
        let ba = s.cost(Cell::new(0, 0)).unwrap();
        assert!((ab - ba).abs() < 1e-12);
        // Σ (c_k + c_{k+1}) / 2 · d = (1.5 + 2.5 + 3.5 + 4.5 + 5.5) · 0.1
        assert!((ab - 1.75).abs() < 1e-9, "{ab}");
    }

    #[test]
    fn walls_and_corners_block() {
        // Wall at i = 2 except a gap at j = 4; the diagonal squeeze through (1,1)-(2,2) style
        // corners between two inadmissible cells is not allowed.
        let inf = f32::INFINITY;
        let mut c = vec![1.0f32; 25];
        for j in 0..4 {
            c[j * 5 + 2] = inf;
        }
        let g = grid(5, 5, c);
        let mut s = MeanEdgeDijkstra::new();
        s.run(&g, Cell::new(0, 0)).unwrap();
        let p = s.path_to(Cell::new(4, 0)).unwrap();
        assert!(p.iter().all(|q| g.is_admissible(*q)));
        assert!(p.iter().any(|q| q.j == 4));
        assert!(s.cost(Cell::new(2, 0)).is_none());
        assert!(s.run(&g, Cell::new(2, 0)).is_err());
        assert!(s.run(&g, Cell::new(9, 9)).is_err());
        assert!(s.cost(Cell::new(-1, 0)).is_none());
    }
}
