//! Hand-built worlds and scenarios for the simulator tests.
#![allow(dead_code)]

use std::collections::BTreeMap;

use strider_core::{Cell, CellRect, Point2, Pose2, Rgb8};
use strider_scenario::{
    Bounds, GaitResponse, GaitSpec, RobotProfile, Scenario, SensorKind, SensorSpec, SimParams,
    TerrainType, World,
};

/// Terrain indices of [`terrains`].
pub const GROUND: u8 = 0;
pub const SLOW: u8 = 1;
pub const TURF: u8 = 2;
pub const WALL: u8 = 3;
pub const CURTAIN: u8 = 4;
pub const ROUGH: u8 = 5;
pub const BOX: u8 = 6;

fn resp(speed_factor: f64, stuck: bool, roll_variance: f64, power_w: f64) -> GaitResponse {
    GaitResponse {
        speed_factor,
        stuck,
        roll_variance,
        power_w,
    }
}

fn terrain(index: u8, name: &str, fast: GaitResponse, tall: GaitResponse) -> TerrainType {
    let mut gaits = BTreeMap::new();
    gaits.insert("fast".to_string(), fast);
    gaits.insert("tall".to_string(), tall);
    TerrainType {
        index,
        name: name.into(),
        gaits,
        vibration: 0.0,
        energy_per_m: 1.0,
        push_force_n: None,
    }
}

/// The test terrain table.
pub fn terrains() -> Vec<TerrainType> {
    let level = resp(1.0, false, 0.0, 0.0);
    let pushable = resp(1.0, false, 0.0, 2.0);
    let slow = resp(0.5, false, 0.0, 2.0);
    // (index, name, fast gait, tall gait, vibration, push force)
    #[rustfmt::skip]
    let table = [
        (GROUND, "ground", resp(1.0, false, 0.005, 1.0), resp(1.0, false, 0.005, 1.5), 0.5, None),
        (SLOW, "slow", slow.clone(), slow, 2.5, None),
        (TURF, "turf", resp(1.0, true, 0.01, 3.0), resp(0.8, false, 0.01, 3.0), 0.5, None),
        (WALL, "wall", level.clone(), level, 0.5, None),
        (CURTAIN, "curtain", pushable.clone(), pushable.clone(), 0.5, Some(0.8)),
        (ROUGH, "rough", resp(1.0, false, 0.03, 4.0), resp(1.0, false, 0.06, 4.0), 0.5, None),
        (BOX, "box", pushable.clone(), pushable, 0.5, Some(15.0)),
    ];
    table
        .into_iter()
        .map(
            |(index, name, fast, tall, vibration, push_force_n)| TerrainType {
                vibration,
                push_force_n,
                ..terrain(index, name, fast, tall)
            },
        )
        .collect()
}

/// A flat world of `w × h` cells of size `d` at elevation 0, lower-left cell (0, 0).
pub fn flat_world(w: u32, h: u32, d: f64) -> World {
    let n = (w * h) as usize;
    World {
        resolution: d,
        rect: CellRect::new(Cell::new(0, 0), w, h),
        elevation: vec![0.0; n],
        color: (0..n)
            .map(|k| Rgb8::new((k % 200) as u8, 100, 50))
            .collect(),
        terrain: vec![GROUND; n],
        terrains: terrains(),
    }
}

/// Sets cells `[i0, i1) × [j0, j1)` to elevation `z` and terrain `t`.
pub fn fill(world: &mut World, i0: i32, i1: i32, j0: i32, j1: i32, z: f32, t: u8) {
    for j in j0..j1 {
        for i in i0..i1 {
            if let Some(k) = world.rect.index(Cell::new(i, j)) {
                world.elevation[k] = z;
                world.terrain[k] = t;
            }
        }
    }
}

/// An RGB-D sensor spec.
pub fn rgbd(width: u32, height: u32, range: f64) -> SensorSpec {
    SensorSpec {
        kind: SensorKind::RgbD {
            hfov_deg: 87.0,
            vfov_deg: 58.0,
            width,
            height,
            tilt_deg: 20.0,
        },
        range,
        height: 0.3,
        yaw_deg: 0.0,
        rate_hz: 5.0,
    }
}

/// An omnidirectional sensor spec.
pub fn omni(columns: u32, rows: u32, range: f64) -> SensorSpec {
    SensorSpec {
        kind: SensorKind::Omni {
            min_elevation_deg: -30.0,
            max_elevation_deg: 15.0,
            columns,
            rows,
        },
        range,
        height: 0.5,
        yaw_deg: 0.0,
        rate_hz: 2.0,
    }
}

/// A two-gait hexapod (fast 0.05 m/s, tall 0.0125 m/s) with the given sensors.
pub fn robot(sensors: Vec<SensorSpec>) -> RobotProfile {
    RobotProfile {
        name: "test-hexapod".into(),
        gaits: vec![
            GaitSpec {
                name: "fast".into(),
                max_speed: 0.05,
            },
            GaitSpec {
                name: "tall".into(),
                max_speed: 0.0125,
            },
        ],
        sensors,
        footprint_radius: 0.1,
        body: None,
        mass_kg: 3.0,
        hotel_load_w: 0.5,
        max_step_m: 0.25,
        turn_rate: 0.5,
        bumper: true,
        max_push_force_n: 3.0,
    }
}

/// Simulator parameters without any noise.
pub fn noiseless() -> SimParams {
    SimParams {
        depth_sigma: 0.0,
        depth_k: 0.0,
        color_sigma: 0.0,
        pose_sigma_xy: 0.0,
        pose_sigma_yaw: 0.0,
        speed_noise: 0.0,
        proprio_noise: 0.0,
        ..SimParams::default()
    }
}

/// A scenario of `world` with `robot` starting at `start`.
pub fn scenario(world: World, robot: RobotProfile, sim: SimParams, start: Pose2) -> Scenario {
    let d = world.resolution;
    let max = Point2::new(
        (world.rect.min.i as f64 + world.rect.width as f64) * d,
        (world.rect.min.j as f64 + world.rect.height as f64) * d,
    );
    Scenario {
        name: "test".into(),
        description: "hand-built test scenario".into(),
        world_seed: 0,
        world,
        robot,
        map: Default::default(),
        sim,
        strategy: Default::default(),
        start,
        bounds: Bounds {
            min: Point2::new(0.0, 0.0),
            max,
        },
        tours: Vec::new(),
        time_limit_s: 3600.0,
        elevation_encoding: Default::default(),
    }
}
