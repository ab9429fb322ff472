//! Shared by the log targets: a small valid ROS 2 log, the gaits it is replayed with, and a
//! bounded drain of a replay.
#![allow(dead_code)] // each target uses only part of it

use std::path::{Path, PathBuf};

use strider_core::GaitSpec;
use strider_core::interface::{Robot, SensorSink};
use strider_core::msg::ColoredPoint;
use strider_core::{PointCloud, PoseStamped};
use strider_log::ros2::{
    self, Header, MsgType, Odometry, Quaternion, StringMsg, TfMessage, Time, Transform,
    TransformStamped, UInt8Msg, Vector3,
};
use strider_log::{LogError, LogReplay, McapWriter};

pub fn gaits() -> Vec<GaitSpec> {
    vec![
        GaitSpec {
            name: "fast".into(),
            v_max: 0.05,
        },
        GaitSpec {
            name: "tall".into(),
            v_max: 0.0125,
        },
    ]
}

/// A per-process scratch folder under the test's target directory.
pub fn scratch(tmp: &str, what: &str) -> PathBuf {
    let d = Path::new(tmp).join(format!("fuzz-{what}-{}", std::process::id()));
    std::fs::create_dir_all(&d).expect("scratch folder");
    d
}

fn header(ns: i64, frame: &str) -> Header {
    Header {
        stamp: Time::from_nanos(ns),
        frame_id: frame.into(),
    }
}

fn odom(ns: i64, x: f64) -> Odometry {
    let mut o = Odometry {
        header: header(ns, "odom"),
        child_frame_id: "base_link".into(),
        ..Default::default()
    };
    o.pose.pose.position = Vector3 { x, y: 0.5, z: 0.0 };
    o.pose.pose.orientation = Quaternion::IDENTITY;
    o
}

fn tf(ns: i64, parent: &str, child: &str, t: [f64; 3]) -> TfMessage {
    TfMessage {
        transforms: vec![TransformStamped {
            header: header(ns, parent),
            child_frame_id: child.into(),
            transform: Transform {
                translation: Vector3 {
                    x: t[0],
                    y: t[1],
                    z: t[2],
                },
                rotation: Quaternion::IDENTITY,
            },
        }],
    }
}

fn points() -> Vec<ColoredPoint> {
    (0..12)
        .map(|k| ColoredPoint {
            x: 0.3 + 0.05 * k as f32,
            y: 0.1 * (k % 3) as f32,
            z: 0.0,
            rgb: [40 + 10 * k as u8, 120, 30],
        })
        .collect()
}

/// Half a second of a log as a robot records it: odometry in an `odom` frame chained to `map`
/// by /tf_static, clouds in the sensor frame, gait and motion topics.
pub fn small_log(path: &Path) -> Result<(), Box<dyn std::error::Error>> {
    let mut w = McapWriter::create(path)?;
    w.write_ros2(
        "/tf_static",
        MsgType::TfMessage,
        0,
        &tf(0, "map", "odom", [0.0, 0.0, 0.0]),
    )?;
    w.write_ros2(
        "/robot/gait",
        MsgType::String,
        0,
        &StringMsg {
            data: "tall".into(),
        },
    )?;
    for k in 0..=10i64 {
        let ns = k * 50_000_000;
        let x = 0.01 * k as f64;
        w.write_ros2("/robot/odom", MsgType::Odometry, ns, &odom(ns, x))?;
        let body = tf(ns, "odom", "base_link", [x, 0.5, 0.0]);
        w.write_ros2("/tf", MsgType::TfMessage, ns, &body)?;
        if k % 2 == 0 {
            let t = tf(ns, "base_link", "sensor_0", [0.1, 0.0, 0.3]);
            w.write_ros2("/tf", MsgType::TfMessage, ns, &t)?;
            let c = ros2::encode_cloud(Time::from_nanos(ns), "sensor_0", &points())?;
            w.write_cdr("/robot/sensor_0/points", MsgType::PointCloud2, ns, &c)?;
        }
        w.write_ros2("/robot/motion", MsgType::UInt8, ns, &UInt8Msg { data: 0 })?;
    }
    w.finish()?;
    Ok(())
}

#[derive(Default)]
pub struct Count {
    pub poses: usize,
    pub clouds: usize,
    pub points: usize,
}

impl SensorSink for Count {
    fn on_pose(&mut self, p: &PoseStamped) {
        assert!(
            p.position.x.is_finite() && p.position.y.is_finite() && p.stamp.is_finite(),
            "a replayed pose is not finite: {p:?}"
        );
        self.poses += 1;
    }
    fn on_cloud(&mut self, c: &PointCloud) {
        self.clouds += 1;
        self.points += c.points.len();
    }
}

/// Replays to the end in 50 ms steps, at most `max_steps` of them (a bound on a replay whose
/// stamps claim a huge duration).
pub fn drain(r: &mut LogReplay, max_steps: usize) -> Result<Count, LogError> {
    let mut c = Count::default();
    let limit = r.time_limit_s(0.05);
    let mut steps = 0;
    while r.now() < limit && steps < max_steps {
        r.advance(0.05, &mut c)?;
        steps += 1;
    }
    Ok(c)
}
