//! Property tests of the grid planner against independent oracles: the `pathfinding` crate's
//! Dijkstra, brute-force definitions of the distance transform, footprint max, best gait and
//! gait choice, and single-source runs for the all-pairs matrix.

use pathfinding::num_traits::Zero;
use pathfinding::prelude::dijkstra_all;
use proptest::prelude::*;
use std::cmp::Ordering;
use std::collections::HashMap;
use strider_core::{Cell, CellRect, Point2};
use strider_plan::grid::{
    CostGrid, Dijkstra, MeanEdgeDijkstra, all_pairs, best_gait, choose_gait, distance_transform,
    footprint_max, path_cost, planning_grid, segment_cost, segment_cost_between, smooth_between,
    smooth_path,
};

/// f64 with a total order, as the oracle's cost type.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Of(f64);
impl Eq for Of {}
impl PartialOrd for Of {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Of {
    fn cmp(&self, o: &Self) -> Ordering {
        self.0.total_cmp(&o.0)
    }
}
impl std::ops::Add for Of {
    type Output = Of;
    fn add(self, o: Of) -> Of {
        Of(self.0 + o.0)
    }
}
impl Zero for Of {
    fn zero() -> Self {
        Of(0.0)
    }
    fn is_zero(&self) -> bool {
        self.0 == 0.0
    }
}

/// Independent successor function: Eq. 1 moves, the corner rule, source-cell edge cost.
fn successors(g: &CostGrid, a: Cell) -> Vec<(Cell, Of)> {
    let mut v = Vec::new();
    let ca = g.cost(a).unwrap() as f64;
    for di in -1..=1 {
        for dj in -1..=1 {
            if di == 0 && dj == 0 {
                continue;
            }
            let b = a.offset(di, dj);
            if !g.is_admissible(b) {
                continue;
            }
            if di != 0
                && dj != 0
                && !g.is_admissible(a.offset(di, 0))
                && !g.is_admissible(a.offset(0, dj))
            {
                continue;
            }
            let len = g.cell_size() * ((di * di + dj * dj) as f64).sqrt();
            v.push((b, Of(len * ca)));
        }
    }
    v
}

fn close(a: f64, b: f64) -> bool {
    if a.is_infinite() || b.is_infinite() {
        return a == b;
    }
    (a - b).abs() <= 1e-9 * a.abs().max(b.abs()).max(1e-12)
}

/// The cheapest path between two admissible cells picked by `a` and `b`, if there are two and
/// they are connected.
fn cheapest_path(g: &CostGrid, a: u32, b: u32) -> Option<(Cell, Cell, Vec<Cell>)> {
    let free: Vec<Cell> = g.rect().cells().filter(|&c| g.is_admissible(c)).collect();
    if free.len() < 2 {
        return None;
    }
    let (s, t) = (free[a as usize % free.len()], free[b as usize % free.len()]);
    let mut dj = Dijkstra::new();
    dj.run(g, s).ok()?;
    Some((s, t, dj.path_to(t)?))
}

/// A random grid: size, cell size, costs log-uniform in [1, 10] or (to exercise the binary-heap
/// fallback of extreme cost ratios) [1, 1e6], with ~25 % inadmissible cells.
fn grid_strategy(max: u32) -> impl Strategy<Value = CostGrid> {
    (
        1..=max,
        1..=max,
        prop::sample::select(vec![0.1f64, 0.25, 1.0]),
        prop::sample::select(vec![10.0f32, 1e6]),
    )
        .prop_flat_map(|(w, h, d, hi)| {
            let n = (w * h) as usize;
            (
                Just((w, h, d, hi)),
                prop::collection::vec((prop::bool::weighted(0.25), 0.0f32..1.0), n),
            )
        })
        .prop_map(|((w, h, d, hi), v)| {
            let cost = v
                .into_iter()
                .map(|(blocked, u)| {
                    if blocked {
                        f32::INFINITY
                    } else {
                        hi.powf(u).max(1.0)
                    }
                })
                .collect();
            CostGrid::new(CellRect::new(Cell::new(-3, 2), w, h), d, cost).unwrap()
        })
}

fn admissible_cells(g: &CostGrid) -> Vec<Cell> {
    g.rect().cells().filter(|&c| g.is_admissible(c)).collect()
}

fn brute_transform(g: &CostGrid, c_loss: f64) -> Vec<f32> {
    let r = g.rect();
    r.cells()
        .map(|a| {
            let ca = g.cost(a).unwrap();
            if !ca.is_finite() {
                return ca;
            }
            let mut m = ca as f64;
            for b in r.cells() {
                let cb = g.cost(b).unwrap();
                if cb.is_finite() {
                    m = m.max(cb as f64 - c_loss * g.cell_size() * a.dist_cells(b));
                }
            }
            m as f32
        })
        .collect()
}

fn brute_footprint(g: &CostGrid, r_robot: f64, a: Cell) -> f32 {
    g.rect()
        .cells()
        .filter(|&b| a.dist_cells(b) * g.cell_size() <= r_robot + 1e-9)
        .map(|b| g.cost(b).unwrap())
        .fold(f32::NEG_INFINITY, f32::max)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Prágr19 Eq. 14 search equals the `pathfinding` oracle with the mean edge cost, is
    /// symmetric, and its paths stay on admissible cells with legal moves adding up to the cost.
    #[test]
    fn mean_edge_dijkstra_matches_oracle(g in grid_strategy(9), pick in any::<prop::sample::Index>()) {
        let cells = admissible_cells(&g);
        prop_assume!(!cells.is_empty());
        let src = cells[pick.index(cells.len())];
        let mean_succ = |a: &Cell| -> Vec<(Cell, Of)> {
            let ca = g.cost(*a).unwrap() as f64;
            successors(&g, *a)
                .into_iter()
                .map(|(b, Of(w))| {
                    let cb = g.cost(b).unwrap() as f64;
                    (b, Of(w / ca * 0.5 * (ca + cb)))
                })
                .collect()
        };
        let oracle: HashMap<Cell, (Cell, Of)> = dijkstra_all(&src, mean_succ);
        let mut s = MeanEdgeDijkstra::new();
        s.run(&g, src).unwrap();
        for c in g.rect().cells() {
            let want = if c == src { Some(0.0) } else { oracle.get(&c).map(|x| x.1.0) };
            let got = s.cost(c);
            match (want, got) {
                (None, None) => {}
                (Some(w), Some(v)) => prop_assert!(close(w, v), "{c:?}: {w} vs {v}"),
                _ => prop_assert!(false, "{c:?}: {want:?} vs {got:?}"),
            }
            if let Some(path) = s.path_to(c) {
                prop_assert_eq!(path[0], src);
                prop_assert_eq!(*path.last().unwrap(), c);
                let mut total = 0.0;
                for w in path.windows(2) {
                    prop_assert!(g.is_admissible(w[1]));
                    let step = mean_succ(&w[0]).into_iter().find(|(b, _)| *b == w[1]);
                    prop_assert!(step.is_some(), "illegal move {:?} -> {:?}", w[0], w[1]);
                    total += step.unwrap().1.0;
                }
                prop_assert!(close(total, got.unwrap()));
                // Symmetric edge cost: the way back costs the same.
                let mut back = MeanEdgeDijkstra::new();
                back.run(&g, c).unwrap();
                prop_assert!(close(back.cost(src).unwrap(), got.unwrap()));
            }
        }
    }

    /// Smoothing keeps the ends, keeps a subsequence of the cheapest path, only draws segments
    /// through admissible cells (checked by sampling the segment densely, independently of the
    /// traversal), and each shortcut costs no more than the grid sub-path it replaces.
    #[test]
    fn smoothed_paths_are_admissible_and_no_dearer(g in grid_strategy(16), a in any::<u32>(), b in any::<u32>()) {
        let Some((_, _, path)) = cheapest_path(&g, a, b) else { return Ok(()); };
        let sm = smooth_path(&g, &path);
        prop_assert_eq!(sm.first(), path.first());
        prop_assert_eq!(sm.last(), path.last());
        let mut idx = Vec::new();
        let mut k = 0;
        for v in &sm {
            let at = path[k..].iter().position(|c| c == v);
            prop_assert!(at.is_some(), "not a subsequence");
            k += at.unwrap();
            idx.push(k);
        }
        let d = g.cell_size();
        let mut scratch = Vec::new();
        for (w, ix) in sm.windows(2).zip(idx.windows(2)) {
            if ix[1] - ix[0] < 2 {
                continue; // a step of the grid path, kept as it is
            }
            let c = segment_cost(&g, w[0], w[1], &mut scratch);
            prop_assert!(c.is_some());
            let replaced = path_cost(&g, &path[ix[0]..=ix[1]]).unwrap();
            prop_assert!(c.unwrap() <= replaced * (1.0 + 1e-6), "{:?} > {}", c, replaced);
            let (pa, pb) = (w[0].center(d), w[1].center(d));
            for q in 0..=400 {
                let f = q as f64 / 400.0;
                let (x, y) = (pa.x + f * (pb.x - pa.x), pa.y + f * (pb.y - pa.y));
                let cell = Cell::containing(x, y, d).unwrap();
                prop_assert!(g.is_admissible(cell), "segment {:?}-{:?} enters {:?}", w[0], w[1], cell);
            }
        }
    }

    /// Smoothing between exact end points: the polyline runs from `from` to `to` through a
    /// subsequence of the path's cell centres, drops a centre only for an end point in that
    /// cell, draws every shortcut through admissible cells at no more than the stretch it
    /// replaces, and in the open (uniform cost, no obstacle on the way) is the straight segment.
    #[test]
    fn smoothing_between_points_is_admissible_and_no_dearer(
        g in grid_strategy(16), a in any::<u32>(), b in any::<u32>(),
        fa in (0.0f64..1.0, 0.0f64..1.0), fb in (0.0f64..1.0, 0.0f64..1.0),
    ) {
        let Some((s, t, path)) = cheapest_path(&g, a, b) else { return Ok(()); };
        let d = g.cell_size();
        // Points anywhere inside the first and last cells.
        let at = |c: Cell, (u, v): (f64, f64)| Point2::new((c.i as f64 + u) * d, (c.j as f64 + v) * d);
        let (from, to) = (at(s, fa), at(t, fb));
        prop_assume!(Cell::containing(from.x, from.y, d) == Some(s));
        prop_assume!(Cell::containing(to.x, to.y, d) == Some(t));
        let sm = smooth_between(&g, from, &path, to);
        prop_assert_eq!(sm.first(), Some(&from));
        prop_assert_eq!(sm.last(), Some(&to));
        // The polyline before pulling: the end points replace the centres of their cells.
        let inner = if path.len() >= 2 { &path[1..path.len() - 1] } else { &path[..0] };
        let mut cand = vec![from];
        cand.extend(inner.iter().map(|c| c.center(d)));
        cand.push(to);
        // Its legs: the end legs as straight segments, the others as grid moves (Eq. 4).
        let mut scratch = Vec::new();
        let mut legs = Vec::new();
        for k in 0..cand.len() - 1 {
            legs.push(if k == 0 || k + 2 == cand.len() {
                segment_cost_between(&g, cand[k], cand[k + 1], &mut scratch).unwrap_or(f64::INFINITY)
            } else {
                path_cost(&g, &path[k..=k + 1]).unwrap()
            });
        }
        // The result is a subsequence of it with both ends.
        let mut idx = Vec::new();
        let mut k = 0;
        for v in &sm {
            let found = cand[k..].iter().position(|c| c == v);
            prop_assert!(found.is_some(), "{:?} is not a later vertex", v);
            k += found.unwrap();
            idx.push(k);
        }
        prop_assert_eq!(idx.last(), Some(&(cand.len() - 1)));
        // Every segment is admissible (dense sampling); a shortcut costs no more than the legs
        // it replaces.
        for (w, ix) in sm.windows(2).zip(idx.windows(2)) {
            let c = segment_cost_between(&g, w[0], w[1], &mut scratch);
            let budget: f64 = legs[ix[0]..ix[1]].iter().sum();
            if ix[1] - ix[0] >= 2 {
                prop_assert!(c.is_some(), "shortcut {:?}-{:?} not admissible", w[0], w[1]);
                prop_assert!(c.unwrap() <= budget * (1.0 + 1e-6), "{:?} > {}", c, budget);
            }
            if c.is_none() {
                continue; // an end leg through an inadmissible corner, driven as planned
            }
            for q in 0..=400 {
                let f = q as f64 / 400.0;
                let (x, y) = (w[0].x + f * (w[1].x - w[0].x), w[0].y + f * (w[1].y - w[0].y));
                let cell = Cell::containing(x, y, d).unwrap();
                prop_assert!(g.is_admissible(cell), "segment {:?}-{:?} enters {:?}", w[0], w[1], cell);
            }
        }
        // Uniform cost and a clear straight line: the straight segment.
        let flat = CostGrid::new(g.rect(), d, g.costs().iter().map(|c| if c.is_finite() { 1.0 } else { *c }).collect()).unwrap();
        let Some(straight) = segment_cost_between(&flat, from, to, &mut scratch) else { return Ok(()); };
        let mut dj = Dijkstra::new();
        dj.run(&flat, s).unwrap();
        let path = dj.path_to(t).unwrap();
        let sm = smooth_between(&flat, from, &path, to);
        if path.len() <= 5 {
            // Within the look-ahead of the string pulling.
            prop_assert_eq!(sm.clone(), vec![from, to], "straight {}", straight);
        }
    }

    #[test]
    fn dijkstra_matches_pathfinding_and_paths_are_valid(g in grid_strategy(9), pick in any::<u64>()) {
        let cells = admissible_cells(&g);
        prop_assume!(!cells.is_empty());
        let src = cells[(pick % cells.len() as u64) as usize];
        let oracle: HashMap<Cell, (Cell, Of)> = dijkstra_all(&src, |&a| successors(&g, a));
        let mut dj = Dijkstra::new();
        dj.run(&g, src).unwrap();
        prop_assert_eq!(dj.distance(src), 0.0);
        for c in g.rect().cells() {
            let want = if c == src { 0.0 } else { oracle.get(&c).map_or(f64::INFINITY, |x| x.1.0) };
            let got = dj.distance(c);
            prop_assert!(close(got, want), "cell {:?}: got {} want {}", c, got, want);
            match dj.path_to(c) {
                Some(p) => {
                    prop_assert_eq!(p[0], src);
                    prop_assert_eq!(*p.last().unwrap(), c);
                    // path_cost checks admissibility, 8-connectivity and the corner rule.
                    let pc = path_cost(&g, &p);
                    prop_assert!(pc.is_some_and(|pc| close(pc, got)), "path {:?} cost {:?} vs {}", p, pc, got);
                }
                None => prop_assert!(got.is_infinite()),
            }
        }
        // A* equals Dijkstra, for every target; the early-exit one-to-many run too.
        let mut a = Dijkstra::new();
        for &t in &cells {
            let h = a.astar(&g, src, t).unwrap();
            prop_assert!(close(h, dj.distance(t)), "A* {:?}: {} vs {}", t, h, dj.distance(t));
            if h.is_finite() {
                let p = a.path_to(t).unwrap();
                prop_assert!(close(path_cost(&g, &p).unwrap(), h));
            }
        }
        let targets: Vec<Cell> = cells.iter().copied().step_by(3).chain([Cell::new(1000, 0)]).collect();
        let r = a.run_to_targets(&g, src, &targets).unwrap();
        for (t, d) in targets.iter().zip(&r) {
            prop_assert!(close(*d, dj.distance(*t)));
        }
    }

    /// A search object reused for many A* (which reset only the cells the last one touched),
    /// with other searches in between, leaves exactly the fields of a fresh object's A*.
    #[test]
    fn reused_astar_equals_a_fresh_one(
        g in grid_strategy(9),
        picks in prop::collection::vec((any::<u32>(), any::<u32>(), 0u8..4), 1..12),
    ) {
        let cells = admissible_cells(&g);
        prop_assume!(!cells.is_empty());
        let mut reused = Dijkstra::new();
        for (a, b, other) in picks {
            let (s, t) = (cells[a as usize % cells.len()], cells[b as usize % cells.len()]);
            if other == 0 {
                reused.run(&g, t).unwrap();
            } else if other == 1 {
                reused.run_to_targets(&g, t, &[s]).unwrap();
            }
            let mut fresh = Dijkstra::new();
            let want = fresh.astar(&g, s, t).unwrap();
            let got = reused.astar(&g, s, t).unwrap();
            prop_assert_eq!(got, want);
            prop_assert_eq!(reused.distances(), fresh.distances());
            prop_assert_eq!(reused.predecessors(), fresh.predecessors());
            for c in g.rect().cells() {
                prop_assert_eq!(reused.is_settled(c), fresh.is_settled(c));
            }
        }
    }

    #[test]
    fn all_pairs_matches_single_source(g in grid_strategy(8), extra in prop::collection::vec(any::<u32>(), 1..8)) {
        let mut sites: Vec<Cell> = extra.iter().map(|&k| g.cell(k as usize % g.len())).collect();
        sites.push(Cell::new(-100, -100)); // outside: infinite row and column
        let m = all_pairs(&g, &sites);
        prop_assert_eq!(m.len(), sites.len());
        let mut dj = Dijkstra::new();
        for (a, &sa) in sites.iter().enumerate() {
            let ok = dj.run(&g, sa).is_ok();
            for (b, &sb) in sites.iter().enumerate() {
                let want = if a == b { 0.0 } else if ok { dj.distance(sb) } else { f64::INFINITY };
                prop_assert!(close(m.get(a, b), want), "({}, {}): {} vs {}", a, b, m.get(a, b), want);
            }
        }
        // Deterministic.
        prop_assert_eq!(&all_pairs(&g, &sites), &m);
    }

    #[test]
    fn distance_transform_matches_brute_force(g in grid_strategy(9), c_loss in prop::sample::select(vec![0.0, 0.5, 3.0, 10.0, 40.0, 1e5])) {
        let t = distance_transform(&g, c_loss).unwrap();
        let want = brute_transform(&g, c_loss);
        for (k, (&a, &b)) in t.costs().iter().zip(&want).enumerate() {
            prop_assert!(a == b || (a - b).abs() <= 1e-5 * b.abs(), "cell {}: {} vs {}", k, a, b);
            prop_assert!(a >= g.costs()[k]);
        }
    }

    /// Plateaus (a few cost levels, as the c_max band of unclassified cells makes) exercise the
    /// pruning of plateau interiors.
    #[test]
    fn distance_transform_on_plateaus_matches_brute_force(
        (w, h, levels) in (1u32..14, 1u32..14).prop_flat_map(|(w, h)| (Just(w), Just(h),
            prop::collection::vec(prop::sample::select(vec![0usize, 0, 0, 0, 1, 1, 1, 2, 3]),
                (w * h) as usize))),
        c_loss in prop::sample::select(vec![0.5, 3.0, 10.0, 40.0]),
    ) {
        // Mostly the floor, some mid plateaus, rare high ones and obstacles, so that lower
        // plateaus are not all buried under the cones of the highest.
        const LEVEL: [f32; 4] = [1.0, 4.0, 20.0, f32::INFINITY];
        let cost = levels.iter().map(|&l| LEVEL[l]).collect();
        let g = CostGrid::new(CellRect::new(Cell::new(0, 0), w, h), 0.25, cost).unwrap();
        let t = distance_transform(&g, c_loss).unwrap();
        let want = brute_transform(&g, c_loss);
        for (k, (&a, &b)) in t.costs().iter().zip(&want).enumerate() {
            prop_assert!(a == b || (a - b).abs() <= 1e-5 * b.abs(), "cell {}: {} vs {}", k, a, b);
        }
    }

    #[test]
    fn footprint_and_gaits_match_brute_force(
        // Tall grids too: the passes run in bands of 32 rows, the last one partial.
        gs in (1u32..7, prop_oneof![1u32..7, 33u32..70]).prop_flat_map(|(w, h)| prop::collection::vec(
            prop::collection::vec((prop::bool::weighted(0.1), 1.0f32..10.0), (w * h) as usize), 1..4)
            .prop_map(move |v| (w, h, v))),
        r in prop::sample::select(vec![0.0, 0.5, 1.0, 1.5, 2.3]),
    ) {
        let (w, h, v) = gs;
        let rect = CellRect::new(Cell::new(5, -7), w, h);
        let grids: Vec<CostGrid> = v.into_iter().map(|cs| CostGrid::new(rect, 0.5, cs.into_iter()
            .map(|(b, c)| if b { f32::INFINITY } else { c }).collect()).unwrap()).collect();
        for g in &grids {
            let f = footprint_max(g, r).unwrap();
            for c in rect.cells() {
                prop_assert_eq!(f.cost(c).unwrap(), brute_footprint(g, r, c));
            }
        }
        let bg = best_gait(&grids).unwrap();
        for (k, c) in rect.cells().enumerate() {
            let m = grids.iter().map(|g| g.cost(c).unwrap()).fold(f32::INFINITY, f32::min);
            prop_assert_eq!(bg.cost.costs()[k], m);
            match bg.gait[k] {
                Some(gi) => prop_assert_eq!(grids[gi as usize].cost(c).unwrap(), m),
                None => prop_assert!(m.is_infinite()),
            }
            // Alg. 4: argmin over gaits of the footprint max (first gait on ties).
            let fm: Vec<f32> = grids.iter().map(|g| brute_footprint(g, r, c)).collect();
            let best = fm.iter().copied().enumerate().filter(|x| x.1.is_finite())
                .fold(None::<(usize, f32)>, |acc, x| match acc { Some(a) if a.1 <= x.1 => Some(a), _ => Some(x) });
            prop_assert_eq!(choose_gait(&grids, c, r), best);
        }
    }
}

#[test]
fn planning_grid_chain() {
    let rect = CellRect::new(Cell::new(0, 0), 5, 1);
    let g = CostGrid::new(rect, 1.0, vec![1.0, 1.0, 4.0, 1.0, 1.0]).unwrap();
    let p = planning_grid(&g, 1.0, 1.0).unwrap();
    // Transform: [2, 3, 4, 3, 2]; footprint radius 1 cell: [3, 4, 4, 4, 3].
    assert_eq!(p.costs(), &[3.0, 4.0, 4.0, 4.0, 3.0]);
}

#[test]
fn buffers_are_reused_across_grids() {
    // Same search object over different grids (different sizes) stays correct.
    let mut dj = Dijkstra::new();
    for w in [3u32, 10, 4] {
        let g = CostGrid::filled(CellRect::new(Cell::new(0, 0), w, 2), 1.0, 1.0).unwrap();
        dj.run(&g, Cell::new(0, 0)).unwrap();
        assert_eq!(dj.distance(Cell::new(w as i32 - 1, 0)), (w - 1) as f64);
        let g2 = CostGrid::filled(CellRect::new(Cell::new(0, 0), w, 2), 1.0, 2.0).unwrap();
        dj.run(&g2, Cell::new(0, 0)).unwrap();
        assert_eq!(
            dj.distance(Cell::new(w as i32 - 1, 0)),
            2.0 * (w - 1) as f64
        );
    }
}

#[test]
fn all_pairs_is_deterministic_across_thread_counts() {
    let rect = CellRect::new(Cell::new(0, 0), 40, 30);
    let g = CostGrid::from_fn(rect, 0.2, |c| {
        let h = (c.i * 7919 + c.j * 104_729).rem_euclid(97);
        if h < 15 {
            f32::INFINITY
        } else {
            1.0 + (h % 9) as f32 * 0.37
        }
    })
    .unwrap();
    let sites: Vec<Cell> = (0..23)
        .map(|k| Cell::new((k * 13) % 40, (k * 7) % 30))
        .collect();
    let par = all_pairs(&g, &sites);
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap()
        .install(|| all_pairs(&g, &sites));
    let three = rayon::ThreadPoolBuilder::new()
        .num_threads(3)
        .build()
        .unwrap()
        .install(|| all_pairs(&g, &sites));
    assert_eq!(par.as_slice(), one.as_slice());
    assert_eq!(par.as_slice(), three.as_slice());
    // Source-cell edge costs: not symmetric in general, but some pair must be finite.
    assert!(par.as_slice().iter().any(|v| v.is_finite() && *v > 0.0));
}
