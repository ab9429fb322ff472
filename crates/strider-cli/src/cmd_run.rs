//! `strider run`: an exploration mission (`001` Alg. 1) on a scenario in the simulator, the
//! benchmark tours in every navigation mode, and the report (JSON, PNG figures).

use std::fs;
use std::path::Path;
use std::time::Instant;

use anyhow::{Context, Result, bail};
use serde_json::json;
use strider_core::Point2;
use strider_explore::evaluate::{NavigationMode, TourResult};
use strider_explore::planner::{CostMode, PlanningView};
use strider_explore::{Mission, MissionLog, Strategy};

use crate::cmd_scenario::load;
use crate::render::{Canvas, palette, rgb_canvas, scalar_canvas};
use crate::trial::{mission_params, run_mission, run_tours};

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

    // Progress on stderr (hidden when stderr is not a terminal).
    let bar = indicatif::ProgressBar::new(params.time_limit_s.max(1.0) as u64);
    bar.set_style(
        indicatif::ProgressStyle::with_template(
            "{spinner} exploring {pos}/{len} s simulated ({elapsed}) {msg}",
        )
        .unwrap_or_else(|_| indicatif::ProgressStyle::default_spinner()),
    );
    let (mission, log) = run_mission(&sc, params, seed, |p| {
        bar.set_position(p.time_s as u64);
        bar.set_message(format!(
            "{} cells mapped, {} spatial + {} cost goals, {} learning pairs",
            p.observed_cells, p.spatial_goals, p.cost_goals, p.learning_set
        ));
    })?;
    bar.finish_and_clear();
    let spin = indicatif::ProgressBar::new_spinner();
    spin.enable_steady_tick(std::time::Duration::from_millis(200));
    let tours = run_tours(&sc, &mission, seed, &NavigationMode::ALL, |tour, mode| {
        spin.set_message(format!("tour {tour} with {} navigation", mode.name()));
    })?;
    spin.finish_and_clear();
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
