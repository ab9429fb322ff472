//! What the replay tests share: small synthetic logs and their replay configuration.

// Each test binary uses a part of these.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use strider_core::GaitSpec;
use strider_core::interface::{Robot, SensorSink};
use strider_core::msg::ColoredPoint;
use strider_core::{PointCloud, PoseStamped};
use strider_log::ros2::{
    self, Header, MsgType, Odometry, Quaternion, StringMsg, TfMessage, Time, Transform,
    TransformStamped, UInt8Msg, Vector3,
};
use strider_log::{LogError, LogReplay, McapWriter, ReplayConfig};
use strider_map::ElevationMap;
use strider_map::params::MapParams;

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

pub fn dir() -> PathBuf {
    let d = std::env::temp_dir().join(format!("strider-log-bad-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

pub fn header(ns: i64, frame: &str) -> Header {
    Header {
        stamp: Time::from_nanos(ns),
        frame_id: frame.into(),
    }
}

pub fn odom(ns: i64, frame: &str, x: f64, q: Quaternion) -> Odometry {
    let mut o = Odometry {
        header: header(ns, frame),
        child_frame_id: "base_link".into(),
        ..Default::default()
    };
    o.pose.pose.position = Vector3 { x, y: 0.5, z: 0.0 };
    o.pose.pose.orientation = q;
    o
}

pub fn tf(ns: i64, parent: &str, child: &str, t: [f64; 3], q: Quaternion) -> TfMessage {
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
                rotation: q,
            },
        }],
    }
}

pub fn pts() -> Vec<ColoredPoint> {
    (0..20)
        .map(|k| ColoredPoint {
            x: 0.5 + 0.02 * k as f32,
            y: 0.5,
            z: 0.0,
            rgb: [200, 30, 30],
        })
        .collect()
}

/// One second of a simple log: poses at 20 Hz, clouds at 5 Hz in the world frame with the
/// sensor frame on /tf, a gait message and motion states.
pub fn simple_log(path: &Path) {
    let mut w = McapWriter::create(path).unwrap();
    w.write_ros2(
        "/robot/gait",
        MsgType::String,
        0,
        &StringMsg {
            data: "tall".into(),
        },
    )
    .unwrap();
    for k in 0..=20i64 {
        let ns = k * 50_000_000;
        w.write_ros2(
            "/robot/odom",
            MsgType::Odometry,
            ns,
            &odom(ns, "map", 0.01 * k as f64, Quaternion::IDENTITY),
        )
        .unwrap();
        if k % 4 == 0 {
            w.write_ros2(
                "/tf",
                MsgType::TfMessage,
                ns,
                &tf(ns, "map", "sensor_0", [0.0, 0.5, 0.3], Quaternion::IDENTITY),
            )
            .unwrap();
            let c = ros2::encode_cloud(Time::from_nanos(ns), "map", &pts()).unwrap();
            w.write_cdr("/robot/sensor_0/points", MsgType::PointCloud2, ns, &c)
                .unwrap();
        }
        w.write_ros2("/robot/motion", MsgType::UInt8, ns, &UInt8Msg { data: 0 })
            .unwrap();
    }
    w.finish().unwrap();
}

pub fn config(extra: &str) -> ReplayConfig {
    ReplayConfig::parse(&format!(
        "{extra}\n[mission]\ngaits = [{{ name = \"fast\", v_max = 0.05 }}]\n\
         sensor_hfov_deg = [87.0]\n"
    ))
    .unwrap()
}

#[derive(Default)]
pub struct Collect {
    pub poses: Vec<PoseStamped>,
    pub clouds: Vec<PointCloud>,
}

impl SensorSink for Collect {
    fn on_pose(&mut self, p: &PoseStamped) {
        self.poses.push(*p);
    }
    fn on_cloud(&mut self, c: &PointCloud) {
        self.clouds.push(c.clone());
    }
}

/// The error of opening the log at `p` with `cfg`.
pub fn open_error(p: &Path, cfg: &ReplayConfig) -> String {
    LogReplay::open(p, cfg, &gaits()).err().unwrap().to_string()
}

pub fn drain(r: &mut LogReplay) -> Result<Collect, LogError> {
    let mut c = Collect::default();
    let limit = r.time_limit_s(0.05);
    while r.now() < limit {
        r.advance(0.05, &mut c)?;
    }
    Ok(c)
}

/// Rewrites the log at `src` into `dst` with the mcap crate's writer, its chunks compressed
/// with `compression` (`None`: uncompressed) and small, so that the log spans several.
pub fn recompress(src: &Path, dst: &Path, compression: Option<mcap::Compression>) {
    let bytes = std::fs::read(src).unwrap();
    let f = std::io::BufWriter::new(std::fs::File::create(dst).unwrap());
    let mut w = mcap::WriteOptions::new()
        .compression(compression)
        .chunk_size(Some(2048))
        .profile("ros2")
        .create(f)
        .unwrap();
    for m in mcap::MessageStream::new(&bytes).unwrap() {
        w.write(&m.unwrap()).unwrap();
    }
    w.finish().unwrap();
}

/// A cloud bit for bit: stamp, sensor, origin, points' coordinates and colours.
pub type CloudBits = (u64, u8, [u64; 3], Vec<([u32; 3], [u8; 3])>);

/// The delivered clouds bit for bit.
pub fn cloud_bits(c: &Collect) -> Vec<CloudBits> {
    c.clouds
        .iter()
        .map(|c| {
            let o = [c.origin.x, c.origin.y, c.origin.z].map(f64::to_bits);
            let pts = c
                .points
                .iter()
                .map(|p| ([p.x, p.y, p.z].map(f32::to_bits), p.rgb));
            (c.stamp.to_bits(), c.sensor, o, pts.collect())
        })
        .collect()
}

/// The map of the delivered clouds (default map parameters).
pub fn map_of(c: &Collect) -> ElevationMap {
    let mut map = ElevationMap::new(MapParams::default());
    for cloud in &c.clouds {
        map.integrate(cloud);
    }
    map
}

/// Asserts that two maps observed the same cells with the same elevations, bit for bit.
pub fn assert_same_map(a: &ElevationMap, b: &ElevationMap, what: &str) {
    assert_eq!(a.scan_count(), b.scan_count(), "{what}: scans");
    let rect = a.known_bounds().expect("a non-empty map");
    assert_eq!(Some(rect), b.known_bounds(), "{what}: bounds");
    assert_eq!(a.observed_raster(rect), b.observed_raster(rect), "{what}");
    let bits = |m: &ElevationMap| -> Vec<u32> {
        m.elevation_raster(rect)
            .iter()
            .map(|v| v.to_bits())
            .collect()
    };
    assert_eq!(bits(a), bits(b), "{what}: elevations");
}
