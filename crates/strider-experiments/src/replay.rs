//! `strider replay`: a recorded ROS 2 log (MCAP) behind the robot interface, ingested by the
//! mission's own mapping and learning ([`strider_explore::Mission::ingest`]); writes the report
//! of `strider run` without the benchmark tours (`report.json`, `report.html`, the figures).

use std::fmt;
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result, bail};
use serde::Serialize;
use strider_core::Point2;
use strider_explore::kernel::TrajectorySample;
use strider_explore::registry::{self, RobotSpec};
use strider_explore::{FromParams, MissionParams, PhaseWall, TourExplorer};
use strider_log::config::MissionConfig;
use strider_log::replay::Plausibility;
use strider_log::{LogReplay, ReplayConfig};
use strider_map::rect::WorldRect;

use crate::cancel::{Completion, Interrupted};
use crate::io::create_dir;
use crate::live::{Loop, Watch};
use crate::parallel::on_worker;
use crate::pragr22::report::{MedianMax, ModelReport, models};
use crate::pragr22::write_figures;
use crate::progress::Progress;
use crate::report::write_reports;
use crate::trial::{load, robot_spec, section, termination};

/// The mission parameters of a replay: the robot of a scenario (its `[strategy.<name>]`
/// section overridden by `parameters`) or the robot given in the configuration, and the
/// Prágr22 learner of the strategy named (replay maps and learns as that strategy's mission
/// does).
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
                "replay config: strategy {} has no Prágr22 learner to replay with; use gtsp, greedy or spatial-only",
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

/// What the replay read from the log.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ReplayCounts {
    /// Messages read.
    pub messages: usize,
    /// Poses read.
    pub poses: usize,
    /// Poses delivered to the mission.
    pub poses_delivered: usize,
    /// Poses refused.
    pub bad_poses: usize,
    /// Point clouds read.
    pub clouds: usize,
    /// Clouds fused into the map.
    pub clouds_fused: usize,
    /// Clouds skipped between keyframes.
    pub clouds_skipped_keyframes: usize,
    /// Clouds without colour.
    pub clouds_uncoloured: usize,
    /// Points read.
    pub points: usize,
    /// Notes about the fallbacks the replay took (no gait or motion topic, skipped poses).
    pub warnings: Vec<String>,
    /// The plausibility checks of the log: speeds above the gaits' v_max, pose jumps, stamps
    /// going backwards, clouds without a pose near them.
    pub plausibility: Plausibility,
    /// What the plausibility checks warn about, one line each.
    pub plausibility_warnings: Vec<String>,
}

/// Learning-update latency of a replay.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct LearningMs {
    /// Learning updates.
    pub learning: MedianMax,
}

/// `report.json` of `strider replay`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ReplayReport {
    /// Whether the whole log was replayed or the replay was interrupted (then the report
    /// describes the log up to the interruption).
    #[serde(flatten)]
    pub completion: Completion,
    /// The MCAP file.
    pub source_log: String,
    /// The replay configuration.
    pub config: String,
    /// The scenario the configuration names, if any.
    pub scenario: Option<String>,
    /// Seed.
    pub seed: u64,
    /// `replay`.
    pub strategy: &'static str,
    /// Why the replay stopped (`Interrupted` when it was).
    pub termination: String,
    /// Recorded time replayed, s.
    pub exploration_time_s: f64,
    /// Duration of the log, s.
    pub log_duration_s: f64,
    /// Distance driven, m.
    pub driven_m: f64,
    /// Observed map cells.
    pub observed_cells: usize,
    /// Scans fused.
    pub scans_fused: u64,
    /// What was read.
    pub replay: ReplayCounts,
    /// Wall time per part of the mission loop, s.
    pub phase_wall_s: PhaseWall,
    /// Per-gait models.
    pub models: Vec<ModelReport>,
    /// Stuck events.
    pub stuck_events: usize,
    /// Cost samples skipped while turning.
    pub turn_skipped_cost_samples: usize,
    /// Learning latency.
    pub goal_identification_ms: LearningMs,
    /// Wall time of the ingestion, s.
    pub mission_wall_s: f64,
    /// Recorded over wall time.
    pub speedup: f64,
    /// Wall time of the command, s.
    pub wall_time_s: f64,
    /// The trajectory.
    pub trajectory: Vec<TrajectorySample>,
}

/// A finished replay; its `Display` is the summary for the terminal.
#[derive(Debug)]
pub struct Replay {
    /// The report written.
    pub report: ReplayReport,
    /// Where `report.json` is.
    pub path: PathBuf,
    /// Cost samples learned from.
    pub cost_samples: usize,
}

impl Replay {
    /// Whether the replay was interrupted, and if so what was kept (for the terminal).
    pub fn interrupted(&self) -> Option<Interrupted> {
        let r = &self.report;
        r.completion.interrupted.then(|| {
            Interrupted::new(format!(
                "kept the report of the first {:.0} s of {:.0} s of log, {} (marked \"complete\": false); run the command again for the whole log",
                r.exploration_time_s,
                r.log_duration_s,
                self.path.display()
            ))
        })
    }
}

impl fmt::Display for Replay {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let r = &self.report;
        write!(
            f,
            "{}: {:.0} s of log replayed in {:.1} s ({:.0}x real time): {} cells mapped from {} of {} scans, {} poses, {} cost samples -> {}",
            r.source_log,
            r.exploration_time_s,
            r.mission_wall_s,
            r.speedup,
            r.observed_cells,
            r.replay.clouds_fused,
            r.replay.clouds,
            r.replay.poses_delivered,
            self.cost_samples,
            self.path.display()
        )?;
        for w in &r.replay.plausibility_warnings {
            write!(f, "\n  warning: {w}")?;
        }
        for w in &r.replay.warnings {
            write!(f, "\n  note: {w}")?;
        }
        Ok(())
    }
}

/// Runs `strider replay` of `log_path` with the configuration file `config` into `out` (on a
/// pool thread, see [`on_worker`]) until the log ends or the cancellation flag of `watch` is
/// requested; paced and published on a live view as `watch` says ([`Watch::run`]).
pub fn replay<'a>(
    (log_path, config): (&Path, &Path),
    out: &Path,
    watch: impl Into<Watch<'a>>,
    progress: &dyn Progress,
) -> Result<Replay> {
    let watch = watch.into();
    on_worker(|| replay_on_worker((log_path, config), out, watch, progress))
}

fn replay_on_worker(
    (log_path, config): (&Path, &Path),
    out: &Path,
    watch: Watch,
    progress: &dyn Progress,
) -> Result<Replay> {
    let wall = Instant::now();
    let cfg = ReplayConfig::load(config)?;
    let mut params = mission_params_of(&cfg.mission)?;
    let mut replay = LogReplay::open(log_path, &cfg, &params.gaits)?;
    params.time_limit_s = replay.time_limit_s(1.0 / params.rates.control_hz);
    create_dir(out)?;
    progress.start(params.time_limit_s.max(1.0) as u64);
    let gaits = params.gaits.iter().map(|g| g.name.clone()).collect();
    let mut mission = TourExplorer::mission(params)?;
    watch.run(&mut mission, &mut replay, (gaits, Loop::Ingest), |_, p| {
        progress.at(
            p.time_s as u64,
            &format!(
                "{} cells mapped, {} learning pairs",
                p.observed_cells, p.learning_set
            ),
        );
    })?;
    let log = mission.strategy().log().clone();
    let figures = write_figures(&mission, &[], out)?;
    let stats = replay.stats().clone();
    let record = mission.record();
    let report = ReplayReport {
        completion: Completion::of(mission.interrupted()),
        source_log: log_path.display().to_string(),
        config: config.display().to_string(),
        scenario: cfg.mission.scenario.clone(),
        seed: cfg.mission.seed,
        strategy: "replay",
        termination: termination(&mission),
        exploration_time_s: record.exploration_time_s,
        log_duration_s: replay.duration_s(),
        driven_m: record.driven_m,
        observed_cells: mission.body().map().observed_count(),
        scans_fused: mission.body().map().scan_count(),
        replay: ReplayCounts {
            messages: stats.messages,
            poses: stats.poses,
            poses_delivered: stats.poses_delivered,
            bad_poses: stats.bad_poses,
            clouds: stats.clouds,
            clouds_fused: stats.clouds_delivered,
            clouds_skipped_keyframes: stats.clouds_skipped,
            clouds_uncoloured: stats.clouds_uncoloured,
            points: stats.points,
            warnings: replay.warnings().to_vec(),
            plausibility: replay.plausibility().clone(),
            plausibility_warnings: replay.plausibility().warnings(),
        },
        phase_wall_s: log.phase_wall_s,
        models: models(&mission, &log),
        stuck_events: log.stuck_events,
        turn_skipped_cost_samples: log.turn_skipped,
        goal_identification_ms: LearningMs {
            learning: MedianMax::of(&log.learning_ms),
        },
        mission_wall_s: record.wall_s,
        speedup: record.exploration_time_s / record.wall_s.max(1e-9),
        wall_time_s: wall.elapsed().as_secs_f64(),
        trajectory: record.trajectory.clone(),
    };
    let path = write_reports(out, &report, &figures, &[])?;
    Ok(Replay {
        report,
        path,
        cost_samples: log.cost_samples.iter().sum::<usize>(),
    })
}
