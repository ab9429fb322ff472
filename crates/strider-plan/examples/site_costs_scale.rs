//! Exact against two-level site costs as the grid grows: 100 random sites on square grids of
//! 300² to 1200² cells (30 to 120 m a side at 0.1 m) with cost patches in
//! [1, 4] and walls with doorways. Prints, per size, the exact matrix's time, the two-level
//! one's with a cold and a warm cache (one corner of the grid changed), and the mean and worst
//! ratio of the two-level costs to the exact ones.
//!
//! `cargo run --release -p strider-plan --example site_costs_scale [-- SEED]`

use rand::{RngExt, SeedableRng};
use std::time::Instant;
use strider_core::{Cell, CellRect};
use strider_plan::grid::hierarchy::{SiteCostCache, hierarchical};
use strider_plan::grid::{CostGrid, all_pairs};

fn world(side: u32, rng: &mut rand::rngs::ChaCha8Rng) -> Vec<f32> {
    let patch = 20;
    let per_row = side / patch + 1;
    let patches: Vec<f32> = (0..per_row * per_row)
        .map(|_| rng.random_range(1.0..4.0))
        .collect();
    let mut cost: Vec<f32> = (0..side * side)
        .map(|k| patches[((k / side / patch) * per_row + (k % side) / patch) as usize])
        .collect();
    // Walls every 150 cells with a 10-cell doorway at a random place into each room.
    for w in (150..side).step_by(150) {
        for vertical in [true, false] {
            let doors: Vec<u32> = (0..side)
                .step_by(150)
                .map(|s| s + rng.random_range(10..130))
                .collect();
            for t in 0..side {
                if doors.iter().any(|&d| (d..d + 10).contains(&t)) {
                    continue;
                }
                let (i, j) = if vertical { (w, t) } else { (t, w) };
                cost[(j * side + i) as usize] = f32::INFINITY;
            }
        }
    }
    cost
}

fn main() {
    let seed: u64 = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(7);
    println!("| side, cells | exact ms | two-level cold ms | warm ms | mean ratio | worst ratio |");
    println!("|---|---|---|---|---|---|");
    for side in [300u32, 600, 900, 1200] {
        let mut rng = rand::rngs::ChaCha8Rng::seed_from_u64(seed);
        let rect = CellRect::new(Cell::new(0, 0), side, side);
        let cost = world(side, &mut rng);
        let grid = CostGrid::new(rect, 0.1, cost.clone()).expect("valid grid");
        let mut sites = Vec::new();
        while sites.len() < 100 {
            let c = rect.cell(rng.random_range(0..rect.len()));
            if grid.is_admissible(c) {
                sites.push(c);
            }
        }
        let t = Instant::now();
        let exact = all_pairs(&grid, &sites);
        let exact_ms = t.elapsed().as_secs_f64() * 1e3;
        let mut cache = SiteCostCache::new();
        let t = Instant::now();
        let two = hierarchical(&grid, &sites, &mut cache);
        let cold_ms = t.elapsed().as_secs_f64() * 1e3;
        let mut changed = cost;
        for j in 0..20 {
            for i in 0..20 {
                changed[j * side as usize + i] = 3.5;
            }
        }
        let changed = CostGrid::new(rect, 0.1, changed).expect("valid grid");
        let t = Instant::now();
        let _ = hierarchical(&changed, &sites, &mut cache);
        let warm_ms = t.elapsed().as_secs_f64() * 1e3;
        let (mut sum, mut worst, mut n) = (0.0, 1.0f64, 0);
        for a in 0..sites.len() {
            for b in 0..sites.len() {
                let (e, x) = (exact.get(a, b), two.get(a, b));
                if a != b && e > 0.0 && e.is_finite() && x.is_finite() {
                    sum += x / e;
                    worst = worst.max(x / e);
                    n += 1;
                }
            }
        }
        println!(
            "| {side}², {} | {exact_ms:.1} | {cold_ms:.1} | {warm_ms:.1} | {:.4} | {worst:.3} |",
            rect.len(),
            sum / n.max(1) as f64
        );
    }
}
