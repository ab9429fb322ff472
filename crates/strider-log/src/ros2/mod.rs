//! The ROS 2 messages Strider writes and reads, as serde structs for CDR ([`crate::cdr`]), with
//! their `ros2msg` schema texts (the concatenated definitions rosbag2 stores in MCAP, which
//! `mcap-ros2-support` and Foxglove parse to decode the messages).
//!
//! Types: `builtin_interfaces/msg/Time`, `std_msgs/msg/Header`, `std_msgs/msg/String`,
//! `std_msgs/msg/UInt8`, `geometry_msgs/msg/{Point, Quaternion, Pose, Vector3, Twist,
//! Transform, TransformStamped, PoseWithCovariance, TwistWithCovariance}`,
//! `nav_msgs/msg/Odometry`, `tf2_msgs/msg/TFMessage`, `sensor_msgs/msg/{PointField,
//! PointCloud2, LaserScan}`.
//!
//! PointCloud2 is decoded field-generically ([`decode_cloud`]): `x`, `y`, `z` as FLOAT32 or
//! FLOAT64 at any offset, colour from a packed `rgb`/`rgba` field (FLOAT32 or UINT32 holding
//! `0x00RRGGBB`, PCL's convention) or separate `r`, `g`, `b` UINT8 fields, either byte order,
//! any `row_step`. A cloud without colour is an error or gray points, as configured
//! ([`MissingRgb`]).
//!
//! A LaserScan is read as a cloud without colour in its frame ([`decode_scan`]): one point
//! (r cos a, r sin a, 0) per beam with a valid range.
//!
//! The parts: `std_msgs` (time, headers, strings), `geometry` (poses, transforms, odometry),
//! `cloud` (PointCloud2), `scan` (LaserScan) and `schema` (the definitions).

mod cloud;
mod geometry;
mod scan;
mod schema;
mod std_msgs;

pub use cloud::{
    DecodedCloud, MAX_CLOUD_POINTS, MissingRgb, PointCloud2Head, PointField, datatype,
    decode_cloud, encode_cloud, encode_cloud_raw,
};
pub use geometry::{
    Odometry, Pose, PoseWithCovariance, Quaternion, TfMessage, Transform, TransformStamped, Twist,
    TwistWithCovariance, Vector3,
};
pub use scan::{LaserScan, decode_scan, encode_scan};
pub use schema::MsgType;
pub use std_msgs::{
    Header, HeaderPrefix, StringMsg, Time, UInt8Msg, motion_bits, nanos_to_seconds,
    seconds_to_nanos,
};

#[cfg(test)]
mod tests;
