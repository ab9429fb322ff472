//! Property tests of the Nardi19 LCB planner (Eq. 7–8) against a brute-force oracle: on random
//! grids with obstacles and random μ, σ, the planned path never enters or cuts past an
//! impassable cell, is 8-connected, costs what Eq. 7 says (cells entered), and is optimal.

use proptest::prelude::*;
use strider_core::{Cell, CellRect};
use strider_plan::grid::lcb::{LcbParams, Rectifier, entered_cost, lcb_grid, lcb_path};
use strider_plan::grid::{CostGrid, Dijkstra};

/// Cheapest cost from `s` to every cell when each step costs its length × the cost of the
/// cell entered, by plain O(V²) Dijkstra with the same move rules (8-neighbours, both ends
/// admissible, no diagonal between two inadmissible side cells).
fn oracle(grid: &CostGrid, s: Cell) -> Vec<f64> {
    let rect = grid.rect();
    let n = rect.len();
    let d = grid.cell_size();
    let adm = |c: Cell| grid.is_admissible(c);
    let mut dist = vec![f64::INFINITY; n];
    let mut done = vec![false; n];
    dist[rect.index(s).unwrap()] = 0.0;
    while let Some(k) = (0..n)
        .filter(|&k| !done[k] && dist[k].is_finite())
        .min_by(|&a, &b| dist[a].total_cmp(&dist[b]))
    {
        done[k] = true;
        let a = rect.cell(k);
        for (di, dj) in strider_core::grid::NEIGHBOURS8 {
            let b = a.offset(di, dj);
            if !adm(b) {
                continue;
            }
            if di != 0 && dj != 0 && !adm(a.offset(di, 0)) && !adm(a.offset(0, dj)) {
                continue;
            }
            let len = if di != 0 && dj != 0 {
                d * 2f64.sqrt()
            } else {
                d
            };
            let kb = rect.index(b).unwrap();
            let nd = dist[k] + len * grid.cost(b).unwrap() as f64;
            if nd < dist[kb] {
                dist[kb] = nd;
            }
        }
    }
    dist
}

/// Grid width and height, per cell (μ, σ, admissible), ReLU?, λ, start and goal offsets.
type Case = (
    u32,
    u32,
    Vec<(f64, f64, bool)>,
    bool,
    f64,
    (u32, u32, u32, u32),
);

fn arb_case() -> impl Strategy<Value = Case> {
    (3u32..12, 3u32..10).prop_flat_map(|(w, h)| {
        let n = (w * h) as usize;
        (
            Just(w),
            Just(h),
            prop::collection::vec((-3.0f64..5.0, 0.0f64..3.0, prop::bool::weighted(0.75)), n),
            any::<bool>(),
            0.0f64..2.0,
            (0..w, 0..h, 0..w, 0..h),
        )
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 200, .. ProptestConfig::default() })]

    #[test]
    fn planned_paths_avoid_impassable_cells_and_are_optimal(
        (w, h, cells, relu, lambda, (si, sj, gi, gj)) in arb_case()
    ) {
        let rect = CellRect::new(Cell::new(-3, 2), w, h);
        let mean: Vec<f64> = cells.iter().map(|c| c.0).collect();
        let std: Vec<f64> = cells.iter().map(|c| c.1).collect();
        let mut adm: Vec<bool> = cells.iter().map(|c| c.2).collect();
        let start = Cell::new(rect.min.i + si as i32, rect.min.j + sj as i32);
        let goal = Cell::new(rect.min.i + gi as i32, rect.min.j + gj as i32);
        adm[rect.index(start).unwrap()] = true;
        let params = LcbParams {
            lambda,
            rectifier: if relu { Rectifier::Relu } else { Rectifier::Softplus },
            floor: 1e-3,
        };
        let grid = lcb_grid(rect, 0.5, &mean, &std, &adm, &params).unwrap();
        let best = oracle(&grid, start);
        let kg = rect.index(goal).unwrap();
        let planned = lcb_path(&mut Dijkstra::new(), &grid, start, goal).unwrap();
        match planned {
            None => prop_assert!(!best[kg].is_finite() || !adm[kg]),
            Some((path, cost)) => {
                prop_assert_eq!(path.first(), Some(&start));
                prop_assert_eq!(path.last(), Some(&goal));
                for c in &path {
                    prop_assert!(adm[rect.index(*c).unwrap()], "entered impassable {:?}", c);
                }
                // Legal 8-connected path without corner cutting, charged by entered cells.
                let eq7 = entered_cost(&grid, &path);
                prop_assert!(eq7.is_some());
                let eq7 = eq7.unwrap();
                prop_assert!((eq7 - cost).abs() <= 1e-9 * (1.0 + cost));
                prop_assert!((cost - best[kg]).abs() <= 1e-6 * (1.0 + cost),
                    "planned {} oracle {}", cost, best[kg]);
            }
        }
    }
}

#[test]
fn relu_flattens_negative_bounds_and_softplus_keeps_their_order() {
    // Cells: a known cheap one (μ 0.05, σ 0.1: bound −0.05), a very uncertain one (μ 0, σ 3:
    // bound −3) and a known costly one (μ 2, σ 0). Nardi19 §V-A: with the ReLU the first two cost
    // the same (here the floor); softplus charges each log(1 + e^bound).
    let rect = CellRect::new(Cell::new(0, 0), 3, 1);
    let (mean, std) = ([0.05, 0.0, 2.0], [0.1, 3.0, 0.0]);
    let costs = |r| {
        let p = LcbParams {
            lambda: 1.0,
            rectifier: r,
            floor: 1e-3,
        };
        lcb_grid(rect, 1.0, &mean, &std, &[true; 3], &p)
            .unwrap()
            .costs()
            .to_vec()
    };
    let relu = costs(Rectifier::Relu);
    assert_eq!(relu[0], relu[1]);
    assert_eq!(relu[0], 1e-3);
    assert_eq!(relu[2], 2.0);
    let sp = costs(Rectifier::Softplus);
    for (k, b) in [-0.05f64, -3.0, 2.0].into_iter().enumerate() {
        assert!((sp[k] as f64 - (1.0 + b.exp()).ln()).abs() < 1e-6);
    }
    assert!(sp[1] < sp[0] && sp[0] < sp[2]);
}
