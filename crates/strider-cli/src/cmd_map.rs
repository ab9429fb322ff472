//! `strider map build`: drive a scripted coverage path through the simulator, fuse the sensor
//! stream into the colored 2.5D elevation map, and judge the map against ground truth.
//!
//! The harness (this file) may read ground truth: it scripts the drive (coverage path, and the
//! gait best suited to the terrain under the robot, so the drive does not crawl over terrain
//! where a gait gets stuck) and it scores the map. The map itself only ever sees the point clouds
//! and poses the simulator emits through the robot interface.

use std::fs;
use std::path::Path;
use std::time::{Duration, Instant};

use anyhow::{Context, Result, bail};
use serde_json::json;
use strider_core::interface::{Robot, SensorSink};
use strider_core::{GaitId, Point2, PointCloud, Pose2, PoseStamped};
use strider_map::{ElevationMap, FuseStats, Passability};
use strider_scenario::Scenario;
use strider_sim::Simulator;
use strider_sim::coverage::{coverage_path, visible_cells};

use crate::cmd_scenario::load;
use crate::render::{Canvas, rgb_canvas, scalar_canvas};

/// Collects the sensor stream: fuses clouds into the map (timing fusion alone) and records the
/// poses at which each sensor scanned.
struct MapSink {
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
        let tot = &mut self.totals;
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
        let yaw = self.last_pose.map_or(0.0, |p| p.yaw);
        let k = cloud.sensor as usize;
        if self.scan_poses.len() <= k {
            self.scan_poses.resize(k + 1, Vec::new());
        }
        self.scan_poses[k].push(Pose2::new(cloud.origin.x, cloud.origin.y, yaw));
    }
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

/// Runs `strider map build`.
pub fn build(
    arg: &str,
    world_seed: u64,
    seed: u64,
    lane_spacing: Option<f64>,
    time_limit: Option<f64>,
    out: &Path,
) -> Result<()> {
    let wall = Instant::now();
    let sc = load(arg, world_seed)?;
    let Some(sensor) = sc.robot.sensors.first() else {
        bail!(
            "scenario {}: robot profile {} has no range sensor to build a map with",
            sc.name,
            sc.robot.name
        );
    };
    let lane = lane_spacing.unwrap_or(0.4 * sensor.range);
    if !(lane.is_finite() && lane > 0.0) {
        bail!("--lane-spacing must be a positive number of metres, got {lane}");
    }
    if (sc.map.cell_size - sc.world.resolution).abs() > 1e-9 {
        bail!(
            "scenario {}: map cell size {} m differs from the world resolution {} m; map build scores cell by cell and needs them equal",
            sc.name,
            sc.map.cell_size,
            sc.world.resolution
        );
    }
    fs::create_dir_all(out)
        .with_context(|| format!("{}: cannot create directory", out.display()))?;

    let path = coverage_path(&sc.world, &sc.robot, sc.start, lane);
    let path_len: f64 = path.windows(2).map(|w| w[0].dist(w[1])).sum();
    let mut sim = Simulator::new(&sc, seed)?;
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
    let limit = time_limit.unwrap_or(60.0 + 10.0 * path_len / vmax);
    sim.follow(&path);
    let step = 0.5;
    let mut blocked_skips = 0usize;
    while sim.now() < limit {
        sim.set_gait(best_gait_here(&sc, sim.pose().position()));
        let st = sim.advance(step, &mut sink)?;
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
    let sim_time = sim.now();
    let mut map = sink.map;
    map.update_passability();

    // Score against ground truth, cell by cell over the world.
    let w = &sc.world;
    let n = w.rect.len();
    let mut visible = vec![false; n];
    for (k, poses) in sink.scan_poses.iter().enumerate() {
        let spec = sc.robot.sensors.get(k).unwrap_or(sensor);
        for (v, s) in visible.iter_mut().zip(visible_cells(w, spec, poses)) {
            *v |= s;
        }
    }
    let gt_pass = w.gt_passability(sc.map.rho_obstacle);
    let (mut n_vis, mut n_vis_obs, mut n_obs, mut se, mut max_err) =
        (0usize, 0usize, 0usize, 0.0f64, 0.0f64);
    let (mut n_pass, mut n_pass_agree) = (0usize, 0usize);
    // Squared error and count over observed cells whose top surface was visible.
    let mut se_visible = (0.0f64, 0usize);
    // Squared error and count split by ground truth: [passable ground, obstacle cells].
    let mut se_split = [(0.0f64, 0usize); 2];
    let mut err_raster = vec![f32::NAN; n];
    for k in 0..n {
        let c = w.rect.cell(k);
        let obs = map.is_observed(c);
        if visible[k] {
            n_vis += 1;
            n_vis_obs += obs as usize;
        }
        if !obs {
            continue;
        }
        n_obs += 1;
        if let Some(z) = map.elevation(c) {
            let e = (z as f64 - w.elevation[k] as f64).abs();
            se += e * e;
            max_err = max_err.max(e);
            if visible[k] {
                se_visible.0 += e * e;
                se_visible.1 += 1;
            }
            let part = &mut se_split[(gt_pass[k] == Passability::Impassable) as usize];
            part.0 += e * e;
            part.1 += 1;
            err_raster[k] = e as f32;
        }
        let p = map.passability(c);
        if p != Passability::Unknown {
            n_pass += 1;
            n_pass_agree += (p == gt_pass[k]) as usize;
        }
    }
    let observed_fraction = if n_vis > 0 {
        n_vis_obs as f64 / n_vis as f64
    } else {
        0.0
    };
    let rmse = if n_obs > 0 {
        (se / n_obs as f64).sqrt()
    } else {
        f64::NAN
    };
    let split_rmse = |(s, n): (f64, usize)| {
        if n > 0 {
            (s / n as f64).sqrt()
        } else {
            f64::NAN
        }
    };
    let agreement = if n_pass > 0 {
        n_pass_agree as f64 / n_pass as f64
    } else {
        f64::NAN
    };
    let fuse_s = sink.fuse_time.as_secs_f64();
    let pps = if fuse_s > 0.0 {
        sink.totals.fused_points as f64 / fuse_s
    } else {
        0.0
    };

    // Figures over the world rectangle.
    let rect = w.rect;
    let res = w.resolution;
    let scale = Canvas::auto_scale(rect, 900);
    let colors = map.color_raster(rect);
    rgb_canvas(rect, res, scale, &colors).save(&out.join("color.png"))?;
    let gt_range = w
        .elevation
        .iter()
        .fold((f32::INFINITY, f32::NEG_INFINITY), |(a, b), &z| {
            (a.min(z), b.max(z))
        });
    scalar_canvas(
        rect,
        res,
        scale,
        &map.elevation_raster(rect),
        Some(gt_range),
    )
    .0
    .save(&out.join("elevation.png"))?;
    let var: Vec<f32> = map
        .variance_raster(rect)
        .iter()
        .map(|v| v.max(1e-12).log10())
        .collect();
    scalar_canvas(rect, res, scale, &var, None)
        .0
        .save(&out.join("variance.png"))?;
    scalar_canvas(rect, res, scale, &err_raster, Some((0.0, 0.05)))
        .0
        .save(&out.join("elevation_error.png"))?;
    let pass = map.passability_raster(rect);
    let adm = map.admissible_raster(rect);
    let mut pc = Canvas::new(rect, res, scale);
    pc.fill(|k| match pass[k] {
        Passability::Unknown => None,
        Passability::Impassable => Some([20, 20, 20]),
        Passability::Passable if adm[k] => Some([230, 230, 230]),
        Passability::Passable => Some([150, 150, 150]),
    });
    pc.save(&out.join("passability.png"))?;
    let obs = map.observed_raster(rect);
    let mut ac = Canvas::new(rect, res, scale);
    ac.fill(|k| {
        obs[k].then_some(if adm[k] {
            [230, 230, 230]
        } else {
            [60, 20, 20]
        })
    });
    ac.save(&out.join("admissible.png"))?;
    let mut pathc = rgb_canvas(rect, res, scale, &colors);
    pathc.polyline(&sink.trajectory, [255, 60, 0], (scale as i64 / 3).max(1));
    pathc.marker(sc.start.position(), [255, 255, 255], (scale as i64).max(3));
    pathc.save(&out.join("path.png"))?;

    let stats = json!({
        "scenario": sc.name,
        "world_seed": sc.world_seed,
        "seed": seed,
        "observed_fraction": observed_fraction,
        "elevation_rmse_m": rmse,
        "elevation_max_abs_error_m": max_err,
        "elevation_rmse_visible_top_m": split_rmse(se_visible),
        "elevation_rmse_ground_m": split_rmse(se_split[0]),
        "elevation_rmse_obstacle_m": split_rmse(se_split[1]),
        "observed_obstacle_cells": se_split[1].1,
        "passability_agreement": agreement,
        "fused_points": sink.totals.fused_points,
        "points_per_second": pps,
        "fusion_s": fuse_s,
        "scans": sink.scans,
        "skipped_non_finite_points": sink.totals.skipped_non_finite,
        "skipped_out_of_range_points": sink.totals.skipped_out_of_range,
        "face_points": sink.totals.face_points,
        "cells_gated": sink.totals.cells_gated,
        "face_bounds_raised": sink.totals.face_bounds_raised,
        "face_bounds_ignored": sink.totals.face_bounds_ignored,
        "carved_points": sink.totals.carved_points,
        "cells_carved": sink.totals.cells_carved,
        "visible_cells": n_vis,
        "observed_cells": n_obs,
        "passability_judged_cells": n_pass,
        "coverage_path_m": path_len,
        "driven_m": sim.odometer_m(),
        "coverage_completed": completed,
        "blocked_waypoints_skipped": blocked_skips,
        "sim_time_s": sim_time,
        "wall_time_s": wall.elapsed().as_secs_f64(),
    });
    let p = out.join("map_stats.json");
    fs::write(&p, serde_json::to_string_pretty(&stats)? + "\n")
        .with_context(|| format!("{}: cannot write", p.display()))?;
    println!(
        "{}: observed_fraction {:.4}  elevation_rmse {:.4} m  passability_agreement {:.4}  fused {} points at {:.1} M points/s  ({:.0} s simulated, {:.1} s wall) -> {}",
        sc.name,
        observed_fraction,
        rmse,
        agreement,
        sink.totals.fused_points,
        pps / 1e6,
        sim_time,
        wall.elapsed().as_secs_f64(),
        out.display()
    );
    Ok(())
}
