//! Messages a robot produces: what the autonomy stack sees of the world. The simulator emits these
//! and a real robot's log is decoded into them; nothing else crosses from a robot into the map or
//! the learners.

use crate::geom::Point3;
use serde::{Deserialize, Serialize};

/// Index of a locomotion gait in the robot profile's gait list.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize,
)]
pub struct GaitId(pub u8);

/// One RGB-D return, already transformed into the world frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C)]
pub struct ColoredPoint {
    /// East, metres.
    pub x: f32,
    /// North, metres.
    pub y: f32,
    /// Up, metres.
    pub z: f32,
    /// sRGB colour of the pixel.
    pub rgb: [u8; 3],
}

impl ColoredPoint {
    /// A return at `(x, y, z)` of colour `rgb`.
    pub const fn new(x: f32, y: f32, z: f32, rgb: [u8; 3]) -> Self {
        Self { x, y, z, rgb }
    }
}

/// One scan of an RGB-D (or omnidirectional) sensor in the world frame.
#[derive(Clone, Debug, Default)]
pub struct PointCloud {
    /// Simulated or recorded time, seconds.
    pub stamp: f64,
    /// Index of the producing sensor in the robot profile's sensor list (a frame id).
    pub sensor: u8,
    /// Sensor origin in the world frame (needed for range-dependent noise and ray casting).
    pub origin: Point3,
    /// The returns. May contain non-finite values from a faulty source; consumers skip them.
    pub points: Vec<ColoredPoint>,
}

impl PointCloud {
    /// The scan of sensor `sensor` taken at `stamp` from `origin`.
    pub fn new(stamp: f64, sensor: u8, origin: Point3, points: Vec<ColoredPoint>) -> Self {
        Self {
            stamp,
            sensor,
            origin,
            points,
        }
    }
}

/// A 6-DOF robot body pose with its time stamp (the 20 Hz pose stream).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct PoseStamped {
    /// Time, seconds.
    pub stamp: f64,
    /// Body position, metres (z: the terrain surface under the body centre).
    pub position: Point3,
    /// Roll, radians.
    pub roll: f64,
    /// Pitch, radians.
    pub pitch: f64,
    /// Yaw (heading), radians.
    pub yaw: f64,
    /// The gait in use when the pose was taken.
    pub gait: GaitId,
}

/// Proprioceptive readings: the signals the cost models learn from.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Proprioception {
    /// Time, seconds.
    pub stamp: f64,
    /// Body roll angle, radians (Prágr19 roll-variance cost).
    pub roll: f64,
    /// Electrical power draw, watts (Prágr18 cost of transport, MartinCorke energy).
    pub power_w: f64,
    /// Vertical-acceleration RMS, m/s² (Nardi19 vibration cost).
    pub vibration: f64,
    /// Force on the front bumper, newtons (Prágr23); 0 when not touching anything.
    pub bumper_force: f64,
}
