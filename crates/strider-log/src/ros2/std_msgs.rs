//! `builtin_interfaces/msg/Time` and the `std_msgs` messages: headers, strings and bytes.

use crate::cdr::RosString;
use serde::{Deserialize, Serialize};

/// `builtin_interfaces/msg/Time`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize)]
pub struct Time {
    /// Seconds.
    pub sec: i32,
    /// Nanoseconds within the second.
    pub nanosec: u32,
}

impl Time {
    /// From nanoseconds since the epoch of the log (saturating at the `i32` seconds range).
    pub fn from_nanos(ns: i64) -> Self {
        let sec = ns.div_euclid(1_000_000_000);
        let nanosec = ns.rem_euclid(1_000_000_000) as u32;
        Self {
            sec: sec.clamp(i32::MIN as i64, i32::MAX as i64) as i32,
            nanosec,
        }
    }

    /// Nanoseconds (a `nanosec` ≥ 1e9 from a faulty source simply adds up).
    pub fn nanos(self) -> i64 {
        self.sec as i64 * 1_000_000_000 + self.nanosec as i64
    }
}

/// Seconds of robot time to integer nanoseconds (rounded; non-finite → 0, saturating).
pub fn seconds_to_nanos(t: f64) -> i64 {
    if t.is_finite() {
        (t * 1e9).round().clamp(i64::MIN as f64, i64::MAX as f64) as i64
    } else {
        0
    }
}

/// Robot time in integer nanoseconds to seconds.
pub fn nanos_to_seconds(ns: i64) -> f64 {
    ns as f64 / 1e9
}

/// `std_msgs/msg/Header`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Header {
    /// Time stamp.
    pub stamp: Time,
    /// Coordinate frame.
    pub frame_id: RosString,
}

/// Just the leading header of any message that starts with one (Odometry, PointCloud2,
/// TransformStamped, …): a cheap way to learn a stamp without decoding the payload.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct HeaderPrefix {
    /// The header.
    pub header: Header,
}

/// `std_msgs/msg/String`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct StringMsg {
    /// The text.
    pub data: RosString,
}

/// The bits of the motion-state message (a `std_msgs/msg/UInt8` on the motion topic).
pub mod motion_bits {
    /// The commanded path is done (or none is commanded).
    pub const IDLE: u8 = 1;
    /// The robot refused the next cell of its path.
    pub const BLOCKED: u8 = 2;
}

/// `std_msgs/msg/UInt8`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct UInt8Msg {
    /// The value.
    pub data: u8,
}
