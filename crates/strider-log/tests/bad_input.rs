//! Replay of small synthetic logs: the fallbacks and the errors on bad input (missing topics,
//! foreign encodings and schemas, clouds without colour, truncated and corrupted files, bogus
//! stamps, unknown gaits), and the transform handling (clouds in a sensor frame, poses in an
//! odometry frame or from /tf). Never a panic.

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

fn gaits() -> Vec<GaitSpec> {
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

fn dir() -> PathBuf {
    let d = std::env::temp_dir().join(format!("strider-log-bad-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn header(ns: i64, frame: &str) -> Header {
    Header {
        stamp: Time::from_nanos(ns),
        frame_id: frame.into(),
    }
}

fn odom(ns: i64, frame: &str, x: f64, q: Quaternion) -> Odometry {
    let mut o = Odometry {
        header: header(ns, frame),
        child_frame_id: "base_link".into(),
        ..Default::default()
    };
    o.pose.pose.position = Vector3 { x, y: 0.5, z: 0.0 };
    o.pose.pose.orientation = q;
    o
}

fn tf(ns: i64, parent: &str, child: &str, t: [f64; 3], q: Quaternion) -> TfMessage {
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

fn pts() -> Vec<ColoredPoint> {
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
fn simple_log(path: &Path) {
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

fn config(extra: &str) -> ReplayConfig {
    ReplayConfig::parse(&format!(
        "{extra}\n[mission]\ngaits = [{{ name = \"fast\", v_max = 0.05 }}]\n"
    ))
    .unwrap()
}

#[derive(Default)]
struct Collect {
    poses: Vec<PoseStamped>,
    clouds: Vec<PointCloud>,
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
fn open_error(p: &Path, cfg: &ReplayConfig) -> String {
    LogReplay::open(p, cfg, &gaits()).err().unwrap().to_string()
}

fn drain(r: &mut LogReplay) -> Result<Collect, LogError> {
    let mut c = Collect::default();
    let limit = r.time_limit_s(0.05);
    while r.now() < limit {
        r.advance(0.05, &mut c)?;
    }
    Ok(c)
}

#[test]
fn a_simple_log_replays_in_order_with_its_gait() {
    let p = dir().join("simple.mcap");
    simple_log(&p);
    let mut r = LogReplay::open(&p, &config(""), &gaits()).unwrap();
    assert!((r.duration_s() - 1.0).abs() < 1e-12);
    let c = drain(&mut r).unwrap();
    assert_eq!(c.poses.len(), 21);
    assert_eq!(c.clouds.len(), 6);
    assert!(c.poses.iter().all(|p| p.gait.0 == 1), "gait from the topic");
    assert!(c.poses.windows(2).all(|w| w[0].stamp < w[1].stamp));
    assert_eq!(c.clouds[0].points, pts(), "world-frame points bit for bit");
    assert_eq!(c.clouds[1].origin.z, 0.3, "origin from the sensor frame");
    assert!(r.warnings().is_empty(), "{:?}", r.warnings());
}

#[test]
fn missing_topics_are_named_with_the_topics_present() {
    let p = dir().join("simple-missing.mcap");
    simple_log(&p);
    let cfg = config("[[clouds]]\ntopic = \"/camera/points\"\norigin_frame = \"cam\"");
    let e = open_error(&p, &cfg);
    assert!(e.contains("no message on topic /camera/points"), "{e}");
    assert!(
        e.contains("/robot/sensor_0/points"),
        "lists what is there: {e}"
    );
    let cfg = config("[pose]\ntopic = \"/odom\"");
    let e = open_error(&p, &cfg);
    assert!(e.contains("/odom") && e.contains("the pose"), "{e}");
}

#[test]
fn without_gait_and_motion_topics_the_fallbacks_are_reported() {
    let p = dir().join("simple-nogait.mcap");
    simple_log(&p);
    let cfg = config("motion_topic = \"\"\n[gait]\ntopic = \"\"\ndefault = \"fast\"");
    let mut r = LogReplay::open(&p, &cfg, &gaits()).unwrap();
    let c = drain(&mut r).unwrap();
    assert!(c.poses.iter().all(|p| p.gait.0 == 0));
    assert_eq!(r.warnings().len(), 2, "{:?}", r.warnings());
}

#[test]
fn foreign_encodings_and_schemas_are_refused() {
    let p = dir().join("json.mcap");
    {
        let f = std::io::BufWriter::new(std::fs::File::create(&p).unwrap());
        let mut w = mcap::Writer::new(f).unwrap();
        let s = w
            .add_schema("nav_msgs/msg/Odometry", "jsonschema", b"{}")
            .unwrap();
        let ch = w
            .add_channel(s, "/robot/odom", "json", &Default::default())
            .unwrap();
        w.write_to_known_channel(
            &mcap::records::MessageHeader {
                channel_id: ch,
                sequence: 0,
                log_time: 0,
                publish_time: 0,
            },
            b"{}",
        )
        .unwrap();
        w.finish().unwrap();
    }
    let e = open_error(&p, &config(""));
    assert!(
        e.contains("/robot/odom") && e.contains("\"json\""),
        "encoding named: {e}"
    );

    let p = dir().join("schema.mcap");
    let mut w = McapWriter::create(&p).unwrap();
    w.write_ros2("/robot/odom", MsgType::String, 0, &StringMsg::default())
        .unwrap();
    w.finish().unwrap();
    let e = open_error(&p, &config(""));
    assert!(
        e.contains("std_msgs/msg/String") && e.contains("nav_msgs/msg/Odometry"),
        "{e}"
    );
}

fn uncoloured_log(path: &Path) {
    use strider_log::ros2::{PointCloud2Head, PointField, datatype};
    let f = |name: &str, offset| PointField::new(name, offset, datatype::FLOAT32);
    let head = PointCloud2Head {
        header: header(0, "map"),
        height: 1,
        width: 2,
        fields: vec![f("x", 0), f("y", 4), f("z", 8)],
        is_bigendian: false,
        point_step: 12,
        row_step: 24,
    };
    let mut data = Vec::new();
    for v in [0.5f32, 0.5, 0.0, f32::NAN, 0.5, 0.0] {
        data.extend_from_slice(&v.to_le_bytes());
    }
    let bytes = strider_log::ros2::encode_cloud_raw(&head, &data, false).unwrap();
    let mut w = McapWriter::create(path).unwrap();
    w.write_ros2(
        "/robot/odom",
        MsgType::Odometry,
        0,
        &odom(0, "map", 0.5, Quaternion::IDENTITY),
    )
    .unwrap();
    w.write_ros2(
        "/tf",
        MsgType::TfMessage,
        0,
        &tf(0, "map", "sensor_0", [0.5, 0.5, 0.3], Quaternion::IDENTITY),
    )
    .unwrap();
    w.write_cdr("/robot/sensor_0/points", MsgType::PointCloud2, 0, &bytes)
        .unwrap();
    w.finish().unwrap();
}

#[test]
fn clouds_without_colour_are_an_error_or_gray_with_a_warning() {
    let p = dir().join("norgb.mcap");
    uncoloured_log(&p);
    let mut r = LogReplay::open(&p, &config(""), &gaits()).unwrap();
    let e = drain(&mut r).err().unwrap().to_string();
    assert!(
        e.contains("/robot/sensor_0/points") && e.contains("message 0") && e.contains("colour"),
        "{e}"
    );
    let cfg = config(
        "[[clouds]]\ntopic = \"/robot/sensor_0/points\"\norigin_frame = \"sensor_0\"\n\
         missing_rgb = \"gray\"",
    );
    let mut r = LogReplay::open(&p, &cfg, &gaits()).unwrap();
    let c = drain(&mut r).unwrap();
    assert_eq!(c.clouds[0].points[0].rgb, [128; 3]);
    assert!(
        c.clouds[0].points[1].x.is_nan(),
        "NaN points pass to the map"
    );
    assert_eq!(r.stats().clouds_uncoloured, 1);
    assert!(r.warnings().iter().any(|w| w.contains("gray")));
}

#[test]
fn truncated_and_corrupted_files_are_errors_not_panics() {
    let p = dir().join("whole.mcap");
    simple_log(&p);
    let bytes = std::fs::read(&p).unwrap();
    // Truncations at many lengths, including inside the header and the summary.
    for cut in (0..bytes.len()).step_by(97).chain([bytes.len() - 1]) {
        let q = dir().join("cut.mcap");
        std::fs::write(&q, &bytes[..cut]).unwrap();
        let r = LogReplay::open(&q, &config(""), &gaits());
        let e = r.err().expect("a truncated file is refused").to_string();
        assert!(!e.is_empty());
    }
    // Byte flips anywhere: an error or, where the flip hits padding or an unused field, a log
    // that still replays; never a panic.
    for k in (8..bytes.len() - 8).step_by(31) {
        let mut b = bytes.clone();
        b[k] ^= 0x5a;
        let q = dir().join("flip.mcap");
        std::fs::write(&q, &b).unwrap();
        if let Ok(mut r) = LogReplay::open(&q, &config(""), &gaits()) {
            let _ = drain(&mut r);
        }
    }
    let e = open_error(&dir().join("absent.mcap"), &config(""));
    assert!(e.contains("absent.mcap"), "{e}");
}

#[test]
fn truncation_names_the_position() {
    let p = dir().join("whole2.mcap");
    simple_log(&p);
    let bytes = std::fs::read(&p).unwrap();
    let q = dir().join("half.mcap");
    std::fs::write(&q, &bytes[..bytes.len() / 2]).unwrap();
    let e = open_error(&q, &config(""));
    assert!(
        e.contains("half.mcap") && e.contains("near byte") && e.contains("messages"),
        "{e}"
    );
}

/// A log with the usual sensor frame and one cloud at each of `stamps`, poses as given.
fn log_with(path: &Path, poses: &[(i64, Odometry)], gait: Option<&str>) {
    let mut w = McapWriter::create(path).unwrap();
    for (ns, o) in poses {
        w.write_ros2("/robot/odom", MsgType::Odometry, *ns, o)
            .unwrap();
        w.write_ros2(
            "/tf",
            MsgType::TfMessage,
            *ns,
            &tf(
                *ns,
                "map",
                "sensor_0",
                [0.5, 0.5, 0.3],
                Quaternion::IDENTITY,
            ),
        )
        .unwrap();
        let c = ros2::encode_cloud(Time::from_nanos(*ns), "map", &pts()).unwrap();
        w.write_cdr("/robot/sensor_0/points", MsgType::PointCloud2, *ns, &c)
            .unwrap();
    }
    if let Some(g) = gait {
        w.write_ros2(
            "/robot/gait",
            MsgType::String,
            0,
            &StringMsg { data: g.into() },
        )
        .unwrap();
    }
    w.finish().unwrap();
}

#[test]
fn unknown_gaits_bogus_stamps_and_bad_rotations() {
    let id = Quaternion::IDENTITY;
    let p = dir().join("gait.mcap");
    log_with(&p, &[(0, odom(0, "map", 0.5, id))], Some("gallop"));
    let e = open_error(&p, &config(""));
    assert!(
        e.contains("/robot/gait") && e.contains("gallop") && e.contains("fast, tall"),
        "{e}"
    );

    // One message stamped decades later: refused instead of replaying years of nothing.
    let far = 2_000_000_000i64 * 1_000_000_000;
    let p = dir().join("stamps.mcap");
    log_with(
        &p,
        &[
            (0, odom(0, "map", 0.5, id)),
            (far, odom(far, "map", 0.5, id)),
        ],
        None,
    );
    let e = open_error(&p, &config(""));
    assert!(e.contains("inconsistent"), "{e}");

    // A zero quaternion: the pose is skipped and counted.
    let zero = Quaternion {
        x: 0.0,
        y: 0.0,
        z: 0.0,
        w: 0.0,
    };
    let p = dir().join("quat.mcap");
    let ns = 50_000_000;
    log_with(
        &p,
        &[
            (0, odom(0, "map", 0.5, zero)),
            (ns, odom(ns, "map", 0.5, id)),
        ],
        None,
    );
    let mut r = LogReplay::open(&p, &config(""), &gaits()).unwrap();
    assert_eq!(r.stats().bad_poses, 1);
    assert_eq!(drain(&mut r).unwrap().poses.len(), 1);
}

/// Clouds in a sensor frame are transformed through /tf (sensor → base → odom → map), poses in
/// an odometry frame are chained to the map, and poses can come from /tf alone.
#[test]
fn transform_chains() {
    let p = dir().join("frames.mcap");
    let yaw = std::f64::consts::FRAC_PI_2;
    let mut w = McapWriter::create(&p).unwrap();
    let qz = Quaternion::from_rpy(0.0, 0.0, yaw);
    for k in 0..=4i64 {
        let ns = k * 100_000_000;
        // map → odom: shifted by (10, 0); odom → base_link: at (1, 0) facing +y.
        w.write_ros2(
            "/tf",
            MsgType::TfMessage,
            ns,
            &tf(ns, "map", "odom", [10.0, 0.0, 0.0], Quaternion::IDENTITY),
        )
        .unwrap();
        w.write_ros2(
            "/tf",
            MsgType::TfMessage,
            ns,
            &tf(ns, "odom", "base_link", [1.0, 0.0, 0.0], qz),
        )
        .unwrap();
        w.write_ros2("/robot/odom", MsgType::Odometry, ns, &{
            let mut o = odom(ns, "odom", 1.0, qz);
            o.pose.pose.position.y = 0.0;
            o
        })
        .unwrap();
        // A point 2 m ahead of the camera (x forward in the camera frame).
        let c = ros2::encode_cloud(
            Time::from_nanos(ns),
            "camera",
            &[ColoredPoint {
                x: 2.0,
                y: 0.0,
                z: 0.0,
                rgb: [1, 2, 3],
            }],
        )
        .unwrap();
        w.write_cdr("/cam/points", MsgType::PointCloud2, ns, &c)
            .unwrap();
    }
    // base_link → camera: 0.3 m up (static).
    w.write_ros2(
        "/tf_static",
        MsgType::TfMessage,
        0,
        &tf(
            0,
            "base_link",
            "camera",
            [0.0, 0.0, 0.3],
            Quaternion::IDENTITY,
        ),
    )
    .unwrap();
    w.finish().unwrap();
    for extra in ["", "[pose]\nfrom_tf = true\nbase_frame = \"base_link\""] {
        let cfg = config(&format!(
            "{extra}\n[[clouds]]\ntopic = \"/cam/points\"\n[gait]\ntopic = \"\""
        ));
        let mut r = LogReplay::open(&p, &cfg, &gaits()).unwrap();
        let c = drain(&mut r).unwrap();
        let pose = c.poses.last().unwrap();
        assert!((pose.position.x - 11.0).abs() < 1e-9, "{pose:?}");
        assert!((pose.yaw - yaw).abs() < 1e-9);
        let cl = &c.clouds[0];
        assert!((cl.origin.x - 11.0).abs() < 1e-9 && (cl.origin.z - 0.3).abs() < 1e-9);
        let q = cl.points[0];
        assert!(
            (q.x - 11.0).abs() < 1e-5 && (q.y - 2.0).abs() < 1e-5 && (q.z - 0.3).abs() < 1e-5,
            "{q:?}"
        );
    }
    // A cloud in the world frame needs origin_frame.
    let cfg = config("[[clouds]]\ntopic = \"/robot/sensor_0/points\"");
    let p2 = dir().join("simple-origin.mcap");
    simple_log(&p2);
    let mut r = LogReplay::open(&p2, &cfg, &gaits()).unwrap();
    let e = drain(&mut r).err().unwrap().to_string();
    assert!(e.contains("origin_frame"), "{e}");
}
