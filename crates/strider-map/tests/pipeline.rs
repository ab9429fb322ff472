//! End-to-end: fuse synthetic scans of a floor with a box, then passability, reachability,
//! information gain (Eq. 10–11), Alg. 3 goals, frontier representatives (Eq. 13) and
//! descriptors, as Prágr22 Alg. 2 runs them.

use strider_core::{Cell, ColoredPoint, Point2, Point3, PointCloud};
use strider_map::descriptors::{color_histograms, shape_lab_descriptors};
use strider_map::{
    ElevationMap, MapParams, Passability, Reachability, WorldRect, cluster_information,
    frontier_goals, information_gain, observable,
};

/// Ground truth: floor at 0, a 0.5 m box over x ∈ [1.0, 1.4), y ∈ [0.4, 1.2).
fn height(x: f32, y: f32) -> f32 {
    if (1.0..1.4).contains(&x) && (0.4..1.2).contains(&y) {
        0.5
    } else {
        0.0
    }
}

/// True when the straight beam from `o` to the surface point `p` is not blocked by the ground
/// truth before reaching it (sampled finely; the last 2 % are the target itself).
fn unoccluded(o: Point3, p: (f32, f32, f32)) -> bool {
    (1..=490).all(|k| {
        let t = k as f32 / 500.0;
        let (x, y) = (
            o.x as f32 + t * (p.0 - o.x as f32),
            o.y as f32 + t * (p.1 - o.y as f32),
        );
        height(x, y) <= o.z as f32 + t * (p.2 - o.z as f32) + 1e-4
    })
}

/// A scan of the visible top surfaces within `range` of the sensor, 4 × 4 returns per cell.
/// Returns the beam could not reach are left out: the map's ray carving relies on every beam
/// having travelled its path.
fn scan(origin: Point3, range: f32, d: f32) -> PointCloud {
    let mut points = Vec::new();
    let n = (range / d).ceil() as i32;
    let (ci, cj) = (
        (origin.x as f32 / d).floor() as i32,
        (origin.y as f32 / d).floor() as i32,
    );
    for j in cj - n..=cj + n {
        for i in ci - n..=ci + n {
            for s in 0..16 {
                let x = (i as f32 + 0.125 + 0.25 * (s % 4) as f32) * d;
                let y = (j as f32 + 0.125 + 0.25 * (s / 4) as f32) * d;
                if (x - origin.x as f32).hypot(y - origin.y as f32) > range
                    || !unoccluded(origin, (x, y, height(x, y)))
                {
                    continue;
                }
                let rgb = if x < 0.8 {
                    [50, 150, 50]
                } else {
                    [130, 90, 50]
                };
                points.push(ColoredPoint::new(x, y, height(x, y), rgb));
            }
        }
    }
    PointCloud::new(0.0, 0, origin, points)
}

#[test]
fn exploration_step_on_a_small_world() {
    let params = MapParams {
        cell_size: 0.1,
        tile_size: 16,
        r_sensor: 1.0,
        r_robot: 0.1,
        c_radius: 0.3,
        c_min_cells: 2,
        r_spatial: 0.2,
        ..MapParams::default()
    };
    let d = params.cell_size;
    let mut map = ElevationMap::new(params.clone());
    let origin = Point3::new(0.45, 0.85, 1.0);
    let stats = map.integrate(&scan(origin, 1.2, d as f32));
    assert!(stats.cells_updated > 300);
    assert_eq!(stats.skipped_non_finite, 0);

    // Geometry: box top known, its rim impassable, the floor passable.
    assert_eq!(map.elevation_at(1.15, 0.85), Some(0.5));
    assert_eq!(map.passability_at(1.05, 0.85), Passability::Impassable);
    assert_eq!(map.passability_at(0.95, 0.85), Passability::Impassable);
    assert_eq!(map.passability_at(0.45, 0.85), Passability::Passable);
    assert!(!map.is_admissible_at(0.85, 0.85), "inflated by r_robot");
    assert!(map.is_admissible_at(0.45, 0.85));

    let robot = map.cell_at(origin.x, origin.y).unwrap();
    let reach = Reachability::compute(&map, robot);
    assert!(reach.contains(robot));
    assert!(!reach.contains(map.cell_at(1.15, 0.85).unwrap()));

    // The box top hides the floor right behind it from the robot.
    assert!(!observable(
        &map,
        robot,
        map.cell_at(1.55, 0.85).unwrap(),
        0.3
    ));
    assert!(observable(
        &map,
        robot,
        map.cell_at(0.45, 1.85).unwrap(),
        0.3
    ));

    let gain = information_gain(&map, &reach, None);
    assert!(!gain.cells.is_empty());
    for &(c, g) in &gain.cells {
        assert!(g > 0.0 && reach.is_goal_cell(c));
    }
    let goals = cluster_information(&map, &gain, &reach, None);
    assert!(!goals.is_empty());
    for g in &goals {
        assert!(reach.is_goal_cell(g.cell));
        assert!(g.members > params.c_min_cells);
    }
    let total: f64 = goals.iter().map(|g| g.information).sum();
    assert!(total <= gain.total() + 1e-9);

    // Bounds west of x = 0.7 drop every goal east of it.
    let bounds = WorldRect::new(Point2::new(-5.0, -5.0), Point2::new(0.7, 5.0));
    let gain_b = information_gain(&map, &reach, Some(&bounds));
    for g in cluster_information(&map, &gain_b, &reach, Some(&bounds)) {
        assert!(bounds.contains_cell(g.cell, d));
    }

    let frontiers = frontier_goals(&map, &reach, robot, None);
    assert!(!frontiers.is_empty());
    for f in &frontiers {
        assert!(reach.is_goal_cell(f.cell));
        assert!(f.cell.dist_cells(robot) * d >= params.r_spatial);
    }

    // Descriptors over the known area: the interior has full neighbourhoods.
    let rect = map.known_bounds().unwrap();
    let hist = color_histograms(&map, rect, params.r_hist);
    let shape = shape_lab_descriptors(&map, rect, params.delta_desc);
    let inner = Cell::new(robot.i, robot.j);
    let h = hist.get(inner).unwrap().unwrap();
    assert!((h.iter().sum::<f32>() - 1.0).abs() < 1e-5);
    assert_eq!(h[4], 1.0, "green floor around the robot");
    let s = shape.get(inner).unwrap().unwrap();
    assert!((s[1] - 1.0).abs() < 1e-4, "flat floor is planar: {s:?}");

    // Rasters for rendering have one value per cell.
    assert_eq!(map.elevation_raster(rect).len(), rect.len());
    assert_eq!(map.color_raster(rect).len(), rect.len());
    assert_eq!(gain.raster(rect).len(), rect.len());
}
