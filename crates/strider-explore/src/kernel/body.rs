//! The robot body every strategy drives: the pose, the elevation map fused from the scans the
//! keyframe rule lets through, the distance and trajectory walked, and the wall time spent
//! moving the robot and mapping.

use super::keyframes::{Keyframes, PathRecorder};
use super::record::{RunRecord, Termination};
use crate::planner::nearest_where;
use std::time::Instant;
use strider_core::{Cell, Point2, PointCloud, PoseStamped};
use strider_map::rect::WorldRect;
use strider_map::{ElevationMap, MapParams};

/// What the body needs to know about the robot and the task.
#[derive(Clone, Debug, PartialEq)]
pub struct BodyParams {
    /// Elevation map parameters.
    pub map: MapParams,
    /// Horizontal field of view of each sensor (by sensor id), degrees; 360 for an
    /// omnidirectional sensor. Missing entries count as 360.
    pub sensor_hfov_deg: Vec<f64>,
    /// Exploration bounds; goals outside are ignored.
    pub bounds: Option<WorldRect>,
    /// Mission time limit (robot time), s.
    pub time_limit_s: f64,
}

impl BodyParams {
    /// The body of a strategy on `map`, with the robot's sensors, the task's bounds and time
    /// limit.
    pub fn new(
        map: MapParams,
        sensor_hfov_deg: &[f64],
        bounds: Option<WorldRect>,
        time_limit_s: f64,
    ) -> Self {
        Self {
            map,
            sensor_hfov_deg: sensor_hfov_deg.to_vec(),
            bounds,
            time_limit_s,
        }
    }
}

/// The robot as every strategy sees it (see the module docs).
pub struct Body {
    params: BodyParams,
    map: ElevationMap,
    pose: Option<PoseStamped>,
    keyframes: Keyframes,
    path: PathRecorder,
    pub(super) record: RunRecord,
    /// Offsets of the 3·r_robot disc the anchor cell is searched in (nearest first).
    anchor_offsets: Vec<(i32, i32)>,
    /// Wall time spent fusing scans, s.
    mapping_wall_s: f64,
    /// Wall time spent in the robot's `advance` (the simulator, mapping included), s.
    pub(super) robot_wall_s: f64,
}

impl Body {
    /// A body with an empty map.
    pub fn new(params: BodyParams) -> Self {
        Self {
            map: ElevationMap::new(params.map.clone()),
            anchor_offsets: strider_core::grid::disc_offsets(
                3.0 * params.map.r_robot,
                params.map.cell_size,
            ),
            params,
            pose: None,
            keyframes: Keyframes::default(),
            path: PathRecorder::default(),
            record: RunRecord::new(Termination::TimeLimit),
            mapping_wall_s: 0.0,
            robot_wall_s: 0.0,
        }
    }

    /// The parameters.
    pub fn params(&self) -> &BodyParams {
        &self.params
    }

    /// The map built so far.
    pub fn map(&self) -> &ElevationMap {
        &self.map
    }

    /// The map, for the strategy's derived layers (passability).
    pub fn map_mut(&mut self) -> &mut ElevationMap {
        &mut self.map
    }

    /// The latest pose (finite position and heading), if any.
    pub fn pose(&self) -> Option<PoseStamped> {
        self.pose
    }

    /// The latest position, if any.
    pub fn position(&self) -> Option<Point2> {
        self.pose.map(|p| p.position.xy())
    }

    /// Termination, time, distance, trajectory and wall time so far.
    pub fn record(&self) -> &RunRecord {
        &self.record
    }

    /// The exploration bounds.
    pub fn bounds(&self) -> Option<&WorldRect> {
        self.params.bounds.as_ref()
    }

    /// Horizontal field of view of each sensor, degrees.
    pub fn sensor_hfov_deg(&self) -> &[f64] {
        &self.params.sensor_hfov_deg
    }

    /// True when the sensors together see all around the robot without turning (every sensor
    /// omnidirectional, or none given).
    pub fn sees_all_around(&self) -> bool {
        self.params.sensor_hfov_deg.iter().all(|&f| f >= 360.0)
    }

    /// Wall time spent fusing scans so far, s.
    pub fn mapping_wall_s(&self) -> f64 {
        self.mapping_wall_s
    }

    /// Wall time spent in the robot's `advance` so far (mapping included), s.
    pub fn robot_wall_s(&self) -> f64 {
        self.robot_wall_s
    }

    /// The robot's map cell.
    pub fn robot_cell(&self) -> Option<Cell> {
        let p = self.pose?;
        self.map.cell_at(p.position.x, p.position.y)
    }

    /// The cell plans and reachability start from: the robot's cell when it is observed and
    /// admissible, else the nearest such cell within 3·r_robot (a forward-looking sensor never
    /// sees the ground under the robot at the start).
    pub fn anchor_cell(&self) -> Option<Cell> {
        self.nearest_within_anchor_disc(|c| self.map.is_observed(c) && self.map.is_admissible(c))
    }

    /// The nearest cell to the robot's within 3·r_robot for which `ok` holds.
    pub fn nearest_within_anchor_disc(&self, ok: impl Fn(Cell) -> bool) -> Option<Cell> {
        let here = self.robot_cell()?;
        nearest_where(here, &self.anchor_offsets, ok)
    }

    /// The nearest cell to `from` within 3·r_robot for which `ok` holds.
    pub fn nearest_in_anchor_disc(&self, from: Cell, ok: impl Fn(Cell) -> bool) -> Option<Cell> {
        nearest_where(from, &self.anchor_offsets, ok)
    }

    /// Takes a pose into the body; false (and ignored) unless its position and heading are
    /// finite.
    pub(super) fn take_pose(&mut self, pose: &PoseStamped) -> bool {
        if !(pose.position.x.is_finite() && pose.position.y.is_finite() && pose.yaw.is_finite()) {
            return false;
        }
        let (d, sample) = self.path.push(pose);
        self.record.driven_m += d;
        self.record.trajectory.extend(sample);
        self.pose = Some(*pose);
        true
    }

    /// Scan keyframes ([`super::keyframes`]).
    pub(super) fn wants_cloud(&self, sensor: u8) -> bool {
        self.keyframes.wants(
            sensor,
            self.pose.as_ref(),
            self.map.params(),
            &self.params.sensor_hfov_deg,
        )
    }

    /// Fuses a scan into the map.
    pub(super) fn fuse(&mut self, cloud: &PointCloud) {
        let w = Instant::now();
        self.map.integrate(cloud);
        self.mapping_wall_s += w.elapsed().as_secs_f64();
        self.keyframes.record(cloud.sensor, self.pose.as_ref());
    }
}

/// The map parameters of a strategy with spatial goals: Eq. 11 on a lattice of candidates every
/// `spacing_m` (decision 5 allows one; default max(0.2 m, r_sensor/20): I_model sums over the
/// whole r_sensor disc, so it varies on that scale), each standing for stride² cells in Alg. 3's
/// minimum cluster size. A stride the map parameters set explicitly is kept.
pub fn lattice_map_params(map: &MapParams, spacing_m: Option<f64>) -> MapParams {
    let mut map_params = map.clone();
    let spacing = spacing_m.unwrap_or_else(|| 0.2f64.max(map_params.r_sensor / 20.0));
    let stride = (spacing / map_params.cell_size).round().clamp(1.0, 1024.0) as u32;
    if map_params.info_gain_stride <= 1 && stride > 1 {
        map_params.info_gain_stride = stride;
        let s2 = (stride * stride) as usize;
        map_params.c_min_cells = map_params.c_min_cells.div_ceil(s2).max(1);
    }
    map_params
}
