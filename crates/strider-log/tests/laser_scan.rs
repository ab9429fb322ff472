//! A planar laser's `sensor_msgs/LaserScan` topic as a cloud source: the same scans written as
//! LaserScan and as PointCloud2 (x, y, z without colour) replay to the same clouds and map;
//! invalid ranges give no point; a LaserScan needs `missing_rgb = "gray"` like any cloud
//! without colour; bad scans are named.

mod common;

use common::*;
use std::path::Path;
use strider_core::msg::ColoredPoint;
use strider_log::ros2::{
    self, LaserScan, MsgType, PointCloud2Head, PointField, Quaternion, datatype,
};
use strider_log::{LogReplay, McapWriter, ReplayConfig};

const BEAMS: usize = 181;
const RANGE_MIN: f32 = 0.05;
const RANGE_MAX: f32 = 8.0;

/// Scan `k`'s ranges: a wavy wall about 2 m away, with beams that give no return (NaN, ±inf,
/// below range_min, above range_max) and beams exactly at the limits (valid).
fn ranges(k: usize) -> Vec<f32> {
    (0..BEAMS)
        .map(|i| match i % 40 {
            3 => f32::NAN,
            7 => f32::INFINITY,
            11 => f32::NEG_INFINITY,
            13 => 0.01,
            17 => 50.0,
            19 => RANGE_MAX,
            23 => RANGE_MIN,
            _ => 2.0 + 0.4 * ((i as f32) * 0.11).sin() + 0.02 * k as f32,
        })
        .collect()
}

/// The scan with `ranges`, as a LaserScan from -90° to 90° in 1° steps.
fn scan(ns: i64, ranges: Vec<f32>) -> LaserScan {
    let inc = std::f32::consts::PI / (BEAMS - 1) as f32;
    LaserScan {
        header: header(ns, "laser"),
        angle_min: -std::f32::consts::FRAC_PI_2,
        angle_max: std::f32::consts::FRAC_PI_2,
        angle_increment: inc,
        time_increment: 0.0,
        scan_time: 0.2,
        range_min: RANGE_MIN,
        range_max: RANGE_MAX,
        intensities: vec![1000.0; ranges.len()],
        ranges,
    }
}

/// The same scan as a PointCloud2 of x, y, z (FLOAT32, no colour): one point per valid range
/// at angle_min + i · angle_increment.
fn as_cloud(s: &LaserScan) -> Vec<u8> {
    let mut data = Vec::new();
    let mut n = 0u32;
    for (i, &r) in s.ranges.iter().enumerate() {
        if !(r.is_finite() && (s.range_min..=s.range_max).contains(&r)) {
            continue;
        }
        let a = s.angle_min as f64 + i as f64 * s.angle_increment as f64;
        let (x, y) = ((r as f64 * a.cos()) as f32, (r as f64 * a.sin()) as f32);
        for v in [x, y, 0.0f32] {
            data.extend_from_slice(&v.to_le_bytes());
        }
        n += 1;
    }
    let f = |name: &str, offset| PointField::new(name, offset, datatype::FLOAT32);
    let head = PointCloud2Head {
        header: s.header.clone(),
        height: 1,
        width: n,
        fields: vec![f("x", 0), f("y", 4), f("z", 8)],
        is_bigendian: false,
        point_step: 12,
        row_step: 12 * n,
    };
    ros2::encode_cloud_raw(&head, &data, true).unwrap()
}

/// Four seconds of a robot driving a slow arc in `odom` with a laser ahead of its base (static
/// transform) scanning at 5 Hz on /scan, as LaserScan or as PointCloud2.
fn scan_log(path: &Path, laser_scan: bool) {
    let mut w = McapWriter::create(path).unwrap();
    w.write_ros2(
        "/tf_static",
        MsgType::TfMessage,
        0,
        &tf(
            0,
            "base_link",
            "laser",
            [0.2, 0.0, 0.35],
            Quaternion::from_rpy(0.0, 0.0, 0.1),
        ),
    )
    .unwrap();
    for k in 0..=40usize {
        let ns = k as i64 * 100_000_000;
        let (x, yaw) = (0.05 * k as f64, 0.02 * k as f64);
        let q = Quaternion::from_rpy(0.0, 0.0, yaw);
        w.write_ros2("/odom", MsgType::Odometry, ns, &odom(ns, "odom", x, q))
            .unwrap();
        w.write_ros2(
            "/tf",
            MsgType::TfMessage,
            ns,
            &tf(ns, "odom", "base_link", [x, 0.5, 0.0], q),
        )
        .unwrap();
        if k % 2 == 0 {
            let s = scan(ns, ranges(k));
            if laser_scan {
                w.write_ros2("/scan", MsgType::LaserScan, ns, &s).unwrap();
            } else {
                w.write_cdr("/scan", MsgType::PointCloud2, ns, &as_cloud(&s))
                    .unwrap();
            }
        }
    }
    w.finish().unwrap();
}

const SCAN_CONFIG: &str = "world_frame = \"odom\"\nmotion_topic = \"\"\nkeyframes = false\n\
     [pose]\ntopic = \"/odom\"\n[gait]\ntopic = \"\"\n\
     [[clouds]]\ntopic = \"/scan\"\nmissing_rgb = \"gray\"";

#[test]
fn laser_scans_replay_to_the_map_of_the_same_points_as_pointcloud2() {
    let (ps, pc) = (dir().join("scan-ls.mcap"), dir().join("scan-pc2.mcap"));
    scan_log(&ps, true);
    scan_log(&pc, false);
    let cfg = config(SCAN_CONFIG);
    let mut a = LogReplay::open(&ps, &cfg, &gaits()).unwrap();
    let mut b = LogReplay::open(&pc, &cfg, &gaits()).unwrap();
    let (ca, cb) = (drain(&mut a).unwrap(), drain(&mut b).unwrap());
    assert_eq!(ca.clouds.len(), 21);
    assert_eq!(ca.poses, cb.poses);
    assert_eq!(
        cloud_bits(&ca),
        cloud_bits(&cb),
        "the same points, origins, stamps"
    );
    assert_eq!(a.stats(), b.stats());
    assert_eq!(
        a.warnings(),
        b.warnings(),
        "both mapped gray, with the same note"
    );
    // 181 beams, of which 5 in every 40 give no return (the two at the limits do).
    let valid = (0..BEAMS)
        .filter(|i| ![3, 7, 11, 13, 17].contains(&(i % 40)))
        .count();
    assert!(ca.clouds.iter().all(|c| c.points.len() == valid));
    assert_eq!(ca.clouds[0].points[0].rgb, [128; 3]);
    let map = map_of(&ca);
    assert!(map.observed_count() > 100, "{}", map.observed_count());
    assert_same_map(&map, &map_of(&cb), "LaserScan vs PointCloud2");
}

#[test]
fn a_scan_point_lies_at_its_range_and_bearing_in_the_world() {
    let p = dir().join("scan-geometry.mcap");
    scan_log(&p, true);
    let mut r = LogReplay::open(&p, &config(SCAN_CONFIG), &gaits()).unwrap();
    let c = drain(&mut r).unwrap();
    // Scan 0: the robot at (0, 0.5) facing +x, the laser 0.2 m ahead at 0.35 m, turned 0.1
    // rad; beam 90 (straight ahead of the laser) at range ranges(0)[90].
    let r90 = ranges(0)[90] as f64;
    let expect = [0.2 + r90 * 0.1f64.cos(), 0.5 + r90 * 0.1f64.sin(), 0.35];
    let ColoredPoint { x, y, z, .. } = *c.clouds[0]
        .points
        .iter()
        .min_by(|p, q| {
            let d = |p: &ColoredPoint| (p.x as f64 - expect[0]).hypot(p.y as f64 - expect[1]);
            d(p).total_cmp(&d(q))
        })
        .unwrap();
    assert!(
        (x as f64 - expect[0]).abs() < 1e-4
            && (y as f64 - expect[1]).abs() < 1e-4
            && (z as f64 - expect[2]).abs() < 1e-6,
        "({x}, {y}, {z}) vs {expect:?}"
    );
    let o = c.clouds[0].origin;
    assert!((o.x - 0.2).abs() < 1e-9 && (o.y - 0.5).abs() < 1e-9 && (o.z - 0.35).abs() < 1e-9);
}

#[test]
fn a_laser_scan_needs_missing_rgb_gray_and_unknown_keys_are_refused() {
    let p = dir().join("scan-rgb.mcap");
    scan_log(&p, true);
    let no_gray = SCAN_CONFIG.replace("\nmissing_rgb = \"gray\"", "");
    let e = open_error(&p, &config(&no_gray));
    assert!(
        e.contains("/scan, message 0")
            && e.contains("sensor_msgs/msg/LaserScan has no colour")
            && e.contains("missing_rgb = \"gray\""),
        "{e}"
    );
    let text = format!(
        "{SCAN_CONFIG}\ntype = \"laser_scan\"\n[mission]\ngaits = [{{ name = \"fast\", \
         v_max = 0.05 }}]\nsensor_hfov_deg = [180.0]\n"
    );
    let e = ReplayConfig::parse(&text).unwrap_err().to_string();
    assert!(e.contains("unknown field `type`"), "{e}");
}

#[test]
fn bad_laser_scans_are_named() {
    let good = ros2::encode_scan(&scan(0, ranges(0))).unwrap();
    // The ranges' count (after the header and seven float32) claims more than is there.
    let count_at = good.len() - 4 * (2 * BEAMS + 2);
    let mut long = good.clone();
    long[count_at..count_at + 4].copy_from_slice(&u32::MAX.to_le_bytes());
    let mut nan_angle = scan(0, ranges(0));
    nan_angle.angle_increment = f32::NAN;
    let cases = [
        (long, "array of 4294967295 float32 announced"),
        (good[..good.len() / 2].to_vec(), "float32 announced"),
        (
            ros2::encode_scan(&nan_angle).unwrap(),
            "angle_increment = NaN: not a finite angle",
        ),
    ];
    for (bytes, needle) in cases {
        let p = dir().join("scan-bad.mcap");
        let mut w = McapWriter::create(&p).unwrap();
        w.write_ros2(
            "/odom",
            MsgType::Odometry,
            0,
            &odom(0, "odom", 0.0, Quaternion::IDENTITY),
        )
        .unwrap();
        w.write_cdr("/scan", MsgType::LaserScan, 0, &bytes).unwrap();
        w.finish().unwrap();
        let mut r = LogReplay::open(&p, &config(SCAN_CONFIG), &gaits()).unwrap();
        let e = drain(&mut r).err().unwrap().to_string();
        assert!(e.contains("/scan, message 0") && e.contains(needle), "{e}");
        assert!(!e.contains('\n'), "{e}");
    }
}
