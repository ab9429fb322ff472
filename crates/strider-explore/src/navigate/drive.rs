//! Driving a task and measuring it: the per-cell average filter of the robot's proprioception
//! (Nardi19 §VI-A) and the experienced cost of each drive.

use super::map::NavigationMap;
use super::params::{NavigateError, NavigateParams, Objective};
use crate::planner::waypoints;
use serde::Serialize;
use strider_core::interface::{Robot, SensorSink};
use strider_core::{Cell, Point2, PoseStamped, Proprioception};

/// Per-cell accumulator of the average filter.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct CellAcc {
    /// Vibration: Σ v. Energy: Σ P·dt, J.
    sum: f64,
    /// Vibration: readings. Energy: unused.
    count: u32,
    /// Σ ds, metres.
    dist: f64,
}

/// What one drive of a task measured.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct DriveResult {
    /// The experienced cost: ∫ v ds (vibration) or Σ P·dt (energy).
    pub experienced_cost: f64,
    /// Distance driven, metres (from the pose stream).
    pub distance_m: f64,
    /// Robot time, seconds.
    pub time_s: f64,
    /// Every goal was reached.
    pub reached: bool,
    /// The trajectory at 2 Hz, (x, y).
    pub trajectory: Vec<[f64; 2]>,
}

/// Records poses and proprioception into the per-cell average filter.
struct ObservationSink<'a> {
    map: &'a NavigationMap,
    objective: Objective,
    acc: &'a mut [CellAcc],
    pose: Option<Point2>,
    /// Pose and time at the previous proprioceptive reading.
    last: Option<(f64, Point2)>,
    cost: f64,
    dist: f64,
    poses: u64,
    trajectory: Vec<[f64; 2]>,
}

impl SensorSink for ObservationSink<'_> {
    fn wants_cloud(&self, _sensor: u8) -> bool {
        false
    }

    fn on_pose(&mut self, pose: &PoseStamped) {
        let p = Point2::new(pose.position.x, pose.position.y);
        if !p.is_finite() {
            return;
        }
        self.pose = Some(p);
        // The pose stream is 20 Hz: every tenth pose is 2 Hz.
        if self.poses.is_multiple_of(10) {
            self.trajectory.push([p.x, p.y]);
        }
        self.poses += 1;
    }

    fn on_proprioception(&mut self, r: &Proprioception) {
        let Some(p) = self.pose else { return };
        let prev = self.last.replace((r.stamp, p));
        let Some((t0, p0)) = prev else { return };
        let dt = r.stamp - t0;
        let ds = p.dist(p0);
        if !(dt > 0.0 && ds.is_finite()) {
            return;
        }
        let mid = Point2::new(0.5 * (p.x + p0.x), 0.5 * (p.y + p0.y));
        let cell = self.map.index_of(mid);
        match self.objective {
            Objective::Vibration => {
                // At rest the sensor reads 0 and the reading describes no terrain.
                if ds <= 0.0 || !r.vibration.is_finite() || r.vibration < 0.0 {
                    return;
                }
                self.cost += r.vibration * ds;
                self.dist += ds;
                if let Some(k) = cell {
                    let a = &mut self.acc[k];
                    a.sum += r.vibration;
                    a.count += 1;
                    a.dist += ds;
                }
            }
            Objective::Energy => {
                if !r.power_w.is_finite() || r.power_w < 0.0 {
                    return;
                }
                let e = r.power_w * dt;
                self.cost += e;
                self.dist += ds;
                if let Some(k) = cell {
                    let a = &mut self.acc[k];
                    a.sum += e;
                    a.dist += ds;
                }
            }
        }
    }
}

/// The cell value of the average filter, if the cell has one.
pub(super) fn cell_value(objective: Objective, a: &CellAcc, cell_size: f64) -> Option<f64> {
    match objective {
        Objective::Vibration => (a.count > 0).then(|| a.sum / a.count as f64),
        Objective::Energy => (a.dist >= 0.2 * cell_size).then(|| a.sum / a.dist),
    }
}

/// Drives `segments` (cell paths, each starting where the previous ended) with `robot`,
/// recording into the average filter `acc` (one entry per cell of `map`).
pub(super) fn drive<R: Robot>(
    robot: &mut R,
    map: &NavigationMap,
    objective: Objective,
    acc: &mut [CellAcc],
    segments: &[Vec<Cell>],
    params: &NavigateParams,
) -> Result<DriveResult, NavigateError> {
    let d = map.cell_size;
    let t_start = robot.now();
    let mut sink = ObservationSink {
        map,
        objective,
        acc,
        pose: None,
        last: None,
        cost: 0.0,
        dist: 0.0,
        poses: 0,
        trajectory: Vec::new(),
    };
    let robot_err = |e: R::Error| NavigateError::Robot(e.to_string());
    let mut reached = true;
    for seg in segments {
        let (Some(&first), Some(&last)) = (seg.first(), seg.last()) else {
            continue;
        };
        let goal = last.center(d);
        let limit = 60.0 + 20.0 * first.center(d).dist(goal) / params.max_speed;
        let t0 = robot.now();
        robot.follow(&waypoints(seg, d));
        let mut ok = false;
        while robot.now() - t0 < limit {
            let st = robot
                .advance(params.control_dt, &mut sink)
                .map_err(robot_err)?;
            if st.idle {
                ok = sink.pose.is_some_and(|p| p.dist(goal) <= 1.5 * d);
                break;
            }
            if st.blocked {
                // The grid map said traversable but the robot refuses: the run fails here.
                break;
            }
        }
        // One more period so the last readings of the segment arrive.
        robot
            .advance(params.control_dt, &mut sink)
            .map_err(robot_err)?;
        robot.follow(&[]);
        reached &= ok;
    }
    Ok(DriveResult {
        experienced_cost: sink.cost,
        distance_m: sink.dist,
        time_s: robot.now() - t_start,
        reached,
        trajectory: sink.trajectory,
    })
}

/// Drives fixed cell paths (a baseline: the shortest or the least-cost path) and measures them
/// exactly like a learned run. The robot must stand at the start of the first segment.
pub fn drive_task<R: Robot>(
    robot: &mut R,
    map: &NavigationMap,
    objective: Objective,
    segments: &[Vec<Cell>],
    params: &NavigateParams,
) -> Result<DriveResult, NavigateError> {
    params.validate()?;
    let mut acc = vec![CellAcc::default(); map.rect.len()];
    drive(robot, map, objective, &mut acc, segments, params)
}

/// The training set of the visited cells: indices, positions, values.
pub(super) fn training_set(
    map: &NavigationMap,
    objective: Objective,
    acc: &[CellAcc],
) -> (Vec<usize>, Vec<f64>, Vec<f64>) {
    let mut idx = Vec::new();
    let mut pos = Vec::new();
    let mut y = Vec::new();
    for (k, a) in acc.iter().enumerate() {
        if let Some(v) = cell_value(objective, a, map.cell_size) {
            let c = map.rect.cell(k).center(map.cell_size);
            idx.push(k);
            pos.extend([c.x, c.y]);
            y.push(v);
        }
    }
    (idx, pos, y)
}
