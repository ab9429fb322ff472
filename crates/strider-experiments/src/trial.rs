//! One trial of a mission experiment: a scenario's world in the simulator behind the robot
//! interface, an exploration mission on it, then the scenario's benchmark tours on the frozen
//! map and models. Shared by `strider run` and `strider bench table5`.
//!
//! This is the glue between the scenario (world, robot profile, strategy table) and the
//! mission: it converts the profile and the Prágr22 Tbl. 3 values into [`MissionParams`]. The
//! mission itself never sees the scenario's world.

use anyhow::{Context, Result, bail};
use strider_core::Pose2;
use strider_explore::FromParams;
use strider_explore::evaluate::{NavigationMode, TourResult, run_tour};
use strider_explore::registry::{self, Configured, RobotSpec, StrategyInfo};
use strider_explore::{
    GaitSpec, Mission, MissionLog, MissionParams, MissionProgress, MissionStrategy, Strategy,
    TourExplorer,
};
use strider_log::writer::WriteSummary;
use strider_map::rect::WorldRect;
use strider_scenario::{Scenario, SensorKind};
use strider_sim::Simulator;

use crate::live::{Loop, Watch};

/// The horizontal field of view of each of the robot's sensors, degrees (360: omnidirectional).
pub fn sensor_hfovs(robot: &strider_scenario::RobotProfile) -> Vec<f64> {
    robot
        .sensors
        .iter()
        .map(|s| match s.kind {
            SensorKind::RgbD { hfov_deg, .. } => hfov_deg,
            SensorKind::Omni { .. } => 360.0,
        })
        .collect()
}

/// What the strategies know of a scenario: its robot profile, map parameters, bounds and time
/// limit. Never its world.
pub fn robot_spec(sc: &Scenario) -> RobotSpec {
    let b = &sc.bounds;
    RobotSpec {
        name: sc.robot.name.clone(),
        gaits: sc
            .robot
            .gaits
            .iter()
            .map(|g| GaitSpec {
                name: g.name.clone(),
                v_max: g.max_speed,
            })
            .collect(),
        sensor_hfov_deg: sensor_hfovs(&sc.robot),
        map: sc.map.clone(),
        bounds: Some(WorldRect::new(b.min, b.max)),
        time_limit_s: sc.time_limit_s,
        bumper: sc.robot.bumper,
        proprio_rate_hz: sc.sim.proprio_rate_hz,
        pose_rate_hz: sc.sim.pose_rate_hz,
    }
}

/// The scenario's `[strategy.<name>]` section, if it has one. Parameters directly under
/// `[strategy]` belong to no strategy: they are an error that says which section they go in.
pub fn section<'a>(sc: &'a Scenario, name: &str) -> Result<Option<&'a toml::Table>> {
    if let Some((key, _)) = sc.strategy.iter().find(|(_, v)| !v.is_table()) {
        bail!(
            "scenario {}: [strategy] key `{key}` must sit in the section of its strategy, e.g. [strategy.gtsp] (`strider strategies` lists them)",
            sc.name
        );
    }
    if let Some(unknown) = sc
        .strategy
        .keys()
        .find(|k| registry::find(k).is_err() && !COMMAND_SECTIONS.contains(&k.as_str()))
    {
        bail!(
            "scenario {}: [strategy.{unknown}] is neither a strategy ({}) nor a command's section ({})",
            sc.name,
            registry::names().join(", "),
            COMMAND_SECTIONS.join(", ")
        );
    }
    Ok(sc.strategy.get(name).and_then(|v| v.as_table()))
}

/// `[strategy.<name>]` sections read by commands rather than exploration strategies.
pub const COMMAND_SECTIONS: [&str; 3] = ["tours", "navigate", "learn-bench"];

/// The strategy `name` configured from the scenario's `[strategy.<name>]` and the overrides
/// `sets`, after checking that the scenario's robot can carry it.
pub fn configure(
    sc: &Scenario,
    name: &str,
    sets: &[(String, String)],
) -> Result<(&'static StrategyInfo, Configured)> {
    let info = registry::find(name)?;
    info.fits(&robot_spec(sc))?;
    let table = section(sc, info.name)?;
    // The scenario's section first, so that an error in it says where it is.
    let from_file = info.configure(table, &[]).map_err(|e| {
        anyhow::anyhow!(
            "scenario {}, section [strategy.{}]: {e}",
            sc.name,
            info.name
        )
    })?;
    if sets.is_empty() {
        return Ok((info, from_file));
    }
    let configured = info.configure(table, sets)?;
    Ok((info, configured))
}

/// Loads a built-in scenario by name or a scenario file by path.
pub fn load(name_or_file: &str, world_seed: u64) -> Result<Scenario> {
    Ok(Scenario::from_name_or_file(name_or_file, world_seed)?)
}

/// The most trials a bench runs per row or cell (`--trials`): 400 times Prágr22's 25, days of
/// computing; the cap keeps a mistyped count from queueing billions of trials.
pub const MAX_TRIALS: usize = 10_000;

/// The longest mission time limit a command accepts, simulated s (about 11.6 days). The
/// built-in scenarios end within 7200 s; a mission runs at a few hundred times real time, so
/// this bounds one mission to hours of wall time while leaving room for much larger worlds.
pub const MAX_TIME_LIMIT_S: f64 = 1e6;

/// Validates a `--time-limit` override: finite, > 0 and at most [`MAX_TIME_LIMIT_S`].
pub fn checked_time_limit(t: f64) -> Result<f64> {
    if !(t.is_finite() && t > 0.0 && t <= MAX_TIME_LIMIT_S) {
        bail!(
            "--time-limit {t}: must be a finite number of simulated seconds > 0 and ≤ {MAX_TIME_LIMIT_S:e}"
        );
    }
    Ok(t)
}

/// Validates `--seed S --seeds N`: N in [1, `max`] and the seeds S, S + 1, …, S + N − 1 all
/// fit in a u64.
pub fn check_seed_range(seed: u64, seeds: u64, max: u64) -> Result<()> {
    if !(1..=max).contains(&seeds) {
        bail!("--seeds {seeds}: must be an integer from 1 to {max}");
    }
    if seed.checked_add(seeds - 1).is_none() {
        bail!(
            "--seed {seed} with --seeds {seeds}: the last seed would pass {}",
            u64::MAX
        );
    }
    Ok(())
}

/// Mission parameters of a Prágr22 strategy from a scenario: the robot profile, the map
/// parameters and the strategy's `[strategy.<name>]` section.
pub fn mission_params(sc: &Scenario, strategy: Strategy, seed: u64) -> Result<MissionParams> {
    mission_params_with(sc, strategy, seed, &[])
}

/// [`mission_params`] with strategy parameters `sets` (KEY, VALUE) over the scenario's section.
pub fn mission_params_with(
    sc: &Scenario,
    strategy: Strategy,
    seed: u64,
    sets: &[(String, String)],
) -> Result<MissionParams> {
    let (_, configured) = configure(sc, strategy.name(), sets)?;
    configured
        .tour_mission(&robot_spec(sc), seed)
        .context("not a Prágr22 strategy")
}

/// Drives `mission` on the scenario's world (simulator seeded with `seed`) until it ends or the
/// cancellation flag of `watch` is requested, calling `observe` about once per simulated
/// second; records to the MCAP file of `watch` and publishes on its live view, if any (see
/// [`Watch::run`]), and returns what was written to the file.
///
/// The recording is written to `<mcap>.part` and renamed to `mcap` once finished (summary and
/// footer written): also when the mission is interrupted or fails, so that what was recorded
/// stays readable. A recording that cannot be finished stays `.part`.
pub fn drive<'a, S: MissionStrategy>(
    sc: &Scenario,
    seed: u64,
    mission: &mut Mission<S>,
    watch: impl Into<Watch<'a>>,
    observe: impl FnMut(&Mission<S>, &MissionProgress),
) -> Result<Option<WriteSummary>> {
    let mut sim = Simulator::new(sc, seed)?;
    let names = sc.robot.gaits.iter().map(|g| g.name.clone()).collect();
    watch
        .into()
        .run(mission, &mut sim, (names, Loop::Explore), observe)
}

/// Runs a mission of strategy `S` with `params` on the scenario's world (simulator seeded with
/// `seed`) until it ends or the cancellation flag of `watch` is requested, reporting progress
/// about once per simulated second; records and serves it as `watch` says (ROS 2 sensor stream
/// and Foxglove visualisation, see [`drive`]) and returns what was written to the MCAP file too.
pub fn run_strategy<'a, S: FromParams>(
    sc: &Scenario,
    params: S::Params,
    seed: u64,
    watch: impl Into<Watch<'a>>,
    mut progress: impl FnMut(&MissionProgress),
) -> Result<(Mission<S>, Option<WriteSummary>)> {
    let mut mission = S::mission(params)?;
    let written = drive(sc, seed, &mut mission, watch, |_, p| progress(p))?;
    Ok((mission, written))
}

/// [`run_strategy`] of a Prágr22 mission, with its log.
pub fn run_mission<'a>(
    sc: &Scenario,
    params: MissionParams,
    seed: u64,
    watch: impl Into<Watch<'a>>,
    progress: impl FnMut(&MissionProgress),
) -> Result<(Mission<TourExplorer>, MissionLog, Option<WriteSummary>)> {
    let (mission, written) = run_strategy::<TourExplorer>(sc, params, seed, watch, progress)?;
    let log = mission.strategy().log().clone();
    Ok((mission, log, written))
}

/// Why `mission` stopped, for reports: its [`strider_explore::Termination`], or `Interrupted`
/// when the cancellation flag stopped it.
pub fn termination<S: MissionStrategy>(mission: &Mission<S>) -> String {
    if mission.interrupted() {
        "Interrupted".to_string()
    } else {
        format!("{:?}", mission.record().termination)
    }
}

/// Where a trial of a bench ran and how its exploration ended: the first fields of every
/// trial's record.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct TrialRecord {
    /// Scenario.
    pub scenario: String,
    /// Strategy.
    pub strategy: String,
    /// World seed.
    pub world_seed: u64,
    /// Mission seed.
    pub seed: u64,
    /// Why the exploration stopped.
    pub termination: String,
    /// Exploration time, simulated s.
    pub exploration_time_s: f64,
    /// Observed map cells.
    pub observed_cells: usize,
}

impl TrialRecord {
    /// The record of `mission`, run as `strategy` on `scenario` with seeds `(world_seed, seed)`.
    pub fn of<S: MissionStrategy>(
        scenario: &str,
        strategy: &str,
        (world_seed, seed): (u64, u64),
        mission: &Mission<S>,
    ) -> Self {
        Self {
            scenario: scenario.to_string(),
            strategy: strategy.to_string(),
            world_seed,
            seed,
            termination: termination(mission),
            exploration_time_s: mission.record().exploration_time_s,
            observed_cells: mission.body().map().observed_count(),
        }
    }
}

/// The benchmark tours of the scenario on the mission's frozen map and models, once per
/// navigation mode, each in a fresh simulator (seeded with `seed`) standing at the tour's
/// first waypoint facing the second. `on_start` is called before each (tour, mode).
pub fn run_tours(
    sc: &Scenario,
    mission: &Mission<TourExplorer>,
    seed: u64,
    modes: &[NavigationMode],
    on_start: impl FnMut(&str, NavigationMode),
) -> Result<Vec<(String, Vec<TourResult>)>> {
    let ex = mission.strategy();
    run_tours_with(
        sc,
        Learned {
            map: mission.body().map(),
            models: ex.models(),
            params: ex.params(),
        },
        seed,
        modes,
        on_start,
    )
}

/// What benchmark tours navigate with: a map and the Prágr22 per-gait models learned on it.
#[derive(Clone, Copy)]
pub struct Learned<'a> {
    /// The map.
    pub map: &'a strider_map::ElevationMap,
    /// The per-gait cost models.
    pub models: &'a [strider_learn::cost_model::GaitCostModel],
    /// Their mission parameters (gaits, c_loss, bounds, the stuck reflex).
    pub params: &'a MissionParams,
}

/// [`run_tours`] with any map and Prágr22 models.
pub fn run_tours_with(
    sc: &Scenario,
    learned: Learned,
    seed: u64,
    modes: &[NavigationMode],
    mut on_start: impl FnMut(&str, NavigationMode),
) -> Result<Vec<(String, Vec<TourResult>)>> {
    let mut tours = Vec::new();
    for tour in &sc.tours {
        let mut pts = tour.waypoints.clone();
        if tour.closed && pts.len() > 1 {
            pts.push(pts[0]);
        }
        if pts.len() < 2 {
            continue;
        }
        let mut results = Vec::new();
        for &mode in modes {
            on_start(&tour.name, mode);
            let mut sc2 = sc.clone();
            let yaw = (pts[1].y - pts[0].y).atan2(pts[1].x - pts[0].x);
            sc2.start = Pose2::new(pts[0].x, pts[0].y, yaw);
            let mut sim = Simulator::new(&sc2, seed)?;
            results.push(run_tour(
                &mut sim,
                learned.map,
                learned.models,
                learned.params,
                &pts,
                mode,
            )?);
        }
        tours.push((tour.name.clone(), results));
    }
    Ok(tours)
}

#[cfg(test)]
mod seed_range_tests {
    use super::check_seed_range;

    #[test]
    fn seed_counts_outside_the_range_or_past_u64_max_are_refused() {
        assert!(check_seed_range(1, 10, 1000).is_ok());
        assert!(check_seed_range(u64::MAX, 1, 1000).is_ok());
        let e = check_seed_range(1, 0, 1000).unwrap_err().to_string();
        assert_eq!(e, "--seeds 0: must be an integer from 1 to 1000");
        assert!(check_seed_range(1, 1001, 1000).is_err());
        let e = check_seed_range(u64::MAX - 1, 3, 1000)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("the last seed would pass 18446744073709551615"),
            "{e}"
        );
    }
}
