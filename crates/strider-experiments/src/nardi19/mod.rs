//! Nardi19 (Nardi & Stachniss, ICRA 2019): repeated navigation that learns a place-dependent
//! model of vibration or energy and plans with its lower confidence bound (`strider navigate`).
//!
//! For every site (world seed) and mission seed it runs two experiments in the simulator:
//!
//! * **start-goal** (Nardi19 §VI-B): the scenario's `start-goal` task driven `runs` times per
//!   objective (vibration, energy) with each model (`single-gp`, `gp-mixture`,
//!   `gp-mixture-aerial`, softplus LCB) and the aerial mixture with the ReLU LCB; beside them the
//!   shortest path and the least-cost path on the true field, each driven once.
//! * **locations** (Nardi19 §VI-C, Table I): the `locations` tour A → B → C → D driven `runs`
//!   times minimising vibration with each model (softplus); the final model's RMS error and
//!   Mahalanobis distance against the true field.
//!
//! The robot only sees the grid map (ground-truth admissibility: the paper's 𝓜) and the aerial
//! image (the world's colour layer, or a given PNG); the true field (the terrain table's
//! vibration or energy per metre of every cell) is used here only to evaluate and to plan the
//! least-cost baseline. Writes `navigate.json`, `navigate.md` and PNG figures.
//!
//! Aggregation: RMSE = √(mean over admissible cells of (μ − f)²); Mahalanobis distance
//! D = √(Σ over admissible cells of (μ − f)² / σ²) with σ² the mixture's latent variance
//! (Eq. 3, floored at 10⁻¹²); both for the model after the last run, then mean ± sample std
//! over seeds per site. A configuration "converges" at the first run r from which every run
//! r … N experiences at most 1.1 × the cost the least-cost path experienced.

mod figures;
mod lambdas;
mod metrics;
mod report;
mod site;

use std::fmt;
use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result, bail};
use rayon::prelude::*;
use strider_explore::navigate::{ModelKind, NavigateParams, NavigationLog, Objective, navigate};
use strider_plan::grid::lcb::{LcbParams, Rectifier};
use strider_sim::Simulator;

use crate::io::{create_dir, write_json, write_text};
use crate::parallel::pool;
use crate::progress::Progress;
pub use lambdas::sweep_lambdas;
pub use report::NavigateReport;
use site::{Baseline, Site, baseline, max_speed, scenario_at, task_points, true_field};

/// Options of `strider navigate`.
#[derive(Clone, Debug)]
pub struct NavigateOptions {
    /// Built-in scenario name or scenario file.
    pub scenario: String,
    /// First mission seed.
    pub seed: u64,
    /// Output directory.
    pub out: PathBuf,
    /// Sites: world seeds of the scenario family.
    pub sites: Vec<u64>,
    /// Consecutive seeds per site, from `seed`.
    pub seeds: u64,
    /// Runs per task (Nardi19: 25).
    pub runs: usize,
    /// Objectives of the start-goal experiment.
    pub objectives: Vec<Objective>,
    /// λ of the lower confidence bound μ − λσ (decision 26).
    pub lambda: f64,
    /// An aerial image (8-bit RGB PNG, north up, one pixel per grid cell) replacing the
    /// scenario's colour layer.
    pub aerial: Option<PathBuf>,
    /// Navigations run in parallel.
    pub jobs: usize,
}

/// Relative tolerance of "experiences about what the least-cost path experiences".
pub(crate) const WITHIN: f64 = 0.10;

/// One navigation to run: task, objective, model, rectifier.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Config {
    pub(crate) task: Task,
    pub(crate) objective: Objective,
    pub(crate) model: ModelKind,
    pub(crate) rectifier: Rectifier,
}

/// The two experiments.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Task {
    StartGoal,
    Locations,
}

impl Task {
    pub(crate) fn name(self) -> &'static str {
        match self {
            Task::StartGoal => "start-goal",
            Task::Locations => "locations",
        }
    }
}

/// A navigation's configuration, its log and (RMSE, Mahalanobis) after each run.
pub(crate) type ConfigResult = (Config, NavigationLog, Vec<(f64, f64)>);

/// Result of one (site, seed, task, objective) group.
pub(crate) struct Group {
    pub(crate) site: u64,
    pub(crate) seed: u64,
    pub(crate) task: Task,
    pub(crate) objective: Objective,
    pub(crate) shortest: Baseline,
    pub(crate) least_cost: Baseline,
    pub(crate) configs: Vec<ConfigResult>,
}

/// A (site index, seed, task, objective) group to run.
type Job = (usize, u64, Task, Objective);

/// The finished experiment; its `Display` is the summary for the terminal.
pub struct Navigation {
    navigations: usize,
    runs: usize,
    sites: usize,
    seeds: u64,
    wall_s: f64,
    out: PathBuf,
    lines: Vec<String>,
}

impl fmt::Display for Navigation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "navigate: {} navigations of {} runs on {} site(s) × {} seed(s) in {:.1} s; wrote {}",
            self.navigations,
            self.runs,
            self.sites,
            self.seeds,
            self.wall_s,
            self.out.display()
        )?;
        for line in &self.lines {
            write!(f, "\n  {line}")?;
        }
        Ok(())
    }
}

impl NavigateOptions {
    /// The command that reproduces the experiment.
    pub fn command(&self) -> String {
        let list = |v: Vec<String>| v.join(",");
        let aerial = self
            .aerial
            .as_ref()
            .map_or(String::new(), |p| format!(" --aerial {}", p.display()));
        format!(
            "strider navigate --scenario {} --sites {} --seed {} --seeds {} --runs {} --objectives {} --lambda {}{aerial}",
            self.scenario,
            list(self.sites.iter().map(|s| s.to_string()).collect()),
            self.seed,
            self.seeds,
            self.runs,
            list(
                self.objectives
                    .iter()
                    .map(|o| o.name().to_string())
                    .collect()
            ),
            self.lambda
        )
    }
}

/// The most runs per task (`--runs`; Nardi19: 25). Each run is a drive of the task and a refit
/// of the model on everything observed so far.
pub const MAX_RUNS: usize = 1000;

/// The most mission seeds per site (`--seeds`; the acceptance sweep uses 10).
pub const MAX_SEEDS: u64 = 1000;

/// The most sites (`--sites`); each holds its scenario, grid map and true fields in memory.
pub const MAX_SITES: usize = 100;

/// The largest λ of the lower confidence bound μ − λσ (`--lambda`; decision 26 uses 1): beyond
/// a few σ the bound ignores the mean altogether.
pub const MAX_LAMBDA: f64 = 100.0;

/// The most memory the navigations' model fields may take, bytes (4 GiB). Every navigation
/// keeps its model after every run (μ and σ per grid cell, 8 bytes) for the accuracy curves
/// and the figures, so this grows with navigations × runs × cells.
pub const MAX_FIELD_BYTES: u64 = 4 << 30;

fn check(o: &NavigateOptions) -> Result<()> {
    if !(1..=MAX_RUNS).contains(&o.runs) {
        bail!("--runs {}: must be an integer from 1 to {MAX_RUNS}", o.runs);
    }
    crate::trial::check_seed_range(o.seed, o.seeds, MAX_SEEDS)?;
    if !(o.lambda.is_finite() && (0.0..=MAX_LAMBDA).contains(&o.lambda)) {
        bail!(
            "--lambda {}: must be a finite number from 0 to {MAX_LAMBDA}",
            o.lambda
        );
    }
    if o.sites.is_empty() || o.objectives.is_empty() {
        bail!("give at least one site and one objective");
    }
    if o.sites.len() > MAX_SITES {
        bail!("--sites lists {} sites: at most {MAX_SITES}", o.sites.len());
    }
    Ok(())
}

/// Checks that every site's terrains carry the signal of every objective the experiments
/// minimise (a field of zeros would be learnt as zero everywhere, and every cost ratio would
/// be 0/0).
fn check_signals(o: &NavigateOptions, sites: &[Site]) -> Result<()> {
    for site in sites {
        for (task, _) in &site.tasks {
            for &objective in objectives(o, *task) {
                if provides(&site.scenario, objective) {
                    continue;
                }
                let has: Vec<&str> = [Objective::Vibration, Objective::Energy]
                    .into_iter()
                    .filter(|&ob| provides(&site.scenario, ob))
                    .map(Objective::name)
                    .collect();
                let what = match task {
                    Task::StartGoal => format!("--objectives {}", objective.name()),
                    Task::Locations => "the locations task (minimises vibration)".to_string(),
                };
                bail!(
                    "{what}: scenario {} (world seed {}) has no {} signal (its terrains' `{}` is 0 or not a finite non-negative number everywhere); it provides {}",
                    site.scenario.name,
                    site.world_seed,
                    objective.name(),
                    field_key(objective),
                    if has.is_empty() {
                        "neither vibration nor energy".to_string()
                    } else {
                        has.join(", ")
                    }
                );
            }
        }
    }
    Ok(())
}

/// The objectives the experiment `task` minimises.
fn objectives(o: &NavigateOptions, task: Task) -> &[Objective] {
    match task {
        Task::StartGoal => &o.objectives,
        Task::Locations => &[Objective::Vibration],
    }
}

/// The terrain key of an objective's true field.
fn field_key(objective: Objective) -> &'static str {
    match objective {
        Objective::Vibration => "vibration",
        Objective::Energy => "energy_per_m",
    }
}

/// Whether the scenario's world carries `objective`: its true field finite and non-negative
/// on every cell and positive somewhere.
fn provides(sc: &strider_scenario::Scenario, objective: Objective) -> bool {
    let f = true_field(sc, objective);
    f.iter().all(|v| v.is_finite() && *v >= 0.0) && f.iter().any(|&v| v > 0.0)
}

/// Checks the memory the model fields of `navigations` navigations will keep.
fn check_memory(o: &NavigateOptions, navigations: usize, sites: &[Site]) -> Result<()> {
    let cells = sites.iter().map(|s| s.map.rect().len()).max().unwrap_or(0);
    let bytes = [navigations, o.runs, cells, 8]
        .into_iter()
        .try_fold(1u64, |acc, n| acc.checked_mul(u64::try_from(n).ok()?));
    if bytes.is_none_or(|b| b > MAX_FIELD_BYTES) {
        bail!(
            "{navigations} navigations × --runs {} × {cells} cells would keep more than {} GiB of model fields: use fewer --runs, --seeds, --sites or --objectives",
            o.runs,
            MAX_FIELD_BYTES >> 30
        );
    }
    Ok(())
}

/// Runs `strider navigate`; `progress` counts the runs.
pub fn run(o: &NavigateOptions, progress: &dyn Progress) -> Result<Navigation> {
    run_groups(o, progress).map(|(n, _)| n)
}

/// [`run`], also returning every group's results.
fn run_groups(o: &NavigateOptions, progress: &dyn Progress) -> Result<(Navigation, Vec<Group>)> {
    let wall = Instant::now();
    check(o)?;
    let aerial_png = o.aerial.as_deref().map(site::read_png).transpose()?;
    let sites = o
        .sites
        .iter()
        .map(|&ws| site::prepare(&o.scenario, ws, aerial_png.as_ref(), o.aerial.as_deref()))
        .collect::<Result<Vec<Site>>>()?;
    check_signals(o, &sites)?;
    let jobs = jobs(o, &sites);
    let units: Vec<(usize, Config)> = jobs
        .iter()
        .enumerate()
        .flat_map(|(g, &(_, _, task, objective))| {
            configs(task, objective).into_iter().map(move |c| (g, c))
        })
        .collect();
    check_memory(o, units.len(), &sites)?;
    create_dir(&o.out)?;
    progress.start((units.len() * o.runs) as u64);
    let logs = navigate_all(o, &sites, &jobs, &units, progress);
    let groups = groups(&sites, &jobs, &units, logs)?;
    figures::write_figures(&sites[0], &groups, &o.out)?;
    let wall_s = wall.elapsed().as_secs_f64();
    write_json(
        &o.out.join("navigate.json"),
        &NavigateReport::new(o, &groups, wall_s),
    )?;
    write_text(
        &o.out.join("navigate.md"),
        &report::markdown(o, &groups, wall_s),
    )?;
    let done = Navigation {
        navigations: units.len(),
        runs: o.runs,
        sites: o.sites.len(),
        seeds: o.seeds,
        wall_s,
        out: o.out.clone(),
        lines: report::summary_lines(&groups),
    };
    Ok((done, groups))
}

/// Every (site, seed, task, objective) group.
fn jobs(o: &NavigateOptions, sites: &[Site]) -> Vec<Job> {
    let mut jobs = Vec::new();
    for (si, site) in sites.iter().enumerate() {
        for seed in o.seed..=o.seed + (o.seeds - 1) {
            for (task, _) in &site.tasks {
                for &objective in objectives(o, *task) {
                    jobs.push((si, seed, *task, objective));
                }
            }
        }
    }
    jobs
}

/// Every navigation of `units` on `o.jobs` threads, in order.
fn navigate_all(
    o: &NavigateOptions,
    sites: &[Site],
    jobs: &[Job],
    units: &[(usize, Config)],
    progress: &dyn Progress,
) -> Result<Vec<Result<NavigationLog>>> {
    let base = NavigateParams {
        lcb: LcbParams {
            lambda: o.lambda,
            ..LcbParams::default()
        },
        runs: o.runs,
        ..NavigateParams::default()
    };
    Ok(pool(o.jobs)?.install(|| {
        units
            .par_iter()
            .map(|&(g, c)| {
                let (si, seed, _, _) = jobs[g];
                navigate_one(&sites[si], seed, c, &base, progress)
            })
            .collect()
    }))
}

fn navigate_one(
    site: &Site,
    seed: u64,
    c: Config,
    base: &NavigateParams,
    progress: &dyn Progress,
) -> Result<NavigationLog> {
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
    navigate(
        &site.map,
        task,
        &params,
        |run| Simulator::new(&sc, sim_seed(seed, run)),
        |_| progress.inc(),
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
    })
}

/// The groups with their baselines and the navigations' accuracy after every run.
fn groups(
    sites: &[Site],
    jobs: &[Job],
    units: &[(usize, Config)],
    logs: Result<Vec<Result<NavigationLog>>>,
) -> Result<Vec<Group>> {
    let mut logs = logs?.into_iter();
    let mut groups = Vec::new();
    for (g, &(si, seed, task, objective)) in jobs.iter().enumerate() {
        let site = &sites[si];
        let truth = true_field(&site.scenario, objective);
        let points = task_points(site, task);
        let shortest = baseline(site, points, objective, baseline_seed(seed), None)?;
        let least_cost = baseline(site, points, objective, baseline_seed(seed), Some(&truth))?;
        let mut configs = Vec::new();
        for &(_, c) in units.iter().filter(|(ug, _)| *ug == g) {
            let log = logs.next().context("missing navigation result")??;
            let accuracy: Vec<(f64, f64)> = log
                .fields
                .iter()
                .map(|f| metrics::accuracy(f, &truth, site.map.admissible()))
                .collect();
            configs.push((c, log, accuracy));
        }
        groups.push(Group {
            site: site.world_seed,
            seed,
            task,
            objective,
            shortest,
            least_cost,
            configs,
        });
    }
    Ok(groups)
}

/// The configurations of one group: every model with softplus, and for start-goal also the
/// aerial mixture with ReLU (Nardi19 Fig. 3 compares the rectifiers on the proposed model).
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
