//! `strider map build`: drive a scripted coverage path through the simulator, fuse the sensor
//! stream into the colored 2.5D elevation map, and judge the map against ground truth.
//!
//! The harness (this module) may read ground truth: it scripts the drive (coverage path, and
//! the gait best suited to the terrain under the robot, so the drive does not crawl over
//! terrain where a gait gets stuck) and it scores the map. The map itself only ever sees the
//! point clouds and poses the simulator emits through the robot interface.

mod figures;
mod score;

use std::fmt;
use std::path::PathBuf;
use std::time::{Duration, Instant};

use anyhow::{Result, bail};
use strider_core::interface::{Robot, SensorSink};
use strider_core::{GaitId, Point2, PointCloud, Pose2, PoseStamped};
use strider_map::{ElevationMap, FuseStats};
use strider_scenario::{Scenario, SensorSpec};
use strider_sim::Simulator;
use strider_sim::coverage::coverage_path;

use crate::io::{create_dir, write_json};
use crate::trial::{checked_time_limit, load};
pub use score::MapStats;

/// Options of `strider map build`.
#[derive(Clone, Debug)]
pub struct MapBuildOptions {
    /// Built-in scenario name or scenario file.
    pub scenario: String,
    /// World seed.
    pub world_seed: u64,
    /// Simulator seed.
    pub seed: u64,
    /// Spacing of the coverage lanes, m (default: 0.4 × sensor range).
    pub lane_spacing: Option<f64>,
    /// Stop driving after this many simulated seconds (default: when the path is done).
    pub time_limit: Option<f64>,
    /// Output directory.
    pub out: PathBuf,
}

/// Collects the sensor stream: fuses clouds into the map (timing fusion alone) and records the
/// poses at which each sensor scanned.
pub(crate) struct MapSink {
    map: ElevationMap,
    fuse_time: Duration,
    totals: FuseStats,
    scans: u64,
    last_pose: Option<PoseStamped>,
    /// Scan poses per sensor index.
    scan_poses: Vec<Vec<Pose2>>,
    trajectory: Vec<Point2>,
}

impl SensorSink for MapSink {
    fn on_pose(&mut self, pose: &PoseStamped) {
        let p = pose.position.xy();
        if self.trajectory.last().is_none_or(|q| q.dist(p) > 0.02) {
            self.trajectory.push(p);
        }
        self.last_pose = Some(*pose);
    }

    fn on_cloud(&mut self, cloud: &PointCloud) {
        let t = Instant::now();
        let s = self.map.fuse(cloud);
        self.fuse_time += t.elapsed();
        self.scans += 1;
        add_fuse_stats(&mut self.totals, &s);
        let yaw = self.last_pose.map_or(0.0, |p| p.yaw);
        let k = cloud.sensor as usize;
        if self.scan_poses.len() <= k {
            self.scan_poses.resize(k + 1, Vec::new());
        }
        self.scan_poses[k].push(Pose2::new(cloud.origin.x, cloud.origin.y, yaw));
    }
}

fn add_fuse_stats(tot: &mut FuseStats, s: &FuseStats) {
    tot.fused_points += s.fused_points;
    tot.skipped_non_finite += s.skipped_non_finite;
    tot.skipped_out_of_range += s.skipped_out_of_range;
    tot.face_points += s.face_points;
    tot.cells_updated += s.cells_updated;
    tot.cells_gated += s.cells_gated;
    tot.face_bounds_raised += s.face_bounds_raised;
    tot.face_bounds_ignored += s.face_bounds_ignored;
    tot.carved_points += s.carved_points;
    tot.cells_carved += s.cells_carved;
}

/// The gait with the highest true speed on the terrain under the robot (harness only).
fn best_gait_here(sc: &Scenario, p: Point2) -> GaitId {
    let w = &sc.world;
    let Some(t) = w.index_at(p).and_then(|k| w.terrain_type(w.terrain[k])) else {
        return GaitId(0);
    };
    let speed = |g: &strider_scenario::GaitSpec| {
        let r = t.gaits.get(&g.name).cloned().unwrap_or_default();
        if r.stuck {
            0.0
        } else {
            g.max_speed * r.speed_factor
        }
    };
    let best = (0..sc.robot.gaits.len())
        .max_by(|&a, &b| {
            speed(&sc.robot.gaits[a])
                .total_cmp(&speed(&sc.robot.gaits[b]))
                .then(b.cmp(&a))
        })
        .unwrap_or(0);
    GaitId(best as u8)
}

/// What the drive left: the sink, the simulator, the coverage path's length, whether it was
/// completed and the waypoints skipped.
pub(crate) struct Drive {
    sink: MapSink,
    sim: Simulator,
    path_m: f64,
    completed: bool,
    blocked_skips: usize,
}

/// Drives the coverage path with lanes `lane` metres apart until it is done or `time_limit`.
fn drive(sc: &Scenario, seed: u64, lane: f64, time_limit: Option<f64>) -> Result<Drive> {
    let path = coverage_path(&sc.world, &sc.robot, sc.start, lane);
    let path_m: f64 = path.windows(2).map(|w| w[0].dist(w[1])).sum();
    let mut sim = Simulator::new(sc, seed)?;
    let mut sink = MapSink {
        map: ElevationMap::new(sc.map.clone()),
        fuse_time: Duration::ZERO,
        totals: FuseStats::default(),
        scans: 0,
        last_pose: None,
        scan_poses: Vec::new(),
        trajectory: Vec::new(),
    };
    // Generous default limit: the path at a tenth of the fastest gait's speed.
    let vmax = sc
        .robot
        .gaits
        .iter()
        .map(|g| g.max_speed)
        .fold(0.0, f64::max)
        .max(1e-6);
    let limit = time_limit.unwrap_or(60.0 + 10.0 * path_m / vmax);
    sim.follow(&path);
    let mut blocked_skips = 0usize;
    while sim.now() < limit {
        sim.set_gait(best_gait_here(sc, sim.pose().position()));
        let st = sim.advance(0.5, &mut sink)?;
        if st.idle {
            break;
        }
        if st.blocked {
            // The coverage path runs over admissible ground only; a block means the motion
            // judge disagrees at a corner. Skip the waypoint rather than push forever.
            blocked_skips += 1;
            let rest: Vec<Point2> = sim.remaining_path().iter().skip(1).copied().collect();
            sim.follow(&rest);
        }
    }
    let completed = sim.remaining_path().is_empty();
    sink.map.update_passability();
    Ok(Drive {
        sink,
        sim,
        path_m,
        completed,
        blocked_skips,
    })
}

/// The widest `--lane-spacing`, m. Lanes wider than the world are one lane, so the spacing is
/// also capped at the world's longer side (the coverage path marks a disc of half the spacing
/// around every lane cell).
pub const MAX_LANE_SPACING_M: f64 = 1000.0;

/// The first range sensor and the lane spacing (at most the world's longer side), checked.
fn check<'a>(sc: &'a Scenario, o: &MapBuildOptions) -> Result<(&'a SensorSpec, f64)> {
    let Some(sensor) = sc.robot.sensors.first() else {
        bail!(
            "scenario {}: robot profile {} has no range sensor to build a map with",
            sc.name,
            sc.robot.name
        );
    };
    if let Some(t) = o.time_limit {
        checked_time_limit(t)?;
    }
    if let Some(lane) = o.lane_spacing
        && !(lane.is_finite() && lane > 0.0 && lane <= MAX_LANE_SPACING_M)
    {
        bail!(
            "--lane-spacing {lane}: must be a finite number of metres > 0 and ≤ {MAX_LANE_SPACING_M}"
        );
    }
    let lane = o.lane_spacing.unwrap_or(0.4 * sensor.range);
    if !(lane.is_finite() && lane > 0.0) {
        bail!(
            "scenario {}: the lane spacing 0.4 × sensor range = {lane} m is not a positive number of metres; give --lane-spacing",
            sc.name
        );
    }
    let w = &sc.world;
    let side = f64::from(w.rect.width.max(w.rect.height)) * w.resolution;
    let lane = lane.min(side.max(w.resolution));
    if (sc.map.cell_size - sc.world.resolution).abs() > 1e-9 {
        bail!(
            "scenario {}: map cell size {} m differs from the world resolution {} m; map build scores cell by cell and needs them equal",
            sc.name,
            sc.map.cell_size,
            sc.world.resolution
        );
    }
    Ok((sensor, lane))
}

/// A built map's statistics; its `Display` is the summary for the terminal.
pub struct MapBuild {
    /// `map_stats.json`.
    pub stats: MapStats,
    /// Where the files are.
    pub out: PathBuf,
}

impl fmt::Display for MapBuild {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let s = &self.stats;
        write!(
            f,
            "{}: observed_fraction {:.4}  elevation_rmse {:.4} m  passability_agreement {:.4}  fused {} points at {:.1} M points/s  ({:.0} s simulated, {:.1} s wall) -> {}",
            s.scenario,
            s.observed_fraction,
            s.elevation_rmse_m,
            s.passability_agreement,
            s.fused_points,
            s.points_per_second / 1e6,
            s.sim_time_s,
            s.wall_time_s,
            self.out.display()
        )
    }
}

/// Runs `strider map build`: the drive, the score, the figures and `map_stats.json`.
pub fn build(o: &MapBuildOptions) -> Result<MapBuild> {
    let wall = Instant::now();
    let sc = load(&o.scenario, o.world_seed)?;
    let (sensor, lane) = check(&sc, o)?;
    let d = drive(&sc, o.seed, lane, o.time_limit)?;
    if d.sink.map.observed_count() == 0 {
        bail!(
            "scenario {}: the drive observed no map cell in {} s simulated, so there is no map to score; give a longer --time-limit",
            sc.name,
            d.sim.now()
        );
    }
    create_dir(&o.out)?;
    let score = score::Score::of(&sc, sensor, &d.sink.map, &d.sink.scan_poses);
    figures::write(&sc, &d.sink.map, &score, &d.sink.trajectory, &o.out)?;
    let stats = MapStats::new(&sc, o.seed, &d, &score, wall);
    write_json(&o.out.join("map_stats.json"), &stats)?;
    Ok(MapBuild {
        stats,
        out: o.out.clone(),
    })
}
