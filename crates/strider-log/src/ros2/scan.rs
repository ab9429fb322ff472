//! `sensor_msgs/msg/LaserScan`: a planar laser's ranges, read as a cloud of points in the scan's
//! frame.

use super::cloud::{DecodedCloud, MAX_CLOUD_POINTS};
use super::std_msgs::Header;
use crate::cdr::{self, CdrError, Decoder};
use serde::{Deserialize, Serialize};
use strider_core::msg::ColoredPoint;

/// `sensor_msgs/msg/LaserScan` (angles in rad, ranges in m).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct LaserScan {
    /// Stamp of the first beam, and the scan's frame.
    pub header: Header,
    /// Angle of the first beam about the frame's z axis (0 along x), rad.
    pub angle_min: f32,
    /// Angle of the last beam, rad.
    pub angle_max: f32,
    /// Angle between beams, rad.
    pub angle_increment: f32,
    /// Time between beams, s.
    pub time_increment: f32,
    /// Time between scans, s.
    pub scan_time: f32,
    /// Shortest valid range, m.
    pub range_min: f32,
    /// Longest valid range, m.
    pub range_max: f32,
    /// One range per beam, m (outside [range_min, range_max], NaN or ±inf: no return).
    pub ranges: Vec<f32>,
    /// One intensity per beam, or none (not used).
    pub intensities: Vec<f32>,
}

/// A LaserScan up to (excluding) `ranges`; the arrays are read by hand ([`decode_scan`]).
#[derive(Deserialize)]
struct LaserScanHead {
    header: Header,
    angle_min: f32,
    _angle_max: f32,
    angle_increment: f32,
    _time_increment: f32,
    _scan_time: f32,
    range_min: f32,
    range_max: f32,
}

/// Encodes a LaserScan.
pub fn encode_scan(scan: &LaserScan) -> Result<Vec<u8>, CdrError> {
    cdr::encode(scan)
}

/// Decodes a LaserScan into points in its frame: beam `i` with a valid range `r` (finite,
/// within [`range_min`, `range_max`]) gives (r cos a, r sin a, 0) at the angle
/// a = `angle_min` + i · `angle_increment`, computed in f64 and rounded to f32; other beams
/// give no point. Intensities are ignored and the points are gray (the cloud counts as
/// uncoloured). At most [`MAX_CLOUD_POINTS`] beams.
pub fn decode_scan(msg: &[u8]) -> Result<DecodedCloud, CdrError> {
    let mut d = Decoder::new(msg)?;
    let head: LaserScanHead = d.read()?;
    let at = d.offset();
    let bad = |reason: String| CdrError::Malformed { offset: at, reason };
    for (name, v) in [
        ("angle_min", head.angle_min),
        ("angle_increment", head.angle_increment),
    ] {
        if !v.is_finite() {
            return Err(bad(format!("{name} = {v}: not a finite angle")));
        }
    }
    let (n, ranges) = d.float32s()?;
    if n > MAX_CLOUD_POINTS {
        return Err(bad(format!(
            "{n} ranges: more than the {MAX_CLOUD_POINTS} a cloud may have"
        )));
    }
    let (lo, hi) = (head.range_min, head.range_max);
    let (a0, da) = (head.angle_min as f64, head.angle_increment as f64);
    let points = (0..n)
        .filter_map(|i| {
            let r = d.f32_at(ranges, i)?;
            // NaN fails both comparisons; ±inf is outside any finite limit, and a range
            // within infinite limits must still be finite.
            if !(r.is_finite() && r >= lo && r <= hi) {
                return None;
            }
            let a = a0 + i as f64 * da;
            let r = r as f64;
            Some(ColoredPoint {
                x: (r * a.cos()) as f32,
                y: (r * a.sin()) as f32,
                z: 0.0,
                rgb: [128, 128, 128],
            })
        })
        .collect();
    Ok(DecodedCloud {
        header: head.header,
        points,
        uncoloured: true,
    })
}
