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
mod searched;

use portals::intersect;
pub use portals::{CLUSTER, ClusterKey, MAX_RUN, Portal, cluster_of, cluster_rect, portals};

use super::all_pairs::{SiteCosts, all_pairs};
use super::cost_grid::CostGrid;
use graph::Graph;
use rayon::prelude::*;
use searched::{Scratch, Searched};
use std::collections::HashMap;
use strider_core::{Cell, CellRect};

/// Largest grid, in cells, whose site costs are computed exactly by [`all_pairs`]: a 25 × 25 m
/// view at 0.1 m, where a search per site takes well under a millisecond.
pub const EXACT_MAX_CELLS: usize = 1 << 16;

/// What [`site_costs`] keeps from one call to the next: each cluster's portal costs.
#[derive(Clone, Debug, Default)]
pub struct SiteCostCache {
    cell_size: f64,
    /// Per cluster with portals: the costs among them on the cluster alone.
    clusters: HashMap<ClusterKey, Searched>,
    /// Per site: the costs from it to the portals and sites of its window.
    out_of_site: HashMap<Cell, Searched>,
    /// Per cluster with sites: the costs from its portals to its sites.
    into_sites: HashMap<ClusterKey, Searched>,
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
    let crossings = portals(grid);
    let (nodes, groups) = portal_nodes(&crossings);
    refresh_clusters(grid, &nodes, &groups, cache);
    let valid: Vec<bool> = sites.iter().map(|&s| grid.is_admissible(s)).collect();
    let mut g = Graph::new(nodes.len() + n);
    add_portal_edges(grid, &crossings, &nodes, &groups, cache, &mut g);
    add_site_edges(grid, sites, &valid, &nodes, &groups, cache, &mut g);
    let g = g.finish();
    let first_site = nodes.len();
    let wanted = valid.iter().filter(|&&v| v).count();
    let rows: Vec<Vec<f64>> = (0..n)
        .into_par_iter()
        .map_init(graph::Search::default, |search, a| {
            if !valid[a] {
                let mut row = vec![f64::INFINITY; n];
                row[a] = 0.0;
                return row;
            }
            // Every valid site settled: the costs to them are final.
            search.run(&g, first_site + a, first_site..first_site + n, wanted);
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
    SiteCosts::from_rows(n, rows.concat())
}

/// The portal cells, sorted by cluster (then row, column), and each cluster's range of them.
fn portal_nodes(crossings: &[Portal]) -> (Vec<Cell>, HashMap<ClusterKey, std::ops::Range<usize>>) {
    let mut nodes: Vec<Cell> = crossings.iter().flat_map(|p| [p.low, p.high]).collect();
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
        *cache = SiteCostCache {
            cell_size: grid.cell_size(),
            ..SiteCostCache::default()
        };
    }
    let mut keys: Vec<ClusterKey> = groups.keys().copied().collect();
    keys.sort_unstable();
    let jobs: Vec<(ClusterKey, CellRect, Vec<Cell>, Vec<Cell>)> = keys
        .into_iter()
        .map(|key| {
            let members = nodes[groups[&key].clone()].to_vec();
            (
                key,
                cluster_rect(key, grid.rect()),
                members.clone(),
                members,
            )
        })
        .collect();
    cache.recomputed = refresh(grid, jobs, &mut cache.clusters);
}

/// Brings `map` to the searches of `jobs` (key, rect, sources, targets): an entry that is for
/// the same searches on unchanged costs is kept, the others are computed in parallel, keys not
/// in `jobs` are dropped. Returns how many were computed.
fn refresh<K: std::hash::Hash + Eq + Copy + Send + Sync>(
    grid: &CostGrid,
    jobs: Vec<(K, CellRect, Vec<Cell>, Vec<Cell>)>,
    map: &mut HashMap<K, Searched>,
) -> usize {
    let fresh: Vec<(K, Option<Searched>)> = jobs
        .par_iter()
        .map_init(Scratch::default, |s, (key, rect, sources, targets)| {
            let prev = map.get(key);
            let new = Searched::reuse_or_compute(prev, s, grid, *rect, sources, targets);
            (*key, new)
        })
        .collect();
    let mut old = std::mem::take(map);
    let mut computed = 0;
    for (key, entry) in fresh {
        let entry = match entry {
            Some(e) => {
                computed += 1;
                e
            }
            None => old.remove(&key).expect("a reused entry is cached"),
        };
        map.insert(key, entry);
    }
    computed
}

/// Portal edges: across each border (one axis step, paid at the cell it leaves) and, from the
/// cache, within each cluster.
fn add_portal_edges(
    grid: &CostGrid,
    crossings: &[Portal],
    nodes: &[Cell],
    groups: &HashMap<ClusterKey, std::ops::Range<usize>>,
    cache: &SiteCostCache,
    g: &mut Graph,
) {
    let index: HashMap<Cell, usize> = nodes.iter().enumerate().map(|(k, &c)| (c, k)).collect();
    let d = grid.cell_size();
    for p in crossings {
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
        for (a, u) in range.clone().enumerate() {
            for (b, v) in range.clone().enumerate() {
                if a != b {
                    g.edge(u, v, entry.cost(a, b));
                }
            }
        }
    }
}

/// Site edges: from each site to the sites and portals of the 3 × 3 clusters around it (a
/// search on that window), and from the portals of each site's cluster to the site (a search
/// on the cluster from each portal). Both are cached per site and per cluster.
fn add_site_edges(
    grid: &CostGrid,
    sites: &[Cell],
    valid: &[bool],
    nodes: &[Cell],
    groups: &HashMap<ClusterKey, std::ops::Range<usize>>,
    cache: &mut SiteCostCache,
    g: &mut Graph,
) {
    let first_site = nodes.len();
    // Out of each site: its index, and its targets as (graph node, index in its search).
    let mut outs: Vec<(usize, Vec<(usize, usize)>)> = Vec::new();
    let mut jobs = Vec::new();
    for (a, &site) in sites.iter().enumerate() {
        if !valid[a] {
            continue;
        }
        let window = window_rect(cluster_of(site), grid.rect());
        let mut targets: Vec<usize> = window_clusters(cluster_of(site))
            .filter_map(|key| groups.get(&key))
            .flat_map(|r| r.clone())
            .collect();
        targets.extend(
            (0..sites.len())
                .filter(|&b| b != a && valid[b] && window.contains(sites[b]))
                .map(|b| first_site + b),
        );
        let cell = |v: usize| {
            if v < first_site {
                nodes[v]
            } else {
                sites[v - first_site]
            }
        };
        // Sorted and without repeats, so that the search of a cell does not depend on the
        // sites' order (a repeated site, or the same sites in another call, reuse it).
        let mut cells: Vec<Cell> = targets.iter().map(|&v| cell(v)).collect();
        cells.sort_unstable_by_key(|c| (c.j, c.i));
        cells.dedup();
        let at: Vec<(usize, usize)> = targets
            .iter()
            .map(|&v| {
                let c = cell(v);
                (v, cells.partition_point(|x| (x.j, x.i) < (c.j, c.i)))
            })
            .collect();
        jobs.push((site, window, vec![site], cells));
        outs.push((a, at));
    }
    // Duplicate sites ask for the same searches; one job each is enough.
    jobs.sort_by_key(|j| (j.0.j, j.0.i));
    jobs.dedup_by_key(|j| j.0);
    refresh(grid, jobs, &mut cache.out_of_site);
    for (a, targets) in outs {
        let searched = &cache.out_of_site[&sites[a]];
        for (to, b) in targets {
            g.edge(first_site + a, to, searched.cost(0, b));
        }
    }
    // Into each site: from the portals of its cluster.
    let mut by_cluster: Vec<(ClusterKey, Vec<usize>)> = Vec::new();
    for (a, &s) in sites.iter().enumerate() {
        if !valid[a] || !groups.contains_key(&cluster_of(s)) {
            continue;
        }
        let key = cluster_of(s);
        match by_cluster.iter_mut().find(|(k, _)| *k == key) {
            Some((_, v)) => v.push(a),
            None => by_cluster.push((key, vec![a])),
        }
    }
    let jobs = by_cluster
        .iter()
        .map(|(key, members)| {
            let portals = nodes[groups[key].clone()].to_vec();
            let cells = members.iter().map(|&a| sites[a]).collect();
            (*key, cluster_rect(*key, grid.rect()), portals, cells)
        })
        .collect();
    refresh(grid, jobs, &mut cache.into_sites);
    for (key, members) in &by_cluster {
        let searched = &cache.into_sites[key];
        for (p, u) in groups[key].clone().enumerate() {
            for (b, &a) in members.iter().enumerate() {
                g.edge(u, first_site + a, searched.cost(p, b));
            }
        }
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
