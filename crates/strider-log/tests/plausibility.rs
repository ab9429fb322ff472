//! The plausibility checks of a replay: speeds above the gait's v_max, pose jumps, stamps
//! going backwards, clouds without a pose near them; counted and said as warnings.

mod common;

use common::*;
use std::path::Path;
use strider_core::GaitSpec;
use strider_log::LogReplay;
use strider_log::McapWriter;
use strider_log::ros2::{self, MsgType, Quaternion, Time};

const S: i64 = 1_000_000_000;

/// Ten seconds of a robot driving at 0.5 m/s along x, poses at 20 Hz and clouds at 1 Hz, with
/// optional faults: a 5 m jump at 5 s, the pose of 7 s written after that of 7.05 s, a cloud
/// at 12 s (two seconds after the last pose).
fn drive_log(path: &Path, faults: bool) {
    let mut w = McapWriter::create(path).unwrap();
    w.write_ros2(
        "/tf_static",
        MsgType::TfMessage,
        0,
        &tf(0, "map", "sensor_0", [0.0, 0.5, 0.3], Quaternion::IDENTITY),
    )
    .unwrap();
    let mut order: Vec<i64> = (0..=200).collect();
    if faults {
        order.swap(140, 141);
    }
    for k in order {
        let ns = k * S / 20;
        let jump = if faults && k >= 100 { 5.0 } else { 0.0 };
        let x = 0.5 * ns as f64 / S as f64 + jump;
        w.write_ros2(
            "/robot/odom",
            MsgType::Odometry,
            ns,
            &odom(ns, "map", x, Quaternion::IDENTITY),
        )
        .unwrap();
    }
    let last = if faults { 12 } else { 10 };
    for s in 0..=last {
        let c = ros2::encode_cloud(Time::from_nanos(s * S), "map", &pts()).unwrap();
        w.write_cdr("/robot/sensor_0/points", MsgType::PointCloud2, s * S, &c)
            .unwrap();
    }
    w.finish().unwrap();
}

fn gait(v_max: f64) -> Vec<GaitSpec> {
    vec![GaitSpec {
        name: "drive".into(),
        v_max,
    }]
}

#[test]
fn a_too_slow_profile_is_reported_with_counts() {
    let p = dir().join("plausible-speed.mcap");
    drive_log(&p, false);
    let cfg = config("motion_topic = \"\"\n[gait]\ntopic = \"\"");
    let mut r = LogReplay::open(&p, &cfg, &gait(0.05)).unwrap();
    drain(&mut r).unwrap();
    let pl = r.plausibility().clone();
    // Poses from 2 s on have a 2 s baseline: 161 of them, all at 0.5 m/s.
    assert_eq!(pl.speed_checked_poses, 161, "{pl:?}");
    assert_eq!(pl.too_fast_poses, 161, "{pl:?}");
    assert!((pl.max_speed_mps - 0.5).abs() < 1e-9, "{pl:?}");
    assert_eq!(pl.max_speed_gait, Some(("drive".into(), 0.05)));
    let w = pl.warnings();
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(
        w[0].starts_with(
            "the robot moved faster than its gait's v_max at 161 of 161 poses (speed over 2 s \
             more than 20 % above v_max; up to 0.500 m/s; gait \"drive\" has v_max = 0.05 m/s)"
        ),
        "{}",
        w[0]
    );
    // The robot's own speed passes, as does up to 20 % less.
    for v in [0.5, 0.42] {
        let r = LogReplay::open(&p, &cfg, &gait(v)).unwrap();
        assert_eq!(r.plausibility().too_fast_poses, 0, "v_max {v}");
        assert!(r.plausibility().warnings().is_empty(), "v_max {v}");
    }
    assert!(r.warnings().iter().all(|w| !w.contains("faster")));
}

#[test]
fn jumps_backward_stamps_and_clouds_without_poses_are_counted() {
    let p = dir().join("plausible-faults.mcap");
    drive_log(&p, true);
    let cfg = config("motion_topic = \"\"\n[gait]\ntopic = \"\"");
    let r = LogReplay::open(&p, &cfg, &gait(0.5)).unwrap();
    let pl = r.plausibility();
    assert_eq!(pl.pose_jumps, 1, "{pl:?}");
    assert!((pl.max_jump_m - 5.025).abs() < 1e-9, "{pl:?}");
    assert_eq!(
        pl.too_fast_poses, 0,
        "the speed is not measured across the jump: {pl:?}"
    );
    assert_eq!(pl.backward_stamps, 1);
    assert_eq!(pl.first_backward, Some(("/robot/odom".into(), 141)));
    assert_eq!(pl.clouds_without_pose, 2, "the clouds at 11 and 12 s");
    let w = pl.warnings();
    assert_eq!(w.len(), 3, "{w:?}");
    assert!(w[0].starts_with("1 pose jumps (steps over 0.5 m") && w[0].contains("5.03 m"));
    assert!(
        w[1].starts_with(
            "1 messages are stamped before the previous one on their topic (the first: \
             /robot/odom, message 141)"
        ),
        "{}",
        w[1]
    );
    assert!(
        w[2].starts_with("2 clouds have no pose within [tf] tolerance_s = 0.5 s"),
        "{}",
        w[2]
    );
    // The plain log has none of them.
    let q = dir().join("plausible-clean.mcap");
    drive_log(&q, false);
    let r = LogReplay::open(&q, &cfg, &gait(0.5)).unwrap();
    assert_eq!(r.plausibility().warnings(), Vec::<String>::new());
}
