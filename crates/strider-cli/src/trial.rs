//! One trial of a mission experiment: a scenario's world in the simulator behind the robot
//! interface, an exploration mission on it, then the scenario's benchmark tours on the frozen
//! map and models. Shared by `strider run` and `strider bench table5`.
//!
//! This is the glue between the scenario (world, robot profile, strategy table) and the
//! mission: it converts the profile and the `001` Tbl. 3 values into [`MissionParams`]. The
//! mission itself never sees the scenario's world.

use anyhow::{Result, bail};
use std::cell::RefCell;
use std::rc::Rc;
use strider_core::Pose2;
use strider_explore::evaluate::{NavigationMode, TourResult, run_tour};
use strider_explore::{
    GaitSpec, Mission, MissionLog, MissionParams, MissionProgress, Rates, Strategy,
};
use strider_learn::cost_model::CostModelParams;
use strider_learn::gp::{GpParams, Kernel, KernelKind};
use strider_log::recorder::{Recorder, RecorderOptions, Recording};
use strider_log::writer::WriteSummary;
use strider_map::params::MapParams;
use strider_map::rect::WorldRect;
use strider_scenario::{Scenario, SensorKind};
use strider_sim::Simulator;

/// A number (float or integer) from a `[strategy]` table, or `default`.
pub fn num(table: &toml::Table, key: &str, default: f64) -> f64 {
    let v = table.get(key);
    v.and_then(|v| v.as_float())
        .or_else(|| v.and_then(|v| v.as_integer()).map(|i| i as f64))
        .unwrap_or(default)
}

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
    let b = &sc.bounds;
    let hfov = sensor_hfovs(&sc.robot);
    let mut p = robot_mission_params(
        sc.map.clone(),
        gaits,
        hfov,
        &sc.strategy,
        Some(WorldRect::new(b.min, b.max)),
        strategy,
        seed,
    );
    p.time_limit_s = sc.time_limit_s;
    Ok(p)
}

/// Mission parameters from a robot's description without a scenario (a real robot's log):
/// map parameters, gaits, sensor fields of view, the `001` Tbl. 3 values by the names of a
/// scenario's `[strategy]` table, bounds. The time limit is one hour.
pub fn robot_mission_params(
    map: MapParams,
    gaits: Vec<GaitSpec>,
    sensor_hfov_deg: Vec<f64>,
    table: &toml::Table,
    bounds: Option<WorldRect>,
    strategy: Strategy,
    seed: u64,
) -> MissionParams {
    let sc = table;
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
    MissionParams {
        map,
        gaits,
        cost_model: cm,
        window_s: num(sc, "delta_t", 5.0),
        c_high: num(sc, "c_high", 20.0),
        c_loss: num(sc, "c_loss", 10.0),
        dt_sample: num(sc, "dt_sample", 30.0),
        dt_fallback: num(sc, "dt_fallback", 30.0),
        turning_baseline_s: num(sc, "turning_baseline_s", 0.5),
        bounds,
        time_limit_s: 3600.0,
        strategy,
        rates: Rates::default(),
        max_sites_per_goal: 16,
        sensor_hfov_deg,
        seed,
    }
}

/// Runs `work` on a thread of rayon's global pool while the caller waits (directly when the
/// caller is already one of its threads).
///
/// A mission loop is sequential with parallel parts (ray casting, fusion, all-pairs, the
/// learning update). Run from the main thread, each parallel part is handed to the pool while
/// the main thread sleeps, and between the parts the pool's idle threads spin on the cores the
/// main thread needs: on two cores, three busy threads. On a pool thread, the loop does its
/// share of every parallel part and the pool keeps one thread per core. Measured on the default
/// `strider run` (interleaved, three pairs): 445–470× real time from the main thread, 508–537×
/// on a pool thread, with identical missions.
pub fn on_worker<T: Send>(work: impl FnOnce() -> T + Send) -> T {
    // `rayon::scope` runs its closure on a pool thread (injecting it when called from outside
    // the pool) and returns once the closure and everything it spawned are done.
    rayon::scope(|_| work())
}

/// Runs an exploration mission with `params` on the scenario's world (simulator seeded with
/// `seed`), reporting progress about once per simulated second.
pub fn run_mission(
    sc: &Scenario,
    params: MissionParams,
    seed: u64,
    progress: impl FnMut(&MissionProgress),
) -> Result<(Mission, MissionLog)> {
    let mut sim = Simulator::new(sc, seed)?;
    let mut mission = Mission::new(params)?;
    let log = mission.run_observed(&mut sim, progress)?.clone();
    Ok((mission, log))
}

/// [`run_mission`] recording the mission to the MCAP file `mcap` (ROS 2 sensor stream and
/// Foxglove visualisation, see `strider_log::recorder`); returns what was written too.
pub fn run_mission_recorded(
    sc: &Scenario,
    params: MissionParams,
    seed: u64,
    mut progress: impl FnMut(&MissionProgress),
    mcap: &std::path::Path,
) -> Result<(Mission, MissionLog, WriteSummary)> {
    let sim = Simulator::new(sc, seed)?;
    let names = params.gaits.iter().map(|g| g.name.clone()).collect();
    let rec = Rc::new(RefCell::new(Recorder::create(
        mcap,
        RecorderOptions::new(names),
    )?));
    let mut robot = Recording::new(sim, rec.clone());
    let mut mission = Mission::new(params)?;
    let log = mission
        .run_watched(&mut robot, |m, p| {
            progress(p);
            rec.borrow_mut().snapshot(m, false);
        })?
        .clone();
    rec.borrow_mut().snapshot(&mission, true);
    drop(robot);
    let rec = Rc::try_unwrap(rec)
        .map_err(|_| anyhow::anyhow!("the recorder is still shared"))?
        .into_inner();
    let written = rec.finish()?;
    Ok((mission, log, written))
}

/// The benchmark tours of the scenario on the mission's frozen map and models, once per
/// navigation mode, each in a fresh simulator (seeded with `seed`) standing at the tour's
/// first waypoint facing the second. `on_start` is called before each (tour, mode).
pub fn run_tours(
    sc: &Scenario,
    mission: &Mission,
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
                mission.map(),
                mission.models(),
                mission.params(),
                &pts,
                mode,
            )?);
        }
        tours.push((tour.name.clone(), results));
    }
    Ok(tours)
}
