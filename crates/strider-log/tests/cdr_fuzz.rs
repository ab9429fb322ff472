//! Fuzzing of the ROS 2 CDR decoders with proptest: no panic (and no runaway allocation) on
//! arbitrary bytes or on mutated valid messages, and exact round trips of valid ones.
//!
//! The default run is short (proptest's 256 cases per property, or `PROPTEST_CASES`). The long
//! run is the ignored time-budget test:
//!
//! ```sh
//! FUZZ_SECONDS=600 cargo test --release -p strider-log --test cdr_fuzz -- --ignored --nocapture
//! ```
//!
//! Inputs that once broke a decoder (or could, by construction) are kept below as regression
//! tests (`corpus_*`).

use proptest::prelude::*;
use proptest::strategy::ValueTree;
use proptest::test_runner::{Config, TestRunner};
use strider_core::msg::ColoredPoint;
use strider_log::cdr::{self, RosString};
use strider_log::ros2::{
    self, HeaderPrefix, MissingRgb, Odometry, PointCloud2Head, PointField, Quaternion, StringMsg,
    TfMessage, Time, Transform, TransformStamped, UInt8Msg, Vector3, datatype, encode_cloud_raw,
};

/// Runs every decoder on `bytes`; only a panic (or an abort) fails.
fn decode_all(bytes: &[u8]) {
    let _ = cdr::decode::<Odometry>(bytes);
    let _ = cdr::decode::<TfMessage>(bytes);
    let _ = cdr::decode::<StringMsg>(bytes);
    let _ = cdr::decode::<UInt8Msg>(bytes);
    let _ = cdr::decode::<HeaderPrefix>(bytes);
    let _ = cdr::decode::<PointCloud2Head>(bytes);
    let _ = ros2::decode_cloud(bytes, MissingRgb::Error);
    if let Ok(c) = ros2::decode_cloud(bytes, MissingRgb::Gray) {
        // A decoded cloud never holds more points than the bytes could carry.
        assert!(c.points.len() <= bytes.len());
    }
}

fn point() -> impl Strategy<Value = ColoredPoint> {
    (any::<f32>(), any::<f32>(), any::<f32>(), any::<[u8; 3]>())
        .prop_map(|(x, y, z, rgb)| ColoredPoint { x, y, z, rgb })
}

fn text() -> impl Strategy<Value = String> {
    "[a-z_/0-9]{0,12}"
}

fn finite() -> impl Strategy<Value = f64> {
    -1e6..1e6f64
}

fn odometry() -> impl Strategy<Value = Odometry> {
    (
        any::<i64>(),
        text(),
        text(),
        [finite(), finite(), finite()],
        [finite(), finite(), finite(), finite()],
    )
        .prop_map(|(ns, frame, child, p, q)| {
            let mut o = Odometry {
                header: ros2::Header {
                    stamp: Time::from_nanos(ns / 4),
                    frame_id: RosString(frame),
                },
                child_frame_id: RosString(child),
                ..Default::default()
            };
            o.pose.pose.position = Vector3 {
                x: p[0],
                y: p[1],
                z: p[2],
            };
            o.pose.pose.orientation = Quaternion {
                x: q[0],
                y: q[1],
                z: q[2],
                w: q[3],
            };
            o.pose.covariance.0[5] = p[0];
            o
        })
}

fn tf_message() -> impl Strategy<Value = TfMessage> {
    prop::collection::vec((text(), text(), [finite(), finite(), finite()]), 0..4).prop_map(|v| {
        TfMessage {
            transforms: v
                .into_iter()
                .map(|(p, c, t)| TransformStamped {
                    header: ros2::Header {
                        stamp: Time::default(),
                        frame_id: RosString(p),
                    },
                    child_frame_id: RosString(c),
                    transform: Transform {
                        translation: Vector3 {
                            x: t[0],
                            y: t[1],
                            z: t[2],
                        },
                        rotation: Quaternion::IDENTITY,
                    },
                })
                .collect(),
        }
    })
}

/// A valid encoded message of any supported type.
fn valid_message() -> impl Strategy<Value = Vec<u8>> {
    prop_oneof![
        (any::<i64>(), text(), prop::collection::vec(point(), 0..40)).prop_map(
            |(ns, frame, pts)| ros2::encode_cloud(Time::from_nanos(ns / 4), &frame, &pts).unwrap()
        ),
        odometry().prop_map(|o| cdr::encode(&o).unwrap()),
        tf_message().prop_map(|t| cdr::encode(&t).unwrap()),
        text().prop_map(|s| cdr::encode(&StringMsg { data: RosString(s) }).unwrap()),
        any::<u8>().prop_map(|v| cdr::encode(&UInt8Msg { data: v }).unwrap()),
    ]
}

/// Edits of a message: (position fraction, kind, byte).
fn mutated() -> impl Strategy<Value = Vec<u8>> {
    (
        valid_message(),
        prop::collection::vec((0.0..1.0f64, 0u8..4, any::<u8>()), 1..6),
    )
        .prop_map(|(mut m, edits)| {
            for (at, kind, b) in edits {
                let k = ((m.len() as f64) * at) as usize;
                match kind {
                    // Overwrite one byte.
                    0 if k < m.len() => m[k] = b,
                    // A length-like word: all ones or a large count at an aligned spot.
                    1 if k + 4 <= m.len() => {
                        let k = k & !3;
                        m[k..k + 4].copy_from_slice(&[b, 0xff, 0xff, 0x7f]);
                    }
                    // Truncate.
                    2 => m.truncate(k),
                    // Insert a byte (shifts every later alignment).
                    _ => m.insert(k.min(m.len()), b),
                }
            }
            m
        })
}

fn arbitrary() -> impl Strategy<Value = Vec<u8>> {
    prop_oneof![
        prop::collection::vec(any::<u8>(), 0..256),
        // With a valid CDR_LE header, so the decoders get past it.
        prop::collection::vec(any::<u8>(), 0..256).prop_map(|mut v| {
            let mut m = vec![0, 1, 0, 0];
            m.append(&mut v);
            m
        }),
    ]
}

proptest! {
    #[test]
    fn arbitrary_bytes_never_panic(bytes in arbitrary()) {
        decode_all(&bytes);
    }

    #[test]
    fn mutated_messages_never_panic(bytes in mutated()) {
        decode_all(&bytes);
    }

    #[test]
    fn odometry_round_trips(o in odometry()) {
        let b = cdr::encode(&o).unwrap();
        prop_assert_eq!(cdr::decode::<Odometry>(&b).unwrap(), o);
    }

    #[test]
    fn tf_round_trips(t in tf_message()) {
        let b = cdr::encode(&t).unwrap();
        prop_assert_eq!(cdr::decode::<TfMessage>(&b).unwrap(), t);
    }

    #[test]
    fn clouds_round_trip_bit_for_bit(pts in prop::collection::vec(point(), 0..60), frame in text()) {
        let b = ros2::encode_cloud(Time { sec: 7, nanosec: 9 }, &frame, &pts).unwrap();
        let c = ros2::decode_cloud(&b, MissingRgb::Error).unwrap();
        prop_assert_eq!(c.header.frame_id.as_str(), frame.as_str());
        prop_assert_eq!(c.points.len(), pts.len());
        for (a, b) in c.points.iter().zip(&pts) {
            prop_assert_eq!(a.x.to_bits(), b.x.to_bits());
            prop_assert_eq!(a.y.to_bits(), b.y.to_bits());
            prop_assert_eq!(a.z.to_bits(), b.z.to_bits());
            prop_assert_eq!(a.rgb, b.rgb);
        }
    }
}

/// The long fuzz run: both generators for `FUZZ_SECONDS` (default 600) of wall time.
#[test]
#[ignore = "long fuzz run; FUZZ_SECONDS=600 cargo test --release -p strider-log --test cdr_fuzz -- --ignored"]
fn fuzz_for_a_time_budget() {
    let secs: u64 = std::env::var("FUZZ_SECONDS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(600);
    let start = std::time::Instant::now();
    let mut runner = TestRunner::new(Config::default());
    let (a, m) = (arbitrary(), mutated());
    let mut cases: u64 = 0;
    while start.elapsed().as_secs() < secs {
        for _ in 0..1000 {
            let x = a.new_tree(&mut runner).unwrap().current();
            decode_all(&x);
            let y = m.new_tree(&mut runner).unwrap().current();
            decode_all(&y);
            cases += 2;
        }
    }
    println!(
        "fuzzed {cases} inputs in {:.0} s without a panic",
        start.elapsed().as_secs_f64()
    );
}

/// Regression corpus: inputs built to hit each guard of the decoders.
#[test]
fn corpus_hostile_lengths() {
    // A string (frame_id) announcing 4 GiB.
    let mut m = vec![0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0];
    m.extend_from_slice(&[0xff, 0xff, 0xff, 0xff, b'm', 0]);
    decode_all(&m);
    assert!(cdr::decode::<HeaderPrefix>(&m).is_err());
    // A TFMessage announcing 2^31 transforms.
    decode_all(&[0, 1, 0, 0, 0, 0, 0, 0x80]);
    assert!(cdr::decode::<TfMessage>(&[0, 1, 0, 0, 0, 0, 0, 0x80]).is_err());
}

fn cloud_with(head: PointCloud2Head, data: &[u8]) -> Vec<u8> {
    encode_cloud_raw(&head, data, true).unwrap()
}

fn xyz_fields(step_offset: u32) -> Vec<PointField> {
    ["x", "y", "z", "rgb"]
        .iter()
        .enumerate()
        .map(|(k, n)| PointField::new(n, step_offset + 4 * k as u32, datatype::FLOAT32))
        .collect()
}

#[test]
fn corpus_cloud_geometry() {
    let base = PointCloud2Head {
        header: Default::default(),
        height: 1,
        width: 1,
        fields: xyz_fields(0),
        is_bigendian: false,
        point_step: 16,
        row_step: 16,
    };
    let ok = cloud_with(base.clone(), &[0; 16]);
    assert_eq!(
        ros2::decode_cloud(&ok, MissingRgb::Error)
            .unwrap()
            .points
            .len(),
        1
    );
    let cases = [
        // width × height overflowing usize.
        PointCloud2Head {
            width: u32::MAX,
            height: u32::MAX,
            row_step: u32::MAX,
            ..base.clone()
        },
        // point_step 0 with points.
        PointCloud2Head {
            point_step: 0,
            ..base.clone()
        },
        // Rows overlapping (row_step shorter than a row).
        PointCloud2Head {
            height: 2,
            width: 2,
            row_step: 4,
            ..base.clone()
        },
        // A field outside the point.
        PointCloud2Head {
            fields: xyz_fields(8),
            ..base.clone()
        },
        // More points than data.
        PointCloud2Head {
            width: 1000,
            row_step: 16000,
            ..base.clone()
        },
        // An unknown datatype.
        PointCloud2Head {
            fields: {
                let mut f = xyz_fields(0);
                f[0].datatype = 200;
                f
            },
            ..base.clone()
        },
    ];
    for head in cases {
        let m = cloud_with(head.clone(), &[0; 16]);
        decode_all(&m);
        assert!(
            ros2::decode_cloud(&m, MissingRgb::Gray).is_err(),
            "{head:?} should be refused"
        );
    }
}
