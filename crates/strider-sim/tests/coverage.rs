//! The coverage harness: paths over admissible cells and ground-truth visibility.
mod common;

use common::*;
use strider_core::interface::Robot;
use strider_core::{Cell, Point2, Pose2};
use strider_scenario::World;
use strider_sim::{Simulator, admissible_cells, coverage_path, visible_cells};

/// Two rooms joined by a door, a box in the first, and a sealed room in the corner.
fn rooms() -> World {
    let mut w = flat_world(60, 50, 0.1);
    fill(&mut w, 30, 32, 0, 50, 0.6, WALL); // dividing wall
    fill(&mut w, 30, 32, 20, 28, 0.0, GROUND); // door
    fill(&mut w, 10, 16, 10, 14, 0.4, WALL); // box
    fill(&mut w, 45, 47, 35, 50, 0.6, WALL); // sealed corner room
    fill(&mut w, 45, 60, 35, 37, 0.6, WALL);
    w
}

fn seg_dist(p: Point2, a: Point2, b: Point2) -> f64 {
    let (dx, dy) = (b.x - a.x, b.y - a.y);
    let l2 = dx * dx + dy * dy;
    let t = if l2 > 0.0 {
        (((p.x - a.x) * dx + (p.y - a.y) * dy) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    p.dist(Point2::new(a.x + t * dx, a.y + t * dy))
}

#[test]
fn coverage_path_stays_admissible_and_covers_the_reachable_area() {
    let world = rooms();
    let robot = robot(Vec::new());
    let adm = admissible_cells(&world, &robot);
    let start = Pose2::new(0.53, 0.57, 0.3);
    let spacing = 1.0;
    let path = coverage_path(&world, &robot, start, spacing);
    assert!(path.len() > 10);
    assert_eq!(path[0], Cell::new(5, 5).center(0.1));
    // Every point of every segment lies on an admissible cell.
    for w in path.windows(2) {
        let n = (w[0].dist(w[1]) / 0.005).ceil() as usize;
        for k in 0..=n {
            let t = k as f64 / n.max(1) as f64;
            let p = Point2::new(
                w[0].x + t * (w[1].x - w[0].x),
                w[0].y + t * (w[1].y - w[0].y),
            );
            let idx = world.index_at(p).unwrap();
            assert!(
                adm[idx],
                "segment {:?} leaves the admissible area at {p:?}",
                w
            );
        }
    }
    // Every reachable admissible cell is within spacing/2 of the path; the sealed room is not
    // visited.
    let mut covered = 0;
    for (k, &admissible) in adm.iter().enumerate() {
        let c = world.rect.cell(k);
        let sealed = c.i >= 47 && c.j >= 37;
        if !admissible {
            continue;
        }
        let centre = c.center(0.1);
        let d = path
            .windows(2)
            .map(|w| seg_dist(centre, w[0], w[1]))
            .fold(f64::INFINITY, f64::min);
        if sealed {
            assert!(d > 0.1, "sealed cell {c:?} visited");
        } else {
            assert!(d <= spacing / 2.0 + 1e-9, "cell {c:?} is {d} from the path");
            covered += 1;
        }
    }
    assert!(covered > 1500);
    // Both rooms are visited.
    assert!(path.iter().any(|p| p.x > 4.0));
    assert!(path.iter().any(|p| p.x < 2.0));

    // The simulated robot can drive it to the end.
    let mut sc = scenario(world.clone(), robot.clone(), noiseless(), start);
    sc.robot.gaits[0].max_speed = 1.0;
    let mut sim = Simulator::new(&sc, 1).unwrap();
    sim.follow(&path);
    let mut st = Default::default();
    while sim.now() < 3000.0 {
        st = sim.advance(5.0, &mut ()).unwrap();
        if st.idle || st.blocked {
            break;
        }
    }
    assert!(st.idle && !st.blocked, "{st:?} at {:?}", sim.pose());
    assert!(sim.pose().position().dist(*path.last().unwrap()) <= 0.05);
}

#[test]
fn inadmissible_start_snaps_to_the_nearest_admissible_cell() {
    let world = rooms();
    let robot = robot(Vec::new());
    let path = coverage_path(&world, &robot, Pose2::new(3.05, 0.55, 0.0), 2.0);
    let adm = admissible_cells(&world, &robot);
    assert!(adm[world.index_at(path[0]).unwrap()]);
    assert!(path[0].dist(Point2::new(3.05, 0.55)) < 0.35);
}

#[test]
fn visibility_respects_walls_range_and_fov() {
    let mut world = flat_world(80, 40, 0.1);
    fill(&mut world, 40, 41, 0, 40, 0.3, WALL);
    let pose = Pose2::new(2.05, 2.05, 0.0);
    let vis = visible_cells(&world, &omni(360, 16, 5.0), &[pose]);
    let at = |x: f64, y: f64| vis[world.index_at(Point2::new(x, y)).unwrap()];
    assert!(at(3.0, 2.0) && at(1.0, 3.0) && at(3.5, 0.5));
    assert!(at(4.05, 2.05), "the wall top");
    assert!(!at(4.5, 2.0), "behind the wall");
    assert!(
        !at(2.05, 2.05),
        "below the sensor, outside the elevation limits"
    );
    // A wall top exactly at sensor height (omni at 0.5 m) is seen edge-on only: not visible,
    // though the ground in front of it is.
    fill(&mut world, 40, 41, 0, 40, 0.5, WALL);
    let vis = visible_cells(&world, &omni(360, 16, 5.0), &[pose]);
    assert!(!vis[world.index_at(Point2::new(4.05, 2.05)).unwrap()]);
    assert!(vis[world.index_at(Point2::new(3.95, 2.05)).unwrap()]);
    // A taller wall hides its own top from a lower sensor.
    fill(&mut world, 40, 41, 0, 40, 1.0, WALL);
    let vis = visible_cells(&world, &omni(360, 16, 5.0), &[pose]);
    assert!(!vis[world.index_at(Point2::new(4.05, 2.05)).unwrap()]);
    // Beyond range (5 m) nothing.
    let mut far = flat_world(120, 40, 0.1);
    fill(&mut far, 0, 120, 0, 40, 0.0, GROUND);
    let vis = visible_cells(&far, &omni(360, 16, 5.0), &[pose]);
    assert!(vis[far.index_at(Point2::new(6.5, 2.05)).unwrap()]);
    assert!(!vis[far.index_at(Point2::new(7.2, 2.05)).unwrap()]);
    // A forward RGB-D camera does not see behind itself; two poses see the union.
    let cam = rgbd(16, 12, 2.5);
    let vis = visible_cells(&far, &cam, &[pose]);
    let at = |v: &[bool], x: f64, y: f64| v[far.index_at(Point2::new(x, y)).unwrap()];
    assert!(at(&vis, 3.0, 2.05));
    assert!(!at(&vis, 1.0, 2.05));
    let back = Pose2::new(2.05, 2.05, std::f64::consts::PI);
    let both = visible_cells(&far, &cam, &[pose, back]);
    assert!(at(&both, 3.0, 2.05) && at(&both, 1.0, 2.05));
}

/// A lane spacing far wider than the world (or not a number) still gives a bounded path over
/// the reachable area.
#[test]
fn any_lane_spacing_gives_a_bounded_path() {
    let world = rooms();
    let robot = robot(Vec::new());
    let start = Pose2::new(0.53, 0.57, 0.0);
    let wide = coverage_path(&world, &robot, start, 1e9);
    let diagonal = coverage_path(&world, &robot, start, 6.0_f64.hypot(5.0));
    assert_eq!(wide, diagonal);
    assert!(!wide.is_empty() && wide.len() < 100, "{}", wide.len());
    for spacing in [f64::NAN, f64::INFINITY, -1.0, 0.0, 1e-9, 1e300] {
        let p = coverage_path(&world, &robot, start, spacing);
        assert!(!p.is_empty(), "{spacing}");
    }
}
