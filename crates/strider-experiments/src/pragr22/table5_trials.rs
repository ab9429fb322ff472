//! The trials of the Prágr22 Table 5 bench: which experiments to run, and running them side by
//! side on a thread pool.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result};
use rayon::prelude::*;
use serde::Serialize;
use strider_explore::Strategy;
use strider_explore::evaluate::NavigationMode;

use crate::parallel::pool;
use crate::progress::Progress;
use crate::stats::median_max;
use crate::trial::{TrialRecord, load, mission_params, run_mission, run_tours};

/// Options of `strider bench table5` (the first fields of `table5.json`).
#[derive(Clone, Debug, Serialize)]
pub struct Table5Options {
    /// Trials per row of the small world.
    pub trials: usize,
    /// Trials per row of the large world.
    pub large_trials: usize,
    /// Number of random worlds the trials cycle through.
    pub world_seeds: u64,
    /// Parallel trials.
    pub jobs: usize,
    /// Mission time limit override, simulated seconds.
    #[serde(rename = "time_limit_s")]
    pub time_limit: Option<f64>,
    /// Record every trial's mission to `DIR/<scenario>-<strategy>-w<world>-s<seed>.mcap`.
    #[serde(skip)]
    pub mcap_dir: Option<PathBuf>,
}

/// One experiment to run: a world, a strategy, a seed, and which tour modes to drive after.
#[derive(Clone, Debug)]
pub(crate) struct Task {
    scenario: &'static str,
    strategy: Strategy,
    world_seed: u64,
    seed: u64,
    modes: Vec<NavigationMode>,
}

/// What one trial measured.
#[derive(Clone, Debug, Serialize)]
pub struct TrialResult {
    /// Where it ran and how the exploration ended.
    #[serde(flatten)]
    pub trial: TrialRecord,
    /// Per benchmark tour (scenario order) and navigation mode: (tour, mode, total_s,
    /// completed).
    pub tours: Vec<Vec<(String, String, f64, bool)>>,
    /// Median replan latency, ms.
    pub replan_ms_median: f64,
    /// Worst replan latency, ms.
    pub replan_ms_max: f64,
    /// Wall time of the trial, s.
    pub wall_s: f64,
}

impl TrialResult {
    /// (total_s, completed) of the scenario's `index`-th tour driven in `mode`.
    pub(crate) fn tour(&self, index: usize, mode: NavigationMode) -> Option<(f64, bool)> {
        self.tours
            .get(index)?
            .iter()
            .find(|t| t.1 == mode.name())
            .map(|t| (t.2, t.3))
    }
}

/// Every trial of the table, longest first (large worlds), so the pool does not end on one
/// long trial.
pub(crate) fn tasks(o: &Table5Options) -> Vec<Task> {
    let task = |scenario, strategy, i: usize, modes: &[NavigationMode]| Task {
        scenario,
        strategy,
        world_seed: 1 + (i as u64 % o.world_seeds),
        seed: 1 + i as u64,
        modes: modes.to_vec(),
    };
    let mut tasks = Vec::new();
    for i in 0..o.trials {
        tasks.push(task(
            "courtyard-small",
            Strategy::Gtsp,
            i,
            &NavigationMode::ALL,
        ));
        tasks.push(task("courtyard-small", Strategy::Greedy, i, &[]));
    }
    for i in 0..o.large_trials {
        for strategy in [Strategy::Gtsp, Strategy::SpatialOnly] {
            tasks.push(task(
                "courtyard-large",
                strategy,
                i,
                &[NavigationMode::Learned],
            ));
        }
    }
    tasks.sort_by_key(|t| (t.scenario != "courtyard-large", t.seed));
    tasks
}

/// Runs the trials on `o.jobs` threads; the results sorted by scenario, strategy and seed.
pub(crate) fn run_trials(
    o: &Table5Options,
    tasks: &[Task],
    progress: &dyn Progress,
) -> Result<Vec<TrialResult>> {
    let results: Vec<Result<TrialResult>> = pool(o.jobs)?.install(|| {
        tasks
            .par_iter()
            .with_max_len(1)
            .map(|t| {
                let r = run_task(t, o.time_limit, o.mcap_dir.as_deref()).with_context(|| {
                    format!(
                        "trial {} {} world seed {} seed {}",
                        t.scenario,
                        t.strategy.name(),
                        t.world_seed,
                        t.seed
                    )
                });
                progress.inc();
                r
            })
            .collect()
    });
    let mut trials = results.into_iter().collect::<Result<Vec<_>>>()?;
    trials.sort_by(|a, b| {
        let (a, b) = (&a.trial, &b.trial);
        (&a.scenario, &a.strategy, a.seed).cmp(&(&b.scenario, &b.strategy, b.seed))
    });
    Ok(trials)
}

fn run_task(task: &Task, time_limit: Option<f64>, mcap_dir: Option<&Path>) -> Result<TrialResult> {
    let wall = Instant::now();
    let sc = load(task.scenario, task.world_seed)?;
    let mut params = mission_params(&sc, task.strategy, task.seed)?;
    if let Some(t) = time_limit {
        params.time_limit_s = t;
    }
    let file = mcap_dir.map(|dir| {
        dir.join(format!(
            "{}-{}-w{}-s{}.mcap",
            task.scenario,
            task.strategy.name(),
            task.world_seed,
            task.seed
        ))
    });
    let (mission, log, _) = run_mission(&sc, params, task.seed, file.as_deref(), |_| {})?;
    let tours = if task.modes.is_empty() {
        Vec::new()
    } else {
        run_tours(&sc, &mission, task.seed, &task.modes, |_, _| {})?
    };
    let (replan_ms_median, replan_ms_max) = median_max(&log.replan_ms);
    Ok(TrialResult {
        trial: TrialRecord::of(
            task.scenario,
            task.strategy.name(),
            (task.world_seed, task.seed),
            &mission,
        ),
        tours: tours
            .iter()
            .map(|(name, rs)| {
                rs.iter()
                    .map(|r| {
                        (
                            name.clone(),
                            r.mode.name().to_string(),
                            r.total_s,
                            r.completed,
                        )
                    })
                    .collect()
            })
            .collect(),
        replan_ms_median,
        replan_ms_max,
        wall_s: wall.elapsed().as_secs_f64(),
    })
}
