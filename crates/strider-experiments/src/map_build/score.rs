//! The map judged against ground truth, cell by cell over the world, and `map_stats.json`.

use std::time::Instant;

use serde::Serialize;
use strider_core::Pose2;
use strider_core::interface::Robot;
use strider_map::{ElevationMap, Passability};
use strider_scenario::{Scenario, SensorSpec};
use strider_sim::coverage::visible_cells;

use super::Drive;

/// The map's agreement with ground truth.
pub(crate) struct Score {
    /// World cells some sensor saw the top of, and those of them the map observed.
    pub(crate) visible: usize,
    pub(crate) visible_observed: usize,
    /// Observed cells.
    pub(crate) observed: usize,
    /// Squared elevation error and count over observed cells with an elevation.
    pub(crate) all: (f64, usize),
    /// The largest absolute elevation error, m.
    pub(crate) max_err: f64,
    /// Squared error and count over observed cells whose top surface was visible.
    pub(crate) visible_top: (f64, usize),
    /// Squared error and count split by ground truth: [passable ground, obstacle cells].
    pub(crate) split: [(f64, usize); 2],
    /// Cells whose passability the map judged, and those that agree with ground truth.
    pub(crate) judged: usize,
    pub(crate) agreed: usize,
    /// Absolute elevation error per world cell (NaN where not observed).
    pub(crate) error_raster: Vec<f32>,
}

impl Score {
    /// Scores `map` against the scenario's world; `scan_poses` are the poses each sensor
    /// scanned from (sensor `k` of the robot, or `sensor` when the robot has fewer).
    pub(crate) fn of(
        sc: &Scenario,
        sensor: &SensorSpec,
        map: &ElevationMap,
        scan_poses: &[Vec<Pose2>],
    ) -> Self {
        let w = &sc.world;
        let n = w.rect.len();
        let mut visible = vec![false; n];
        for (k, poses) in scan_poses.iter().enumerate() {
            let spec = sc.robot.sensors.get(k).unwrap_or(sensor);
            for (v, s) in visible.iter_mut().zip(visible_cells(w, spec, poses)) {
                *v |= s;
            }
        }
        let gt_pass = w.gt_passability(sc.map.rho_obstacle);
        let mut s = Score {
            visible: 0,
            visible_observed: 0,
            observed: 0,
            all: (0.0, 0),
            max_err: 0.0,
            visible_top: (0.0, 0),
            split: [(0.0, 0); 2],
            judged: 0,
            agreed: 0,
            error_raster: vec![f32::NAN; n],
        };
        for k in 0..n {
            let c = w.rect.cell(k);
            let obs = map.is_observed(c);
            if visible[k] {
                s.visible += 1;
                s.visible_observed += obs as usize;
            }
            if !obs {
                continue;
            }
            s.observed += 1;
            if let Some(z) = map.elevation(c) {
                let e = (z as f64 - w.elevation[k] as f64).abs();
                s.all.0 += e * e;
                s.all.1 += 1;
                s.max_err = s.max_err.max(e);
                if visible[k] {
                    s.visible_top.0 += e * e;
                    s.visible_top.1 += 1;
                }
                let part = &mut s.split[(gt_pass[k] == Passability::Impassable) as usize];
                part.0 += e * e;
                part.1 += 1;
                s.error_raster[k] = e as f32;
            }
            let p = map.passability(c);
            if p != Passability::Unknown {
                s.judged += 1;
                s.agreed += (p == gt_pass[k]) as usize;
            }
        }
        s
    }
}

/// √(sum / n) of a (sum of squares, count) pair; NaN without cells.
fn rmse((sum, n): (f64, usize)) -> f64 {
    if n > 0 {
        (sum / n as f64).sqrt()
    } else {
        f64::NAN
    }
}

/// `map_stats.json`.
#[derive(Clone, Debug, Serialize)]
pub struct MapStats {
    pub scenario: String,
    pub world_seed: u64,
    pub seed: u64,
    pub observed_fraction: f64,
    pub elevation_rmse_m: f64,
    pub elevation_max_abs_error_m: f64,
    pub elevation_rmse_visible_top_m: f64,
    pub elevation_rmse_ground_m: f64,
    pub elevation_rmse_obstacle_m: f64,
    pub observed_obstacle_cells: usize,
    pub passability_agreement: f64,
    pub fused_points: usize,
    pub points_per_second: f64,
    pub fusion_s: f64,
    pub scans: u64,
    pub skipped_non_finite_points: usize,
    pub skipped_out_of_range_points: usize,
    pub face_points: usize,
    pub cells_gated: usize,
    pub face_bounds_raised: usize,
    pub face_bounds_ignored: usize,
    pub carved_points: usize,
    pub cells_carved: usize,
    pub visible_cells: usize,
    pub observed_cells: usize,
    pub passability_judged_cells: usize,
    pub coverage_path_m: f64,
    pub driven_m: f64,
    pub coverage_completed: bool,
    pub blocked_waypoints_skipped: usize,
    pub sim_time_s: f64,
    pub wall_time_s: f64,
}

impl MapStats {
    pub(crate) fn new(sc: &Scenario, seed: u64, d: &Drive, s: &Score, wall: Instant) -> Self {
        let t = &d.sink.totals;
        let fusion_s = d.sink.fuse_time.as_secs_f64();
        // RMSE over observed cells: a cell observed without an elevation counts in the
        // denominator.
        let rmse_observed = if s.observed > 0 {
            (s.all.0 / s.observed as f64).sqrt()
        } else {
            f64::NAN
        };
        Self {
            scenario: sc.name.clone(),
            world_seed: sc.world_seed,
            seed,
            observed_fraction: if s.visible > 0 {
                s.visible_observed as f64 / s.visible as f64
            } else {
                0.0
            },
            elevation_rmse_m: rmse_observed,
            elevation_max_abs_error_m: s.max_err,
            elevation_rmse_visible_top_m: rmse(s.visible_top),
            elevation_rmse_ground_m: rmse(s.split[0]),
            elevation_rmse_obstacle_m: rmse(s.split[1]),
            observed_obstacle_cells: s.split[1].1,
            passability_agreement: if s.judged > 0 {
                s.agreed as f64 / s.judged as f64
            } else {
                f64::NAN
            },
            fused_points: t.fused_points,
            points_per_second: if fusion_s > 0.0 {
                t.fused_points as f64 / fusion_s
            } else {
                0.0
            },
            fusion_s,
            scans: d.sink.scans,
            skipped_non_finite_points: t.skipped_non_finite,
            skipped_out_of_range_points: t.skipped_out_of_range,
            face_points: t.face_points,
            cells_gated: t.cells_gated,
            face_bounds_raised: t.face_bounds_raised,
            face_bounds_ignored: t.face_bounds_ignored,
            carved_points: t.carved_points,
            cells_carved: t.cells_carved,
            visible_cells: s.visible,
            observed_cells: s.observed,
            passability_judged_cells: s.judged,
            coverage_path_m: d.path_m,
            driven_m: d.sim.odometer_m(),
            coverage_completed: d.completed,
            blocked_waypoints_skipped: d.blocked_skips,
            sim_time_s: d.sim.now(),
            wall_time_s: wall.elapsed().as_secs_f64(),
        }
    }
}
