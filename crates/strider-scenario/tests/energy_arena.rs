//! The arena rule of `energy-arena` (decision 27) for world seeds 1–20, on the ground truth and
//! with the tour planner that `strider tours` drives: the carpet covers at least 85 % of the
//! shortest tour through the base and the three waypoints, and a tour over timber alone is at
//! most 10 % longer. Also the powers of decision 28.

use strider_core::{GaitId, Point2};
use strider_explore::energy_tours::{EnergyMap, EnergyTourParams, PlannedTour, TourPlanner};
use strider_scenario::{Scenario, builtin};

const CARPET: u8 = 1;

/// Carpet a tour may touch at cell corners, metres (a few millimetre samples).
const TOUCH_M: f64 = 0.01;

fn arena(seed: u64) -> Scenario {
    builtin::generate("energy-arena", seed).unwrap_or_else(|e| panic!("seed {seed}: {e}"))
}

fn params(s: &Scenario) -> EnergyTourParams {
    let t = &s.tours[0];
    EnergyTourParams::new(
        t.waypoints.clone(),
        t.closed,
        s.bounds.min,
        s.bounds.max,
        s.map.cell_size,
        GaitId(0),
        s.robot.gaits[0].max_speed,
        s.robot.hotel_load_w,
        s.robot.mass_kg,
    )
}

/// The cheapest tour when every cell costs `motive(terrain)` J/m on top of the hotel load.
fn plan(s: &Scenario, p: &EnergyTourParams, motive: impl Fn(u8) -> f32) -> PlannedTour {
    let mut planner = TourPlanner::new(p).unwrap();
    let rect = planner.rect();
    let mean = rect
        .cells()
        .map(|c| motive(s.world.terrain[s.world.index_at(c.center(p.cell_size)).unwrap()]))
        .collect::<Vec<f32>>();
    let map = EnergyMap {
        rect,
        cell_size: p.cell_size,
        variance: vec![0.0; mean.len()],
        mean,
        bins: Vec::new(),
    };
    let grid = planner.cost_grid(&map, p).unwrap();
    planner.plan(&grid).unwrap()
}

/// Length of `path` on carpet and in all, metres (ground truth under each millimetre).
fn carpet_and_length(s: &Scenario, path: &[Point2]) -> (f64, f64) {
    let (mut carpet, mut all) = (0.0, 0.0);
    for w in path.windows(2) {
        let len = w[0].dist(w[1]);
        let n = (len / 0.001).ceil().max(1.0) as usize;
        for k in 0..n {
            let f = (k as f64 + 0.5) / n as f64;
            let q = Point2::new(
                w[0].x + f * (w[1].x - w[0].x),
                w[0].y + f * (w[1].y - w[0].y),
            );
            let k = s.world.index_at(q).unwrap();
            if s.world.terrain[k] == CARPET {
                carpet += len / n as f64;
            }
        }
        all += len;
    }
    (carpet, all)
}

#[test]
fn carpet_blocks_the_shortest_tour_and_a_timber_tour_skirts_it() {
    for seed in 1..=20 {
        let s = arena(seed);
        let p = params(&s);
        let shortest = plan(&s, &p, |_| 0.0);
        let (on_carpet, len) = carpet_and_length(&s, &shortest.path);
        assert!((len - shortest.length_m).abs() < 1e-6);
        let share = on_carpet / len;
        assert!(
            share >= 0.85,
            "seed {seed}: {share:.3} of the shortest tour on carpet"
        );
        // A carpet cell costs far more than any detour: the tour avoids carpet if it can.
        let skirting = plan(&s, &p, |t| if t == CARPET { 1e4 } else { 0.0 });
        let (skirt_carpet, skirt_len) = carpet_and_length(&s, &skirting.path);
        // Its diagonal steps pass the corners of carpet cells: a millimetre sample there may
        // round into the carpet cell.
        assert!(
            skirt_carpet < TOUCH_M,
            "seed {seed}: skirting tour has {skirt_carpet:.4} m on carpet"
        );
        let longer = skirt_len / len - 1.0;
        assert!(
            (0.0..=0.10).contains(&longer),
            "seed {seed}: skirting tour {skirt_len:.3} m against {len:.3} m"
        );
        // On the true costs the planner takes the skirting tour: the bound learning aims at.
        let truth = |t| if t == CARPET { 10.0 } else { 4.2 };
        let known = plan(&s, &p, truth);
        let (known_carpet, _) = carpet_and_length(&s, &known.path);
        assert!(known_carpet < TOUCH_M, "seed {seed}: {known_carpet:.4} m");
        let shortest_j = 12.1 * on_carpet + 6.3 * (len - on_carpet);
        assert!(
            known.predicted_energy_j < 0.65 * shortest_j,
            "seed {seed}: {:.1} J against {shortest_j:.1} J",
            known.predicted_energy_j
        );
    }
}

#[test]
fn powers_are_the_papers_totals_with_the_hotel_load() {
    let s = arena(1);
    assert_eq!(s.robot.hotel_load_w, 0.21);
    let total = |name: &str| {
        let t = s.world.terrains.iter().find(|t| t.name == name).unwrap();
        t.gaits["drive"].power_w + s.robot.hotel_load_w
    };
    assert!((total("timber") - 0.63).abs() < 1e-12);
    assert!((total("grey carpet") - 1.21).abs() < 1e-12);
}

#[test]
fn world_seeds_vary_the_arena() {
    let tours: Vec<Vec<Point2>> = (1..=20)
        .map(|k| arena(k).tours[0].waypoints.clone())
        .collect();
    let distinct = (0..tours.len())
        .filter(|&a| (0..a).all(|b| tours[a] != tours[b]))
        .count();
    assert!(distinct >= 18, "{distinct} distinct tours in 20 seeds");
}
