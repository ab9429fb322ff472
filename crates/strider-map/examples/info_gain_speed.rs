//! Timing of one exploration step at the default (Prágr22 small-simulation) parameters: the known
//! area is a 2.5 m disc around the robot with a few boxes; Eq. 11 on every candidate cell
//! (stride 1, 2, 4), then Alg. 3 and the frontier representatives.
//!
//! `cargo run --release -p strider-map --example info_gain_speed`

use std::time::Instant;
use strider_core::{Cell, Rgb8};
use strider_map::{
    ElevationMap, MapParams, Reachability, cluster_information, frontier_goals, information_gain,
};

fn main() {
    let mut map = ElevationMap::new(MapParams::default());
    let n: i32 = 50;
    for j in -n..=n {
        for i in -n..=n {
            if i * i + j * j > n * n {
                continue;
            }
            let boxy = (i.rem_euclid(25) < 4 && j.rem_euclid(25) < 4) as i32 as f32 * 0.4;
            map.set_cell(Cell::new(i, j), boxy, 1e-4, Rgb8::new(120, 120, 120));
        }
    }
    map.update_passability();
    let robot = Cell::new(10, 10);
    let t = Instant::now();
    let reach = Reachability::compute(&map, robot);
    println!(
        "reachability: {} cells in {:.1} ms",
        reach.count(),
        t.elapsed().as_secs_f64() * 1e3
    );
    for stride in [1, 2, 4] {
        let mut m = map.clone();
        m.set_info_gain_stride(stride);
        let t = Instant::now();
        let gain = information_gain(&m, &reach, None);
        let dt = t.elapsed().as_secs_f64();
        let goals = cluster_information(&m, &gain, &reach, None);
        println!(
            "stride {stride}: {} candidates, {} with gain, {:.1} ms ({} threads); {} Alg. 3 goals",
            gain.candidates,
            gain.cells.len(),
            dt * 1e3,
            rayon::current_num_threads(),
            goals.len()
        );
    }
    let t = Instant::now();
    let f = frontier_goals(&map, &reach, robot, None);
    println!(
        "frontiers: {} representatives in {:.1} ms",
        f.len(),
        t.elapsed().as_secs_f64() * 1e3
    );
}
