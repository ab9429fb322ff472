//! Scan keyframes shared by every mission: a scan is fused when the robot moved at least
//! max(d_ν, r_sensor/50) or (for a sensor with a limited field of view) turned at least 10° since
//! the last fused scan of that sensor. In a static world a scan from (almost) the same pose adds
//! nothing to the map; skipping it lets a simulator skip producing it.

use strider_core::PoseStamped;
use strider_map::MapParams;

/// Minimum turn since the last fused scan of a limited-field-of-view sensor, degrees.
const TURN_DEG: f64 = 10.0;

/// The pose of the last fused scan per sensor.
#[derive(Clone, Debug, Default)]
pub struct Keyframes {
    last: Vec<Option<(f64, f64, f64)>>,
}

impl Keyframes {
    /// Whether a scan of `sensor` taken at `pose` is worth fusing (`sees_all_around`: the sensor
    /// is omnidirectional, so turning shows it nothing new). Without a pose or an earlier scan of
    /// that sensor: yes.
    pub fn wants(
        &self,
        sensor: u8,
        pose: Option<&PoseStamped>,
        map: &MapParams,
        sees_all_around: bool,
    ) -> bool {
        let (Some(p), Some(Some(k))) = (pose, self.last.get(sensor as usize)) else {
            return true;
        };
        let dist = (p.position.x - k.0).hypot(p.position.y - k.1);
        let turn = strider_core::geom::wrap_angle(p.yaw - k.2).abs();
        dist >= map.cell_size.max(map.r_sensor / 50.0)
            || (!sees_all_around && turn >= TURN_DEG.to_radians())
    }

    /// Records that a scan of `sensor` was fused at `pose`.
    pub fn record(&mut self, sensor: u8, pose: Option<&PoseStamped>) {
        let Some(p) = pose else { return };
        let k = sensor as usize;
        if self.last.len() <= k {
            self.last.resize(k + 1, None);
        }
        self.last[k] = Some((p.position.x, p.position.y, p.yaw));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use strider_core::{GaitId, Point3};

    fn pose(x: f64, yaw: f64) -> PoseStamped {
        PoseStamped {
            stamp: 0.0,
            position: Point3::new(x, 0.0, 0.0),
            roll: 0.0,
            pitch: 0.0,
            yaw,
            gait: GaitId(0),
        }
    }

    #[test]
    fn moves_and_turns() {
        let m = MapParams {
            cell_size: 0.05,
            r_sensor: 2.5,
            ..MapParams::default()
        };
        let mut k = Keyframes::default();
        assert!(k.wants(0, Some(&pose(0.0, 0.0)), &m, false));
        k.record(0, Some(&pose(0.0, 0.0)));
        assert!(!k.wants(0, Some(&pose(0.04, 0.0)), &m, false));
        assert!(k.wants(0, Some(&pose(0.05, 0.0)), &m, false));
        assert!(k.wants(0, Some(&pose(0.0, 0.2)), &m, false));
        assert!(!k.wants(0, Some(&pose(0.0, 0.2)), &m, true));
        assert!(
            k.wants(1, Some(&pose(0.0, 0.0)), &m, false),
            "another sensor"
        );
        assert!(k.wants(0, None, &m, false));
    }
}
