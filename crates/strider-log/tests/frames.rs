//! Errors about frames name the frame looked up, the world frame it was sought in (and whether
//! that was the default), the transforms the file has, and a missing or empty /tf_static.

mod common;

use common::*;
use std::path::Path;
use strider_log::ros2::{self, MsgType, Quaternion, TfMessage, Time};
use strider_log::{LogReplay, McapWriter};

/// What the log has on /tf_static.
#[derive(Clone, Copy)]
enum Static {
    /// base_link → laser.
    Laser,
    /// A message without transforms.
    Empty,
    /// No message.
    Missing,
}

/// A second of a robot as a wheeled robot's driver logs it: odometry in `odom`, odom →
/// base_link on /tf, a laser's clouds in `laser`.
fn robot_log(path: &Path, statics: Static) {
    let mut w = McapWriter::create(path).unwrap();
    let id = Quaternion::IDENTITY;
    match statics {
        Static::Laser => w.write_ros2(
            "/tf_static",
            MsgType::TfMessage,
            0,
            &tf(0, "base_link", "laser", [0.2, 0.0, 0.3], id),
        ),
        Static::Empty => w.write_ros2("/tf_static", MsgType::TfMessage, 0, &TfMessage::default()),
        Static::Missing => Ok(()),
    }
    .unwrap();
    for k in 0..=10i64 {
        let ns = k * 100_000_000;
        w.write_ros2(
            "/odom",
            MsgType::Odometry,
            ns,
            &odom(ns, "odom", 0.01 * k as f64, id),
        )
        .unwrap();
        w.write_ros2(
            "/tf",
            MsgType::TfMessage,
            ns,
            &tf(ns, "odom", "base_link", [0.01 * k as f64, 0.5, 0.0], id),
        )
        .unwrap();
        let c = ros2::encode_cloud(Time::from_nanos(ns), "laser", &pts()).unwrap();
        w.write_cdr("/scan/points", MsgType::PointCloud2, ns, &c)
            .unwrap();
    }
    w.finish().unwrap();
}

const ROBOT: &str = "motion_topic = \"\"\n[pose]\ntopic = \"/odom\"\n[gait]\ntopic = \"\"\n\
                     [[clouds]]\ntopic = \"/scan/points\"";

/// The error of replaying the log at `p` with the keys `top` before [`ROBOT`] and the
/// `tables` after it.
fn replay_error(p: &Path, top: &str, tables: &str) -> String {
    let cfg = config(&format!("{top}\n{ROBOT}\n{tables}"));
    let e = match LogReplay::open(p, &cfg, &gaits()) {
        Ok(mut r) => drain(&mut r).err().unwrap(),
        Err(e) => e,
    };
    let e = e.to_string();
    assert!(!e.contains('\n'), "{e}");
    e
}

#[test]
fn a_default_world_frame_absent_from_the_file_is_named_as_the_default() {
    let p = dir().join("frames-default.mcap");
    robot_log(&p, Static::Laser);
    let e = replay_error(&p, "", "");
    assert!(
        e.starts_with("topic /odom, message 0: no transform from frame \"odom\" to the world frame \"map\" (world_frame is not set; \"map\" is its default) at 0.000 s: frame \"odom\" has no parent on /tf or /tf_static"),
        "{e}"
    );
    assert!(
        e.contains("set world_frame = \"odom\" (the root of the tree)"),
        "{e}"
    );
    assert!(
        e.contains(
            "transforms in the file: base_link → laser (/tf_static), odom → base_link (/tf)"
        ),
        "{e}"
    );
    assert!(!e.contains("/tf_static is"), "{e}");
    // Set explicitly, it is not called the default.
    let e = replay_error(&p, "world_frame = \"map\"", "");
    assert!(e.contains("the world frame \"map\" at 0.000 s"), "{e}");
    // The right world frame replays.
    let cfg = config(&format!("world_frame = \"odom\"\n{ROBOT}"));
    let mut r = LogReplay::open(&p, &cfg, &gaits()).unwrap();
    let c = drain(&mut r).unwrap();
    assert!((c.clouds[0].origin.x - 0.2).abs() < 1e-9);
}

#[test]
fn a_missing_or_empty_tf_static_is_said() {
    for (statics, name, note) in [
        (
            Static::Missing,
            "frames-missing.mcap",
            "/tf_static is missing (no message in the file)",
        ),
        (
            Static::Empty,
            "frames-empty.mcap",
            "/tf_static is empty (1 messages, no transform)",
        ),
    ] {
        let p = dir().join(name);
        robot_log(&p, statics);
        let e = replay_error(&p, "world_frame = \"odom\"", "");
        assert!(
            e.starts_with("topic /scan/points, message 0: no transform from frame \"laser\" to the world frame \"odom\" at 0.000 s: frame \"laser\" has no parent on /tf or /tf_static"),
            "{e}"
        );
        assert!(
            e.contains("transforms in the file: odom → base_link (/tf)"),
            "{e}"
        );
        assert!(e.ends_with(note), "{e}");
    }
}

#[test]
fn a_broken_chain_and_stamps_outside_the_transforms_are_named() {
    let p = dir().join("frames-chain.mcap");
    robot_log(&p, Static::Laser);
    // The pose from /tf: the chain base_link → odom never reaches "world".
    let cfg = config(
        "world_frame = \"world\"\nmotion_topic = \"\"\n[pose]\nfrom_tf = true\n\
         [gait]\ntopic = \"\"\n[[clouds]]\ntopic = \"/scan/points\"",
    );
    let e = LogReplay::open(&p, &cfg, &gaits())
        .err()
        .unwrap()
        .to_string();
    assert!(
        e.starts_with("topic /tf, message 0: no transform from frame \"base_link\" to the world frame \"world\" at 0.000 s: its chain base_link → odom ends at \"odom\", which has no parent; the world frame \"world\" is in no transform of the file: set world_frame = \"odom\""),
        "{e}"
    );
    // odom → base_link only at 0 s: the clouds' chain breaks once the tolerance is spent.
    let p = dir().join("frames-late.mcap");
    let mut w = McapWriter::create(&p).unwrap();
    let id = Quaternion::IDENTITY;
    w.write_ros2(
        "/tf_static",
        MsgType::TfMessage,
        0,
        &tf(0, "base_link", "laser", [0.2, 0.0, 0.3], id),
    )
    .unwrap();
    w.write_ros2(
        "/tf",
        MsgType::TfMessage,
        0,
        &tf(0, "odom", "base_link", [0.0; 3], id),
    )
    .unwrap();
    for k in 0..=10i64 {
        let ns = k * 100_000_000;
        w.write_ros2("/odom", MsgType::Odometry, ns, &odom(ns, "odom", 0.0, id))
            .unwrap();
        let c = ros2::encode_cloud(Time::from_nanos(ns), "laser", &pts()).unwrap();
        w.write_cdr("/scan/points", MsgType::PointCloud2, ns, &c)
            .unwrap();
    }
    w.finish().unwrap();
    let e = replay_error(&p, "world_frame = \"odom\"", "[tf]\ntolerance_s = 0.25");
    assert!(
        e.contains(
            "topic /scan/points, message 3: no transform from frame \"laser\" to the world frame \"odom\" at 0.300 s: frame \"base_link\" has no transform after 0.300 s (last at 0.000 s; [tf] tolerance_s = 0.25)"
        ),
        "{e}"
    );
}
