//! Timing of the parallel all-pairs site-cost matrix: 100 random sites on a 250 × 200 grid
//! (50 000 cells) with random costs in [1, 5] and ~20 % random obstacles.
//!
//! `cargo run --release -p strider-plan --example grid_all_pairs [-- SEED]`

use rand::{RngExt, SeedableRng};
use std::time::Instant;
use strider_core::{Cell, CellRect};
use strider_plan::grid::{CostGrid, all_pairs};

fn main() {
    let seed: u64 = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(7);
    let mut rng = rand::rngs::ChaCha8Rng::seed_from_u64(seed);
    let rect = CellRect::new(Cell::new(-100, -50), 250, 200);
    let cost: Vec<f32> = (0..rect.len())
        .map(|_| {
            if rng.random_bool(0.2) {
                f32::INFINITY
            } else {
                rng.random_range(1.0..5.0)
            }
        })
        .collect();
    let grid = CostGrid::new(rect, 0.1, cost).expect("valid grid");
    let mut sites = Vec::new();
    while sites.len() < 100 {
        let c = rect.cell(rng.random_range(0..rect.len()));
        if grid.is_admissible(c) {
            sites.push(c);
        }
    }
    single(&grid, &sites);
    // Warm-up (thread pool start, page faults).
    let _ = all_pairs(&grid, &sites);
    let reps = 10;
    let mut best = f64::INFINITY;
    let mut total = 0.0;
    let mut m = None;
    for _ in 0..reps {
        let t = Instant::now();
        m = Some(all_pairs(&grid, &sites));
        let dt = t.elapsed().as_secs_f64() * 1e3;
        best = best.min(dt);
        total += dt;
    }
    let m = m.expect("ran");
    println!(
        "all-pairs: {} sites, {} cells, {} threads: best {:.1} ms, mean {:.1} ms; {} unreachable pairs",
        sites.len(),
        rect.len(),
        rayon::current_num_threads(),
        best,
        total / reps as f64,
        m.unreachable_pairs().len()
    );
}

/// Reference: single-thread one-to-all searches, without early exit.
fn single(grid: &CostGrid, sites: &[Cell]) {
    let mut dj = strider_plan::grid::Dijkstra::new();
    let t = Instant::now();
    for &s in sites {
        dj.run(grid, s).unwrap();
    }
    println!(
        "single-thread full runs: {:.2} ms each",
        t.elapsed().as_secs_f64() * 1e3 / sites.len() as f64
    );
}
