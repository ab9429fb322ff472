//! The exploration tour and paths on a small synthetic map.

use proptest::prelude::*;
use std::borrow::Cow;
use strider_core::{Cell, CellRect, GaitId, Point2, Rgb8};
use strider_explore::params::TourSolver;
use strider_explore::planner::{
    CostMode, GoalKey, PlanningView, TourGoal, TourOrder, farthest_point_subsample, horizon,
    plan_tour, window_around,
};
use strider_learn::cost_model::{CostModelParams, GaitCostModel};
use strider_map::ElevationMap;
use strider_map::params::MapParams;
use strider_plan::grid::Dijkstra;

/// A 40 × 30 flat map with a wall (0.5 m) across x = 20 for rows 0..22, leaving a gap at the top.
fn map() -> ElevationMap {
    let mut m = ElevationMap::new(MapParams {
        cell_size: 0.05,
        r_robot: 0.1,
        ..MapParams::default()
    });
    for c in CellRect::new(Cell::new(0, 0), 40, 30).cells() {
        let wall = c.i == 20 && c.j < 22;
        m.set_cell(c, if wall { 0.5 } else { 0.0 }, 1e-4, Rgb8([128, 128, 128]));
    }
    m.update_passability();
    m
}

fn models() -> Vec<GaitCostModel> {
    (0..2)
        .map(|g| GaitCostModel::new(GaitId(g), 9, CostModelParams::default(), 1).unwrap())
        .collect()
}

#[test]
fn paths_avoid_inadmissible_cells_and_go_around_the_wall() {
    let m = map();
    let view = PlanningView::build(&m, &models(), CostMode::Flat, 10.0, None).unwrap();
    let mut dij = Dijkstra::new();
    let path = view
        .path(&mut dij, Cell::new(5, 5), Cell::new(35, 5))
        .expect("reachable through the gap");
    for c in &path {
        assert!(m.is_admissible(*c), "{c:?} inadmissible");
    }
    assert!(path.iter().any(|c| c.j >= 22), "detours through the gap");
}

#[test]
fn a_robot_in_the_first_cell_of_its_path_does_not_walk_to_that_cell_centre_first() {
    let m = map();
    let view = PlanningView::build(&m, &models(), CostMode::Flat, 10.0, None).unwrap();
    let path = view
        .path(&mut Dijkstra::new(), Cell::new(5, 5), Cell::new(15, 5))
        .unwrap();
    let all = view.drive_waypoints(&path);
    let centre = Point2::new(0.275, 0.275);
    assert!(all[0].dist(centre) < 1e-9 && all.len() >= 2);
    // Standing past the centre of cell (5, 5), behind it as seen from the goal.
    let inside = view.drive_waypoints_from(&path, Point2::new(0.26, 0.29));
    assert_eq!(inside, all[1..].to_vec());
    // Standing in the admissible cell next to it: straight to the goal as well.
    let beside = view.drive_waypoints_from(&path, Point2::new(0.22, 0.29));
    assert_eq!(beside, all[1..].to_vec());
}

#[test]
fn a_robot_off_the_admissible_grid_first_walks_back_onto_its_path() {
    let m = map();
    let view = PlanningView::build(&m, &models(), CostMode::Flat, 10.0, None).unwrap();
    // Cell (19, 5) touches the wall at i = 20 with the 0.1 m footprint.
    assert!(!view.grid.cost(Cell::new(19, 5)).unwrap().is_finite());
    let path = view
        .path(&mut Dijkstra::new(), Cell::new(15, 5), Cell::new(5, 5))
        .unwrap();
    let pts = view.drive_waypoints_from(&path, Point2::new(0.97, 0.28));
    assert_eq!(
        pts,
        vec![Point2::new(0.775, 0.275), Point2::new(0.275, 0.275)]
    );
}

#[test]
fn a_straight_cheapest_route_is_driven_along_the_exact_segment() {
    let m = map();
    let view = PlanningView::build(&m, &models(), CostMode::Flat, 10.0, None).unwrap();
    let (from, to) = (Point2::new(0.26, 0.29), Point2::new(0.79, 0.31));
    let path = view
        .path(&mut Dijkstra::new(), Cell::new(5, 5), Cell::new(15, 6))
        .unwrap();
    // Not through the centre of the goal's cell, (0.775, 0.325), first.
    assert_eq!(view.drive_waypoints_between(&path, from, to), vec![to]);
}

#[test]
fn the_tour_visits_one_site_per_reachable_goal_and_skips_unreachable_ones() {
    let m = map();
    let view = PlanningView::build(&m, &models(), CostMode::Flat, 10.0, None).unwrap();
    let goals = vec![
        TourGoal {
            key: GoalKey::Spatial(Cell::new(35, 5)),
            sites: vec![Cell::new(35, 5)],
        },
        TourGoal {
            key: GoalKey::Cost { gait: 1, class: 3 },
            sites: vec![Cell::new(10, 25), Cell::new(30, 25)],
        },
        TourGoal {
            key: GoalKey::Spatial(Cell::new(20, 5)),
            // On the wall: never reachable.
            sites: vec![Cell::new(20, 5)],
        },
    ];
    for greedy in [false, true] {
        let tour = plan_tour(&view, Cell::new(5, 5), &goals, order(greedy), 1, &[], None).unwrap();
        if greedy {
            assert_eq!(tour.order.len(), 1);
            continue;
        }
        assert_eq!(tour.order.len(), 2);
        let keys: Vec<GoalKey> = tour.order.iter().map(|o| o.0).collect();
        assert!(keys.contains(&goals[0].key) && keys.contains(&goals[1].key));
        // The cost goal is on the way through the gap: visited first, from its nearer site.
        assert_eq!(tour.order[0], (goals[1].key, Cell::new(10, 25)));
    }
}

#[test]
fn a_warm_started_replan_keeps_the_standing_tour_and_drops_what_is_gone() {
    let m = map();
    let view = PlanningView::build(&m, &models(), CostMode::Flat, 10.0, None).unwrap();
    let goals: Vec<TourGoal> = [(35, 5), (10, 25), (30, 25), (5, 15)]
        .iter()
        .map(|&(i, j)| TourGoal {
            key: GoalKey::Spatial(Cell::new(i, j)),
            sites: vec![Cell::new(i, j)],
        })
        .collect();
    let cold = plan_tour(&view, Cell::new(5, 5), &goals, order(false), 1, &[], None).unwrap();
    assert_eq!(cold.order.len(), 4);
    // Re-solving from its own tour finds the same order and cost.
    let warm = plan_tour(
        &view,
        Cell::new(5, 5),
        &goals,
        order(false),
        1,
        &cold.order,
        None,
    )
    .unwrap();
    assert_eq!(warm.order, cold.order);
    assert_eq!(warm.cost, cold.cost);
    // A previous tour naming goals that are gone, sites that moved and a goal not yet known:
    // the stale entries are dropped, the new goal inserted, every goal visited once.
    let mut previous = vec![(GoalKey::Spatial(Cell::new(1, 1)), Cell::new(1, 1))];
    previous.extend(cold.order.iter().skip(1).copied());
    previous.push((goals[1].key, Cell::new(11, 25)));
    let fewer = &goals[1..];
    let t = plan_tour(
        &view,
        Cell::new(5, 5),
        fewer,
        order(false),
        1,
        &previous,
        None,
    )
    .unwrap();
    let mut keys: Vec<GoalKey> = t.order.iter().map(|o| o.0).collect();
    keys.sort();
    let mut want: Vec<GoalKey> = fewer.iter().map(|g| g.key).collect();
    want.sort();
    assert_eq!(keys, want);
    assert!(t.cost.is_finite() && t.vertices == 4);
}

#[test]
fn a_committed_goal_comes_first_and_the_rest_is_ordered_behind_it() {
    let m = map();
    let view = PlanningView::build(&m, &models(), CostMode::Flat, 10.0, None).unwrap();
    let mut goals: Vec<TourGoal> = [(6, 8), (10, 25), (30, 25), (35, 5)]
        .iter()
        .map(|&(i, j)| TourGoal {
            key: GoalKey::Spatial(Cell::new(i, j)),
            sites: vec![Cell::new(i, j)],
        })
        .collect();
    goals.push(TourGoal {
        key: GoalKey::Spatial(Cell::new(20, 5)),
        sites: vec![Cell::new(20, 5)], // on the wall: unreachable
    });
    let robot = Cell::new(5, 5);
    let free = plan_tour(&view, robot, &goals, order(false), 1, &[], None).unwrap();
    assert_eq!(
        free.order[0].0, goals[0].key,
        "the nearest goal starts the free tour"
    );
    for greedy in [false, true] {
        // Committed to the far goal behind the wall.
        let t = plan_tour(&view, robot, &goals, order(greedy), 1, &[], Some(3)).unwrap();
        assert_eq!(
            t.order[0],
            (goals[3].key, Cell::new(35, 5)),
            "greedy={greedy}"
        );
        if !greedy {
            assert_eq!(t.order.len(), 4);
            assert!(t.cost > free.cost);
            // Behind the committed goal the tour is the cheapest one: it continues to the
            // nearer of the two remaining top goals rather than back to the start.
            assert_eq!(t.order[1].0, goals[2].key);
        }
        // A committed goal that is unreachable, or out of range, commits to nothing.
        for first in [Some(4), Some(99)] {
            let u = plan_tour(&view, robot, &goals, order(greedy), 1, &[], first).unwrap();
            assert_eq!(
                u.order[0].0, goals[0].key,
                "greedy={greedy} first={first:?}"
            );
        }
    }
}

#[test]
fn a_bounded_horizon_plans_over_the_nearest_goals_and_keeps_the_committed_one() {
    let m = map();
    let view = PlanningView::build(&m, &models(), CostMode::Flat, 10.0, None).unwrap();
    let spatial = |i: i32, j: i32| TourGoal {
        key: GoalKey::Spatial(Cell::new(i, j)),
        sites: vec![Cell::new(i, j)],
    };
    let goals = vec![
        spatial(35, 5),
        TourGoal {
            key: GoalKey::Cost { gait: 1, class: 3 },
            sites: vec![Cell::new(9, 9), Cell::new(10, 25)],
        },
        spatial(8, 5),
        spatial(30, 25),
        spatial(5, 15),
    ];
    let robot = Cell::new(5, 5);
    let keys = |t: &strider_explore::planner::Tour| {
        let mut k: Vec<GoalKey> = t.order.iter().map(|o| o.0).collect();
        k.sort();
        k
    };
    let sorted = |mut k: Vec<GoalKey>| {
        k.sort();
        k
    };
    // The tour over the goals of the horizon, with the committed goal first.
    let bounded = |max_sites: usize, first: Option<usize>| {
        let (near, near_first) = horizon(&goals, robot, first, Some(max_sites));
        assert_eq!(
            matches!(near, Cow::Borrowed(_)),
            max_sites >= 6,
            "borrowed iff all"
        );
        plan_tour(&view, robot, &near, order(false), 1, &[], near_first).unwrap()
    };
    // Six sites: a bound of six (or more) plans over every goal, as without one.
    let all = plan_tour(&view, robot, &goals, order(false), 1, &[], None).unwrap();
    assert_eq!(bounded(6, None).order, all.order);
    // Four sites: the nearest ones, (8, 5), (9, 9) and (10, 25) of the cost goal, (5, 15);
    // (30, 25) and (35, 5) no longer fit.
    let near = bounded(4, None);
    assert_eq!(
        keys(&near),
        sorted(vec![goals[1].key, goals[2].key, goals[4].key])
    );
    // Committed to the farthest goal: it comes first and takes its place in the horizon; the
    // cost goal keeps only its site within the horizon.
    let committed = bounded(3, Some(0));
    assert_eq!(committed.order[0].0, goals[0].key);
    assert_eq!(
        keys(&committed),
        sorted(vec![goals[0].key, goals[1].key, goals[2].key])
    );
    let (near, near_first) = horizon(&goals, robot, Some(0), Some(3));
    assert_eq!(near_first, Some(0));
    let sites: Vec<Vec<Cell>> = near.iter().map(|g| g.sites.clone()).collect();
    assert_eq!(
        sites,
        vec![
            vec![Cell::new(35, 5)],
            vec![Cell::new(9, 9)],
            vec![Cell::new(8, 5)]
        ]
    );
    // A horizon smaller than the nearest goal still plans to that goal.
    assert_eq!(keys(&bounded(1, None)), vec![goals[2].key]);
}

#[test]
fn a_bounded_horizon_plans_on_a_window_around_the_robot_and_its_goals() {
    let m = map();
    let full = PlanningView::build(&m, &models(), CostMode::Flat, 10.0, None).unwrap();
    let spatial = |i: i32, j: i32| TourGoal {
        key: GoalKey::Spatial(Cell::new(i, j)),
        sites: vec![Cell::new(i, j)],
    };
    let goals = vec![spatial(12, 8), spatial(35, 5), spatial(9, 14)];
    let robot = Cell::new(5, 5);
    assert!(matches!(
        horizon(&goals, robot, None, None).0,
        Cow::Borrowed(_)
    ));
    assert!(matches!(
        horizon(&goals, robot, None, Some(3)).0,
        Cow::Borrowed(_)
    ));
    // Two of three sites: the window holds the robot and the two nearest goals, plus 3 cells.
    let (near, _) = horizon(&goals, robot, None, Some(2));
    let w = window_around(robot, &near, 3);
    assert_eq!(w, CellRect::new(Cell::new(2, 2), 14, 16));
    let view =
        PlanningView::build_within(&m, &models(), CostMode::Flat, 10.0, None, Some(w)).unwrap();
    assert_eq!(view.rect(), w);
    // Inside the window, away from its edge, the costs are those of the whole map's view.
    for c in CellRect::new(Cell::new(4, 4), 10, 12).cells() {
        assert_eq!(view.grid.cost(c), full.grid.cost(c), "{c:?}");
    }
    // A window off the map builds nothing.
    let off = CellRect::new(Cell::new(100, 100), 5, 5);
    assert!(
        PlanningView::build_within(&m, &models(), CostMode::Flat, 10.0, None, Some(off)).is_none()
    );
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(32))]

    #[test]
    fn farthest_point_subsample_keeps_k_distinct_sites(
        pts in proptest::collection::btree_set((0i32..50, 0i32..50), 1..60),
        k in 1usize..20,
    ) {
        let sites: Vec<Cell> = pts.iter().map(|&(i, j)| Cell::new(i, j)).collect();
        let sub = farthest_point_subsample(&sites, k);
        prop_assert_eq!(sub.len(), k.min(sites.len()));
        let mut dedup = sub.clone();
        dedup.sort();
        dedup.dedup();
        prop_assert_eq!(dedup.len(), sub.len());
        prop_assert!(sub.iter().all(|s| sites.contains(s)));
    }
}

/// The tour order of the GTSP explorer (default budget) or the greedy baseline.
fn order(greedy: bool) -> TourOrder<'static> {
    static SOLVER: std::sync::LazyLock<TourSolver> = std::sync::LazyLock::new(TourSolver::default);
    if greedy {
        TourOrder::CheapestNext
    } else {
        TourOrder::Gtsp(&SOLVER)
    }
}

proptest! {
    /// A bounded horizon keeps the `max_sites` nearest sites (the committed goal's first),
    /// each with its own goal, the goals in their order, and the committed goal's index.
    #[test]
    fn a_bounded_horizon_keeps_the_nearest_sites(
        sites in proptest::collection::vec(
            proptest::collection::vec((-20i32..20, -20i32..20), 1..5), 1..8),
        max_sites in 0usize..12,
        first in proptest::option::of(0usize..8),
    ) {
        let goals: Vec<TourGoal> = sites
            .iter()
            .enumerate()
            .map(|(g, s)| TourGoal {
                key: GoalKey::Cost { gait: 0, class: g as u32 },
                sites: s.iter().map(|&(i, j)| Cell::new(i, j)).collect(),
            })
            .collect();
        let first = first.filter(|&f| f < goals.len());
        let robot = Cell::new(0, 0);
        let (near, near_first) = horizon(&goals, robot, first, Some(max_sites));
        let total: usize = goals.iter().map(|g| g.sites.len()).sum();
        let kept: usize = near.iter().map(|g| g.sites.len()).sum();
        prop_assert_eq!(kept, total.min(max_sites.max(1)));
        // The committed goal always keeps a site.
        prop_assert_eq!(near_first.map(|i| near[i].key), first.map(|f| goals[f].key));
        // Goals in their order, each site one of its goal's.
        let order: Vec<u32> = near
            .iter()
            .map(|g| match g.key {
                GoalKey::Cost { class, .. } => class,
                _ => u32::MAX,
            })
            .collect();
        prop_assert!(order.windows(2).all(|w| w[0] < w[1]));
        for g in near.iter() {
            let GoalKey::Cost { class, .. } = g.key else { unreachable!() };
            for s in &g.sites {
                prop_assert!(goals[class as usize].sites.contains(s));
            }
        }
        // Every dropped site is at least as far as every kept one (the committed goal aside).
        if total > max_sites {
            let committed = first.map(|f| goals[f].key);
            let kept_far = near
                .iter()
                .filter(|g| Some(g.key) != committed)
                .flat_map(|g| g.sites.iter().map(|s| s.dist_cells(robot)))
                .fold(0.0f64, f64::max);
            for (g, goal) in goals.iter().enumerate() {
                if Some(g) == first {
                    continue;
                }
                let in_near = near.iter().find(|n| n.key == goal.key);
                for s in &goal.sites {
                    if !in_near.is_some_and(|n| n.sites.contains(s)) {
                        prop_assert!(s.dist_cells(robot) >= kept_far);
                    }
                }
            }
        }
    }
}
