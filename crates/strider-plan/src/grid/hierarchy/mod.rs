//! Site costs that grow with the sites and the frontier, not with the map: a two-level graph in
//! the manner of hierarchical path-finding (HPA*).
//!
//! [`all_pairs`] runs one search per site over everything it must cross to reach the farthest
//! site, so on a large explored area its cost is sites × area. Here each site searches only a
//! window of 3 × 3 clusters around itself (exact costs to the sites and portals in it); far
//! sites are joined through a graph of the portals between clusters, whose edges within a
//! cluster are exact costs on that cluster alone. A cluster's edges are cached across calls and
//! recomputed only when its costs or its portals changed, so a grid that changed near the robot
//! costs a search of the changed clusters, not of the map.
//!
//! Every edge of the graph is the cost of a real path of the grid (a search on a part of the
//! grid is a search with more cells blocked), so every entry is an **upper bound** of the exact
//! cost; it equals it when the cheapest path stays inside the site's window, and far pairs pay
//! for passing through portals (a few per cent on open ground). A pair that is connected only
//! through a diagonal step across a cluster corner may come out unreachable.
//!
//! Grids of at most [`EXACT_MAX_CELLS`] cells get the exact matrix of [`all_pairs`].

mod graph;
mod portals;

use portals::intersect;
pub use portals::{CLUSTER, ClusterKey, MAX_RUN, Portal, cluster_of, cluster_rect, portals};

use super::all_pairs::{SiteCosts, all_pairs};
use super::cost_grid::CostGrid;
use super::dijkstra::Dijkstra;
use graph::Graph;
use rayon::prelude::*;
use std::collections::HashMap;
use strider_core::{Cell, CellRect};

/// Largest grid, in cells, whose site costs are computed exactly by [`all_pairs`]: a 25 × 25 m
/// view at 0.1 m, where a search per site takes well under a millisecond.
pub const EXACT_MAX_CELLS: usize = 1 << 16;

/// A cluster's portal cells and the exact costs among them on the cluster alone, with the
/// costs they were computed from.
#[derive(Clone, Debug)]
struct ClusterEntry {
    rect: CellRect,
    costs: Vec<f32>,
    nodes: Vec<Cell>,
    /// Row-major `nodes × nodes`, `+∞` where the cluster does not connect them.
    dists: Vec<f64>,
}

/// What [`site_costs`] keeps from one call to the next: each cluster's portal costs.
#[derive(Clone, Debug, Default)]
pub struct SiteCostCache {
    cell_size: f64,
    clusters: HashMap<ClusterKey, ClusterEntry>,
    /// Clusters whose portal costs the last call computed (not taken from the cache).
    recomputed: usize,
}

impl SiteCostCache {
    /// An empty cache.
    pub fn new() -> Self {
        Self::default()
    }

    /// Clusters whose portal costs the last call had to compute.
    pub fn recomputed(&self) -> usize {
        self.recomputed
    }

    /// Clusters held.
    pub fn len(&self) -> usize {
        self.clusters.len()
    }

    /// True when no cluster is held.
    pub fn is_empty(&self) -> bool {
        self.clusters.is_empty()
    }
}

/// Costs between all ordered pairs of `sites` on `grid`: exact ([`all_pairs`]) on grids of at
/// most [`EXACT_MAX_CELLS`] cells, otherwise from the two-level graph (see the module docs).
/// Same conventions as [`all_pairs`]: zero diagonal, `+∞` for a pair without a path or a site
/// outside the grid or inadmissible. Deterministic, whatever the thread count.
pub fn site_costs(grid: &CostGrid, sites: &[Cell], cache: &mut SiteCostCache) -> SiteCosts {
    if grid.len() <= EXACT_MAX_CELLS {
        return all_pairs(grid, sites);
    }
    hierarchical(grid, sites, cache)
}

/// [`site_costs`] through the two-level graph whatever the grid's size.
pub fn hierarchical(grid: &CostGrid, sites: &[Cell], cache: &mut SiteCostCache) -> SiteCosts {
    let n = sites.len();
    if n == 0 {
        return SiteCosts::from_rows(0, Vec::new());
    }
    let (nodes, groups) = portal_nodes(grid);
    refresh_clusters(grid, &nodes, &groups, cache);
    let valid: Vec<bool> = sites.iter().map(|&s| grid.is_admissible(s)).collect();
    let mut g = Graph::new(nodes.len() + n);
    add_portal_edges(grid, &nodes, &groups, cache, &mut g);
    add_site_edges(grid, sites, &valid, &nodes, &groups, &mut g);
    let g = g.finish();
    let first_site = nodes.len();
    let rows: Vec<Vec<f64>> = (0..n)
        .into_par_iter()
        .map_init(graph::Search::default, |search, a| {
            if !valid[a] {
                return vec![f64::INFINITY; n];
            }
            search.run(&g, first_site + a);
            let mut row: Vec<f64> = (0..n)
                .map(|b| {
                    if valid[b] {
                        search.dist(first_site + b)
                    } else {
                        f64::INFINITY
                    }
                })
                .collect();
            row[a] = 0.0;
            row
        })
        .collect();
    let mut data = Vec::with_capacity(n * n);
    for (a, row) in rows.into_iter().enumerate() {
        let mut row = row;
        row[a] = 0.0;
        data.extend(row);
    }
    SiteCosts::from_rows(n, data)
}

/// The portal cells, sorted by cluster (then row, column), and each cluster's range of them.
fn portal_nodes(grid: &CostGrid) -> (Vec<Cell>, HashMap<ClusterKey, std::ops::Range<usize>>) {
    let mut nodes: Vec<Cell> = portals(grid).iter().flat_map(|p| [p.low, p.high]).collect();
    nodes.sort_unstable_by_key(|&c| (cluster_of(c).1, cluster_of(c).0, c.j, c.i));
    nodes.dedup();
    let mut groups = HashMap::new();
    let mut start = 0;
    for k in 1..=nodes.len() {
        if k == nodes.len() || cluster_of(nodes[k]) != cluster_of(nodes[start]) {
            groups.insert(cluster_of(nodes[start]), start..k);
            start = k;
        }
    }
    (nodes, groups)
}

/// Brings the cache to `grid`: clusters whose costs and portals are unchanged keep their
/// entries, the others are computed (in parallel), clusters without portals are dropped.
fn refresh_clusters(
    grid: &CostGrid,
    nodes: &[Cell],
    groups: &HashMap<ClusterKey, std::ops::Range<usize>>,
    cache: &mut SiteCostCache,
) {
    if cache.cell_size != grid.cell_size() {
        cache.clusters.clear();
        cache.cell_size = grid.cell_size();
    }
    let mut keys: Vec<ClusterKey> = groups.keys().copied().collect();
    keys.sort_unstable();
    let fresh: Vec<(ClusterKey, Option<ClusterEntry>)> = keys
        .par_iter()
        .map_init(Dijkstra::new, |dj, &key| {
            let rect = cluster_rect(key, grid.rect());
            let members = &nodes[groups[&key].clone()];
            let unchanged = cache.clusters.get(&key).is_some_and(|e| {
                e.rect == rect && e.nodes == members && same_costs(grid, rect, &e.costs)
            });
            (
                key,
                (!unchanged).then(|| cluster_entry(dj, grid, rect, members)),
            )
        })
        .collect();
    let mut old = std::mem::take(&mut cache.clusters);
    cache.recomputed = 0;
    for (key, entry) in fresh {
        let entry = match entry {
            Some(e) => {
                cache.recomputed += 1;
                e
            }
            None => old.remove(&key).expect("an unchanged cluster is cached"),
        };
        cache.clusters.insert(key, entry);
    }
}

/// The costs of `grid` over `rect` (inside the grid), row by row.
fn costs_of(grid: &CostGrid, rect: CellRect) -> Vec<f32> {
    let mut out = Vec::with_capacity(rect.len());
    for_rows(grid, rect, |row| out.extend_from_slice(row));
    out
}

/// Calls `f` with each row of `grid`'s costs over `rect` (inside the grid), lowest first.
fn for_rows(grid: &CostGrid, rect: CellRect, mut f: impl FnMut(&[f32])) {
    let gw = grid.rect().width as usize;
    let costs = grid.costs();
    for dj in 0..rect.height as i32 {
        let Some(k) = grid.index(Cell::new(rect.min.i, rect.min.j + dj)) else {
            continue;
        };
        debug_assert!(k % gw + rect.width as usize <= gw);
        f(&costs[k..k + rect.width as usize]);
    }
}

/// True when `grid` over `rect` holds exactly `costs`.
fn same_costs(grid: &CostGrid, rect: CellRect, costs: &[f32]) -> bool {
    let w = rect.width as usize;
    let mut k = 0;
    let mut same = costs.len() == rect.len();
    for_rows(grid, rect, |row| {
        same = same && row == &costs[k..k + w];
        k += w;
    });
    same
}

/// A search grid of `grid` cut to `rect`.
fn sub_grid(grid: &CostGrid, rect: CellRect) -> CostGrid {
    CostGrid::new(rect, grid.cell_size(), costs_of(grid, rect))
        .expect("a part of a valid grid is valid")
}

/// The exact costs among a cluster's portal cells on the cluster alone.
fn cluster_entry(
    dj: &mut Dijkstra,
    grid: &CostGrid,
    rect: CellRect,
    nodes: &[Cell],
) -> ClusterEntry {
    let sub = sub_grid(grid, rect);
    let mut dists = Vec::with_capacity(nodes.len() * nodes.len());
    let (mut row, mut pending) = (Vec::new(), Vec::new());
    for &u in nodes {
        if dj.row_into(&sub, u, nodes, &mut pending, &mut row).is_err() {
            row.clear();
            row.resize(nodes.len(), f64::INFINITY);
        }
        dists.extend_from_slice(&row);
    }
    ClusterEntry {
        rect,
        costs: sub.into_costs(),
        nodes: nodes.to_vec(),
        dists,
    }
}

/// Portal edges: across each border (one axis step, paid at the cell it leaves) and, from the
/// cache, within each cluster.
fn add_portal_edges(
    grid: &CostGrid,
    nodes: &[Cell],
    groups: &HashMap<ClusterKey, std::ops::Range<usize>>,
    cache: &SiteCostCache,
    g: &mut Graph,
) {
    let index: HashMap<Cell, usize> = nodes.iter().enumerate().map(|(k, &c)| (c, k)).collect();
    let d = grid.cell_size();
    for p in portals(grid) {
        let (lo, hi) = (index[&p.low], index[&p.high]);
        let cost = |c: Cell| grid.cost(c).map_or(f64::INFINITY, |v| v as f64 * d);
        g.edge(lo, hi, cost(p.low));
        g.edge(hi, lo, cost(p.high));
    }
    let mut keys: Vec<&ClusterKey> = groups.keys().collect();
    keys.sort_unstable();
    for key in keys {
        let range = groups[key].clone();
        let entry = &cache.clusters[key];
        let m = range.len();
        for (a, u) in range.clone().enumerate() {
            for (b, v) in range.clone().enumerate() {
                if a != b {
                    g.edge(u, v, entry.dists[a * m + b]);
                }
            }
        }
    }
}

/// Site edges: from each site to the sites and portals of the 3 × 3 clusters around it (a
/// search on that window), and from the portals of each site's cluster to the site (a search
/// on the cluster from each portal).
fn add_site_edges(
    grid: &CostGrid,
    sites: &[Cell],
    valid: &[bool],
    nodes: &[Cell],
    groups: &HashMap<ClusterKey, std::ops::Range<usize>>,
    g: &mut Graph,
) {
    let first_site = nodes.len();
    let out_edges: Vec<Vec<(usize, f64)>> = (0..sites.len())
        .into_par_iter()
        .map_init(
            || (Dijkstra::new(), Vec::new(), Vec::new()),
            |(dj, row, pending), a| {
                if !valid[a] {
                    return Vec::new();
                }
                let window = window_rect(cluster_of(sites[a]), grid.rect());
                let mut targets: Vec<(usize, Cell)> = window_clusters(cluster_of(sites[a]))
                    .filter_map(|key| groups.get(&key))
                    .flat_map(|r| r.clone().map(|k| (k, nodes[k])))
                    .collect();
                targets.extend(
                    (0..sites.len())
                        .filter(|&b| b != a && valid[b] && window.contains(sites[b]))
                        .map(|b| (first_site + b, sites[b])),
                );
                let cells: Vec<Cell> = targets.iter().map(|t| t.1).collect();
                let sub = sub_grid(grid, window);
                if dj.row_into(&sub, sites[a], &cells, pending, row).is_err() {
                    return Vec::new();
                }
                targets
                    .iter()
                    .zip(row.iter())
                    .map(|(t, &c)| (t.0, c))
                    .collect()
            },
        )
        .collect();
    for (a, edges) in out_edges.into_iter().enumerate() {
        for (to, c) in edges {
            g.edge(first_site + a, to, c);
        }
    }
    // Into each site: from the portals of its cluster.
    let mut by_cluster: Vec<(ClusterKey, Vec<usize>)> = Vec::new();
    for (a, &s) in sites.iter().enumerate() {
        if !valid[a] {
            continue;
        }
        let key = cluster_of(s);
        match by_cluster.iter_mut().find(|(k, _)| *k == key) {
            Some((_, v)) => v.push(a),
            None => by_cluster.push((key, vec![a])),
        }
    }
    let in_edges: Vec<Vec<(usize, usize, f64)>> = by_cluster
        .par_iter()
        .map_init(
            || (Dijkstra::new(), Vec::new(), Vec::new()),
            |(dj, row, pending), (key, members)| {
                let Some(range) = groups.get(key) else {
                    return Vec::new();
                };
                let sub = sub_grid(grid, cluster_rect(*key, grid.rect()));
                let cells: Vec<Cell> = members.iter().map(|&a| sites[a]).collect();
                let mut out = Vec::new();
                for u in range.clone() {
                    if dj.row_into(&sub, nodes[u], &cells, pending, row).is_ok() {
                        out.extend(
                            members
                                .iter()
                                .zip(row.iter())
                                .map(|(&a, &c)| (u, first_site + a, c)),
                        );
                    }
                }
                out
            },
        )
        .collect();
    for (u, v, c) in in_edges.into_iter().flatten() {
        g.edge(u, v, c);
    }
}

/// The 3 × 3 clusters centred on `key`.
fn window_clusters(key: ClusterKey) -> impl Iterator<Item = ClusterKey> {
    (-1..=1).flat_map(move |dy| (-1..=1).map(move |dx| (key.0 + dx, key.1 + dy)))
}

/// The cells of the 3 × 3 clusters centred on `key` inside `rect`.
fn window_rect(key: ClusterKey, rect: CellRect) -> CellRect {
    let lo = Cell::new(
        (key.0 - 1).saturating_mul(CLUSTER),
        (key.1 - 1).saturating_mul(CLUSTER),
    );
    let side = 3 * CLUSTER as u32;
    intersect(CellRect::new(lo, side, side), rect)
}
