//! Times the planning view's transforms (decision 21's c_loss distance transform and Eq. 12's
//! footprint maximum) on a 500 × 500 grid of patchy costs from 1 to 15 with scattered obstacles,
//! at c_loss 10 and r_robot 0.4 m on 0.1 m cells (campus's view is about this size).
//!
//! `cargo run --release -p strider-plan --example transform_speed`
use std::time::Instant;
use strider_core::{Cell, CellRect};
use strider_plan::grid::{CostGrid, distance_transform, footprint_max};

fn main() {
    let (w, h) = (500u32, 500u32);
    let mut s = 12345u64;
    let costs: Vec<f32> = (0..w * h)
        .map(|k| {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let (i, j) = (k % w, k / w);
            let patch = ((i / 37 + j / 23) % 5) as f32;
            if (s >> 60) == 0 {
                f32::INFINITY
            } else {
                1.0 + patch * 3.0 + ((s >> 40) % 3) as f32
            }
        })
        .collect();
    let g = CostGrid::new(CellRect::new(Cell::new(0, 0), w, h), 0.1, costs).unwrap();
    for _ in 0..3 {
        let t = Instant::now();
        for _ in 0..20 {
            std::hint::black_box(distance_transform(&g, 10.0).unwrap());
        }
        let dt = t.elapsed().as_secs_f64() / 20.0 * 1e3;
        let t = Instant::now();
        for _ in 0..20 {
            std::hint::black_box(footprint_max(&g, 0.4).unwrap());
        }
        let fp = t.elapsed().as_secs_f64() / 20.0 * 1e3;
        println!("distance_transform {dt:.2} ms, footprint_max {fp:.2} ms");
    }
}
