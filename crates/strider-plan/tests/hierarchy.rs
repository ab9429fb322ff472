//! The two-level site costs against the exact matrix: never below it, close to it on open
//! ground, and the same whether the clusters come from the cache or are computed afresh.

use proptest::prelude::*;
use strider_core::{Cell, CellRect};
use strider_plan::grid::hierarchy::{self, EXACT_MAX_CELLS, SiteCostCache};
use strider_plan::grid::{CostGrid, all_pairs, site_costs};

/// A `w × h` grid at 0.1 m from a seed: costs 1–4 in patches of 7 × 7 cells, and `walls`
/// blocked bars of 2 cells' thickness with gaps.
fn world(w: u32, h: u32, seed: u64, walls: usize) -> CostGrid {
    let mut s = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
    let mut next = move || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        s
    };
    let rect = CellRect::new(Cell::new(-17, 5), w, h);
    let patches: Vec<f32> = (0..(w / 7 + 1) * (h / 7 + 1))
        .map(|_| 1.0 + (next() % 4) as f32)
        .collect();
    let mut cost: Vec<f32> = (0..rect.len() as u32)
        .map(|k| patches[((k / w / 7) * (w / 7 + 1) + (k % w) / 7) as usize])
        .collect();
    for _ in 0..walls {
        let (i0, j0) = ((next() % w as u64) as u32, (next() % h as u64) as u32);
        let len = 10 + (next() % 60) as u32;
        let vertical = next() % 2 == 0;
        let gap = (next() % len as u64) as u32;
        for t in 0..len {
            if t >= gap && t < gap + 4 {
                continue;
            }
            for th in 0..2 {
                let (i, j) = if vertical {
                    (i0 + th, j0 + t)
                } else {
                    (i0 + t, j0 + th)
                };
                if i < w && j < h {
                    cost[(j * w + i) as usize] = f32::INFINITY;
                }
            }
        }
    }
    CostGrid::new(rect, 0.1, cost).unwrap()
}

fn sites_of(g: &CostGrid, seed: u64, n: usize) -> Vec<Cell> {
    (0..n as u64)
        .map(|k| {
            g.cell(
                ((seed.wrapping_add(k).wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as usize)
                    % g.len(),
            )
        })
        .chain([Cell::new(-1000, 0)])
        .collect()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    #[test]
    fn never_below_exact_and_close_on_open_ground(
        w in 70u32..140, h in 70u32..140, seed in any::<u64>(), walls in 0usize..12, n in 2usize..25,
    ) {
        let g = world(w, h, seed, walls);
        let sites = sites_of(&g, seed, n);
        let exact = all_pairs(&g, &sites);
        let approx = hierarchy::hierarchical(&g, &sites, &mut SiteCostCache::new());
        let (mut lost, mut ratio_sum, mut far) = (0, 0.0, 0);
        for a in 0..sites.len() {
            prop_assert_eq!(approx.get(a, a), 0.0);
            for b in 0..sites.len() {
                let (e, x) = (exact.get(a, b), approx.get(a, b));
                prop_assert!(x >= e * (1.0 - 1e-9), "({a}, {b}): {x} below exact {e}");
                if x.is_finite() {
                    prop_assert!(e.is_finite());
                } else if e.is_finite() {
                    lost += 1;
                }
                if walls == 0 && e.is_finite() {
                    // Open ground: a pair pays for its portal crossings, at worst ~40 % of a
                    // short far pair, a few per cent on average.
                    prop_assert!(x <= 1.6 * e + 2.0, "({a}, {b}): {x} against exact {e}");
                    if e > 3.0 {
                        ratio_sum += x / e;
                        far += 1;
                    }
                }
            }
        }
        if far >= 20 {
            let mean = ratio_sum / far as f64;
            prop_assert!(mean <= 1.12, "mean ratio {mean} over {far} pairs");
        }
        if walls == 0 {
            prop_assert_eq!(lost, 0);
        }
    }
}

#[test]
fn a_warm_cache_gives_the_fresh_result_and_computes_only_changed_clusters() {
    let g = world(200, 160, 7, 8);
    let sites = sites_of(&g, 3, 30);
    let mut cache = SiteCostCache::new();
    let first = hierarchy::hierarchical(&g, &sites, &mut cache);
    let clusters = cache.len();
    assert!(clusters > 20);
    assert_eq!(cache.recomputed(), clusters);
    // Unchanged grid: nothing to compute, same result.
    assert_eq!(hierarchy::hierarchical(&g, &sites, &mut cache), first);
    assert_eq!(cache.recomputed(), 0);
    // Block a few cells in one corner: only the clusters there (and those whose portals moved).
    let mut costs = g.costs().to_vec();
    for j in 0..6 {
        for i in 0..6 {
            costs[j * 200 + i] = f32::INFINITY;
        }
    }
    let changed = CostGrid::new(g.rect(), 0.1, costs).unwrap();
    let warm = hierarchy::hierarchical(&changed, &sites, &mut cache);
    assert!(
        cache.recomputed() <= 3,
        "{} clusters recomputed",
        cache.recomputed()
    );
    assert_eq!(
        warm,
        hierarchy::hierarchical(&changed, &sites, &mut SiteCostCache::new())
    );
}

#[test]
fn the_result_does_not_depend_on_the_thread_count() {
    let g = world(180, 150, 11, 6);
    let sites = sites_of(&g, 5, 40);
    let run = |threads| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| hierarchy::hierarchical(&g, &sites, &mut SiteCostCache::new()))
    };
    assert_eq!(run(1), run(3));
}

#[test]
fn small_grids_get_the_exact_matrix() {
    let g = world(200, 160, 2, 5);
    assert!(g.len() <= EXACT_MAX_CELLS);
    let sites = sites_of(&g, 9, 12);
    assert_eq!(
        site_costs(&g, &sites, &mut SiteCostCache::new()),
        all_pairs(&g, &sites)
    );
    assert_eq!(
        hierarchy::hierarchical(&g, &[], &mut SiteCostCache::new()).len(),
        0
    );
}

#[test]
fn repeated_sites_cost_nothing_between_them() {
    let g = world(300, 300, 7, 0);
    let mut sites = sites_of(&g, 3, 10);
    sites.pop();
    sites.push(sites[2]);
    let x = hierarchy::hierarchical(&g, &sites, &mut SiteCostCache::new());
    assert_eq!((x.get(2, 10), x.get(10, 2)), (0.0, 0.0));
    for b in 0..sites.len() {
        assert_eq!(x.get(2, b), x.get(10, b));
        assert_eq!(x.get(b, 2), x.get(b, 10));
    }
}
