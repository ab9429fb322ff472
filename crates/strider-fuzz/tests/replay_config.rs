//! Fuzz target: the replay configuration (TOML). Every accepted configuration must open and
//! replay a small valid log without a panic; every refusal is one clean line.

mod common;

use strider_fuzz::{CappedAlloc, Outcome, Text, config, fuzz};
use strider_log::{LogReplay, ReplayConfig};

#[global_allocator]
static ALLOC: CappedAlloc = CappedAlloc::new();

const DICTIONARY: &[&str] = &[
    "world_frame",
    "keyframes",
    "reorder_window_s",
    "motion_topic",
    "pose",
    "topic",
    "from_tf",
    "base_frame",
    "clouds",
    "origin_frame",
    "missing_rgb",
    "gait",
    "default",
    "tf",
    "static_topic",
    "tolerance_s",
    "mission",
    "scenario",
    "world_seed",
    "seed",
    "strategy",
    "gaits",
    "name",
    "v_max",
    "sensor_hfov_deg",
    "bounds",
    "map",
    "parameters",
    "cell_size",
    "r_robot",
    "r_sensor",
    "tile_size",
    "turning_baseline_s",
    "true",
    "false",
    "error",
    "gray",
    "odom",
    "sensor_0",
    "base_link",
    "fast",
    "tall",
    "gtsp",
    "greedy",
    "courtyard-small",
];

const FULL: &str = r#"world_frame = "map"
keyframes = true
reorder_window_s = 1.0
motion_topic = "/robot/motion"

[pose]
topic = "/robot/odom"
from_tf = false
base_frame = "base_link"

[[clouds]]
topic = "/robot/sensor_0/points"
origin_frame = "sensor_0"
missing_rgb = "error"

[gait]
topic = "/robot/gait"
default = "fast"

[tf]
topic = "/tf"
static_topic = "/tf_static"
tolerance_s = 0.5

[mission]
gaits = [{ name = "fast", v_max = 0.05 }, { name = "tall", v_max = 0.0125 }]
sensor_hfov_deg = [87.0]
bounds = [[-5.0, -5.0], [5.0, 5.0]]
"#;

const FROM_TF: &str = r#"keyframes = false
motion_topic = ""
[pose]
from_tf = true
base_frame = "base_link"
[gait]
topic = ""
[mission]
gaits = [{ name = "fast", v_max = 0.05 }]
sensor_hfov_deg = [360.0]
"#;

const MISSION_ONLY: &str = r#"[mission]
gaits = [{ name = "fast", v_max = 0.05 }, { name = "tall", v_max = 0.0125 }]
sensor_hfov_deg = [120.0]
[mission.map]
cell_size = 0.05
"#;

#[test]
fn fuzz_replay_config() {
    let dir = common::scratch(env!("CARGO_TARGET_TMPDIR"), "replay-config");
    let log = dir.join("small.mcap");
    common::small_log(&log).expect("seed log");
    let check = |input: &Text| -> Result<Outcome, String> {
        let Ok(text) = std::str::from_utf8(&input.0) else {
            return Ok(Outcome::Rejected("not UTF-8".into()));
        };
        let cfg = match ReplayConfig::parse(text) {
            Ok(c) => c,
            Err(e) => return Ok(Outcome::Rejected(e.to_string())),
        };
        let mut replay = match LogReplay::open(&log, &cfg, &common::gaits()) {
            Ok(r) => r,
            Err(e) => return Ok(Outcome::Rejected(e.to_string())),
        };
        match common::drain(&mut replay, 2000) {
            Ok(_) => Ok(Outcome::Accepted),
            Err(e) => Ok(Outcome::Rejected(e.to_string())),
        }
    };
    let seeds: Vec<Text> = [FULL, FROM_TF, MISSION_ONLY]
        .iter()
        .map(|s| Text(s.as_bytes().to_vec()))
        .collect();
    for (k, s) in seeds.iter().enumerate() {
        assert!(
            matches!(check(s), Ok(Outcome::Accepted)),
            "seed {k} must replay: {:?}",
            check(s)
        );
    }
    fuzz(
        config!("replay_config", 1500),
        &ALLOC,
        seeds,
        DICTIONARY,
        check,
    );
}
