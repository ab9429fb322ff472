//! The designed features of `courtyard-small`'s tour 1 (Prágr22 §5.1.1) for world seeds 1–20,
//! on the ground truth with the planner's grid search: beside the bottom-right → top-right
//! segment, whose straight line crosses turf, a pavement detour that the robot's footprint
//! drives without touching turf, at most 2.5 times the straight segment's length; and turf
//! around the top-left waypoint that no route avoids.

use strider_core::{Cell, Point2};
use strider_map::passability::{Passability, dense_admissible};
use strider_plan::grid::{CostGrid, Dijkstra};
use strider_scenario::builtin::courtyard_small::{TOP_LEFT_TURF_RADIUS_M, TURF};
use strider_scenario::ground_truth::flood_fill;
use strider_scenario::{Scenario, builtin};

/// The longest detour the test accepts, as a multiple of the straight segment.
const MAX_DETOUR_RATIO: f64 = 2.5;

fn world(seed: u64) -> Scenario {
    builtin::generate("courtyard-small", seed).unwrap_or_else(|e| panic!("seed {seed}: {e}"))
}

fn is_turf(s: &Scenario, k: usize) -> bool {
    TURF.contains(&s.world.terrain[k])
}

/// Where the robot's centre may be when its footprint must touch neither turf, nor an
/// obstacle, nor cells outside the exploration bounds (the planner's rule for the bounds).
fn turf_free_centres(s: &Scenario) -> Vec<bool> {
    let w = &s.world;
    let pass: Vec<Passability> = w
        .gt_passability(s.map.rho_obstacle)
        .into_iter()
        .enumerate()
        .map(|(k, p)| {
            if is_turf(s, k) || !s.bounds.contains(w.cell_center(k)) {
                Passability::Impassable
            } else {
                p
            }
        })
        .collect();
    dense_admissible(&pass, w.width(), w.height(), s.map.r_robot, w.resolution)
}

fn cell(s: &Scenario, p: Point2) -> Cell {
    Cell::containing(p.x, p.y, s.world.resolution).expect("waypoint on the lattice")
}

/// Length of the shortest path from `a` to `b` over the `mask` cells, metres (+∞: none).
fn shortest(s: &Scenario, mask: &[bool], a: Point2, b: Point2) -> f64 {
    let cost = mask
        .iter()
        .map(|&m| if m { 1.0 } else { f32::INFINITY })
        .collect();
    let grid = CostGrid::new(s.world.rect, s.world.resolution, cost).unwrap();
    Dijkstra::new()
        .astar(&grid, cell(s, a), cell(s, b))
        .unwrap()
}

#[test]
fn a_turf_free_pavement_detour_runs_beside_segment_two() {
    let mut ratios = Vec::new();
    for seed in 1..=20 {
        let s = world(seed);
        let (br, tr) = (s.tours[0].waypoints[1], s.tours[0].waypoints[2]);
        let straight = br.dist(tr);
        let on_turf = (0..=200).any(|k| {
            let f = k as f64 / 200.0;
            let p = Point2::new(br.x + f * (tr.x - br.x), br.y + f * (tr.y - br.y));
            is_turf(&s, s.world.index_at(p).unwrap())
        });
        assert!(on_turf, "seed {seed}: the straight segment 2 avoids turf");
        let detour = shortest(&s, &turf_free_centres(&s), br, tr);
        assert!(
            detour.is_finite(),
            "seed {seed}: no detour keeps the footprint off turf"
        );
        let ratio = detour / straight;
        assert!(
            ratio <= MAX_DETOUR_RATIO,
            "seed {seed}: detour {detour:.2} m against {straight:.2} m"
        );
        ratios.push(ratio);
    }
    let (lo, hi) = ratios
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(l, h), &r| (l.min(r), h.max(r)));
    let mean = ratios.iter().sum::<f64>() / ratios.len() as f64;
    eprintln!("detour / straight segment 2: {lo:.2}–{hi:.2}, mean {mean:.2}");
}

#[test]
fn no_route_to_the_top_left_waypoint_avoids_turf() {
    for seed in 1..=20 {
        let s = world(seed);
        let w = &s.world;
        let tl = s.tours[0].waypoints[3];
        let adm = w.gt_admissible(s.map.rho_obstacle, s.map.r_robot);
        let start = w.index_at(s.start.position()).unwrap();
        let reach = flood_fill(&adm, w.width(), w.height(), start);
        assert!(
            reach[w.index_at(tl).unwrap()],
            "seed {seed}: the top-left waypoint is unreachable"
        );
        // Off turf, the robot's centre gets no nearer to the waypoint than the turf radius:
        // every route drives at least that far over turf to reach it.
        let off_turf: Vec<bool> = (0..adm.len()).map(|k| adm[k] && !is_turf(&s, k)).collect();
        let dry = flood_fill(&off_turf, w.width(), w.height(), start);
        let nearest = (0..dry.len())
            .filter(|&k| dry[k])
            .map(|k| w.cell_center(k).dist(tl))
            .fold(f64::INFINITY, f64::min);
        assert!(
            nearest >= TOP_LEFT_TURF_RADIUS_M,
            "seed {seed}: pavement {nearest:.2} m from the top-left waypoint"
        );
    }
}
