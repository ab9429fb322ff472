use super::*;
use crate::cdr;
use strider_core::msg::ColoredPoint;

fn pts() -> Vec<ColoredPoint> {
    vec![
        ColoredPoint::new(1.0, -2.5, 0.25, [10, 20, 30]),
        ColoredPoint::new(f32::NAN, 0.0, 3.0, [255, 0, 128]),
    ]
}

/// A whole PointCloud2 message from its head and data.
fn cloud_msg(head: &PointCloud2Head, data: &[u8]) -> Vec<u8> {
    encode_cloud_raw(head, data, true).unwrap()
}

#[test]
fn cloud_round_trip_keeps_points_bit_exact() {
    let b = encode_cloud(Time::from_nanos(1_500_000_000), "map", &pts()).unwrap();
    let c = decode_cloud(&b, MissingRgb::Error).unwrap();
    assert_eq!(
        c.header.stamp,
        Time {
            sec: 1,
            nanosec: 500_000_000
        }
    );
    assert_eq!(c.header.frame_id.as_str(), "map");
    assert_eq!(c.points.len(), 2);
    assert_eq!(c.points[0], pts()[0]);
    assert!(c.points[1].x.is_nan());
    assert_eq!(c.points[1].rgb, [255, 0, 128]);
    assert!(!c.uncoloured);
}

#[test]
fn cloud_known_layout() {
    let b = encode_cloud(Time::default(), "m", &pts()[..1]).unwrap();
    // header: stamp 8 bytes, frame "m" = 4 + 2 bytes; padding to 4; height, width.
    assert_eq!(&b[4..12], &[0; 8]);
    assert_eq!(&b[12..18], &[2, 0, 0, 0, b'm', 0]);
    assert_eq!(&b[20..28], &[1, 0, 0, 0, 1, 0, 0, 0]);
    // The first PointField: 4 fields, name "x", offset 0, datatype 7 after 3 padding bytes
    // (the alignment after `u8 datatype` that trips hand-written decoders), count 1.
    assert_eq!(&b[28..32], &[4, 0, 0, 0]);
    assert_eq!(&b[32..38], &[2, 0, 0, 0, b'x', 0]);
    assert_eq!(&b[40..44], &[0, 0, 0, 0]);
    assert_eq!(b[44], 7);
    assert_eq!(&b[48..52], &[1, 0, 0, 0]);
    // The data ends with rgb 0x000a141e (LE), then is_dense.
    let n = b.len();
    assert_eq!(&b[n - 5..n - 1], &[30, 20, 10, 0]);
    assert_eq!(b[n - 1], 1);
}

/// A cloud written with separate r, g, b bytes, FLOAT64 coordinates, big-endian data and
/// padded rows decodes too.
#[test]
fn generic_layouts_decode() {
    let f = PointField::new;
    let head = PointCloud2Head {
        header: Header::default(),
        height: 2,
        width: 1,
        fields: vec![
            f("x", 0, datatype::FLOAT64),
            f("y", 8, datatype::FLOAT64),
            f("z", 16, datatype::FLOAT64),
            f("r", 24, datatype::UINT8),
            f("g", 25, datatype::UINT8),
            f("b", 26, datatype::UINT8),
        ],
        is_bigendian: true,
        point_step: 27,
        row_step: 30,
    };
    let mut data = Vec::new();
    for k in 0..2 {
        for v in [1.0f64 + k as f64, 2.0, 3.0] {
            data.extend_from_slice(&v.to_be_bytes());
        }
        data.extend_from_slice(&[7, 8, 9, 0, 0, 0]);
    }
    let msg = cloud_msg(&head, &data);
    let c = decode_cloud(&msg, MissingRgb::Error).unwrap();
    assert_eq!(c.points.len(), 2);
    assert_eq!(c.points[1].x, 2.0);
    assert_eq!(c.points[1].z, 3.0);
    assert_eq!(c.points[0].rgb, [7, 8, 9]);
}

#[test]
fn missing_colour_is_an_error_or_gray() {
    let head = PointCloud2Head {
        header: Header::default(),
        height: 1,
        width: 1,
        fields: vec![
            PointField::new("x", 0, datatype::FLOAT32),
            PointField::new("y", 4, datatype::FLOAT32),
            PointField::new("z", 8, datatype::FLOAT32),
        ],
        is_bigendian: false,
        point_step: 12,
        row_step: 12,
    };
    let msg = cloud_msg(&head, &[0; 12]);
    let e = decode_cloud(&msg, MissingRgb::Error).unwrap_err();
    assert!(e.to_string().contains("no colour field"), "{e}");
    let c = decode_cloud(&msg, MissingRgb::Gray).unwrap();
    assert!(c.uncoloured);
    assert_eq!(c.points[0].rgb, [128; 3]);
}

#[test]
fn short_data_is_an_error() {
    let mut b = encode_cloud(Time::default(), "map", &pts()).unwrap();
    // Claim more points than the data holds: patch width (at byte 24) to 3.
    b[24] = 3;
    let e = decode_cloud(&b, MissingRgb::Error).unwrap_err();
    assert!(e.to_string().contains("need"), "{e}");
}

#[test]
fn odometry_and_tf_round_trip() {
    let mut odom = Odometry {
        header: Header {
            stamp: Time { sec: 3, nanosec: 5 },
            frame_id: "map".into(),
        },
        child_frame_id: "base_link".into(),
        ..Default::default()
    };
    odom.pose.pose.position = Vector3 {
        x: 1.0,
        y: 2.0,
        z: 3.0,
    };
    odom.pose.pose.orientation = Quaternion::from_rpy(0.1, -0.2, 2.0);
    odom.pose.covariance.0[7] = 0.5;
    let b = cdr::encode(&odom).unwrap();
    assert_eq!(cdr::decode::<Odometry>(&b).unwrap(), odom);
    let h: HeaderPrefix = cdr::decode(&b).unwrap();
    assert_eq!(h.header, odom.header);
    let tf = TfMessage {
        transforms: vec![TransformStamped {
            header: odom.header.clone(),
            child_frame_id: "sensor_0".into(),
            transform: Transform::default(),
        }],
    };
    let b = cdr::encode(&tf).unwrap();
    assert_eq!(cdr::decode::<TfMessage>(&b).unwrap(), tf);
}

#[test]
fn rpy_round_trip() {
    for &(r, p, y) in &[(0.0, 0.0, 0.0), (0.1, -0.2, 3.0), (-0.3, 0.4, -2.9)] {
        let q = Quaternion::from_rpy(r, p, y);
        let (r2, p2, y2) = q.to_rpy();
        assert!((r - r2).abs() < 1e-12 && (p - p2).abs() < 1e-12 && (y - y2).abs() < 1e-12);
        // Rotating x̂ by a pure yaw gives (cos, sin, 0).
        let v = Quaternion::from_rpy(0.0, 0.0, y).rotate([1.0, 0.0, 0.0]);
        assert!((v[0] - y.cos()).abs() < 1e-12 && (v[1] - y.sin()).abs() < 1e-12);
    }
}

#[test]
fn time_conversions() {
    assert_eq!(
        Time::from_nanos(-1),
        Time {
            sec: -1,
            nanosec: 999_999_999
        }
    );
    assert_eq!(Time::from_nanos(2_000_000_001).nanos(), 2_000_000_001);
    assert_eq!(seconds_to_nanos(0.15), 150_000_000);
    assert_eq!(seconds_to_nanos(f64::NAN), 0);
}

fn laser_scan(ranges: Vec<f32>) -> LaserScan {
    LaserScan {
        header: Header {
            stamp: Time { sec: 2, nanosec: 7 },
            frame_id: "laser".into(),
        },
        angle_min: -std::f32::consts::FRAC_PI_2,
        angle_max: std::f32::consts::FRAC_PI_2,
        angle_increment: std::f32::consts::FRAC_PI_4,
        range_min: 0.1,
        range_max: 30.0,
        intensities: vec![5.0; ranges.len()],
        ranges,
        ..Default::default()
    }
}

#[test]
fn scan_ranges_become_points_and_invalid_ones_none() {
    let s = laser_scan(vec![
        1.0,
        f32::NAN,
        f32::INFINITY,
        f32::NEG_INFINITY,
        0.05,
        2.0,
    ]);
    let mut s2 = s.clone();
    s2.ranges.push(31.0);
    // The same in both byte orders.
    let le = encode_scan(&s2).unwrap();
    let be = ::cdr::serialize::<_, _, ::cdr::CdrBe>(&s2, ::cdr::Infinite).unwrap();
    for msg in [le, be] {
        let c = decode_scan(&msg).unwrap();
        assert_eq!(c.header, s.header);
        assert!(c.uncoloured);
        assert_eq!(c.points.len(), 2, "{:?}", c.points);
        // Beam 0 at -90°, beam 5 at -90° + 5 · 45° = 135°.
        let (p, q) = (c.points[0], c.points[1]);
        assert!(
            p.x.abs() < 1e-6 && (p.y + 1.0).abs() < 1e-6 && p.z == 0.0,
            "{p:?}"
        );
        let a = -std::f64::consts::FRAC_PI_2 + 5.0 * std::f64::consts::FRAC_PI_4;
        assert!((q.x as f64 - 2.0 * a.cos()).abs() < 1e-6, "{q:?}");
        assert!((q.y as f64 - 2.0 * a.sin()).abs() < 1e-6, "{q:?}");
        assert_eq!(q.rgb, [128; 3]);
    }
}

#[test]
fn scan_sizes_are_checked_before_allocating() {
    let msg = encode_scan(&laser_scan(vec![1.0; 8])).unwrap();
    // The ranges' count sits before the 8 ranges, the intensities' count and 8 intensities.
    let at = msg.len() - 4 * (1 + 8 + 1 + 8);
    assert_eq!(&msg[at..at + 4], &8u32.to_le_bytes());
    // 8 ranges, a count and 8 intensities follow: 17 float32 fit, 18 do not.
    for n in [18u32, 1 << 30, u32::MAX] {
        let mut m = msg.clone();
        m[at..at + 4].copy_from_slice(&n.to_le_bytes());
        let e = decode_scan(&m).unwrap_err().to_string();
        assert!(
            e.contains(&format!("array of {n} float32 announced")),
            "{e}"
        );
    }
    // More beams than a cloud may have points, all present.
    let huge = encode_scan(&laser_scan(vec![1.0; MAX_CLOUD_POINTS + 1])).unwrap();
    let e = decode_scan(&huge).unwrap_err().to_string();
    assert!(e.contains("more than the 16777216"), "{e}");
    let mut s = laser_scan(vec![1.0]);
    s.angle_min = f32::INFINITY;
    let e = decode_scan(&encode_scan(&s).unwrap())
        .unwrap_err()
        .to_string();
    assert!(e.contains("angle_min = inf"), "{e}");
}
