//! Pose-stream bookkeeping shared by every mission: [`PathRecorder`] (distance walked and the
//! 2 Hz trajectory) and [`Keyframes`]. Scan keyframes: a scan is fused when the robot moved at least
//! max(d_ν, r_sensor/50) or (for a sensor with a limited field of view) turned at least 10° since
//! the last fused scan of that sensor. In a static world a scan from (almost) the same pose adds
//! nothing to the map; skipping it lets a simulator skip producing it.

use super::record::TrajectorySample;
use strider_core::{Point2, PoseStamped};
use strider_map::MapParams;

/// Minimum turn since the last fused scan of a limited-field-of-view sensor, degrees.
const TURN_DEG: f64 = 10.0;

/// Poses between trajectory samples (20 Hz poses, a 2 Hz trajectory).
const TRAJECTORY_EVERY: u64 = 10;

/// Distance walked and the trajectory, from the pose stream.
#[derive(Clone, Debug, Default)]
pub struct PathRecorder {
    last: Option<Point2>,
    poses: u64,
}

impl PathRecorder {
    /// Adds a pose with a finite position: the distance from the previous one and, for every
    /// tenth pose from the first, the trajectory sample to log.
    pub fn push(&mut self, pose: &PoseStamped) -> (f64, Option<TrajectorySample>) {
        let p = Point2::new(pose.position.x, pose.position.y);
        let d = self.last.map_or(0.0, |q| (p.x - q.x).hypot(p.y - q.y));
        self.last = Some(p);
        self.poses += 1;
        let sample = (self.poses % TRAJECTORY_EVERY == 1).then_some(TrajectorySample {
            t: pose.stamp,
            x: p.x,
            y: p.y,
            gait: pose.gait.0,
        });
        (d, sample)
    }
}

/// The pose of the last fused scan per sensor.
#[derive(Clone, Debug, Default)]
pub struct Keyframes {
    last: Vec<Option<(f64, f64, f64)>>,
}

impl Keyframes {
    /// Whether a scan of `sensor` taken at `pose` is worth fusing, given each sensor's horizontal
    /// field of view in degrees (a sensor of ≥ 360° or not listed is omnidirectional: turning
    /// shows it nothing new). Without a pose or an earlier scan of that sensor: yes.
    pub fn wants(
        &self,
        sensor: u8,
        pose: Option<&PoseStamped>,
        map: &MapParams,
        hfov_deg: &[f64],
    ) -> bool {
        let sees_all_around = hfov_deg.get(sensor as usize).is_none_or(|&f| f >= 360.0);
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
        let (rgbd, omni) = ([87.0, 87.0], [360.0]);
        assert!(k.wants(0, Some(&pose(0.0, 0.0)), &m, &rgbd));
        k.record(0, Some(&pose(0.0, 0.0)));
        assert!(!k.wants(0, Some(&pose(0.04, 0.0)), &m, &rgbd));
        assert!(k.wants(0, Some(&pose(0.05, 0.0)), &m, &rgbd));
        assert!(k.wants(0, Some(&pose(0.0, 0.2)), &m, &rgbd));
        assert!(!k.wants(0, Some(&pose(0.0, 0.2)), &m, &omni));
        assert!(
            !k.wants(0, Some(&pose(0.0, 0.2)), &m, &[]),
            "unlisted: omnidirectional"
        );
        assert!(
            k.wants(1, Some(&pose(0.0, 0.0)), &m, &rgbd),
            "another sensor"
        );
        assert!(k.wants(0, None, &m, &rgbd));
    }

    #[test]
    fn path_recorder_sums_distance_and_samples_every_tenth_pose() {
        let mut r = PathRecorder::default();
        let mut driven = 0.0;
        let mut traj = Vec::new();
        for k in 0..21 {
            let (d, s) = r.push(&pose(0.01 * k as f64, 0.0));
            driven += d;
            traj.extend(s);
        }
        assert!((driven - 0.2).abs() < 1e-12);
        assert_eq!(traj.len(), 3); // poses 1, 11, 21
        assert!((traj[1].x - 0.1).abs() < 1e-12);
    }
}
