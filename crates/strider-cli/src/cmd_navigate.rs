//! `strider navigate`: `004` (Nardi & Stachniss, ICRA 2019) — repeated navigation that learns a
//! place-dependent model of vibration or energy and plans with its lower confidence bound.
//!
//! For every site (world seed) and mission seed it runs two experiments in the simulator:
//!
//! * **start-goal** (`004` §VI-B): the scenario's `start-goal` task driven `--runs` times per
//!   objective (vibration, energy) with each model (`single-gp`, `gp-mixture`,
//!   `gp-mixture-aerial`, softplus LCB) and the aerial mixture with the ReLU LCB; beside them the
//!   shortest path and the least-cost path on the true field, each driven once.
//! * **locations** (`004` §VI-C, Table I): the `locations` tour A → B → C → D driven `--runs`
//!   times minimising vibration with each model (softplus); the final model's RMS error and
//!   Mahalanobis distance against the true field.
//!
//! The robot only sees the grid map (ground-truth admissibility: the paper's 𝓜) and the aerial
//! image (the world's colour layer, or `--aerial FILE`); the true field (the terrain table's
//! vibration or energy per metre of every cell) is used here only to evaluate and to plan the
//! least-cost baseline. Writes `navigate.json`, `navigate.md` and PNG figures into `--out`.
//!
//! Aggregation: RMSE = √(mean over admissible cells of (μ − f)²); Mahalanobis distance
//! D = √(Σ over admissible cells of (μ − f)² / σ²) with σ² the mixture's latent variance
//! (Eq. 3, floored at 10⁻¹²); both for the model after the last run, then mean ± sample std
//! over seeds per site. A configuration "converges" at the first run r from which every run
//! r … N experiences at most 1.1 × the cost the least-cost path experienced.

use std::fs;
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result, bail};
use clap::Args;
use rayon::prelude::*;
use serde_json::{Value, json};
use strider_core::{Cell, Point2, Pose2, Rgb8};
use strider_explore::navigate::{
    DriveResult, ModelField, ModelKind, NavigateParams, NavigationLog, NavigationMap, Objective,
    drive_task, navigate, task_cells,
};
use strider_explore::stats::Summary;
use strider_plan::grid::lcb::{LcbParams, Rectifier, lcb_grid, lcb_path};
use strider_plan::grid::{CostGrid, Dijkstra};
use strider_scenario::Scenario;
use strider_sim::Simulator;

use crate::cmd_scenario::load;
use crate::render::{Canvas, line_chart, palette, rgb_canvas, scalar_canvas};

/// Arguments of `strider navigate`.
#[derive(Args, Debug)]
pub struct NavigateArgs {
    /// Built-in scenario name or scenario `.toml` file.
    #[arg(long, short = 's', default_value = "bonn-paths")]
    pub scenario: String,
    /// Seed of the simulator's noise (the first of `--seeds` consecutive seeds).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Output directory (created if missing).
    #[arg(long, short = 'o', default_value = "out/navigate")]
    pub out: PathBuf,
    /// Sites: comma-separated world seeds of the scenario family (e.g. `1,2`).
    #[arg(long, default_value = "1")]
    pub sites: String,
    /// Number of consecutive seeds per site, from `--seed` (the acceptance sweep uses 10).
    #[arg(long, default_value_t = 1)]
    pub seeds: u64,
    /// Runs per task (`004`: 25).
    #[arg(long, default_value_t = 25)]
    pub runs: usize,
    /// Objectives of the start-goal experiment: comma-separated `vibration`, `energy`.
    #[arg(long, default_value = "vibration,energy")]
    pub objectives: String,
    /// λ of the lower confidence bound μ − λσ (decision 26).
    #[arg(long, default_value_t = 1.0)]
    pub lambda: f64,
    /// An aerial image (8-bit RGB PNG, north up, one pixel per grid cell) replacing the
    /// scenario's colour layer.
    #[arg(long)]
    pub aerial: Option<PathBuf>,
    /// Navigations run in parallel (default: the number of CPUs).
    #[arg(long)]
    pub jobs: Option<usize>,
}

/// Published `004` Table I: (RMS error, Mahalanobis distance) per model, site 1 then site 2.
const PUBLISHED: [(&str, [(f64, f64); 2]); 3] = [
    ("single-gp", [(16.15, 265.84), (15.364, 316.28)]),
    ("gp-mixture", [(9.29, 132.52), (9.43, 150.24)]),
    ("gp-mixture-aerial", [(4.96, 79.17), (6.91, 151.42)]),
];

/// Relative tolerance of "experiences about what the least-cost path experiences".
const WITHIN: f64 = 0.10;

/// One navigation to run: task, objective, model, rectifier.
#[derive(Clone, Copy, Debug)]
struct Config {
    task: Task,
    objective: Objective,
    model: ModelKind,
    rectifier: Rectifier,
}

/// The two experiments.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Task {
    StartGoal,
    Locations,
}

impl Task {
    fn name(self) -> &'static str {
        match self {
            Task::StartGoal => "start-goal",
            Task::Locations => "locations",
        }
    }
}

/// Everything one site needs: the scenario, the navigation inputs and the true fields.
struct Site {
    world_seed: u64,
    scenario: Scenario,
    map: NavigationMap,
    tasks: Vec<(Task, Vec<Point2>)>,
}

/// A baseline: planned cost (metres for the shortest path, ∫ f ds for the least-cost one),
/// what driving it measured, and its cell paths.
type Baseline = (f64, DriveResult, Vec<Vec<Cell>>);

/// A navigation's configuration, its log and (RMSE, Mahalanobis) after each run.
type ConfigResult = (Config, NavigationLog, Vec<(f64, f64)>);

/// Result of one (site, seed, task, objective) group.
struct Group {
    site: u64,
    seed: u64,
    task: Task,
    objective: Objective,
    shortest: Baseline,
    least_cost: Baseline,
    configs: Vec<ConfigResult>,
}

/// Runs `strider navigate`.
pub fn run(args: &NavigateArgs) -> Result<()> {
    let wall = Instant::now();
    if args.runs == 0 {
        bail!("--runs must be at least 1");
    }
    if args.seeds == 0 {
        bail!("--seeds must be at least 1");
    }
    if !(args.lambda.is_finite() && args.lambda >= 0.0) {
        bail!(
            "--lambda must be a non-negative number, got {}",
            args.lambda
        );
    }
    let sites = parse_list(&args.sites, "--sites", |s| s.parse::<u64>().ok())?;
    let objectives = parse_list(&args.objectives, "--objectives", Objective::parse)?;
    let aerial_png = match &args.aerial {
        Some(p) => Some(read_png(p)?),
        None => None,
    };
    let mut loaded = Vec::new();
    for &ws in &sites {
        loaded.push(prepare_site(&args.scenario, ws, aerial_png.as_ref(), args)?);
    }
    fs::create_dir_all(&args.out)
        .with_context(|| format!("{}: cannot create directory", args.out.display()))?;

    // Every (site, seed, task, objective) group with its configurations.
    let mut jobs: Vec<(usize, u64, Task, Objective)> = Vec::new();
    for (si, site) in loaded.iter().enumerate() {
        for seed in args.seed..args.seed + args.seeds {
            for (task, _) in &site.tasks {
                let objs: &[Objective] = match task {
                    Task::StartGoal => &objectives,
                    Task::Locations => &[Objective::Vibration],
                };
                for &o in objs {
                    jobs.push((si, seed, *task, o));
                }
            }
        }
    }
    let mut units: Vec<(usize, Config)> = Vec::new();
    for (g, &(_, _, task, objective)) in jobs.iter().enumerate() {
        for c in configs(task, objective) {
            units.push((g, c));
        }
    }
    let threads = args
        .jobs
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
        .max(1);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .context("cannot start the thread pool")?;
    let bar = indicatif::ProgressBar::new((units.len() * args.runs) as u64);
    bar.set_style(
        indicatif::ProgressStyle::with_template("{bar:30} {pos}/{len} runs ({elapsed}) {msg}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    let base = NavigateParams {
        lcb: LcbParams {
            lambda: args.lambda,
            ..LcbParams::default()
        },
        runs: args.runs,
        ..NavigateParams::default()
    };
    let logs: Vec<Result<NavigationLog>> = pool.install(|| {
        units
            .par_iter()
            .map(|&(g, c)| {
                let (si, seed, _, _) = jobs[g];
                let site = &loaded[si];
                let task = task_points(site, c.task);
                let params = NavigateParams {
                    model: c.model,
                    objective: c.objective,
                    lcb: LcbParams {
                        rectifier: c.rectifier,
                        ..base.lcb
                    },
                    max_speed: max_speed(&site.scenario),
                    ..base.clone()
                };
                let sc = scenario_at(&site.scenario, task);
                let log = navigate(
                    &site.map,
                    task,
                    &params,
                    |run| Simulator::new(&sc, sim_seed(seed, run)),
                    |_| bar.inc(1),
                )
                .with_context(|| {
                    format!(
                        "site {} seed {seed}, {} {} with {} ({})",
                        site.world_seed,
                        c.task.name(),
                        c.objective.name(),
                        c.model.name(),
                        c.rectifier.name()
                    )
                })?;
                Ok(log)
            })
            .collect()
    });
    bar.finish_and_clear();
    let mut logs = logs.into_iter();
    let mut groups = Vec::new();
    for (g, &(si, seed, task, objective)) in jobs.iter().enumerate() {
        let site = &loaded[si];
        let truth = true_field(&site.scenario, objective);
        let points = task_points(site, task);
        let shortest = baseline(site, points, objective, seed, None)?;
        let least_cost = baseline(site, points, objective, seed, Some(&truth))?;
        let mut configs_out = Vec::new();
        for &(ug, c) in &units {
            if ug != g {
                continue;
            }
            let log = logs.next().context("missing navigation result")??;
            let metrics: Vec<(f64, f64)> = log
                .fields
                .iter()
                .map(|f| accuracy(f, &truth, site.map.admissible()))
                .collect();
            configs_out.push((c, log, metrics));
        }
        groups.push(Group {
            site: site.world_seed,
            seed,
            task,
            objective,
            shortest,
            least_cost,
            configs: configs_out,
        });
    }

    let first = &loaded[0];
    write_figures(first, &groups, &args.out)?;
    let wall_s = wall.elapsed().as_secs_f64();
    let report = report_json(args, &sites, &groups, wall_s);
    let path = args.out.join("navigate.json");
    fs::write(&path, serde_json::to_string_pretty(&report)?)
        .with_context(|| format!("{}: cannot write", path.display()))?;
    let md = report_markdown(args, &sites, &groups, wall_s);
    let path = args.out.join("navigate.md");
    fs::write(&path, md).with_context(|| format!("{}: cannot write", path.display()))?;
    println!(
        "navigate: {} navigations of {} runs on {} site(s) × {} seed(s) in {:.1} s; wrote {}",
        units.len(),
        args.runs,
        sites.len(),
        args.seeds,
        wall_s,
        args.out.display()
    );
    for line in summary_lines(&groups) {
        println!("  {line}");
    }
    Ok(())
}

/// The configurations of one group: every model with softplus, and for start-goal also the
/// aerial mixture with ReLU (`004` Fig. 3 compares the rectifiers on the proposed model).
fn configs(task: Task, objective: Objective) -> Vec<Config> {
    let mut v: Vec<Config> = ModelKind::ALL
        .iter()
        .map(|&model| Config {
            task,
            objective,
            model,
            rectifier: Rectifier::Softplus,
        })
        .collect();
    if task == Task::StartGoal {
        v.push(Config {
            task,
            objective,
            model: ModelKind::GpMixtureAerial,
            rectifier: Rectifier::Relu,
        });
    }
    v
}

/// Simulator seed of run `run` under mission seed `seed` (the same for every model, so models
/// are compared on the same noise).
fn sim_seed(seed: u64, run: usize) -> u64 {
    seed.wrapping_mul(1000).wrapping_add(run as u64)
}

/// Seed of the baselines' drives.
fn baseline_seed(seed: u64) -> u64 {
    seed.wrapping_mul(1000).wrapping_add(999)
}

fn parse_list<T>(s: &str, flag: &str, parse: impl Fn(&str) -> Option<T>) -> Result<Vec<T>> {
    let v: Vec<T> = s
        .split(',')
        .map(str::trim)
        .filter(|t| !t.is_empty())
        .map(|t| parse(t).with_context(|| format!("{flag}: cannot read {t:?}")))
        .collect::<Result<_>>()?;
    if v.is_empty() {
        bail!("{flag} lists nothing");
    }
    Ok(v)
}

/// Reads an 8-bit RGB(A) PNG as (width, height, rows north first).
fn read_png(path: &Path) -> Result<(u32, u32, Vec<Rgb8>)> {
    let img = image::open(path)
        .with_context(|| format!("{}: cannot read the aerial image", path.display()))?
        .to_rgb8();
    let (w, h) = img.dimensions();
    let px = img.pixels().map(|p| Rgb8(p.0)).collect();
    Ok((w, h, px))
}

/// Loads a site: the scenario, its grid map (ground-truth admissibility), the aerial image
/// (the colour layer or the given PNG, which must match the grid) and the tasks.
fn prepare_site(
    name: &str,
    world_seed: u64,
    aerial_png: Option<&(u32, u32, Vec<Rgb8>)>,
    args: &NavigateArgs,
) -> Result<Site> {
    let sc = load(name, world_seed)?;
    let w = &sc.world;
    if sc.robot.gaits.is_empty() {
        bail!("{}: the robot profile has no gait", sc.name);
    }
    let aerial = match aerial_png {
        None => w.color.clone(),
        Some((iw, ih, px)) => {
            if (*iw, *ih) != (w.rect.width, w.rect.height) {
                bail!(
                    "aerial image {} is {iw}×{ih} pixels but the grid map of {} is {}×{} cells",
                    args.aerial.as_deref().unwrap_or(Path::new("?")).display(),
                    sc.name,
                    w.rect.width,
                    w.rect.height
                );
            }
            // PNG rows run north to south; the lattice's row 0 is the southernmost.
            let (iw, ih) = (*iw as usize, *ih as usize);
            (0..iw * ih)
                .map(|k| px[(ih - 1 - k / iw) * iw + k % iw])
                .collect()
        }
    };
    let admissible = w.gt_admissible(sc.map.rho_obstacle, sc.map.r_robot);
    let map = NavigationMap::new(w.rect, w.resolution, admissible, Some(aerial))?;
    let mut tasks = Vec::new();
    let sg = sc
        .tours
        .iter()
        .find(|t| t.name == "start-goal")
        .or(sc.tours.first())
        .with_context(|| format!("{}: the scenario has no tour to navigate", sc.name))?;
    tasks.push((Task::StartGoal, sg.waypoints.clone()));
    if let Some(t) = sc.tours.iter().find(|t| t.name == "locations") {
        tasks.push((Task::Locations, t.waypoints.clone()));
    }
    for (task, pts) in &tasks {
        if pts.len() < 2 {
            bail!(
                "{}: tour {} needs a start and at least one goal",
                sc.name,
                task.name()
            );
        }
        let cells =
            task_cells(&map, pts).with_context(|| format!("{}: tour {}", sc.name, task.name()))?;
        // Reachability on the grid map, so a bad task fails before any run.
        let grid = CostGrid::new(
            w.rect,
            w.resolution,
            map.admissible()
                .iter()
                .map(|&a| if a { 1.0 } else { f32::INFINITY })
                .collect(),
        )?;
        let mut dij = Dijkstra::new();
        for (s, pair) in cells.windows(2).enumerate() {
            if !dij.astar(&grid, pair[0], pair[1])?.is_finite() {
                bail!(
                    "{}: tour {}: no traversable path from waypoint {s} to waypoint {}",
                    sc.name,
                    task.name(),
                    s + 1
                );
            }
        }
    }
    Ok(Site {
        world_seed,
        scenario: sc,
        map,
        tasks,
    })
}

fn task_points(site: &Site, task: Task) -> &[Point2] {
    site.tasks
        .iter()
        .find(|(t, _)| *t == task)
        .map(|(_, p)| p.as_slice())
        .unwrap_or(&[])
}

/// The robot's top speed (its fastest gait).
fn max_speed(sc: &Scenario) -> f64 {
    sc.robot
        .gaits
        .iter()
        .map(|g| g.max_speed)
        .fold(0.0, f64::max)
        .max(1e-3)
}

/// The scenario with the robot standing at the task's start, facing its first goal.
fn scenario_at(sc: &Scenario, task: &[Point2]) -> Scenario {
    let mut s = sc.clone();
    let (a, b) = (task[0], task[1]);
    s.start = Pose2::new(a.x, a.y, (b.y - a.y).atan2(b.x - a.x));
    s
}

/// The true field f per cell: the terrain table's vibration or energy per metre.
fn true_field(sc: &Scenario, objective: Objective) -> Vec<f64> {
    let w = &sc.world;
    w.terrain
        .iter()
        .map(|&t| {
            w.terrains
                .iter()
                .find(|tt| tt.index == t)
                .map_or(f64::NAN, |tt| match objective {
                    Objective::Vibration => tt.vibration,
                    Objective::Energy => tt.energy_per_m,
                })
        })
        .collect()
}

/// Plans and drives a baseline: the shortest path (`truth` = None) or the least-cost path on
/// the true field, both charged per entered cell like Eq. 7. Returns the planned cost (length
/// in metres, or ∫ f ds), the drive and the paths.
fn baseline(
    site: &Site,
    task: &[Point2],
    objective: Objective,
    seed: u64,
    truth: Option<&[f64]>,
) -> Result<Baseline> {
    let map = &site.map;
    let n = map.rect().len();
    let ones = vec![1.0; n];
    let mean = truth.unwrap_or(&ones);
    // λ = 0 and a ReLU: the cost is the field itself (positive everywhere here).
    let p = LcbParams {
        lambda: 0.0,
        rectifier: Rectifier::Relu,
        floor: 1e-6,
    };
    let clean: Vec<f64> = mean
        .iter()
        .zip(map.admissible())
        .map(|(&v, &a)| if a && v.is_finite() { v } else { 1.0 })
        .collect();
    let grid = lcb_grid(
        map.rect(),
        map.cell_size(),
        &clean,
        &vec![0.0; n],
        map.admissible(),
        &p,
    )?;
    let cells = task_cells(map, task)?;
    let mut dij = Dijkstra::new();
    let mut paths = Vec::new();
    let mut planned = 0.0;
    for (s, w) in cells.windows(2).enumerate() {
        let (path, c) = lcb_path(&mut dij, &grid, w[0], w[1])?
            .with_context(|| format!("no path from waypoint {s} to {}", s + 1))?;
        planned += c;
        paths.push(path);
    }
    let sc = scenario_at(&site.scenario, task);
    let mut robot = Simulator::new(&sc, baseline_seed(seed))?;
    let params = NavigateParams {
        objective,
        max_speed: max_speed(&site.scenario),
        ..NavigateParams::default()
    };
    let drive = drive_task(&mut robot, map, objective, &paths, &params)?;
    Ok((planned, drive, paths))
}

/// (RMSE, Mahalanobis distance) of a model field against the truth over admissible cells.
fn accuracy(field: &ModelField, truth: &[f64], admissible: &[bool]) -> (f64, f64) {
    let (mut se, mut m2, mut n) = (0.0, 0.0, 0usize);
    for k in 0..truth.len() {
        if !admissible[k] || !truth[k].is_finite() {
            continue;
        }
        let e = field.mean[k] as f64 - truth[k];
        let s = field.std[k] as f64;
        se += e * e;
        m2 += e * e / (s * s).max(1e-12);
        n += 1;
    }
    if n == 0 {
        return (f64::NAN, f64::NAN);
    }
    ((se / n as f64).sqrt(), m2.sqrt())
}

/// Mean and sample standard deviation of the finite values (NaN, NaN when there are none).
fn mean_std(v: &[f64]) -> (f64, f64) {
    let finite: Vec<f64> = v.iter().copied().filter(|x| x.is_finite()).collect();
    Summary::of(&finite).map_or((f64::NAN, f64::NAN), |s| (s.mean, s.std))
}

/// First run from which every run stays within [`WITHIN`] of the least-cost path's drive.
fn converged_run(costs: &[f64], least: f64) -> Option<usize> {
    let ok = |c: f64| c <= (1.0 + WITHIN) * least;
    let mut first = None;
    for (r, &c) in costs.iter().enumerate() {
        if ok(c) {
            first.get_or_insert(r + 1);
        } else {
            first = None;
        }
    }
    first
}

fn config_name(c: &Config) -> String {
    match c.rectifier {
        Rectifier::Softplus => c.model.name().to_string(),
        Rectifier::Relu => format!("{} (relu)", c.model.name()),
    }
}

fn costs(log: &NavigationLog) -> Vec<f64> {
    log.runs.iter().map(|r| r.drive.experienced_cost).collect()
}

fn report_json(args: &NavigateArgs, sites: &[u64], groups: &[Group], wall_s: f64) -> Value {
    let gj: Vec<Value> = groups
        .iter()
        .map(|g| {
            let lc = g.least_cost.1.experienced_cost;
            json!({
                "site": g.site,
                "seed": g.seed,
                "task": g.task.name(),
                "objective": g.objective.name(),
                "shortest": {
                    "planned_length_m": g.shortest.0,
                    "experienced_cost": g.shortest.1.experienced_cost,
                    "distance_m": g.shortest.1.distance_m,
                    "reached": g.shortest.1.reached,
                },
                "least_cost": {
                    "planned_cost": g.least_cost.0,
                    "experienced_cost": lc,
                    "distance_m": g.least_cost.1.distance_m,
                    "reached": g.least_cost.1.reached,
                },
                "configs": g.configs.iter().map(|(c, log, metrics)| {
                    let cs = costs(log);
                    let last = log.runs.last();
                    json!({
                        "model": c.model.name(),
                        "rectifier": c.rectifier.name(),
                        "final": {
                            "rmse": metrics.last().map(|m| m.0),
                            "mahalanobis": metrics.last().map(|m| m.1),
                            "visited_cells": last.map(|r| r.visited_cells),
                            "experienced_cost": last.map(|r| r.drive.experienced_cost),
                            "ratio_to_least_cost": last.map(|r| r.drive.experienced_cost / lc),
                            "converged_run": converged_run(&cs, lc),
                            "components": log.model.as_ref().map(|m| m.components().len()),
                        },
                        "runs": log.runs.iter().zip(metrics).map(|(r, m)| json!({
                            "run": r.run,
                            "experienced_cost": r.drive.experienced_cost,
                            "distance_m": r.drive.distance_m,
                            "time_s": r.drive.time_s,
                            "reached": r.drive.reached,
                            "new_cells": r.new_cells,
                            "visited_cells": r.visited_cells,
                            "centroids": r.centroids,
                            "rmse": m.0,
                            "mahalanobis": m.1,
                            "plan_ms": r.plan_ms,
                            "update_ms": r.update_ms,
                        })).collect::<Vec<_>>(),
                    })
                }).collect::<Vec<_>>(),
            })
        })
        .collect();
    json!({
        "scenario": args.scenario,
        "sites": sites,
        "seeds": (args.seed..args.seed + args.seeds).collect::<Vec<_>>(),
        "runs": args.runs,
        "lambda": args.lambda,
        "definitions": {
            "experienced_cost": "vibration: integral of the measured vibration over the driven distance (m/s^2 * m); energy: measured energy (J)",
            "rmse": "sqrt(mean over admissible cells of (mu - f)^2), model after the run",
            "mahalanobis": "sqrt(sum over admissible cells of (mu - f)^2 / sigma^2), sigma^2 the mixture's latent variance (Eq. 3)",
            "aggregation": "per site: mean and sample standard deviation over seeds",
            "converged_run": "first run from which every later run experiences at most 1.1 x the least-cost path's drive",
            "visited_cells": "cells with an averaged observation (the training set) after the last run",
        },
        "published_table_1": PUBLISHED.iter().map(|(m, s)| json!({
            "model": m,
            "site_1": {"rmse": s[0].0, "mahalanobis": s[0].1},
            "site_2": {"rmse": s[1].0, "mahalanobis": s[1].1},
        })).collect::<Vec<_>>(),
        "summary": summary_json(groups),
        "groups": gj,
        "wall_s": wall_s,
    })
}

/// Per (site, task, objective, config): the seeds' final figures.
struct Agg {
    rmse: Vec<f64>,
    mahal: Vec<f64>,
    visited: Vec<f64>,
    ratio: Vec<f64>,
    ratio_last5: Vec<f64>,
    converged: Vec<Option<usize>>,
    run1_ratio: Vec<f64>,
}

fn aggregate(
    groups: &[Group],
    site: u64,
    task: Task,
    objective: Objective,
    name: &str,
) -> Option<Agg> {
    let mut a = Agg {
        rmse: vec![],
        mahal: vec![],
        visited: vec![],
        ratio: vec![],
        ratio_last5: vec![],
        converged: vec![],
        run1_ratio: vec![],
    };
    for g in groups
        .iter()
        .filter(|g| g.site == site && g.task == task && g.objective == objective)
    {
        let lc = g.least_cost.1.experienced_cost;
        for (c, log, metrics) in &g.configs {
            if config_name(c) != name {
                continue;
            }
            let cs = costs(log);
            if let Some(m) = metrics.last() {
                a.rmse.push(m.0);
                a.mahal.push(m.1);
            }
            if let Some(r) = log.runs.last() {
                a.visited.push(r.visited_cells as f64);
            }
            if let Some(&c) = cs.last() {
                a.ratio.push(c / lc);
            }
            let tail = &cs[cs.len().saturating_sub(5)..];
            a.ratio_last5
                .push(tail.iter().sum::<f64>() / tail.len().max(1) as f64 / lc);
            if let Some(&c) = cs.first() {
                a.run1_ratio.push(c / lc);
            }
            a.converged.push(converged_run(&cs, lc));
        }
    }
    (!a.rmse.is_empty()).then_some(a)
}

fn all_names() -> Vec<String> {
    let mut v: Vec<String> = ModelKind::ALL
        .iter()
        .map(|m| m.name().to_string())
        .collect();
    v.push(format!("{} (relu)", ModelKind::GpMixtureAerial.name()));
    v
}

fn distinct<T: PartialEq + Copy>(it: impl Iterator<Item = T>) -> Vec<T> {
    let mut v = Vec::new();
    for x in it {
        if !v.contains(&x) {
            v.push(x);
        }
    }
    v
}

fn summary_json(groups: &[Group]) -> Value {
    let mut out = Vec::new();
    for site in distinct(groups.iter().map(|g| g.site)) {
        for (task, objective) in distinct(groups.iter().map(|g| (g.task, g.objective))) {
            for name in all_names() {
                let Some(a) = aggregate(groups, site, task, objective, &name) else {
                    continue;
                };
                let conv: Vec<f64> = a
                    .converged
                    .iter()
                    .map(|c| c.map_or(f64::NAN, |r| r as f64))
                    .collect();
                let ms = |v: &[f64]| {
                    let (m, s) = mean_std(v);
                    json!({"mean": m, "std": s})
                };
                out.push(json!({
                    "site": site,
                    "task": task.name(),
                    "objective": objective.name(),
                    "config": name,
                    "seeds": a.rmse.len(),
                    "rmse": ms(&a.rmse),
                    "mahalanobis": ms(&a.mahal),
                    "visited_cells": ms(&a.visited),
                    "final_ratio_to_least_cost": ms(&a.ratio),
                    "last5_ratio_to_least_cost": ms(&a.ratio_last5),
                    "run1_ratio_to_least_cost": ms(&a.run1_ratio),
                    "converged_seeds": a.converged.iter().filter(|c| c.is_some()).count(),
                    "converged_run_of_converged": ms(&conv),
                }));
            }
        }
    }
    Value::Array(out)
}

fn pm(v: &[f64], digits: usize) -> String {
    let (m, s) = mean_std(v);
    if m.is_nan() {
        return "–".into();
    }
    format!("{m:.digits$} ± {s:.digits$}")
}

fn report_markdown(args: &NavigateArgs, sites: &[u64], groups: &[Group], wall_s: f64) -> String {
    let mut md = String::new();
    let nseeds = args.seeds;
    md.push_str(&format!(
        "# `004` navigation on {} (sites = world seeds {:?}, seeds {}..={}, {} runs, λ = {})\n\n",
        args.scenario,
        sites,
        args.seed,
        args.seed + nseeds - 1,
        args.runs,
        args.lambda
    ));
    md.push_str(
        "Figures are mean ± sample std over seeds. RMSE = √(mean over admissible cells of \
         (μ − f)²) and Mahalanobis D = √(Σ over admissible cells of (μ − f)²/σ²) of the model \
         after the last run against the true field f (terrain vibration, m/s²). Published: \
         `004` Table I (real data, their units), beside ours for the ordering.\n\n",
    );
    md.push_str("## Table I: model accuracy after the last run (locations A→B→C→D, vibration)\n\n");
    md.push_str("| model | site | RMSE (ours) | Mahalanobis (ours) | visited cells | RMSE / Mahal. (published) |\n|---|---|---|---|---|---|\n");
    for (k, site) in sites.iter().enumerate() {
        for (name, publ) in PUBLISHED {
            let Some(a) = aggregate(groups, *site, Task::Locations, Objective::Vibration, name)
            else {
                continue;
            };
            let p = publ
                .get(k)
                .map_or("–".into(), |(r, m)| format!("{r} / {m}"));
            md.push_str(&format!(
                "| {name} | {site} | {} | {} | {} | {p} |\n",
                pm(&a.rmse, 3),
                pm(&a.mahal, 1),
                pm(&a.visited, 1)
            ));
        }
    }
    md.push_str("\nPublished site k is compared with our k-th site; `004` also reports about 20 % fewer visited locations with the aerial image.\n\n");
    for (task, objective) in distinct(groups.iter().map(|g| (g.task, g.objective))) {
        md.push_str(&format!(
            "## {} minimising {}: experienced cost against the least-cost path\n\n",
            task.name(),
            objective.name()
        ));
        md.push_str("| config | site | run 1 / LC | run 25 / LC | last 5 / LC | converged (seeds) | converged run | visited cells | RMSE | Mahalanobis |\n|---|---|---|---|---|---|---|---|---|---|\n");
        for site in sites {
            for name in all_names() {
                let Some(a) = aggregate(groups, *site, task, objective, &name) else {
                    continue;
                };
                let conv: Vec<f64> = a.converged.iter().flatten().map(|&r| r as f64).collect();
                md.push_str(&format!(
                    "| {name} | {site} | {} | {} | {} | {}/{} | {} | {} | {} | {} |\n",
                    pm(&a.run1_ratio, 3),
                    pm(&a.ratio, 3),
                    pm(&a.ratio_last5, 3),
                    conv.len(),
                    a.converged.len(),
                    pm(&conv, 1),
                    pm(&a.visited, 1),
                    pm(&a.rmse, 3),
                    pm(&a.mahal, 1)
                ));
            }
            let sel: Vec<&Group> = groups
                .iter()
                .filter(|g| g.site == *site && g.task == task && g.objective == objective)
                .collect();
            let sp: Vec<f64> = sel
                .iter()
                .map(|g| g.shortest.1.experienced_cost / g.least_cost.1.experienced_cost)
                .collect();
            let lc: Vec<f64> = sel
                .iter()
                .map(|g| g.least_cost.1.experienced_cost)
                .collect();
            md.push_str(&format!(
                "| shortest path | {site} | {} | | | | | | | |\n| least-cost path (LC, experienced {}) | {site} | 1 | | | | | | | |\n",
                pm(&sp, 3),
                pm(&lc, 1)
            ));
        }
        md.push('\n');
    }
    md.push_str(&format!(
        "Runs within {:.0} % of LC: a configuration converges at the first run from which every \
         later run experiences at most {:.2} × the least-cost path's drive; \"converged run\" \
         averages the seeds that converged. Wall time {wall_s:.1} s.\n",
        WITHIN * 100.0,
        1.0 + WITHIN
    ));
    md
}

/// One-line summaries for the terminal.
fn summary_lines(groups: &[Group]) -> Vec<String> {
    let mut out = Vec::new();
    for site in distinct(groups.iter().map(|g| g.site)) {
        for (task, objective) in distinct(groups.iter().map(|g| (g.task, g.objective))) {
            let mut parts = Vec::new();
            for name in all_names() {
                if let Some(a) = aggregate(groups, site, task, objective, &name) {
                    let (r, _) = mean_std(&a.rmse);
                    let (q, _) = mean_std(&a.ratio);
                    let (v, _) = mean_std(&a.visited);
                    parts.push(format!(
                        "{name}: RMSE {r:.3}, run-{} cost {q:.3}×LC, {v:.0} cells",
                        groups[0].configs.first().map_or(0, |c| c.1.runs.len())
                    ));
                }
            }
            out.push(format!(
                "site {site} {} {}: {}",
                task.name(),
                objective.name(),
                parts.join("; ")
            ));
        }
    }
    out
}

/// Colours of the configurations in figures.
fn config_color(c: &Config) -> [u8; 3] {
    match (c.model, c.rectifier) {
        (ModelKind::SingleGp, _) => [230, 85, 13],
        (ModelKind::GpMixture, _) => [117, 107, 177],
        (ModelKind::GpMixtureAerial, Rectifier::Softplus) => [0, 200, 255],
        (ModelKind::GpMixtureAerial, Rectifier::Relu) => [255, 0, 200],
    }
}

const SHORTEST: [u8; 3] = [255, 40, 40];
const LEAST: [u8; 3] = [255, 255, 255];

fn file_stem(g: &Group, c: &Config) -> String {
    format!(
        "{}_{}_{}{}",
        g.task.name(),
        g.objective.name(),
        c.model.name(),
        if c.rectifier == Rectifier::Relu {
            "_relu"
        } else {
            ""
        }
    )
}

/// Figures of the first site and seed: the aerial image with the final paths, the true fields,
/// each model's final mean and σ with its visited cells, and experienced cost per run.
fn write_figures(site: &Site, groups: &[Group], out: &Path) -> Result<()> {
    let map = &site.map;
    let (rect, d) = (map.rect(), map.cell_size());
    let scale = Canvas::auto_scale(rect, 900);
    let Some(g0) = groups.first() else {
        return Ok(());
    };
    let colors: Vec<Option<Rgb8>> = map
        .aerial()
        .map(|a| a.iter().map(|&c| Some(c)).collect())
        .unwrap_or_else(|| vec![None; rect.len()]);
    let line = (scale as i64 / 3).max(1);
    let mut terrain = Canvas::new(rect, d, scale);
    terrain.fill(|k| Some(palette(site.scenario.world.terrain[k] as usize)));
    terrain.save(&out.join("terrain.png"))?;
    for g in groups
        .iter()
        .filter(|g| g.site == g0.site && g.seed == g0.seed)
    {
        let stem = format!("{}_{}", g.task.name(), g.objective.name());
        let truth = true_field(&site.scenario, g.objective);
        let t32: Vec<f32> = truth.iter().map(|&v| v as f32).collect();
        let (tc, range) = scalar_canvas(rect, d, scale, &t32, None);
        tc.save(&out.join(format!("truth_{}.png", g.objective.name())))?;
        let mut paths = rgb_canvas(rect, d, scale, &colors);
        let to_pts =
            |p: &[Vec<Cell>]| -> Vec<Point2> { p.iter().flatten().map(|c| c.center(d)).collect() };
        paths.polyline(&to_pts(&g.shortest.2), SHORTEST, line);
        paths.polyline(&to_pts(&g.least_cost.2), LEAST, line);
        for (c, log, _) in &g.configs {
            if let Some(r) = log.runs.last() {
                paths.polyline(&to_pts(&r.planned), config_color(c), line);
            }
            // Final model: mean (the truth's colour range), σ, visited cells.
            if let Some(f) = log.fields.last() {
                let (mc, _) = scalar_canvas(rect, d, scale, &f.mean, Some(range));
                mc.save(&out.join(format!("{}_mean.png", file_stem(g, c))))?;
                let (mut sc, _) = scalar_canvas(rect, d, scale, &f.std, None);
                for &(k, _) in &log.visited {
                    sc.marker(rect.cell(k).center(d), [255, 255, 255], 0);
                }
                sc.save(&out.join(format!("{}_std.png", file_stem(g, c))))?;
            }
        }
        for p in task_points(site, g.task) {
            paths.marker(*p, [255, 255, 0], (scale as i64).max(3));
        }
        paths.save(&out.join(format!("{stem}_paths.png")))?;
        cost_chart(g)?.save(&out.join(format!("{stem}_cost_per_run.png")))?;
    }
    Ok(())
}

/// Experienced cost per run for every configuration (coloured as in the path figure), with the
/// shortest (red) and least-cost (dark grey) drives as horizontal lines; y from 0.
fn cost_chart(g: &Group) -> Result<Canvas> {
    let series: Vec<(Vec<f64>, [u8; 3])> = g
        .configs
        .iter()
        .map(|(cfg, log, _)| (costs(log), config_color(cfg)))
        .collect();
    let hlines = [
        (g.shortest.1.experienced_cost, SHORTEST),
        (g.least_cost.1.experienced_cost, [40, 40, 40]),
    ];
    Ok(line_chart(&series, &hlines, "RUN", ""))
}
