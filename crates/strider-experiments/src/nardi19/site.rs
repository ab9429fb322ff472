//! A Nardi19 site: the scenario of one world seed, the navigation inputs the robot sees (grid
//! map, aerial image, tasks), the true fields, and the shortest and least-cost baselines.

use std::path::Path;

use anyhow::{Context, Result, bail};
use strider_core::{Cell, Point2, Pose2, Rgb8};
use strider_explore::navigate::{
    DriveResult, NavigateParams, NavigationMap, Objective, drive_task, task_cells,
};
use strider_plan::grid::lcb::{LcbParams, Rectifier, lcb_grid, lcb_path};
use strider_plan::grid::{CostGrid, Dijkstra};
use strider_scenario::Scenario;
use strider_sim::Simulator;

use super::Task;
use crate::trial::load;

/// Everything one site needs: the scenario, the navigation inputs and the true fields.
pub(crate) struct Site {
    pub(crate) world_seed: u64,
    pub(crate) scenario: Scenario,
    pub(crate) map: NavigationMap,
    pub(crate) tasks: Vec<(Task, Vec<Point2>)>,
}

/// A baseline: planned cost (metres for the shortest path, ∫ f ds for the least-cost one),
/// what driving it measured, and its cell paths.
pub(crate) type Baseline = (f64, DriveResult, Vec<Vec<Cell>>);

/// An aerial image: width, height and pixels, rows north first.
pub(crate) type Png = (u32, u32, Vec<Rgb8>);

/// Reads an 8-bit RGB(A) PNG as (width, height, rows north first).
pub(crate) fn read_png(path: &Path) -> Result<Png> {
    let img = image::open(path)
        .with_context(|| format!("{}: cannot read the aerial image", path.display()))?
        .to_rgb8();
    let (w, h) = img.dimensions();
    let px = img.pixels().map(|p| Rgb8(p.0)).collect();
    Ok((w, h, px))
}

/// Loads a site: the scenario, its grid map (ground-truth admissibility), the aerial image
/// (the colour layer or the given PNG `aerial_png` read from `aerial_file`, which must match
/// the grid) and the tasks.
pub(crate) fn prepare(
    name: &str,
    world_seed: u64,
    aerial_png: Option<&Png>,
    aerial_file: Option<&Path>,
) -> Result<Site> {
    let sc = load(name, world_seed)?;
    let w = &sc.world;
    if sc.robot.gaits.is_empty() {
        bail!("{}: the robot profile has no gait", sc.name);
    }
    let aerial = match aerial_png {
        None => w.color.clone(),
        Some(png) => aerial_layer(&sc, png, aerial_file)?,
    };
    let admissible = w.gt_admissible(sc.map.rho_obstacle, sc.map.r_robot);
    let map = NavigationMap::new(w.rect, w.resolution, admissible, Some(aerial))?;
    let tasks = tasks(&sc, &map)?;
    Ok(Site {
        world_seed,
        scenario: sc,
        map,
        tasks,
    })
}

/// The aerial image as the grid's colour layer.
fn aerial_layer(sc: &Scenario, (iw, ih, px): &Png, file: Option<&Path>) -> Result<Vec<Rgb8>> {
    let w = &sc.world;
    if (*iw, *ih) != (w.rect.width, w.rect.height) {
        bail!(
            "aerial image {} is {iw}×{ih} pixels but the grid map of {} is {}×{} cells",
            file.unwrap_or(Path::new("?")).display(),
            sc.name,
            w.rect.width,
            w.rect.height
        );
    }
    // PNG rows run north to south; the lattice's row 0 is the southernmost.
    let (iw, ih) = (*iw as usize, *ih as usize);
    Ok((0..iw * ih)
        .map(|k| px[(ih - 1 - k / iw) * iw + k % iw])
        .collect())
}

/// The scenario's tasks (`start-goal`, or its first tour, and `locations` if it has one),
/// checked reachable on the grid map so that a bad task fails before any run.
fn tasks(sc: &Scenario, map: &NavigationMap) -> Result<Vec<(Task, Vec<Point2>)>> {
    let w = &sc.world;
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
    let grid = CostGrid::new(
        w.rect,
        w.resolution,
        map.admissible()
            .iter()
            .map(|&a| if a { 1.0 } else { f32::INFINITY })
            .collect(),
    )?;
    let mut dij = Dijkstra::new();
    for (task, pts) in &tasks {
        if pts.len() < 2 {
            bail!(
                "{}: tour {} needs a start and at least one goal",
                sc.name,
                task.name()
            );
        }
        let cells =
            task_cells(map, pts).with_context(|| format!("{}: tour {}", sc.name, task.name()))?;
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
    Ok(tasks)
}

pub(crate) fn task_points(site: &Site, task: Task) -> &[Point2] {
    site.tasks
        .iter()
        .find(|(t, _)| *t == task)
        .map(|(_, p)| p.as_slice())
        .unwrap_or(&[])
}

/// The robot's top speed (its fastest gait).
pub(crate) fn max_speed(sc: &Scenario) -> f64 {
    sc.robot
        .gaits
        .iter()
        .map(|g| g.max_speed)
        .fold(0.0, f64::max)
        .max(1e-3)
}

/// The scenario with the robot standing at the task's start, facing its first goal.
pub(crate) fn scenario_at(sc: &Scenario, task: &[Point2]) -> Scenario {
    let mut s = sc.clone();
    let (a, b) = (task[0], task[1]);
    s.start = Pose2::new(a.x, a.y, (b.y - a.y).atan2(b.x - a.x));
    s
}

/// The true field f per cell: the terrain table's vibration or energy per metre.
pub(crate) fn true_field(sc: &Scenario, objective: Objective) -> Vec<f64> {
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
/// the true field, both charged per entered cell like Eq. 7, driven with simulator seed
/// `seed`. Returns the planned cost (length in metres, or ∫ f ds), the drive and the paths.
pub(crate) fn baseline(
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
    let mut robot = Simulator::new(&sc, seed)?;
    let params = NavigateParams {
        objective,
        max_speed: max_speed(&site.scenario),
        ..NavigateParams::default()
    };
    let drive = drive_task(&mut robot, map, objective, &paths, &params)?;
    Ok((planned, drive, paths))
}
