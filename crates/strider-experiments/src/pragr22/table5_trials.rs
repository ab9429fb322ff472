//! The trials of the Prágr22 Table 5 bench: which experiments to run, and running them side by
//! side on a thread pool.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use strider_explore::Strategy;
use strider_explore::evaluate::NavigationMode;

use crate::cancel::Cancel;
use crate::compare::Shard;
use crate::journal::{Journal, Kept};
use crate::parallel::pool;
use crate::progress::Progress;
use crate::stats::median_max;
use crate::trial::{TrialRecord, load, mission_params_with, run_mission, run_tours};

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
    /// Reuse the trials an earlier run with the same options finished (`OUT/trials`) and run
    /// only the missing ones; without it, earlier trial files are removed first.
    #[serde(skip)]
    pub resume: bool,
    /// Stops the bench early: running trials stop, finished ones are kept.
    #[serde(skip)]
    pub cancel: Cancel,
    /// Run only this shard of the trials (`--shard K/N`); `strider bench merge` joins the
    /// shards' folders into the whole table.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub shard: Option<Shard>,
    /// Strategy parameters set for every trial (`--set KEY=VALUE`, e.g. for ablations),
    /// over the scenarios' `[strategy.<name>]` sections.
    #[serde(rename = "set", skip_serializing_if = "Vec::is_empty")]
    pub sets: Vec<(String, String)>,
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
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct TrialResult {
    /// Where it ran and how the exploration ended.
    #[serde(flatten)]
    pub trial: TrialRecord,
    /// Per benchmark tour (scenario order) and navigation mode: (tour, mode, total_s,
    /// completed).
    pub tours: Vec<Vec<(String, String, f64, bool)>>,
    /// Per benchmark tour and navigation mode, in the order of `tours`: the time of each
    /// segment (start → waypoint 1, waypoint 1 → 2, …), s. Empty in trials kept by a build
    /// that did not record them.
    #[serde(default)]
    pub segments_s: Vec<Vec<Vec<f64>>>,
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

    /// The segment times of the scenario's `index`-th tour driven in `mode`, s (`None` when
    /// the trial did not record them).
    pub(crate) fn segments(&self, index: usize, mode: NavigationMode) -> Option<&[f64]> {
        let k = self
            .tours
            .get(index)?
            .iter()
            .position(|t| t.1 == mode.name())?;
        self.segments_s.get(index)?.get(k).map(Vec::as_slice)
    }
}

/// Every trial of the table (of its shard, with `o.shard`), longest first (large worlds), so
/// the pool does not end on one long trial.
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
    match o.shard {
        Some(s) => tasks
            .into_iter()
            .enumerate()
            .filter(|(i, _)| s.owns(*i))
            .map(|(_, t)| t)
            .collect(),
        None => tasks,
    }
}

impl Task {
    /// The trial's name in the journal and in errors.
    fn key(&self) -> String {
        format!(
            "{}-{}-w{}-s{}",
            self.scenario,
            self.strategy.name(),
            self.world_seed,
            self.seed
        )
    }
}

/// What else than its task decides a trial's result (the journal's setting).
pub(crate) fn setting(o: &Table5Options) -> serde_json::Value {
    if o.sets.is_empty() {
        serde_json::json!({ "bench": "table5", "time_limit_s": o.time_limit })
    } else {
        serde_json::json!({ "bench": "table5", "time_limit_s": o.time_limit, "set": o.sets })
    }
}

/// The trials of `tasks` an earlier run kept in `journal` (when resuming), and the tasks left.
pub(crate) fn kept<'a>(
    o: &Table5Options,
    tasks: &'a [Task],
    journal: &Journal,
    progress: &dyn Progress,
) -> Result<(Vec<TrialResult>, Vec<&'a Task>)> {
    let (mut done, mut todo) = (Vec::new(), Vec::new());
    for t in tasks {
        if !o.resume {
            todo.push(t);
            continue;
        }
        match journal.load::<TrialResult>(&t.key())? {
            Kept::Trial(r) => done.push(r),
            Kept::Missing(why) => {
                if let Some(why) = why {
                    progress.warn(&format!("running trial {} again: {why}", t.key()));
                }
                todo.push(t);
            }
        }
    }
    Ok((done, todo))
}

/// Runs the trials on `o.jobs` threads, keeping each in `journal` as it finishes, until they
/// are done or `o.cancel` is requested; returns the finished ones (an interrupted trial is
/// not one). A failed trial is an error once the others are done (they are kept).
pub(crate) fn run_trials(
    o: &Table5Options,
    tasks: &[&Task],
    journal: &Journal,
    progress: &dyn Progress,
) -> Result<Vec<TrialResult>> {
    let results: Vec<Result<Option<TrialResult>>> = pool(o.jobs)?.install(|| {
        tasks
            .par_iter()
            .with_max_len(1)
            .map(|t| -> Result<Option<TrialResult>> {
                if o.cancel.requested() {
                    return Ok(None);
                }
                let r = run_task(t, o).with_context(|| format!("trial {}", t.key()))?;
                if let Some(r) = &r {
                    journal.save(&t.key(), r)?;
                    progress.inc();
                }
                Ok(r)
            })
            .collect()
    });
    let mut trials = Vec::new();
    for r in results {
        trials.extend(r?);
    }
    Ok(trials)
}

/// Sorts trials by scenario, strategy and seed (the report's order).
pub(crate) fn sort(trials: &mut [TrialResult]) {
    trials.sort_by(|a, b| {
        let (a, b) = (&a.trial, &b.trial);
        (&a.scenario, &a.strategy, a.seed).cmp(&(&b.scenario, &b.strategy, b.seed))
    });
}

/// One trial; `None` when it was interrupted.
pub(crate) fn run_task(task: &Task, o: &Table5Options) -> Result<Option<TrialResult>> {
    let wall = Instant::now();
    let sc = load(task.scenario, task.world_seed)?;
    let mut params = mission_params_with(&sc, task.strategy, task.seed, &o.sets)?;
    if let Some(t) = o.time_limit {
        params.time_limit_s = t;
    }
    let file = o
        .mcap_dir
        .as_deref()
        .map(|dir| dir.join(format!("{}.mcap", task.key())));
    let watch = (file.as_deref(), &o.cancel);
    let (mission, log, _) = run_mission(&sc, params, task.seed, watch, |_| {})?;
    if mission.interrupted() {
        return Ok(None);
    }
    let tours = if task.modes.is_empty() {
        Vec::new()
    } else {
        run_tours(&sc, &mission, task.seed, &task.modes, |_, _| {})?
    };
    let (replan_ms_median, replan_ms_max) = median_max(&log.replan_ms);
    Ok(Some(TrialResult {
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
        segments_s: tours
            .iter()
            .map(|(_, rs)| {
                rs.iter()
                    .map(|r| r.segments.iter().map(|s| s.time_s).collect())
                    .collect()
            })
            .collect(),
        replan_ms_median,
        replan_ms_max,
        wall_s: wall.elapsed().as_secs_f64(),
    }))
}
