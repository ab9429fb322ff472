//! The built-in scenarios: determinism, seed families, admissible start and waypoints, and the
//! per-world layout promises of each built-in world.

use strider_core::Point2;
use strider_scenario::ground_truth::{flood_fill, point_in_mask};
use strider_scenario::{Scenario, ScenarioError, builtin};

fn make(name: &str, seed: u64) -> Scenario {
    builtin::generate(name, seed).unwrap_or_else(|e| panic!("{name} seed {seed}: {e}"))
}

#[test]
fn every_builtin_is_deterministic_valid_and_admissible() {
    for &name in builtin::names() {
        assert!(builtin::describe(name).is_some_and(|d| !d.is_empty()));
        let mut layers = Vec::new();
        for seed in 1..=5 {
            let s = make(name, seed);
            assert_eq!(s, make(name, seed), "{name} seed {seed} not deterministic");
            s.validate(std::path::Path::new(name)).unwrap();
            let adm = s.world.gt_admissible(s.map.rho_obstacle, s.map.r_robot);
            assert!(
                point_in_mask(&s.world, &adm, s.start.position()),
                "{name} seed {seed}: start not admissible"
            );
            assert!(!s.tours.is_empty(), "{name}: no tours");
            for t in &s.tours {
                for (k, &p) in t.waypoints.iter().enumerate() {
                    assert!(
                        point_in_mask(&s.world, &adm, p),
                        "{name} seed {seed}: tour {} waypoint {k} not admissible",
                        t.name
                    );
                    assert!(s.bounds.contains(p), "{name}: waypoint outside bounds");
                }
            }
            // Every terrain response names a robot gait.
            for t in &s.world.terrains {
                for g in t.gaits.keys() {
                    assert!(
                        s.robot.gaits.iter().any(|r| &r.name == g),
                        "{name}: gait {g}"
                    );
                }
            }
            layers.push(s.world.terrain.clone());
        }
        for a in 0..layers.len() {
            for b in a + 1..layers.len() {
                assert_ne!(
                    layers[a],
                    layers[b],
                    "{name}: seeds {} and {} equal",
                    a + 1,
                    b + 1
                );
            }
        }
    }
}

#[test]
fn unknown_builtin_lists_the_valid_names() {
    let e = builtin::generate("courtyard-medium", 1).unwrap_err();
    let m = e.to_string();
    assert!(matches!(e, ScenarioError::UnknownBuiltin { .. }));
    for n in builtin::names() {
        assert!(m.contains(n), "{m}");
    }
    let e = Scenario::from_name_or_file("no/such/scenario.toml", 1).unwrap_err();
    assert!(e.to_string().contains("no such file"), "{e}");
    let s = Scenario::from_name_or_file("energy-arena", 3).unwrap();
    assert_eq!(s.world_seed, 3);
}

/// The ground-truth admissible cells of `s`, and those of them reachable from the start.
fn admissible_and_reachable(s: &Scenario) -> (Vec<bool>, Vec<bool>) {
    let w = &s.world;
    let adm = w.gt_admissible(s.map.rho_obstacle, s.map.r_robot);
    let start = w.index_at(s.start.position()).unwrap();
    let reach = flood_fill(&adm, w.width(), w.height(), start);
    (adm, reach)
}

fn on(s: &Scenario, p: Point2, set: &[u8]) -> bool {
    s.world
        .index_at(p)
        .is_some_and(|k| set.contains(&s.world.terrain[k]))
}

#[test]
fn courtyard_small_turf_and_tour_geometry() {
    let turf = [2u8, 3];
    let pave = [0u8, 1];
    for seed in 1..=5 {
        let s = make("courtyard-small", seed);
        let w = &s.world;
        assert_eq!(w.resolution, 0.05);
        assert_eq!((w.width(), w.height()), (120, 100));
        assert_eq!(s.map.c_radius, 0.5);
        assert_eq!(s.map.r_robot, 0.25);
        let frac =
            w.terrain.iter().filter(|t| turf.contains(t)).count() as f64 / w.terrain.len() as f64;
        assert!((0.28..=0.38).contains(&frac), "seed {seed}: turf {frac}");
        assert!(
            w.terrain.contains(&2) && w.terrain.contains(&3),
            "both turf kinds"
        );
        assert!(w.terrain.contains(&1), "red line");
        // Turf: fast stuck, tall 0.8; pavement 1.0.
        let t = w.terrain_type(2).unwrap();
        assert!(t.gaits["fast"].stuck);
        assert_eq!(t.gaits["tall"].speed_factor, 0.8);
        assert_eq!(w.terrain_type(0).unwrap().gaits["fast"].speed_factor, 1.0);

        let t1 = &s.tours[0].waypoints;
        assert_eq!(t1.len(), 4);
        assert_eq!(s.tours[1].waypoints.len(), 20);
        // Counter-clockwise from the bottom-left: BL, BR, TR, TL.
        let (bl, br, tr, tl) = (t1[0], t1[1], t1[2], t1[3]);
        assert!(bl.x < br.x && bl.y < tl.y && br.y < tr.y && tl.x < tr.x);
        let area: f64 = (0..4)
            .map(|k| {
                let (a, b) = (t1[k], t1[(k + 1) % 4]);
                a.x * b.y - b.x * a.y
            })
            .sum();
        assert!(area > 0.0, "counter-clockwise");
        assert_eq!(s.start.position(), bl);
        assert!(on(&s, tl, &turf), "top-left waypoint on turf");
        assert!(on(&s, br, &pave) && on(&s, tr, &pave) && on(&s, bl, &pave));
        // The straight BR→TR segment crosses turf …
        let crosses = (0..=200).any(|k| {
            let f = k as f64 / 200.0;
            on(
                &s,
                Point2::new(br.x + f * (tr.x - br.x), br.y + f * (tr.y - br.y)),
                &turf,
            )
        });
        assert!(crosses, "seed {seed}: BR→TR does not cross turf");
        // … while a pavement-only admissible detour exists.
        let adm = w.gt_admissible(s.map.rho_obstacle, s.map.r_robot);
        let pav: Vec<bool> = (0..adm.len())
            .map(|k| adm[k] && pave.contains(&w.terrain[k]))
            .collect();
        let reach = flood_fill(&pav, w.width(), w.height(), w.index_at(br).unwrap());
        assert!(
            reach[w.index_at(tr).unwrap()],
            "seed {seed}: no pavement detour"
        );
    }
}

#[test]
fn courtyard_large_is_connected() {
    for seed in 1..=10 {
        let s = make("courtyard-large", seed);
        let w = &s.world;
        assert_eq!((w.width(), w.height()), (200, 250));
        assert_eq!(s.map.r_robot, 0.40);
        assert_eq!(s.tours[0].waypoints.len(), 8);
        let (adm, reach) = admissible_and_reachable(&s);
        assert_eq!(
            reach, adm,
            "seed {seed}: admissible cells unreachable from the start"
        );
        // Walls/boxes are real obstacles: some impassable cells exist.
        assert!(adm.iter().filter(|a| !**a).count() > 1000);
    }
}

#[test]
fn escape_arena_curtains_separate_sections() {
    for seed in 1..=5 {
        let s = make("escape-arena", seed);
        let w = &s.world;
        let (_, reach) = admissible_and_reachable(&s);
        let sections = &s.tours[0].waypoints;
        assert_eq!(sections.len(), 3);
        assert!(point_in_mask(w, &reach, sections[0]));
        assert!(!point_in_mask(w, &reach, sections[1]) && !point_in_mask(w, &reach, sections[2]));
        let curtain = w.terrains.iter().find(|t| t.name == "curtain").unwrap();
        let f = curtain.push_force_n.unwrap();
        assert!((0.5..=1.0).contains(&f));
        assert!(f <= s.robot.max_push_force_n);
        for t in w.terrains.iter().filter(|t| t.name != "curtain") {
            assert!(t.push_force_n.is_none_or(|f| f >= 10.0), "{}", t.name);
        }
        let area = w.width() as f64 * w.height() as f64 * w.resolution * w.resolution;
        assert!((30.0..=40.0).contains(&area));
    }
}

#[test]
fn lab_track_roll_variance_table() {
    let s = make("lab-track", 1);
    let rv = |n: &str, g: &str| {
        s.world.terrains.iter().find(|t| t.name == n).unwrap().gaits[g].roll_variance
    };
    assert_eq!(rv("flat", "adaptive"), 0.005);
    assert_eq!(rv("cubes", "regular"), 2.0 * rv("cubes", "adaptive"));
    assert_eq!(rv("stairs", "regular"), 2.0 * rv("stairs", "adaptive"));
    assert_eq!(rv("grass", "regular"), rv("grass", "adaptive"));
}
