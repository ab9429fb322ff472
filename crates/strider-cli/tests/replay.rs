//! MCAP round trip and `strider replay` end to end: a simulated mission recorded as ROS 2
//! messages and replayed through the log reader gives the live run's map and learned costs;
//! bad input ends in one clear error line.

mod common;

use std::path::Path;
use strider_core::msg::ColoredPoint;
use strider_experiments::cancel::Cancel;
use strider_experiments::trial::{configure, drive, mission_params, robot_spec, run_mission};
use strider_explore::FromParams;
use strider_explore::{Strategy, TourExplorer};
use strider_log::ros2::{self, Header, MsgType, Odometry, Quaternion, Time, UInt8Msg};
use strider_log::{LogReplay, McapWriter, ReplayConfig};
use strider_scenario::Scenario;

const TOL: f64 = 1e-4;

fn close(a: f64, b: f64) -> bool {
    (a.is_nan() && b.is_nan()) || (a - b).abs() <= TOL
}

#[test]
fn replay_of_a_recorded_mission_gives_the_live_map_and_costs() {
    let sc = Scenario::from_name_or_file("courtyard-small", 1).unwrap();
    let mut params = mission_params(&sc, Strategy::Gtsp, 1).unwrap();
    // Long enough for the live run to learn terrain classes (the fast gait's, after about 70
    // cost samples), which the replay must reproduce.
    params.time_limit_s = 250.0;
    let dir = common::temp_dir("replay", "round-trip");
    let file = dir.join("run.mcap");
    let (live, live_log, written) = run_mission(
        &sc,
        params.clone(),
        1,
        (Some(file.as_path()), &Cancel::new()),
        |_| {},
    )
    .unwrap();
    let written = written.expect("the recording wrote messages");
    assert!(written.messages["/robot/sensor_0/points"] > 10);
    assert!(written.messages["/strider/map"] > 5);

    // Recording does not change the mission.
    let (plain, plain_log, _) =
        run_mission(&sc, params.clone(), 1, (None, &Cancel::new()), |_| {}).unwrap();
    assert_eq!(plain.record().trajectory, live.record().trajectory);
    assert_eq!(plain_log.cost_samples, live_log.cost_samples);

    // Replay through the log reader and the mission's passive loop.
    let cfg = ReplayConfig::parse("[mission]\nscenario = \"courtyard-small\"\n").unwrap();
    let mut replay = LogReplay::open(&file, &cfg, &params.gaits).unwrap();
    let mut rp = params.clone();
    rp.time_limit_s = replay.time_limit_s(1.0 / rp.rates.control_hz);
    let mut mission = TourExplorer::mission(rp).unwrap();
    let run = mission.ingest(&mut replay, |_, _| {}).unwrap().clone();
    assert!(replay.warnings().is_empty(), "{:?}", replay.warnings());
    assert!(
        replay.plausibility().warnings().is_empty(),
        "the simulator's log is plausible: {:?}",
        replay.plausibility()
    );
    assert_eq!(mission.strategy().log().cost_samples, live_log.cost_samples);
    assert!((run.exploration_time_s - live.record().exploration_time_s).abs() < 1e-9);

    // Map layers.
    let (a, b) = (live.body().map(), mission.body().map());
    let (live, mission) = (live.strategy(), mission.strategy());
    let rect = a.known_bounds().unwrap();
    assert_eq!(Some(rect), b.known_bounds());
    assert_eq!(a.scan_count(), b.scan_count());
    assert_eq!(a.observed_raster(rect), b.observed_raster(rect));
    assert_eq!(a.color_raster(rect), b.color_raster(rect));
    assert_eq!(a.passability_raster(rect), b.passability_raster(rect));
    for (x, y) in [
        (a.elevation_raster(rect), b.elevation_raster(rect)),
        (a.variance_raster(rect), b.variance_raster(rect)),
    ] {
        let worst = x
            .iter()
            .zip(&y)
            .filter(|(p, q)| !close(**p as f64, **q as f64))
            .count();
        assert_eq!(worst, 0, "{worst} cells differ by more than {TOL}");
    }

    // Learned costs: classes, planning costs, measured cells.
    let classes: usize = live.model_updates().iter().map(|u| u.classes.len()).sum();
    assert!(classes > 0, "the live run learned terrain classes");
    for (g, (ma, mb)) in live.models().iter().zip(mission.models()).enumerate() {
        let (ua, ub) = (&live.model_updates()[g], &mission.model_updates()[g]);
        assert_eq!(ua.classes.len(), ub.classes.len(), "gait {g}");
        for (ca, cb) in ua.classes.iter().zip(&ub.classes) {
            assert_eq!(ca.id, cb.id);
            assert!(close(ca.cost, cb.cost), "gait {g}: {ca:?} vs {cb:?}");
            assert!(
                close(ca.variance, cb.variance),
                "gait {g}: {ca:?} vs {cb:?}"
            );
        }
        let (pa, pb) = (ma.planning_costs(rect), mb.planning_costs(rect));
        assert!(pa.iter().zip(&pb).all(|(x, y)| close(*x as f64, *y as f64)));
        assert_eq!(ma.measured_cells(), mb.measured_cells());
        for &c in ma.measured_cells() {
            let (x, y) = (ma.cell_cost(c).unwrap(), mb.cell_cost(c).unwrap());
            assert!(close(x.cost, y.cost) && x.count == y.count);
        }
    }

    // The command: the same class costs in its report.
    let cfg_file = dir.join("replay.toml");
    std::fs::write(&cfg_file, "[mission]\nscenario = \"courtyard-small\"\n").unwrap();
    let out = dir.join("out");
    let o = common::strider(&[
        "replay",
        file.to_str().unwrap(),
        "--config",
        cfg_file.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", common::stderr(&o));
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("report.json")).unwrap()).unwrap();
    assert_eq!(
        report["observed_cells"].as_u64(),
        Some(a.observed_count() as u64)
    );
    for (g, m) in report["models"].as_array().unwrap().iter().enumerate() {
        let classes = &live.model_updates()[g].classes;
        let table = m["class_table"].as_array().unwrap();
        assert_eq!(table.len(), classes.len());
        for (row, c) in table.iter().zip(classes) {
            assert!(close(row["cost"].as_f64().unwrap(), c.cost));
        }
    }
    assert!(out.join("report.html").exists() && out.join("color.png").exists());
}

/// Every exploration strategy on both robots records with `--mcap` (the kernel's recorder
/// reads the mission's snapshot, whatever the strategy), and replaying each recording maps the
/// same cells with the same elevations as the live run.
#[test]
fn every_strategy_records_and_its_replay_gives_its_map() {
    let dir = common::temp_dir("replay", "every-strategy");
    for scenario in ["courtyard-small", "lab-track"] {
        let sc = Scenario::from_name_or_file(scenario, 1).unwrap();
        let mut robot = robot_spec(&sc);
        robot.time_limit_s = 60.0;
        for name in ["gtsp", "greedy", "spatial-only", "rbcm-greedy"] {
            let (_, configured) = configure(&sc, name, &[]).unwrap();
            let mut live = configured.build(&robot, 2).unwrap();
            let file = dir.join(format!("{scenario}-{name}.mcap"));
            let written = drive(
                &sc,
                2,
                &mut live,
                (Some(file.as_path()), &Cancel::new()),
                |_, _| {},
            )
            .unwrap()
            .unwrap();
            assert!(written.messages["/strider/map"] > 0, "{name} on {scenario}");
            assert!(
                written.messages["/strider/goals"] > 10,
                "{name} on {scenario}"
            );

            let cfg =
                ReplayConfig::parse(&format!("[mission]\nscenario = \"{scenario}\"\n")).unwrap();
            let params = mission_params(&sc, Strategy::Gtsp, 2).unwrap();
            let mut replay = LogReplay::open(&file, &cfg, &params.gaits).unwrap();
            let mut rp = params.clone();
            rp.time_limit_s = replay.time_limit_s(1.0 / rp.rates.control_hz);
            let mut replayed = TourExplorer::mission(rp).unwrap();
            replayed.ingest(&mut replay, |_, _| {}).unwrap();
            assert!(
                replay.plausibility().warnings().is_empty(),
                "{name} on {scenario}: {:?}",
                replay.plausibility()
            );

            let (a, b) = (live.body().map(), replayed.body().map());
            let what = format!("{name} on {scenario}");
            assert!(a.observed_count() > 500, "{what}: {}", a.observed_count());
            assert_eq!(a.scan_count(), b.scan_count(), "{what}");
            let rect = a.known_bounds().unwrap();
            assert_eq!(Some(rect), b.known_bounds(), "{what}");
            assert_eq!(a.observed_raster(rect), b.observed_raster(rect), "{what}");
            let (x, y) = (a.elevation_raster(rect), b.elevation_raster(rect));
            let differ = x
                .iter()
                .zip(&y)
                .filter(|(p, q)| !close(**p as f64, **q as f64))
                .count();
            assert_eq!(differ, 0, "{what}: {differ} elevations differ");
        }
    }
}

/// A small valid log: poses, one coloured scan, motion states.
fn small_log(path: &Path) {
    driving_log(path, 10, 0.002, "map");
}

/// `n` poses at 20 Hz, `step` m apart along x, motion states, and one coloured scan at 0 s in
/// `frame` (the sensor frame is on /tf).
fn driving_log(path: &Path, n: i64, step: f64, frame: &str) {
    let mut w = McapWriter::create(path).unwrap();
    for k in 0..n {
        let ns = k * 50_000_000;
        let mut o = Odometry {
            header: Header {
                stamp: Time::from_nanos(ns),
                frame_id: "map".into(),
            },
            child_frame_id: "base_link".into(),
            ..Default::default()
        };
        o.pose.pose.position.x = 0.5 + step * k as f64;
        o.pose.pose.orientation = Quaternion::IDENTITY;
        w.write_ros2("/robot/odom", MsgType::Odometry, ns, &o)
            .unwrap();
        w.write_ros2("/robot/motion", MsgType::UInt8, ns, &UInt8Msg { data: 0 })
            .unwrap();
    }
    let pts: Vec<ColoredPoint> = (0..50)
        .map(|k| ColoredPoint {
            x: 0.6 + 0.01 * k as f32,
            y: 0.5,
            z: 0.0,
            rgb: [90, 160, 60],
        })
        .collect();
    let mut tf = ros2::TfMessage::default();
    tf.transforms.push(ros2::TransformStamped {
        header: Header {
            stamp: Time::default(),
            frame_id: "map".into(),
        },
        child_frame_id: "sensor_0".into(),
        transform: ros2::Transform {
            translation: ros2::Vector3 {
                x: 0.5,
                y: 0.5,
                z: 0.3,
            },
            rotation: Quaternion::IDENTITY,
        },
    });
    w.write_ros2("/tf", MsgType::TfMessage, 0, &tf).unwrap();
    let c = ros2::encode_cloud(Time::default(), frame, &pts).unwrap();
    w.write_cdr("/robot/sensor_0/points", MsgType::PointCloud2, 0, &c)
        .unwrap();
    w.finish().unwrap();
}

fn replay(log: &Path, config: &str, dir: &Path) -> std::process::Output {
    let cfg = dir.join("c.toml");
    std::fs::write(&cfg, config).unwrap();
    common::strider(&[
        "replay",
        log.to_str().unwrap(),
        "--config",
        cfg.to_str().unwrap(),
        "--out",
        dir.join("out").to_str().unwrap(),
    ])
}

const CONFIG: &str = "[gait]\ntopic = \"\"\n[mission]\nscenario = \"courtyard-small\"\n";

#[test]
fn replay_errors_are_one_clear_line() {
    let dir = common::temp_dir("replay", "errors");
    let log = dir.join("small.mcap");
    small_log(&log);
    let o = replay(&log, CONFIG, &dir);
    assert!(o.status.success(), "{}", common::stderr(&o));

    // Missing file.
    let e = common::one_line_error(&replay(&dir.join("nope.mcap"), CONFIG, &dir));
    assert!(e.contains("nope.mcap"), "{e}");

    // Truncated file.
    let bytes = std::fs::read(&log).unwrap();
    let cut = dir.join("cut.mcap");
    std::fs::write(&cut, &bytes[..bytes.len() * 2 / 3]).unwrap();
    let e = common::one_line_error(&replay(&cut, CONFIG, &dir));
    assert!(
        e.contains("cut.mcap") && e.contains("ends in the middle of a record"),
        "{e}"
    );

    // Not an MCAP file at all.
    let junk = dir.join("junk.mcap");
    std::fs::write(&junk, b"#!/bin/sh\necho hello\n").unwrap();
    let e = common::one_line_error(&replay(&junk, CONFIG, &dir));
    assert!(e.contains("junk.mcap"), "{e}");

    // Missing topic.
    let e = common::one_line_error(&replay(
        &log,
        "[[clouds]]\ntopic = \"/camera/points\"\n[gait]\ntopic = \"\"\n\
         [mission]\nscenario = \"courtyard-small\"\n",
        &dir,
    ));
    assert!(
        e.contains("/camera/points") && e.contains("/robot/sensor_0/points"),
        "{e}"
    );

    // A configuration without the robot.
    let e = common::one_line_error(&replay(&log, "[gait]\ntopic = \"\"\n", &dir));
    assert!(e.contains("replay config") && e.contains("mission"), "{e}");
}

/// A robot of one 0.05 m/s gait.
const SLOW: &str = "motion_topic = \"\"\n[gait]\ntopic = \"\"\n[mission]\n\
                    gaits = [{ name = \"slow\", v_max = 0.05 }]\nsensor_hfov_deg = [87.0]\n";

#[test]
fn a_too_slow_profile_is_warned_about_once_with_counts() {
    let dir = common::temp_dir("replay", "too-slow");
    let log = dir.join("drive.mcap");
    // 0.3 m/s for 5 s: poses from 2 s on are checked over a 2 s baseline.
    driving_log(&log, 100, 0.015, "map");
    let o = replay(&log, SLOW, &dir);
    assert!(o.status.success(), "{}", common::stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    let warning = "warning: the robot moved faster than its gait's v_max at 60 of 60 poses";
    assert_eq!(out.matches(warning).count(), 1, "{out}");
    assert_eq!(out.matches("warning:").count(), 1, "{out}");
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("out/report.json")).unwrap())
            .unwrap();
    let p = &report["replay"]["plausibility"];
    assert_eq!(p["too_fast_poses"].as_u64(), Some(60), "{p}");
    assert_eq!(p["speed_checked_poses"].as_u64(), Some(60), "{p}");
    assert!(
        (p["max_speed_mps"].as_f64().unwrap() - 0.3).abs() < 1e-9,
        "{p}"
    );
    assert_eq!(p["pose_jumps"].as_u64(), Some(0), "{p}");
    let w = report["replay"]["plausibility_warnings"]
        .as_array()
        .unwrap();
    assert_eq!(w.len(), 1);
    assert!(w[0].as_str().unwrap().contains("up to 0.300 m/s"), "{w:?}");
    let html = std::fs::read_to_string(dir.join("out/report.html")).unwrap();
    assert!(
        html.contains("<title>Strider: replay of "),
        "a meaningful title"
    );
    assert!(!html.contains("null"), "no null in the page");
}

#[test]
fn a_replay_that_fails_midway_leaves_no_output_directory() {
    let dir = common::temp_dir("replay", "midway");
    let log = dir.join("drive.mcap");
    // The scan's frame has no transform: found when the scan is delivered, after the output
    // directory was made.
    driving_log(&log, 20, 0.002, "lidar");
    let e = common::one_line_error(&replay(&log, SLOW, &dir));
    assert!(
        e.contains("/robot/sensor_0/points, message 0")
            && e.contains("no transform from frame \"lidar\" to the world frame \"map\" (world_frame is not set; \"map\" is its default)")
            && e.contains("transforms in the file: map → sensor_0 (/tf)")
            && e.contains("/tf_static is missing"),
        "{e}"
    );
    assert!(
        !dir.join("out").exists(),
        "the empty output directory stayed"
    );
}
