//! `strider replay`: a recorded ROS 2 log (MCAP) behind the robot interface, ingested by the
//! mission's own mapping and learning ([`strider_explore::Mission::ingest`]); writes the report of `strider run`
//! without the benchmark tours (`report.json`, `report.html`, the figures).

use std::fs;
use std::path::Path;
use std::time::Instant;
use strider_explore::FromParams;

use anyhow::{Context, Result, bail};
use serde_json::json;
use strider_core::Point2;
use strider_explore::registry::{self, RobotSpec};
use strider_explore::{MissionParams, TourExplorer};
use strider_log::config::MissionConfig;
use strider_log::{LogReplay, ReplayConfig};
use strider_map::rect::WorldRect;

use crate::cmd_run::{median_max, models_json, write_figures, write_reports};
use crate::cmd_scenario::load;
use strider_cli::trial::{robot_spec, section};

/// The mission parameters of a replay: the robot of a scenario (its `[strategy.<name>]`
/// section overridden by `parameters`) or the robot given in the configuration, and the `001`
/// learner of the strategy named (replay maps and learns as that strategy's mission does).
pub fn mission_params_of(c: &MissionConfig) -> Result<MissionParams> {
    let info = registry::find(&c.strategy)?;
    let (robot, mut table) = match &c.scenario {
        Some(name) => {
            let sc = load(name, c.world_seed)?;
            let table = section(&sc, info.name)?.cloned().unwrap_or_default();
            (robot_spec(&sc), table)
        }
        None => (robot_of(c)?, toml::Table::new()),
    };
    table.extend(c.parameters.clone());
    info.configure(Some(&table), &[])?
        .tour_mission(&robot, c.seed)
        .with_context(|| {
            format!(
                "replay config: strategy {} has no 001 learner to replay with; use gtsp, greedy or spatial-only",
                info.name
            )
        })
}

/// The robot a replay configuration describes without a scenario.
fn robot_of(c: &MissionConfig) -> Result<RobotSpec> {
    for g in &c.gaits {
        if !(g.v_max.is_finite() && g.v_max > 0.0) {
            bail!(
                "replay config: gait {:?} needs a positive v_max, got {}",
                g.name,
                g.v_max
            );
        }
    }
    let bounds = c
        .bounds
        .map(|[a, b]| WorldRect::new(Point2::new(a[0], a[1]), Point2::new(b[0], b[1])));
    Ok(RobotSpec {
        name: "replay".into(),
        gaits: c.gaits.clone(),
        sensor_hfov_deg: c.sensor_hfov_deg.clone(),
        map: c.map.clone().unwrap_or_default(),
        bounds,
        time_limit_s: 3600.0,
        bumper: false,
        proprio_rate_hz: 0.0,
        pose_rate_hz: 20.0,
    })
}

/// Runs `strider replay` (on a pool thread, see [`strider_cli::trial::on_worker`]).
pub fn run(log_path: &Path, config: &Path, out: &Path) -> Result<()> {
    strider_cli::trial::on_worker(|| run_on_worker(log_path, config, out))
}

fn run_on_worker(log_path: &Path, config: &Path, out: &Path) -> Result<()> {
    let wall = Instant::now();
    let cfg = ReplayConfig::load(config)?;
    let mut params = mission_params_of(&cfg.mission)?;
    let mut replay = LogReplay::open(log_path, &cfg, &params.gaits)?;
    params.time_limit_s = replay.time_limit_s(1.0 / params.rates.control_hz);
    fs::create_dir_all(out)
        .with_context(|| format!("{}: cannot create directory", out.display()))?;
    let bar = indicatif::ProgressBar::new(params.time_limit_s.max(1.0) as u64);
    bar.set_style(
        indicatif::ProgressStyle::with_template(
            "{spinner} replaying {pos}/{len} s recorded ({elapsed}) {msg}",
        )
        .unwrap_or_else(|_| indicatif::ProgressStyle::default_spinner()),
    );
    let mut mission = TourExplorer::mission(params)?;
    mission.ingest(&mut replay, |_, p| {
        bar.set_position(p.time_s as u64);
        bar.set_message(format!(
            "{} cells mapped, {} learning pairs",
            p.observed_cells, p.learning_set
        ));
    })?;
    let log = mission.strategy().log().clone();
    bar.finish_and_clear();
    write_figures(&mission, &[], out)?;
    let stats = replay.stats().clone();
    let (le_med, le_max) = median_max(&log.learning_ms);
    let wall_s = wall.elapsed().as_secs_f64();
    let report = json!({
        "source_log": log_path.display().to_string(),
        "config": config.display().to_string(),
        "scenario": cfg.mission.scenario,
        "seed": cfg.mission.seed,
        "strategy": "replay",
        "termination": format!("{:?}", mission.record().termination),
        "exploration_time_s": mission.record().exploration_time_s,
        "log_duration_s": replay.duration_s(),
        "driven_m": mission.record().driven_m,
        "observed_cells": mission.body().map().observed_count(),
        "scans_fused": mission.body().map().scan_count(),
        "replay": {
            "messages": stats.messages,
            "poses": stats.poses,
            "poses_delivered": stats.poses_delivered,
            "bad_poses": stats.bad_poses,
            "clouds": stats.clouds,
            "clouds_fused": stats.clouds_delivered,
            "clouds_skipped_keyframes": stats.clouds_skipped,
            "clouds_uncoloured": stats.clouds_uncoloured,
            "points": stats.points,
            "warnings": replay.warnings(),
        },
        "phase_wall_s": log.phase_wall_s,
        "models": models_json(&mission, &log),
        "stuck_events": log.stuck_events,
        "turn_skipped_cost_samples": log.turn_skipped,
        "goal_identification_ms": {
            "learning": {"median": le_med, "max": le_max},
        },
        "mission_wall_s": mission.record().wall_s,
        "speedup": mission.record().exploration_time_s / mission.record().wall_s.max(1e-9),
        "wall_time_s": wall_s,
        "trajectory": mission.record().trajectory,
    });
    let path = write_reports(out, &report, &mission, &[])?;
    println!(
        "{}: {:.0} s of log replayed in {:.1} s ({:.0}x real time): {} cells mapped from {} of {} scans, {} poses, {} cost samples -> {}",
        log_path.display(),
        mission.record().exploration_time_s,
        mission.record().wall_s,
        mission.record().exploration_time_s / mission.record().wall_s.max(1e-9),
        mission.body().map().observed_count(),
        stats.clouds_delivered,
        stats.clouds,
        stats.poses_delivered,
        log.cost_samples.iter().sum::<usize>(),
        path.display()
    );
    for w in replay.warnings() {
        println!("  note: {w}");
    }
    Ok(())
}
