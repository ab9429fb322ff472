//! A small directed graph in compressed rows and a reusable Dijkstra over it.

use super::super::dijkstra::Entry;
use std::collections::BinaryHeap;

/// Edges as they are added; [`finish`](Self::finish) sorts them into rows.
pub(super) struct Graph {
    nodes: usize,
    edges: Vec<(u32, u32, f64)>,
}

/// The graph in compressed rows: `targets[start[u]..start[u + 1]]` are the edges leaving `u`.
pub(super) struct Csr {
    start: Vec<usize>,
    targets: Vec<(u32, f64)>,
}

impl Graph {
    pub(super) fn new(nodes: usize) -> Self {
        Self {
            nodes,
            edges: Vec::new(),
        }
    }

    /// Adds `u → v` at `cost`; non-finite costs (no path) are left out.
    pub(super) fn edge(&mut self, u: usize, v: usize, cost: f64) {
        if cost.is_finite() && u != v {
            self.edges.push((u as u32, v as u32, cost));
        }
    }

    pub(super) fn finish(mut self) -> Csr {
        // Stable: edges of one node keep the order they were added in.
        self.edges.sort_by_key(|e| e.0);
        let mut start = vec![0usize; self.nodes + 1];
        for e in &self.edges {
            start[e.0 as usize + 1] += 1;
        }
        for k in 0..self.nodes {
            start[k + 1] += start[k];
        }
        Csr {
            start,
            targets: self.edges.iter().map(|e| (e.1, e.2)).collect(),
        }
    }
}

/// Dijkstra's buffers, kept between searches.
#[derive(Default)]
pub(super) struct Search {
    dist: Vec<f64>,
    heap: BinaryHeap<Entry>,
}

impl Search {
    /// From `source` until `left` nodes of `wanted` (a range of nodes) are settled or nothing
    /// is left to settle; costs of nodes not settled by then are upper bounds or `+∞`.
    pub(super) fn run(
        &mut self,
        g: &Csr,
        source: usize,
        wanted: std::ops::Range<usize>,
        mut left: usize,
    ) {
        let n = g.start.len() - 1;
        self.dist.clear();
        self.dist.resize(n, f64::INFINITY);
        self.heap.clear();
        self.dist[source] = 0.0;
        self.heap.push(Entry {
            key: 0.0,
            idx: source as u32,
        });
        while let Some(Entry { key: du, idx: u }) = self.heap.pop() {
            let u = u as usize;
            if du > self.dist[u] {
                continue;
            }
            if wanted.contains(&u) {
                left = left.saturating_sub(1);
                if left == 0 {
                    return;
                }
            }
            for &(v, c) in &g.targets[g.start[u]..g.start[u + 1]] {
                let nd = du + c;
                if nd < self.dist[v as usize] {
                    self.dist[v as usize] = nd;
                    self.heap.push(Entry { key: nd, idx: v });
                }
            }
        }
    }

    /// Cost from the last source to `v` (`+∞` when unreachable).
    pub(super) fn dist(&self, v: usize) -> f64 {
        self.dist[v]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shortest_costs_on_a_small_graph() {
        let mut g = Graph::new(4);
        g.edge(0, 1, 1.0);
        g.edge(1, 2, 1.0);
        g.edge(0, 2, 5.0);
        g.edge(2, 0, f64::INFINITY);
        let g = g.finish();
        let mut s = Search::default();
        s.run(&g, 0, 0..4, 4);
        assert_eq!((s.dist(1), s.dist(2), s.dist(3)), (1.0, 2.0, f64::INFINITY));
        s.run(&g, 2, 0..4, 4);
        assert_eq!(s.dist(0), f64::INFINITY);
        // Stops once node 1 is settled: node 2 keeps the upper bound 5 from node 0.
        s.run(&g, 0, 1..2, 1);
        assert_eq!((s.dist(1), s.dist(2)), (1.0, 5.0));
    }
}
