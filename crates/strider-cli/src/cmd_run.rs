//! `strider run`: an exploration mission (`001` Alg. 1) on a scenario in the simulator.
//!
//! This file is the glue between the scenario (world, robot profile, strategy table) and the
//! mission: it converts the profile and the `001` Tbl. 3 values into [`MissionParams`], puts the
//! simulator behind the robot interface and writes the report. The mission itself never sees
//! the scenario's world.

use std::fs;
use std::path::Path;
use std::time::Instant;

use anyhow::{Context, Result, bail};
use serde_json::json;
use strider_core::Pose2;
use strider_explore::evaluate::{NavigationMode, run_tour};
use strider_explore::{GaitSpec, Mission, MissionParams, Rates, Strategy};
use strider_learn::cost_model::CostModelParams;
use strider_learn::gp::{GpParams, Kernel, KernelKind};
use strider_map::rect::WorldRect;
use strider_scenario::Scenario;
use strider_sim::Simulator;

use crate::cmd_scenario::load;
use crate::render::{Canvas, palette, rgb_canvas, scalar_canvas};
use strider_core::Point2;
use strider_explore::MissionLog;
use strider_explore::evaluate::TourResult;
use strider_explore::planner::{CostMode, PlanningView};

/// A number from the scenario's `[strategy]` table, or `default`.
fn num(sc: &Scenario, key: &str, default: f64) -> f64 {
    let v = sc.strategy.get(key);
    v.and_then(|v| v.as_float())
        .or_else(|| v.and_then(|v| v.as_integer()).map(|i| i as f64))
        .unwrap_or(default)
}

/// Mission parameters from a scenario: the robot profile, the map parameters and the
/// `[strategy]` table (`001` Tbl. 3 names).
pub fn mission_params(sc: &Scenario, strategy: Strategy, seed: u64) -> Result<MissionParams> {
    let gaits: Vec<GaitSpec> = sc
        .robot
        .gaits
        .iter()
        .map(|g| GaitSpec {
            name: g.name.clone(),
            v_max: g.max_speed,
        })
        .collect();
    if gaits.is_empty() {
        bail!(
            "scenario {}: robot profile {} has no gait",
            sc.name,
            sc.robot.name
        );
    }
    let l = num(sc, "lengthscale", 0.4);
    let sigma_eps = num(sc, "sigma_eps", 0.5);
    let sigma_s = num(sc, "sigma_s", 1.0);
    let gp = GpParams {
        kernel: Kernel {
            kind: KernelKind::SquaredExponential,
            lengthscales: vec![l],
            signal_variance: sigma_s,
        },
        noise_variance: sigma_eps * sigma_eps,
        // Decision 12: costs are modelled as y − 1 with a zero-mean GP.
        prior_mean: 1.0,
    };
    let mut cm = CostModelParams::new(gp);
    cm.sigma_sense2 = num(sc, "sigma_sense", cm.sigma_sense2);
    cm.sigma0_2 = num(sc, "sigma_0_sq", cm.sigma0_2);
    cm.n_min = num(sc, "n_min", cm.n_min as f64) as usize;
    cm.m_t = num(sc, "m_t", cm.m_t as f64) as usize;
    cm.d_s = num(sc, "d_s", cm.d_s);
    cm.c_max = num(sc, "c_max", cm.c_max);
    cm.erode_steps = num(sc, "n_erode_steps", cm.erode_steps as f64) as usize;
    cm.dilate_steps = num(sc, "n_dilate_steps", cm.dilate_steps as f64) as usize;
    cm.dilate_size = num(sc, "n_dilate_size", cm.dilate_size as f64) as usize;
    cm.igng.eps_winner = num(sc, "igng_eps_winner", cm.igng.eps_winner);
    cm.igng.eps_neighbour = num(sc, "igng_eps_neighbour", cm.igng.eps_neighbour);
    cm.igng.age_mature = num(sc, "igng_age_mature", cm.igng.age_mature as f64) as u32;
    cm.igng.age_max = num(sc, "igng_age_max", cm.igng.age_max as f64) as u32;
    cm.igng.batch = num(sc, "igng_batch", cm.igng.batch as f64) as usize;
    let b = &sc.bounds;
    Ok(MissionParams {
        map: sc.map.clone(),
        gaits,
        cost_model: cm,
        window_s: num(sc, "delta_t", 5.0),
        c_high: num(sc, "c_high", 20.0),
        c_loss: num(sc, "c_loss", 10.0),
        dt_sample: num(sc, "dt_sample", 30.0),
        dt_fallback: num(sc, "dt_fallback", 30.0),
        bounds: Some(WorldRect::new(b.min, b.max)),
        time_limit_s: sc.time_limit_s,
        strategy,
        rates: Rates::default(),
        max_sites_per_goal: 16,
        seed,
    })
}

fn median_max(v: &[f64]) -> (f64, f64) {
    if v.is_empty() {
        return (0.0, 0.0);
    }
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    (s[s.len() / 2], s[s.len() - 1])
}

/// Runs `strider run`.
pub fn run(
    arg: &str,
    world_seed: u64,
    strategy: &str,
    seed: u64,
    time_limit: Option<f64>,
    out: &Path,
) -> Result<()> {
    let wall = Instant::now();
    let Some(strategy) = Strategy::parse(strategy) else {
        bail!("unknown strategy {strategy:?}; expected gtsp, greedy or spatial-only");
    };
    let sc = load(arg, world_seed)?;
    let mut params = mission_params(&sc, strategy, seed)?;
    if let Some(t) = time_limit {
        if !(t.is_finite() && t > 0.0) {
            bail!("--time-limit must be a positive number of seconds, got {t}");
        }
        params.time_limit_s = t;
    }
    fs::create_dir_all(out)
        .with_context(|| format!("{}: cannot create directory", out.display()))?;
    let mut sim = Simulator::new(&sc, seed)?;
    let mut mission = Mission::new(params)?;
    // Progress on stderr (hidden when stderr is not a terminal).
    let bar = indicatif::ProgressBar::new(mission.params().time_limit_s.max(1.0) as u64);
    bar.set_style(
        indicatif::ProgressStyle::with_template(
            "{spinner} exploring {pos}/{len} s simulated ({elapsed}) {msg}",
        )
        .unwrap_or_else(|_| indicatif::ProgressStyle::default_spinner()),
    );
    let log = mission
        .run_observed(&mut sim, |p| {
            bar.set_position(p.time_s as u64);
            bar.set_message(format!(
                "{} cells mapped, {} spatial + {} cost goals, {} learning pairs",
                p.observed_cells, p.spatial_goals, p.cost_goals, p.learning_set
            ));
        })?
        .clone();
    bar.finish_and_clear();

    // Benchmark tours on the frozen map and models, each mode in a fresh simulator standing at
    // the tour's first waypoint.
    let mut tours = Vec::new();
    for tour in &sc.tours {
        let mut pts = tour.waypoints.clone();
        if tour.closed && pts.len() > 1 {
            pts.push(pts[0]);
        }
        if pts.len() < 2 {
            continue;
        }
        let mut modes = Vec::new();
        for mode in NavigationMode::ALL {
            let spin = indicatif::ProgressBar::new_spinner();
            spin.set_message(format!(
                "tour {} with {} navigation",
                tour.name,
                mode.name()
            ));
            spin.enable_steady_tick(std::time::Duration::from_millis(200));
            let mut sc2 = sc.clone();
            let yaw = (pts[1].y - pts[0].y).atan2(pts[1].x - pts[0].x);
            sc2.start = Pose2::new(pts[0].x, pts[0].y, yaw);
            let mut sim = Simulator::new(&sc2, seed)?;
            let r = run_tour(
                &mut sim,
                mission.map(),
                mission.models(),
                mission.params(),
                &pts,
                mode,
            )?;
            spin.finish_and_clear();
            modes.push(r);
        }
        tours.push((tour.name.clone(), modes));
    }
    let tours_json: Vec<_> = tours
        .iter()
        .map(|(name, modes)| {
            json!({
                "name": name,
                "modes": modes.iter().map(|r| json!({
                    "mode": r.mode.name(),
                    "total_s": r.total_s,
                    "completed": r.completed,
                    "segments": r.segments,
                    "trajectory": r.trajectory,
                })).collect::<Vec<_>>(),
            })
        })
        .collect();

    write_figures(&mission, &log, &tours, out)?;

    let (rep_med, rep_max) = median_max(&log.replan_ms);
    let (gid_med, gid_max) = median_max(&log.goal_identification_ms);
    let models: Vec<_> = mission
        .models()
        .iter()
        .enumerate()
        .map(|(g, m)| {
            json!({
                "gait": sc.robot.gaits[g].name,
                "regressor": m.has_regressor(),
                "learning_set": m.learning_set_len(),
                "measured_cells": m.measured_cells().len(),
                "classes": m.igng().len(),
                "cost_samples": log.cost_samples[g],
                "h_gt": mission.model_updates()[g].h_gt,
                "class_table": mission.model_updates()[g].classes.iter().map(|c| json!({
                    "id": c.id.0,
                    "dominant_colour_bin": c.prototype.iter().enumerate()
                        .max_by(|a, b| a.1.total_cmp(b.1)).map(|(k, _)| k),
                    "cells": c.cells,
                    "learning_cells": c.learning_cells,
                    "cost": c.cost,
                    "variance": c.variance,
                    "information_gain": c.information_gain,
                })).collect::<Vec<_>>(),
                "samplings": log.samplings[g],
            })
        })
        .collect();
    let wall_s = wall.elapsed().as_secs_f64();
    let report = json!({
        "scenario": sc.name,
        "world_seed": world_seed,
        "seed": seed,
        "strategy": strategy.name(),
        "termination": format!("{:?}", log.termination),
        "exploration_time_s": log.exploration_time_s,
        "driven_m": log.driven_m,
        "observed_cells": mission.map().observed_count(),
        "scans_fused": mission.map().scan_count(),
        "phase_wall_s": log.phase_wall_s,
        "models": models,
        "tours": tours_json,
        "stuck_events": log.stuck_events,
        "turn_skipped_cost_samples": log.turn_skipped,
        "information_gain_evaluations": {"fresh": log.gain_evaluated, "incremental": log.gain_updated},
        "replans": log.replan_ms.len(),
        "replan_latency_ms": {"median": rep_med, "max": rep_max},
        "goal_identification_ms": {"median": gid_med, "max": gid_max},
        "mission_wall_s": log.wall_s,
        "speedup": log.exploration_time_s / log.wall_s.max(1e-9),
        "wall_time_s": wall_s,
        "trajectory": log.trajectory,
    });
    let path = out.join("report.json");
    fs::write(&path, serde_json::to_string_pretty(&report)?)
        .with_context(|| format!("{}: cannot write", path.display()))?;
    println!(
        "{} ({}): {:?} after {:.0} s simulated, {:.1} m driven, {} replans (median {:.1} ms, max {:.1} ms), {:.0}x real time, {:.1} s wall -> {}",
        sc.name,
        strategy.name(),
        log.termination,
        log.exploration_time_s,
        log.driven_m,
        log.replan_ms.len(),
        rep_med,
        rep_max,
        log.exploration_time_s / log.wall_s.max(1e-9),
        wall_s,
        path.display()
    );
    for (name, modes) in &tours {
        let parts: Vec<String> = modes
            .iter()
            .map(|r| {
                format!(
                    "{} {:.0} s{}",
                    r.mode.name(),
                    r.total_s,
                    if r.completed { "" } else { " (incomplete)" }
                )
            })
            .collect();
        println!("  tour {name}: {}", parts.join(", "));
    }
    Ok(())
}

/// The figures of `001` Fig. 7 over the map's known area: map colour, merged planning cost and
/// selected gait (Eq. 13), per gait the learned cell costs, the classes (dilated, Alg. 10) and
/// the planning cost, the exploration path, and the tour paths of each navigation mode.
fn write_figures(
    mission: &Mission,
    log: &MissionLog,
    tours: &[(String, Vec<TourResult>)],
    out: &Path,
) -> Result<()> {
    let map = mission.map();
    let Some(rect) = map.known_bounds() else {
        return Ok(());
    };
    let d = map.cell_size();
    let scale = Canvas::auto_scale(rect, 900);
    let colors = map.color_raster(rect);
    rgb_canvas(rect, d, scale, &colors).save(&out.join("color.png"))?;
    let c_max = mission.params().cost_model.c_max as f32;
    if let Some(view) = PlanningView::build(
        map,
        mission.models(),
        CostMode::Learned,
        mission.params().c_loss,
        mission.params().bounds.as_ref(),
    ) {
        // The view covers the known area grown by the footprint; crop it to the known area.
        let vr = view.rect();
        let crop = |k: usize| vr.index(rect.cell(k));
        let merged: Vec<f32> = (0..rect.len())
            .map(|k| crop(k).map_or(f32::NAN, |i| view.grid.costs()[i]))
            .collect();
        scalar_canvas(rect, d, scale, &merged, Some((1.0, c_max)))
            .0
            .save(&out.join("merged_cost.png"))?;
        let mut g = Canvas::new(rect, d, scale);
        let obs = map.observed_raster(rect);
        g.fill(|k| {
            obs[k]
                .then(|| crop(k).and_then(|i| view.best_gait[i]))
                .flatten()
                .map(|x| palette(x as usize))
        });
        g.save(&out.join("gait.png"))?;
    }
    for (gi, m) in mission.models().iter().enumerate() {
        let name = &mission.params().gaits[gi].name;
        let costs: Vec<f32> = rect
            .cells()
            .map(|c| m.cell_cost(c).map_or(f32::NAN, |k| k.cost as f32))
            .collect();
        scalar_canvas(rect, d, scale, &costs, Some((1.0, c_max)))
            .0
            .save(&out.join(format!("measured_cost_{name}.png")))?;
        let mut cl = Canvas::new(rect, d, scale);
        let cells: Vec<_> = rect.cells().map(|c| m.planning_class(c)).collect();
        cl.fill(|k| cells[k].map(|t| palette(t.0 as usize)));
        cl.save(&out.join(format!("classes_{name}.png")))?;
        scalar_canvas(rect, d, scale, &m.planning_costs(rect), Some((1.0, c_max)))
            .0
            .save(&out.join(format!("planning_cost_{name}.png")))?;
    }
    let mut path = rgb_canvas(rect, d, scale, &colors);
    let pts: Vec<Point2> = log
        .trajectory
        .iter()
        .map(|s| Point2::new(s.x, s.y))
        .collect();
    path.polyline(&pts, [255, 0, 255], 2);
    path.save(&out.join("exploration_path.png"))?;
    for (name, modes) in tours {
        for r in modes {
            let mut c = rgb_canvas(rect, d, scale, &colors);
            for w in r.trajectory.windows(2) {
                let col = palette(w[0].gait as usize);
                c.polyline(
                    &[Point2::new(w[0].x, w[0].y), Point2::new(w[1].x, w[1].y)],
                    col,
                    2,
                );
            }
            c.save(&out.join(format!("tour_{name}_{}.png", r.mode.name())))?;
        }
    }
    Ok(())
}
