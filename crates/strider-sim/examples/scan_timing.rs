//! Times simulated scans: a 160×120 RGB-D scan on a `courtyard-small`-sized world and a
//! ~35k-ray omnidirectional scan on a `courtyard-large`-sized world (200 × 250 cells) with walls.
//!
//! Also times the coverage harness on the large world: a coverage path and the ground-truth
//! visibility of an omnidirectional sensor from poses along it.
//!
//! `cargo run --release -p strider-sim --example scan_timing`

use std::time::Instant;

use strider_core::{Cell, CellRect, Point3, Pose2, Rgb8};
use strider_scenario::{GaitSpec, RobotProfile, SensorKind, SensorSpec, World};
use strider_sim::{Heightfield, RangeSensor, ScanNoise, coverage_path, visible_cells};

fn world(w: u32, h: u32, d: f64) -> World {
    let n = (w * h) as usize;
    let mut elevation = vec![0.0f32; n];
    // Walls every 4 m with doors, boxes.
    for (k, z) in elevation.iter_mut().enumerate() {
        let (i, j) = (k as u32 % w, k as u32 / w);
        let x = i as f64 * d;
        let y = j as f64 * d;
        if (x % 4.0 < d && (y % 5.0) > 1.2)
            || ((x % 3.0 - 1.5).abs() < 0.3 && (y % 3.0 - 1.5).abs() < 0.3)
        {
            *z = 0.6;
        }
    }
    World {
        resolution: d,
        rect: CellRect::new(Cell::new(0, 0), w, h),
        elevation,
        color: vec![Rgb8::new(128, 128, 128); n],
        terrain: vec![0; n],
        terrains: Vec::new(),
    }
}

fn time(name: &str, spec: SensorSpec, world: &World, origin: Point3) {
    let hf = Heightfield::from_world(world).unwrap();
    let s = RangeSensor::new(&spec, name).unwrap();
    let noise = ScanNoise {
        depth_sigma: 0.003,
        depth_k: 0.0015,
        color_sigma: 4.0,
    };
    let runs = 50;
    let mut points = 0;
    let t = Instant::now();
    for k in 0..runs {
        let yaw = k as f64 * 0.37;
        points += s
            .scan(&hf, &world.color, origin, yaw, &noise, 0.0, 1, k)
            .points
            .len();
    }
    let ms = t.elapsed().as_secs_f64() * 1000.0 / runs as f64;
    println!(
        "{name}: {} rays, {} points/scan, {ms:.2} ms/scan ({} threads)",
        s.ray_count(),
        points / runs as usize,
        rayon::current_num_threads()
    );
}

fn main() {
    let small = world(120, 100, 0.05);
    time(
        "rgbd 160x120",
        SensorSpec {
            kind: SensorKind::RgbD {
                hfov_deg: 87.0,
                vfov_deg: 58.0,
                width: 160,
                height: 120,
                tilt_deg: 20.0,
            },
            range: 2.5,
            height: 0.3,
            yaw_deg: 0.0,
            rate_hz: 5.0,
        },
        &small,
        Point3::new(3.1, 2.45, 0.3),
    );
    let large = world(200, 250, 0.1);
    let omni = SensorSpec {
        kind: SensorKind::Omni {
            min_elevation_deg: -30.0,
            max_elevation_deg: 15.0,
            columns: 1440,
            rows: 24,
        },
        range: 10.0,
        height: 0.5,
        yaw_deg: 0.0,
        rate_hz: 2.0,
    };
    time(
        "omni 1440x24",
        omni.clone(),
        &large,
        Point3::new(10.25, 12.35, 0.5),
    );

    let robot = RobotProfile {
        name: "hexapod-large".into(),
        gaits: vec![GaitSpec {
            name: "fast".into(),
            max_speed: 0.25,
        }],
        sensors: vec![omni.clone()],
        footprint_radius: 0.4,
        body: None,
        mass_kg: 10.0,
        hotel_load_w: 0.0,
        max_step_m: 0.25,
        turn_rate: 0.5,
        bumper: false,
        max_push_force_n: 0.0,
    };
    let t = Instant::now();
    let path = coverage_path(&large, &robot, Pose2::new(2.05, 2.05, 0.0), 2.0);
    let len: f64 = path.windows(2).map(|w| w[0].dist(w[1])).sum();
    println!(
        "coverage_path 200x250, lanes 2 m: {} waypoints, {len:.0} m, {:.1} ms",
        path.len(),
        t.elapsed().as_secs_f64() * 1000.0
    );
    // Poses every 2 m along the path.
    let mut poses = Vec::new();
    let mut acc = 0.0;
    for w in path.windows(2) {
        acc += w[0].dist(w[1]);
        if acc >= 2.0 {
            acc = 0.0;
            poses.push(Pose2::new(w[1].x, w[1].y, 0.0));
        }
    }
    let t = Instant::now();
    let vis = visible_cells(&large, &omni, &poses);
    println!(
        "visible_cells 200x250 omni from {} poses: {:.1} % seen, {:.1} ms",
        poses.len(),
        100.0 * vis.iter().filter(|&&v| v).count() as f64 / vis.len() as f64,
        t.elapsed().as_secs_f64() * 1000.0
    );
}
