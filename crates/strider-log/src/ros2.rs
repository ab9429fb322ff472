//! The ROS 2 messages Strider writes and reads, as serde structs for CDR ([`crate::cdr`]), with
//! their `ros2msg` schema texts (the concatenated definitions rosbag2 stores in MCAP, which
//! `mcap-ros2-support` and Foxglove parse to decode the messages).
//!
//! Types: `builtin_interfaces/msg/Time`, `std_msgs/msg/Header`, `std_msgs/msg/String`,
//! `std_msgs/msg/UInt8`, `geometry_msgs/msg/{Point, Quaternion, Pose, Vector3, Twist,
//! Transform, TransformStamped, PoseWithCovariance, TwistWithCovariance}`,
//! `nav_msgs/msg/Odometry`, `tf2_msgs/msg/TFMessage`, `sensor_msgs/msg/{PointField,
//! PointCloud2}`.
//!
//! PointCloud2 is decoded field-generically ([`decode_cloud`]): `x`, `y`, `z` as FLOAT32 or
//! FLOAT64 at any offset, colour from a packed `rgb`/`rgba` field (FLOAT32 or UINT32 holding
//! `0x00RRGGBB`, PCL's convention) or separate `r`, `g`, `b` UINT8 fields, either byte order,
//! any `row_step`. A cloud without colour is an error or gray points, as configured
//! ([`MissingRgb`]).

use crate::cdr::{self, Bytes, CdrError, Cov36, Decoder, RosString};
use serde::{Deserialize, Serialize};
use strider_core::msg::ColoredPoint;

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

/// `std_msgs/msg/Header`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Header {
    /// Time stamp.
    pub stamp: Time,
    /// Coordinate frame.
    pub frame_id: RosString,
}

/// `std_msgs/msg/String`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct StringMsg {
    /// The text.
    pub data: RosString,
}

/// `std_msgs/msg/UInt8`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct UInt8Msg {
    /// The value.
    pub data: u8,
}

/// `geometry_msgs/msg/Vector3` (also `geometry_msgs/msg/Point`, which has the same layout).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Vector3 {
    /// x.
    pub x: f64,
    /// y.
    pub y: f64,
    /// z.
    pub z: f64,
}

/// `geometry_msgs/msg/Quaternion`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Quaternion {
    /// x.
    pub x: f64,
    /// y.
    pub y: f64,
    /// z.
    pub z: f64,
    /// w.
    pub w: f64,
}

impl Default for Quaternion {
    fn default() -> Self {
        Self::IDENTITY
    }
}

impl Quaternion {
    /// No rotation.
    pub const IDENTITY: Self = Self {
        x: 0.0,
        y: 0.0,
        z: 0.0,
        w: 1.0,
    };

    /// From roll, pitch, yaw (extrinsic x-y-z, i.e. R = Rz(yaw)·Ry(pitch)·Rx(roll), ROS's
    /// convention).
    pub fn from_rpy(roll: f64, pitch: f64, yaw: f64) -> Self {
        let (sr, cr) = (roll * 0.5).sin_cos();
        let (sp, cp) = (pitch * 0.5).sin_cos();
        let (sy, cy) = (yaw * 0.5).sin_cos();
        Self {
            w: cr * cp * cy + sr * sp * sy,
            x: sr * cp * cy - cr * sp * sy,
            y: cr * sp * cy + sr * cp * sy,
            z: cr * cp * sy - sr * sp * cy,
        }
    }

    /// This quaternion normalised; `None` when its norm is zero or not finite.
    pub fn normalized(self) -> Option<Self> {
        let n = (self.x * self.x + self.y * self.y + self.z * self.z + self.w * self.w).sqrt();
        (n.is_finite() && n > 1e-12).then(|| Self {
            x: self.x / n,
            y: self.y / n,
            z: self.z / n,
            w: self.w / n,
        })
    }

    /// Roll, pitch, yaw of a unit quaternion (pitch clamped at ±90°).
    pub fn to_rpy(self) -> (f64, f64, f64) {
        let Self { x, y, z, w } = self;
        let roll = (2.0 * (w * x + y * z)).atan2(1.0 - 2.0 * (x * x + y * y));
        let pitch = (2.0 * (w * y - z * x)).clamp(-1.0, 1.0).asin();
        let yaw = (2.0 * (w * z + x * y)).atan2(1.0 - 2.0 * (y * y + z * z));
        (roll, pitch, yaw)
    }

    /// The Hamilton product `self · o`.
    pub fn product(self, o: Self) -> Self {
        Self {
            w: self.w * o.w - self.x * o.x - self.y * o.y - self.z * o.z,
            x: self.w * o.x + self.x * o.w + self.y * o.z - self.z * o.y,
            y: self.w * o.y - self.x * o.z + self.y * o.w + self.z * o.x,
            z: self.w * o.z + self.x * o.y - self.y * o.x + self.z * o.w,
        }
    }

    /// Rotates `v` by this unit quaternion.
    pub fn rotate(self, v: [f64; 3]) -> [f64; 3] {
        let Self { x, y, z, w } = self;
        // v' = v + 2w(q×v) + 2q×(q×v)
        let (tx, ty, tz) = (
            2.0 * (y * v[2] - z * v[1]),
            2.0 * (z * v[0] - x * v[2]),
            2.0 * (x * v[1] - y * v[0]),
        );
        [
            v[0] + w * tx + (y * tz - z * ty),
            v[1] + w * ty + (z * tx - x * tz),
            v[2] + w * tz + (x * ty - y * tx),
        ]
    }
}

/// `geometry_msgs/msg/Pose`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Pose {
    /// Position (`geometry_msgs/Point`).
    pub position: Vector3,
    /// Orientation.
    pub orientation: Quaternion,
}

/// `geometry_msgs/msg/PoseWithCovariance`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct PoseWithCovariance {
    /// The pose.
    pub pose: Pose,
    /// Row-major 6 × 6 covariance.
    pub covariance: Cov36,
}

/// `geometry_msgs/msg/Twist`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Twist {
    /// Linear velocity.
    pub linear: Vector3,
    /// Angular velocity.
    pub angular: Vector3,
}

/// `geometry_msgs/msg/TwistWithCovariance`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct TwistWithCovariance {
    /// The twist.
    pub twist: Twist,
    /// Row-major 6 × 6 covariance.
    pub covariance: Cov36,
}

/// `nav_msgs/msg/Odometry`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Odometry {
    /// Stamp and the frame of `pose`.
    pub header: Header,
    /// The body frame.
    pub child_frame_id: RosString,
    /// The body pose in `header.frame_id`.
    pub pose: PoseWithCovariance,
    /// The body velocity in `child_frame_id`.
    pub twist: TwistWithCovariance,
}

/// `geometry_msgs/msg/Transform`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Transform {
    /// Translation.
    pub translation: Vector3,
    /// Rotation.
    pub rotation: Quaternion,
}

/// `geometry_msgs/msg/TransformStamped`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct TransformStamped {
    /// Stamp and the parent frame.
    pub header: Header,
    /// The child frame.
    pub child_frame_id: RosString,
    /// Child frame in the parent frame.
    pub transform: Transform,
}

/// `tf2_msgs/msg/TFMessage`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct TfMessage {
    /// The transforms.
    pub transforms: Vec<TransformStamped>,
}

/// `sensor_msgs/msg/PointField`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct PointField {
    /// Field name.
    pub name: RosString,
    /// Offset from the start of the point, bytes.
    pub offset: u32,
    /// Datatype constant (1 INT8 … 8 FLOAT64).
    pub datatype: u8,
    /// Elements in the field.
    pub count: u32,
}

/// PointField datatype constants.
pub mod datatype {
    /// int8.
    pub const INT8: u8 = 1;
    /// uint8.
    pub const UINT8: u8 = 2;
    /// int16.
    pub const INT16: u8 = 3;
    /// uint16.
    pub const UINT16: u8 = 4;
    /// int32.
    pub const INT32: u8 = 5;
    /// uint32.
    pub const UINT32: u8 = 6;
    /// float32.
    pub const FLOAT32: u8 = 7;
    /// float64.
    pub const FLOAT64: u8 = 8;
}

/// Byte size of a PointField datatype.
fn datatype_size(t: u8) -> Option<usize> {
    match t {
        1 | 2 => Some(1),
        3 | 4 => Some(2),
        5..=7 => Some(4),
        8 => Some(8),
        _ => None,
    }
}

/// `sensor_msgs/msg/PointCloud2` up to (excluding) `data` and `is_dense`; decoded with serde,
/// the byte array by hand ([`decode_cloud`]).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct PointCloud2Head {
    /// Stamp and frame.
    pub header: Header,
    /// Rows.
    pub height: u32,
    /// Points per row.
    pub width: u32,
    /// Layout of one point.
    pub fields: Vec<PointField>,
    /// Byte order of `data`.
    pub is_bigendian: bool,
    /// Bytes per point.
    pub point_step: u32,
    /// Bytes per row.
    pub row_step: u32,
}

/// Just the leading header of any message that starts with one (Odometry, PointCloud2,
/// TransformStamped, …): a cheap way to learn a stamp without decoding the payload.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct HeaderPrefix {
    /// The header.
    pub header: Header,
}

/// A whole PointCloud2 for writing.
#[derive(Serialize)]
struct PointCloud2Out<'a> {
    head: &'a PointCloud2Head,
    data: Bytes<'a>,
    is_dense: bool,
}

/// Encodes world-frame coloured points as a PointCloud2 with fields `x`, `y`, `z` (FLOAT32) and
/// `rgb` (FLOAT32 whose bits are `0x00RRGGBB`, as PCL packs it), 16 bytes a point, one row.
pub fn encode_cloud(
    stamp: Time,
    frame_id: &str,
    points: &[ColoredPoint],
) -> Result<Vec<u8>, CdrError> {
    let f = |name: &str, offset: u32| PointField {
        name: name.into(),
        offset,
        datatype: datatype::FLOAT32,
        count: 1,
    };
    let n = u32::try_from(points.len())
        .ok()
        .filter(|n| n.checked_mul(16).is_some())
        .ok_or_else(|| CdrError::Encode(format!("{} points: too many", points.len())))?;
    let head = PointCloud2Head {
        header: Header {
            stamp,
            frame_id: frame_id.into(),
        },
        height: 1,
        width: n,
        fields: vec![f("x", 0), f("y", 4), f("z", 8), f("rgb", 12)],
        is_bigendian: false,
        point_step: 16,
        row_step: 16 * n,
    };
    let mut data = Vec::with_capacity(points.len() * 16);
    let mut dense = true;
    for p in points {
        dense &= p.x.is_finite() && p.y.is_finite() && p.z.is_finite();
        data.extend_from_slice(&p.x.to_le_bytes());
        data.extend_from_slice(&p.y.to_le_bytes());
        data.extend_from_slice(&p.z.to_le_bytes());
        let rgb = u32::from_be_bytes([0, p.rgb[0], p.rgb[1], p.rgb[2]]);
        data.extend_from_slice(&rgb.to_le_bytes());
    }
    cdr::encode(&PointCloud2Out {
        head: &head,
        data: Bytes(&data),
        is_dense: dense,
    })
}

/// What to do with a PointCloud2 that has no colour field.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum MissingRgb {
    /// Refuse the cloud (the coloured map and the colour descriptors need colour).
    #[default]
    Error,
    /// Map the geometry with every point mid-gray (128, 128, 128).
    Gray,
}

/// A decoded PointCloud2.
#[derive(Clone, Debug, PartialEq)]
pub struct DecodedCloud {
    /// Stamp and frame.
    pub header: Header,
    /// The points in the cloud's frame. Non-finite coordinates are kept (the map skips them).
    pub points: Vec<ColoredPoint>,
    /// True when the cloud had no colour field and the points were made gray.
    pub uncoloured: bool,
}

/// Where the colour of a point comes from.
enum ColorSource {
    Packed { offset: usize },
    Separate([usize; 3]),
    Gray,
}

/// Decodes a PointCloud2 (see the module docs for what is accepted).
pub fn decode_cloud(msg: &[u8], missing_rgb: MissingRgb) -> Result<DecodedCloud, CdrError> {
    let mut d = Decoder::new(msg)?;
    let head: PointCloud2Head = d.read()?;
    let data_at = d.offset();
    let data = d.bytes()?;
    // `is_dense` is informative only; a writer that stops after `data` is tolerated.
    let _ = d.bool();
    let bad = |reason: String| CdrError::Malformed {
        offset: data_at,
        reason,
    };
    let field = |name: &str| head.fields.iter().find(|f| f.name.as_str() == name);
    let step = head.point_step as usize;
    // A field must lie inside the point.
    let place = |f: &PointField| -> Result<(usize, u8), CdrError> {
        let size = datatype_size(f.datatype).ok_or_else(|| {
            bad(format!(
                "field {:?} has unknown datatype {}",
                f.name.as_str(),
                f.datatype
            ))
        })?;
        let off = f.offset as usize;
        if off + size > step {
            return Err(bad(format!(
                "field {:?} (offset {off}, {size} bytes) outside the {step}-byte point",
                f.name.as_str()
            )));
        }
        Ok((off, f.datatype))
    };
    let mut xyz = [(0usize, 0u8); 3];
    for (k, name) in ["x", "y", "z"].iter().enumerate() {
        let f = field(name).ok_or_else(|| bad(format!("no {name:?} field")))?;
        let (off, t) = place(f)?;
        if t != datatype::FLOAT32 && t != datatype::FLOAT64 {
            return Err(bad(format!(
                "field {name:?} has datatype {t}; FLOAT32 (7) or FLOAT64 (8) expected"
            )));
        }
        xyz[k] = (off, t);
    }
    let color = if let Some(f) = field("rgb").or_else(|| field("rgba")) {
        let (offset, datatype) = place(f)?;
        if !matches!(
            datatype,
            datatype::FLOAT32 | datatype::UINT32 | datatype::INT32
        ) {
            return Err(bad(format!(
                "field {:?} has datatype {datatype}; a packed 4-byte colour expected",
                f.name.as_str()
            )));
        }
        ColorSource::Packed { offset }
    } else if let (Some(r), Some(g), Some(b)) = (field("r"), field("g"), field("b")) {
        let mut offs = [0usize; 3];
        for (k, f) in [r, g, b].into_iter().enumerate() {
            let (off, t) = place(f)?;
            if t != datatype::UINT8 {
                return Err(bad(format!(
                    "colour field {:?} has datatype {t}; UINT8 expected",
                    f.name.as_str()
                )));
            }
            offs[k] = off;
        }
        ColorSource::Separate(offs)
    } else {
        match missing_rgb {
            MissingRgb::Error => {
                return Err(bad(
                    "no colour field (rgb, rgba, or r/g/b); set missing_rgb = \"gray\" in the \
                     cloud's replay config to map it uncoloured"
                        .into(),
                ));
            }
            MissingRgb::Gray => ColorSource::Gray,
        }
    };
    let (w, h) = (head.width as usize, head.height as usize);
    let n = w
        .checked_mul(h)
        .ok_or_else(|| bad(format!("{w} × {h} points overflow")))?;
    if n > 0 {
        if step == 0 {
            return Err(bad("point_step is 0".into()));
        }
        let row = head.row_step as usize;
        let row_len = w.checked_mul(step);
        if h > 1 && row_len.is_none_or(|l| row < l) {
            return Err(bad(format!(
                "row_step {row} is shorter than {w} points of {step} bytes"
            )));
        }
        let need = (h - 1)
            .checked_mul(row)
            .zip(row_len)
            .and_then(|(a, b)| a.checked_add(b))
            .ok_or_else(|| bad(format!("{w} × {h} points of {step} bytes overflow")))?;
        if need > data.len() {
            return Err(bad(format!(
                "{w} × {h} points of {step} bytes need {need} bytes of data, {} present",
                data.len()
            )));
        }
    }
    let big = head.is_bigendian;
    let rd4 = |b: &[u8], o: usize| {
        let a = [b[o], b[o + 1], b[o + 2], b[o + 3]];
        if big {
            u32::from_be_bytes(a)
        } else {
            u32::from_le_bytes(a)
        }
    };
    let rd8 = |b: &[u8], o: usize| {
        let mut a = [0u8; 8];
        a.copy_from_slice(&b[o..o + 8]);
        if big {
            f64::from_be_bytes(a)
        } else {
            f64::from_le_bytes(a)
        }
    };
    let coord = |p: &[u8], (o, t): (usize, u8)| -> f32 {
        if t == datatype::FLOAT32 {
            f32::from_bits(rd4(p, o))
        } else {
            rd8(p, o) as f32
        }
    };
    let mut points = Vec::with_capacity(n);
    for r in 0..h {
        for c in 0..w {
            let start = r * head.row_step as usize + c * step;
            let p = &data[start..start + step];
            let rgb = match color {
                ColorSource::Packed { offset } => {
                    let v = rd4(p, offset);
                    [(v >> 16) as u8, (v >> 8) as u8, v as u8]
                }
                ColorSource::Separate([ro, go, bo]) => [p[ro], p[go], p[bo]],
                ColorSource::Gray => [128, 128, 128],
            };
            points.push(ColoredPoint {
                x: coord(p, xyz[0]),
                y: coord(p, xyz[1]),
                z: coord(p, xyz[2]),
                rgb,
            });
        }
    }
    Ok(DecodedCloud {
        header: head.header,
        points,
        uncoloured: matches!(color, ColorSource::Gray),
    })
}

/// The separator rosbag2 puts between a message definition and each dependency.
const SEP: &str =
    "================================================================================\n";

fn definition(main: &str, deps: &[(&str, &str)]) -> String {
    let mut s = main.to_string();
    for (name, text) in deps {
        s.push('\n');
        s.push_str(SEP);
        s.push_str("MSG: ");
        s.push_str(name);
        s.push('\n');
        s.push_str(text);
    }
    s
}

const TIME: (&str, &str) = ("builtin_interfaces/Time", "int32 sec\nuint32 nanosec\n");
const HEADER: (&str, &str) = (
    "std_msgs/Header",
    "builtin_interfaces/Time stamp\nstring frame_id\n",
);
const POINT: (&str, &str) = ("geometry_msgs/Point", "float64 x\nfloat64 y\nfloat64 z\n");
const VECTOR3: (&str, &str) = ("geometry_msgs/Vector3", "float64 x\nfloat64 y\nfloat64 z\n");
const QUATERNION: (&str, &str) = (
    "geometry_msgs/Quaternion",
    "float64 x 0\nfloat64 y 0\nfloat64 z 0\nfloat64 w 1\n",
);
const POSE: (&str, &str) = (
    "geometry_msgs/Pose",
    "geometry_msgs/Point position\ngeometry_msgs/Quaternion orientation\n",
);
const TRANSFORM: (&str, &str) = (
    "geometry_msgs/Transform",
    "geometry_msgs/Vector3 translation\ngeometry_msgs/Quaternion rotation\n",
);

/// A ROS 2 message type: its schema name and `ros2msg` definition.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MsgType {
    /// `nav_msgs/msg/Odometry`.
    Odometry,
    /// `tf2_msgs/msg/TFMessage`.
    TfMessage,
    /// `sensor_msgs/msg/PointCloud2`.
    PointCloud2,
    /// `std_msgs/msg/String`.
    String,
    /// `std_msgs/msg/UInt8`.
    UInt8,
}

impl MsgType {
    /// The schema name (the MCAP schema record's `name`, as rosbag2 writes it).
    pub fn name(self) -> &'static str {
        match self {
            MsgType::Odometry => "nav_msgs/msg/Odometry",
            MsgType::TfMessage => "tf2_msgs/msg/TFMessage",
            MsgType::PointCloud2 => "sensor_msgs/msg/PointCloud2",
            MsgType::String => "std_msgs/msg/String",
            MsgType::UInt8 => "std_msgs/msg/UInt8",
        }
    }

    /// The full `ros2msg` definition with its dependencies.
    pub fn definition(self) -> String {
        match self {
            MsgType::Odometry => definition(
                "std_msgs/Header header\nstring child_frame_id\n\
                 geometry_msgs/PoseWithCovariance pose\ngeometry_msgs/TwistWithCovariance twist\n",
                &[
                    HEADER,
                    TIME,
                    (
                        "geometry_msgs/PoseWithCovariance",
                        "geometry_msgs/Pose pose\nfloat64[36] covariance\n",
                    ),
                    POSE,
                    POINT,
                    QUATERNION,
                    (
                        "geometry_msgs/TwistWithCovariance",
                        "geometry_msgs/Twist twist\nfloat64[36] covariance\n",
                    ),
                    (
                        "geometry_msgs/Twist",
                        "geometry_msgs/Vector3 linear\ngeometry_msgs/Vector3 angular\n",
                    ),
                    VECTOR3,
                ],
            ),
            MsgType::TfMessage => definition(
                "geometry_msgs/TransformStamped[] transforms\n",
                &[
                    (
                        "geometry_msgs/TransformStamped",
                        "std_msgs/Header header\nstring child_frame_id\n\
                         geometry_msgs/Transform transform\n",
                    ),
                    HEADER,
                    TIME,
                    TRANSFORM,
                    VECTOR3,
                    QUATERNION,
                ],
            ),
            MsgType::PointCloud2 => definition(
                "std_msgs/Header header\nuint32 height\nuint32 width\n\
                 sensor_msgs/PointField[] fields\nbool is_bigendian\nuint32 point_step\n\
                 uint32 row_step\nuint8[] data\nbool is_dense\n",
                &[
                    HEADER,
                    TIME,
                    (
                        "sensor_msgs/PointField",
                        "uint8 INT8=1\nuint8 UINT8=2\nuint8 INT16=3\nuint8 UINT16=4\n\
                         uint8 INT32=5\nuint8 UINT32=6\nuint8 FLOAT32=7\nuint8 FLOAT64=8\n\
                         string name\nuint32 offset\nuint8 datatype\nuint32 count\n",
                    ),
                ],
            ),
            MsgType::String => "string data\n".into(),
            MsgType::UInt8 => "uint8 data\n".into(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pts() -> Vec<ColoredPoint> {
        vec![
            ColoredPoint {
                x: 1.0,
                y: -2.5,
                z: 0.25,
                rgb: [10, 20, 30],
            },
            ColoredPoint {
                x: f32::NAN,
                y: 0.0,
                z: 3.0,
                rgb: [255, 0, 128],
            },
        ]
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
        let f = |name: &str, offset: u32, datatype: u8| PointField {
            name: name.into(),
            offset,
            datatype,
            count: 1,
        };
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
        let msg = cdr::encode(&PointCloud2Out {
            head: &head,
            data: Bytes(&data),
            is_dense: true,
        })
        .unwrap();
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
                PointField {
                    name: "x".into(),
                    offset: 0,
                    datatype: datatype::FLOAT32,
                    count: 1,
                },
                PointField {
                    name: "y".into(),
                    offset: 4,
                    datatype: datatype::FLOAT32,
                    count: 1,
                },
                PointField {
                    name: "z".into(),
                    offset: 8,
                    datatype: datatype::FLOAT32,
                    count: 1,
                },
            ],
            is_bigendian: false,
            point_step: 12,
            row_step: 12,
        };
        let msg = cdr::encode(&PointCloud2Out {
            head: &head,
            data: Bytes(&[0; 12]),
            is_dense: true,
        })
        .unwrap();
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
}
