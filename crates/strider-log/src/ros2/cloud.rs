//! `sensor_msgs/msg/PointCloud2`: coloured points written in one fixed layout and read in any
//! common one (see the module docs of `ros2`).

use super::std_msgs::{Header, Time};
use crate::cdr::{self, Bytes, CdrError, Decoder, RosString};
use serde::{Deserialize, Serialize};
use strider_core::msg::ColoredPoint;

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

impl PointField {
    /// A field of one element.
    pub fn new(name: &str, offset: u32, datatype: u8) -> Self {
        Self {
            name: name.into(),
            offset,
            datatype,
            count: 1,
        }
    }
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

/// A whole PointCloud2 for writing.
#[derive(Serialize)]
struct PointCloud2Out<'a> {
    head: &'a PointCloud2Head,
    data: Bytes<'a>,
    is_dense: bool,
}

/// Encodes a PointCloud2 of any layout from its head and its data bytes.
pub fn encode_cloud_raw(
    head: &PointCloud2Head,
    data: &[u8],
    is_dense: bool,
) -> Result<Vec<u8>, CdrError> {
    cdr::encode(&PointCloud2Out {
        head,
        data: Bytes(data),
        is_dense,
    })
}

/// Encodes world-frame coloured points as a PointCloud2 with fields `x`, `y`, `z` (FLOAT32) and
/// `rgb` (FLOAT32 whose bits are `0x00RRGGBB`, as PCL packs it), 16 bytes a point, one row.
pub fn encode_cloud(
    stamp: Time,
    frame_id: &str,
    points: &[ColoredPoint],
) -> Result<Vec<u8>, CdrError> {
    let f = |name: &str, offset: u32| PointField::new(name, offset, datatype::FLOAT32);
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
    encode_cloud_raw(&head, &data, dense)
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
    let fields = Fields {
        head: &head,
        at: data_at,
    };
    let xyz = fields.coordinates()?;
    let color = fields.color(missing_rgb)?;
    let n = point_count(&head, data.len(), data_at)?;
    let points = read_points(&head, data, n, xyz, &color);
    Ok(DecodedCloud {
        header: head.header,
        points,
        uncoloured: matches!(color, ColorSource::Gray),
    })
}

/// A malformed cloud: the payload at `offset` is wrong for `reason`.
fn bad(offset: usize, reason: String) -> CdrError {
    CdrError::Malformed { offset, reason }
}

/// The field layout of a cloud whose data starts at byte `at` of the message.
struct Fields<'a> {
    head: &'a PointCloud2Head,
    at: usize,
}

impl Fields<'_> {
    /// The field called `name`.
    fn find(&self, name: &str) -> Option<&PointField> {
        self.head.fields.iter().find(|f| f.name.as_str() == name)
    }

    /// Offset and datatype of `f`, which must lie inside the point.
    fn place(&self, f: &PointField) -> Result<(usize, u8), CdrError> {
        let step = self.head.point_step as usize;
        let size = datatype_size(f.datatype).ok_or_else(|| {
            bad(
                self.at,
                format!(
                    "field {:?} has unknown datatype {}",
                    f.name.as_str(),
                    f.datatype
                ),
            )
        })?;
        let off = f.offset as usize;
        if off + size > step {
            return Err(bad(
                self.at,
                format!(
                    "field {:?} (offset {off}, {size} bytes) outside the {step}-byte point",
                    f.name.as_str()
                ),
            ));
        }
        Ok((off, f.datatype))
    }

    /// Offset and datatype (FLOAT32 or FLOAT64) of `x`, `y` and `z`.
    fn coordinates(&self) -> Result<[(usize, u8); 3], CdrError> {
        let mut xyz = [(0usize, 0u8); 3];
        for (k, name) in ["x", "y", "z"].iter().enumerate() {
            let f = self
                .find(name)
                .ok_or_else(|| bad(self.at, format!("no {name:?} field")))?;
            let (off, t) = self.place(f)?;
            if t != datatype::FLOAT32 && t != datatype::FLOAT64 {
                return Err(bad(
                    self.at,
                    format!("field {name:?} has datatype {t}; FLOAT32 (7) or FLOAT64 (8) expected"),
                ));
            }
            xyz[k] = (off, t);
        }
        Ok(xyz)
    }

    /// Where the colour comes from: a packed `rgb`/`rgba` field, separate `r`, `g`, `b` bytes,
    /// or nowhere (gray, when `missing_rgb` allows it).
    fn color(&self, missing_rgb: MissingRgb) -> Result<ColorSource, CdrError> {
        if let Some(f) = self.find("rgb").or_else(|| self.find("rgba")) {
            let (offset, datatype) = self.place(f)?;
            if !matches!(
                datatype,
                datatype::FLOAT32 | datatype::UINT32 | datatype::INT32
            ) {
                return Err(bad(
                    self.at,
                    format!(
                        "field {:?} has datatype {datatype}; a packed 4-byte colour expected",
                        f.name.as_str()
                    ),
                ));
            }
            return Ok(ColorSource::Packed { offset });
        }
        if let (Some(r), Some(g), Some(b)) = (self.find("r"), self.find("g"), self.find("b")) {
            let mut offs = [0usize; 3];
            for (k, f) in [r, g, b].into_iter().enumerate() {
                let (off, t) = self.place(f)?;
                if t != datatype::UINT8 {
                    return Err(bad(
                        self.at,
                        format!(
                            "colour field {:?} has datatype {t}; UINT8 expected",
                            f.name.as_str()
                        ),
                    ));
                }
                offs[k] = off;
            }
            return Ok(ColorSource::Separate(offs));
        }
        match missing_rgb {
            MissingRgb::Error => Err(bad(
                self.at,
                "no colour field (rgb, rgba, or r/g/b); set missing_rgb = \"gray\" in the \
                 cloud's replay config to map it uncoloured"
                    .into(),
            )),
            MissingRgb::Gray => Ok(ColorSource::Gray),
        }
    }
}

/// Most points of one decoded cloud: 16 M points (256 MB decoded) is well above a dense depth
/// camera's 2 M or a 128-beam lidar's 260 k; a cloud whose fields overlap in a few bytes a
/// point would otherwise decode to four times its message size.
pub const MAX_CLOUD_POINTS: usize = 1 << 24;

/// The number of points, checked against the rows' layout and the `data_len` bytes present
/// (data at byte `at` of the message).
fn point_count(head: &PointCloud2Head, data_len: usize, at: usize) -> Result<usize, CdrError> {
    let (w, h) = (head.width as usize, head.height as usize);
    let step = head.point_step as usize;
    let n = w
        .checked_mul(h)
        .ok_or_else(|| bad(at, format!("{w} × {h} points overflow")))?;
    if n == 0 {
        return Ok(n);
    }
    if n > MAX_CLOUD_POINTS {
        return Err(bad(
            at,
            format!("{w} × {h} points: more than the {MAX_CLOUD_POINTS} a cloud may have"),
        ));
    }
    if step == 0 {
        return Err(bad(at, "point_step is 0".into()));
    }
    let row = head.row_step as usize;
    let row_len = w.checked_mul(step);
    if h > 1 && row_len.is_none_or(|l| row < l) {
        return Err(bad(
            at,
            format!("row_step {row} is shorter than {w} points of {step} bytes"),
        ));
    }
    let need = (h - 1)
        .checked_mul(row)
        .zip(row_len)
        .and_then(|(a, b)| a.checked_add(b))
        .ok_or_else(|| bad(at, format!("{w} × {h} points of {step} bytes overflow")))?;
    if need > data_len {
        return Err(bad(
            at,
            format!(
                "{w} × {h} points of {step} bytes need {need} bytes of data, {data_len} present"
            ),
        ));
    }
    Ok(n)
}

/// The `n` points of a checked cloud.
fn read_points(
    head: &PointCloud2Head,
    data: &[u8],
    n: usize,
    xyz: [(usize, u8); 3],
    color: &ColorSource,
) -> Vec<ColoredPoint> {
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
    let (w, h, step) = (
        head.width as usize,
        head.height as usize,
        head.point_step as usize,
    );
    let mut points = Vec::with_capacity(n);
    for r in 0..h {
        for c in 0..w {
            let start = r * head.row_step as usize + c * step;
            let p = &data[start..start + step];
            let rgb = match *color {
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
    points
}
