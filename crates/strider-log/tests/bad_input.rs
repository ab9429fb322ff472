//! Replay of small synthetic logs: the fallbacks and the errors on bad input (empty, foreign,
//! truncated and corrupted files, wrong chunk CRCs, missing topics, foreign encodings and
//! schemas, short messages, clouds without colour or whose size does not match their data,
//! bogus and backward stamps, unknown gaits), and the transform handling (clouds in a sensor
//! frame, poses in an odometry frame or from /tf). Never a panic; every error one plain line.

mod common;

use common::*;
use std::path::Path;
use strider_core::msg::ColoredPoint;
use strider_log::ros2::{self, MsgType, Odometry, Quaternion, StringMsg, Time};
use strider_log::{LogReplay, McapWriter};

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

/// An error line is one line of plain text: no terminal escapes, no backtrace banner.
fn assert_plain(e: &str) {
    assert!(
        !e.contains('\n') && !e.chars().any(|c| c.is_control()) && !e.contains("Backtrace"),
        "{e:?}"
    );
}

#[test]
fn bad_containers_give_one_plain_line_naming_the_file() {
    let p = dir().join("container.mcap");
    simple_log(&p);
    let bytes = std::fs::read(&p).unwrap();
    let cases: Vec<(&str, Vec<u8>, &str)> = vec![
        (
            "empty.mcap",
            Vec::new(),
            "the file is empty, not an MCAP file",
        ),
        (
            "text.mcap",
            b"hello, this is not an MCAP file\n".repeat(4),
            "not an MCAP file: it does not begin with the MCAP magic bytes",
        ),
        (
            "cut.mcap",
            bytes[..bytes.len() / 3].to_vec(),
            "a recording cut short can be repaired",
        ),
        (
            "short.mcap",
            bytes[..5].to_vec(),
            "the file ends in the middle",
        ),
    ];
    for (name, b, needle) in cases {
        let q = dir().join(name);
        std::fs::write(&q, &b).unwrap();
        let e = open_error(&q, &config(""));
        assert!(e.contains(name) && e.contains(needle), "{e}");
        assert_plain(&e);
    }
    // Bits of the header record flipped: the record parser's diagnosis (coloured, with a
    // backtrace banner) is reduced to its cause.
    let mut corrupt = 0;
    for k in 8..60 {
        for bit in [0x01u8, 0x10, 0x80] {
            let mut b = bytes.clone();
            b[k] ^= bit;
            let q = dir().join("header-flip.mcap");
            std::fs::write(&q, &b).unwrap();
            if let Err(e) = LogReplay::open(&q, &config(""), &gaits()) {
                let e = e.to_string();
                assert!(e.contains("header-flip.mcap"), "{e}");
                assert_plain(&e);
                corrupt += usize::from(e.contains("corrupt MCAP: a record"));
            }
        }
    }
    assert!(corrupt > 0, "the header flips reach the record parser");
}

/// The `k`th message of [`uncompressed_log`].
fn odom_bytes(k: i64) -> Vec<u8> {
    strider_log::cdr::encode(&odom(k, "map", 1234.5 + k as f64, Quaternion::IDENTITY)).unwrap()
}

/// An uncompressed log of `n` odometry messages, written with the mcap crate directly.
fn uncompressed_log(path: &Path, n: i64) -> Vec<u8> {
    let f = std::io::BufWriter::new(std::fs::File::create(path).unwrap());
    let mut w = mcap::WriteOptions::new()
        .compression(None)
        .profile("ros2")
        .create(f)
        .unwrap();
    let s = w
        .add_schema(MsgType::Odometry.name(), "ros2msg", b"")
        .unwrap();
    let ch = w
        .add_channel(s, "/robot/odom", "cdr", &Default::default())
        .unwrap();
    for k in 0..n {
        let msg = odom_bytes(k);
        w.write_to_known_channel(
            &mcap::records::MessageHeader {
                channel_id: ch,
                sequence: k as u32,
                log_time: k as u64,
                publish_time: k as u64,
            },
            &msg,
        )
        .unwrap();
    }
    w.finish().unwrap();
    drop(w);
    std::fs::read(path).unwrap()
}

#[test]
fn a_chunk_with_a_wrong_crc_is_named() {
    let p = dir().join("crc.mcap");
    let mut b = uncompressed_log(&p, 4);
    // A byte of the last message's payload, inside the chunk.
    let last = odom_bytes(3);
    let at = b.windows(last.len()).position(|w| w == last).unwrap();
    b[at + last.len() / 2] ^= 0x40;
    std::fs::write(&p, &b).unwrap();
    let e = open_error(&p, &config(""));
    assert!(
        e.contains("crc.mcap") && e.contains("corrupt MCAP: Chunk CRC failed"),
        "{e}"
    );
    assert_plain(&e);
}

#[test]
fn unknown_schemas_and_short_messages_are_named() {
    // A schema the reader does not know, on a configured topic.
    let p = dir().join("unknown-schema.mcap");
    {
        let f = std::io::BufWriter::new(std::fs::File::create(&p).unwrap());
        let mut w = mcap::Writer::new(f).unwrap();
        let s = w
            .add_schema("acme_msgs/msg/Teleport", "ros2msg", b"int8 x")
            .unwrap();
        let ch = w
            .add_channel(s, "/robot/odom", "cdr", &Default::default())
            .unwrap();
        let header = mcap::records::MessageHeader {
            channel_id: ch,
            sequence: 0,
            log_time: 0,
            publish_time: 0,
        };
        w.write_to_known_channel(&header, &[0, 1, 0, 0, 7]).unwrap();
        w.finish().unwrap();
    }
    let e = open_error(&p, &config(""));
    assert!(
        e.contains("/robot/odom") && e.contains("acme_msgs/msg/Teleport"),
        "{e}"
    );
    // CDR messages too short for what they declare: a pose, a gait, a cloud header.
    for (topic, ty) in [
        ("/robot/odom", MsgType::Odometry),
        ("/robot/gait", MsgType::String),
        ("/robot/sensor_0/points", MsgType::PointCloud2),
    ] {
        for data in [&[][..], &[0, 1][..], &[0, 1, 0, 0, 9, 0][..]] {
            let p = dir().join("short-msg.mcap");
            let mut w = McapWriter::create(&p).unwrap();
            w.write_cdr(topic, ty, 0, data).unwrap();
            w.finish().unwrap();
            let e = open_error(&p, &config(""));
            assert!(e.contains(topic) && e.contains("message 0"), "{e}");
            assert_plain(&e);
        }
    }
}

/// A log whose one cloud has `head` and `data`, otherwise like [`simple_log`].
fn cloud_log(path: &Path, head: &strider_log::ros2::PointCloud2Head, data: &[u8]) {
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
    let bytes = strider_log::ros2::encode_cloud_raw(head, data, true).unwrap();
    w.write_cdr("/robot/sensor_0/points", MsgType::PointCloud2, 0, &bytes)
        .unwrap();
    w.finish().unwrap();
}

#[test]
fn clouds_whose_size_does_not_match_their_data_are_refused() {
    use strider_log::ros2::{PointCloud2Head, PointField, datatype};
    let f = |name: &str, offset| PointField::new(name, offset, datatype::FLOAT32);
    let head = |width: u32, height: u32, step: u32| PointCloud2Head {
        header: header(0, "map"),
        height,
        width,
        fields: vec![f("x", 0), f("y", 4), f("z", 8), f("rgb", 12)],
        is_bigendian: false,
        point_step: step,
        row_step: width.wrapping_mul(step),
    };
    let data = vec![0u8; 64];
    for (h, needle) in [
        // 5 points of 16 bytes in 64 bytes.
        (head(5, 1, 16), "need 80 bytes of data, 64 present"),
        // 2^16 × 2^16 points: refused before anything is allocated for them.
        (head(1 << 16, 1 << 16, 16), "points: more than the 16777216"),
        (head(u32::MAX, u32::MAX, 16), "points: more than"),
        (head(4, 1, 0), "outside the 0-byte point"),
        (head(4, 1, 8), "outside the 8-byte point"),
    ] {
        let p = dir().join("cloud-size.mcap");
        cloud_log(&p, &h, &data);
        let mut r = LogReplay::open(&p, &config(""), &gaits()).unwrap();
        let e = drain(&mut r).err().unwrap().to_string();
        assert!(
            e.contains("/robot/sensor_0/points") && e.contains(needle),
            "{needle}: {e}"
        );
        assert_plain(&e);
    }
    // The same layout with the data it needs replays.
    let p = dir().join("cloud-ok.mcap");
    cloud_log(&p, &head(4, 1, 16), &data);
    let mut r = LogReplay::open(&p, &config(""), &gaits()).unwrap();
    assert_eq!(drain(&mut r).unwrap().clouds[0].points.len(), 4);
}

/// A log with poses every 0.1 s for 3 s and clouds at `cloud_ns`, in that file order.
fn unordered_log(path: &Path, cloud_ns: &[i64], pose_order: &[i64]) {
    let mut w = McapWriter::create(path).unwrap();
    w.write_ros2(
        "/tf_static",
        MsgType::TfMessage,
        0,
        &tf(0, "map", "sensor_0", [0.5, 0.5, 0.3], Quaternion::IDENTITY),
    )
    .unwrap();
    for &k in pose_order {
        let ns = k * 100_000_000;
        let o = odom(ns, "map", 0.01 * k as f64, Quaternion::IDENTITY);
        w.write_ros2("/robot/odom", MsgType::Odometry, ns, &o)
            .unwrap();
    }
    for &ns in cloud_ns {
        let c = ros2::encode_cloud(Time::from_nanos(ns), "map", &pts()).unwrap();
        w.write_cdr("/robot/sensor_0/points", MsgType::PointCloud2, ns, &c)
            .unwrap();
    }
    w.finish().unwrap();
}

#[test]
fn stamps_going_backwards() {
    let s = 1_000_000_000i64;
    let forward: Vec<i64> = (0..=30).collect();
    let backward: Vec<i64> = (0..=30).rev().collect();
    // Poses in reverse file order, clouds out of order within the reorder window: replayed in
    // stamp order.
    let p = dir().join("backwards-ok.mcap");
    unordered_log(&p, &[s / 2, 0, 2 * s, s], &backward);
    let mut r = LogReplay::open(&p, &config(""), &gaits()).unwrap();
    let c = drain(&mut r).unwrap();
    let stamps: Vec<f64> = c.clouds.iter().map(|c| c.stamp).collect();
    assert_eq!(stamps, [0.0, 0.5, 1.0, 2.0]);
    assert!(c.poses.windows(2).all(|w| w[0].stamp < w[1].stamp));
    assert_eq!(c.poses.len(), 31);
    // A cloud further out of order than the window: an error that says what to change.
    let p = dir().join("backwards-late.mcap");
    unordered_log(&p, &[0, 3 * s, s / 2], &forward);
    let mut r = LogReplay::open(&p, &config(""), &gaits()).unwrap();
    let e = drain(&mut r).err().unwrap().to_string();
    assert!(
        e.contains("/robot/sensor_0/points, message 2")
            && e.contains("stamped 0.500 s")
            && e.contains("raise reorder_window_s"),
        "{e}"
    );
    // With a window that covers it, the same log replays in stamp order.
    let mut r = LogReplay::open(&p, &config("reorder_window_s = 3.0"), &gaits()).unwrap();
    let stamps: Vec<f64> = drain(&mut r)
        .unwrap()
        .clouds
        .iter()
        .map(|c| c.stamp)
        .collect();
    assert_eq!(stamps, [0.0, 0.5, 3.0]);
}

#[test]
fn a_log_in_memory_replays_as_its_file_does() {
    let p = dir().join("memory.mcap");
    simple_log(&p);
    let bytes = std::fs::read(&p).unwrap();
    let mut a = LogReplay::open(&p, &config(""), &gaits()).unwrap();
    let mut b = LogReplay::from_bytes("memory.mcap", bytes.clone(), &config(""), &gaits()).unwrap();
    let (ca, cb) = (drain(&mut a).unwrap(), drain(&mut b).unwrap());
    assert_eq!(ca.poses, cb.poses);
    let summary = |c: &Collect| -> Vec<(f64, usize)> {
        c.clouds.iter().map(|c| (c.stamp, c.points.len())).collect()
    };
    assert_eq!(summary(&ca), summary(&cb));
    let e = LogReplay::from_bytes("in-memory log", &bytes[..100], &config(""), &gaits())
        .err()
        .unwrap()
        .to_string();
    assert!(e.starts_with("in-memory log: "), "{e}");
}
