//! Built-in robot profiles (the scenario format in docs/guide.md, "Scenarios and your own world").
//!
//! A scenario file selects one with `[robot] profile = "hexapod-small"` and may override any of
//! its keys; [`profile`] returns them by name.
//!
//! Sensor image sizes trade simulation speed against coverage:
//! * RGB-D cameras are 160 × 120 pixels. At 0.3 m height and 16° downward tilt the 58° vertical
//!   field sees the ground from 0.3 m out to beyond 2.5 m (the upper edge is 13° above the
//!   horizon, so walls are seen too). Columns are 0.54° apart (2.4 cm at 2.5 m, denser than the
//!   5 cm cells); rows are 0.48° apart, i.e. about 18 cm on the ground at 2.5 m, so far cells are
//!   filled in as the robot moves rather than in one scan.
//! * The omnidirectional sensor of `hexapod-large` has 720 columns (0.5°, 8.7 cm at 10 m, below
//!   the 10 cm cell) and 48 beams from −40° to +10° at 0.5 m height: the ground is hit from
//!   0.6 m outward, walls and boxes up to the full 10 m.

use crate::model::{GaitSpec, RobotProfile, SensorKind, SensorSpec};

/// Names of the built-in profiles.
pub const PROFILE_NAMES: [&str; 6] = [
    "hexapod-small",
    "hexapod-large",
    "hexapod-rss",
    "hexapod-bumper",
    "rover-small",
    "husky",
];

/// The built-in profile `name`, if there is one.
pub fn profile(name: &str) -> Option<RobotProfile> {
    Some(match name {
        "hexapod-small" => hexapod_small(),
        "hexapod-large" => hexapod_large(),
        "hexapod-rss" => hexapod_rss(),
        "hexapod-bumper" => hexapod_bumper(),
        "rover-small" => rover_small(),
        "husky" => husky(),
        _ => return None,
    })
}

fn gait(name: &str, max_speed: f64) -> GaitSpec {
    GaitSpec {
        name: name.to_string(),
        max_speed,
    }
}

/// The 160 × 120 RGB-D camera (87° × 58°, tilted 16° down) at `height`, range `range`,
/// mounted at heading `yaw_deg`.
fn rgbd(range: f64, height: f64, yaw_deg: f64) -> SensorSpec {
    SensorSpec {
        kind: SensorKind::RgbD {
            hfov_deg: 87.0,
            vfov_deg: 58.0,
            width: 160,
            height: 120,
            tilt_deg: 16.0,
        },
        range,
        height,
        yaw_deg,
        rate_hz: 5.0,
    }
}

/// Prágr22 real robot / small simulation: gaits fast 0.05 and tall 0.0125 m/s (Table 2), RGB-D
/// 87°, 2.5 m range at 0.3 m, r_robot 0.25 m.
pub fn hexapod_small() -> RobotProfile {
    RobotProfile {
        name: "hexapod-small".into(),
        gaits: vec![gait("fast", 0.05), gait("tall", 0.0125)],
        sensors: vec![rgbd(2.5, 0.3, 0.0)],
        footprint_radius: 0.25,
        body: None,
        mass_kg: 3.0,
        hotel_load_w: 0.0,
        max_step_m: 0.15,
        turn_rate: 0.3,
        bumper: false,
        max_push_force_n: 0.0,
    }
}

/// Prágr22 large simulation: gaits fast 0.25 and tall 0.0625 m/s, omnidirectional 10 m sensor
/// (720 × 48 beams, −40°…+10°, 0.5 m high), r_robot 0.40 m.
pub fn hexapod_large() -> RobotProfile {
    RobotProfile {
        name: "hexapod-large".into(),
        gaits: vec![gait("fast", 0.25), gait("tall", 0.0625)],
        sensors: vec![SensorSpec {
            kind: SensorKind::Omni {
                min_elevation_deg: -40.0,
                max_elevation_deg: 10.0,
                columns: 720,
                rows: 48,
            },
            range: 10.0,
            height: 0.5,
            yaw_deg: 0.0,
            rate_hz: 5.0,
        }],
        footprint_radius: 0.40,
        body: None,
        mass_kg: 12.0,
        hotel_load_w: 0.0,
        max_step_m: 0.2,
        turn_rate: 0.5,
        bumper: false,
        max_push_force_n: 0.0,
    }
}

/// Prágr19 (RSS): gaits regular 0.07 (default) and adaptive 0.05 m/s, RGB-D 87°, 2.5 m, body
/// 0.45 × 0.40 m (footprint radius 0.30 m, the half-diagonal).
pub fn hexapod_rss() -> RobotProfile {
    RobotProfile {
        name: "hexapod-rss".into(),
        gaits: vec![gait("regular", 0.07), gait("adaptive", 0.05)],
        sensors: vec![rgbd(2.5, 0.3, 0.0)],
        footprint_radius: 0.30,
        body: Some([0.45, 0.40]),
        mass_kg: 3.0,
        hotel_load_w: 0.0,
        max_step_m: 0.12,
        turn_rate: 0.3,
        bumper: false,
        max_push_force_n: 0.0,
    }
}

/// Prágr23: one gait (walk 0.05 m/s), RGB-D cameras front and rear (2 m), 0.40 m square body
/// (footprint radius 0.28 m), haptic bumper; pushes with up to 3 N (curtains need 0.5–1 N,
/// walls and boxes ≥ 10 N; the strategy's F_trav is 2 N).
pub fn hexapod_bumper() -> RobotProfile {
    RobotProfile {
        name: "hexapod-bumper".into(),
        gaits: vec![gait("walk", 0.05)],
        sensors: vec![rgbd(2.0, 0.3, 0.0), rgbd(2.0, 0.3, 180.0)],
        footprint_radius: 0.28,
        body: Some([0.40, 0.40]),
        mass_kg: 3.0,
        hotel_load_w: 0.0,
        max_step_m: 0.12,
        turn_rate: 0.3,
        bumper: true,
        max_push_force_n: 3.0,
    }
}

/// MartinCorke: a small wheeled rover, one speed 0.1 m/s, no exteroception, radius 0.05 m, hotel
/// load 0.21 W.
pub fn rover_small() -> RobotProfile {
    RobotProfile {
        name: "rover-small".into(),
        gaits: vec![gait("drive", 0.1)],
        sensors: Vec::new(),
        footprint_radius: 0.05,
        body: None,
        mass_kg: 0.5,
        hotel_load_w: 0.21,
        max_step_m: 0.02,
        turn_rate: 1.0,
        bumper: false,
        max_push_force_n: 0.0,
    }
}

/// Nardi19: Clearpath Husky, 1.0 m/s, no exteroception (an aerial image is given), radius 0.5 m.
pub fn husky() -> RobotProfile {
    RobotProfile {
        name: "husky".into(),
        gaits: vec![gait("drive", 1.0)],
        sensors: Vec::new(),
        footprint_radius: 0.5,
        body: Some([0.99, 0.67]),
        mass_kg: 50.0,
        hotel_load_w: 0.0,
        max_step_m: 0.1,
        turn_rate: 1.0,
        bumper: false,
        max_push_force_n: 0.0,
    }
}
