//! `strider bench compare`: strategies from different papers on the same worlds.
//!
//! Per scenario × strategy × trial (world seed 1 + (i mod K), mission seed 1 + i) the strategy
//! explores the scenario's world; then
//! * the **learned cost's error**: per model of the strategy (per gait for the Prágr22 explorers),
//!   the RMSE of its planning cost against the terrain table in the model's own quantity
//!   (inverse-velocity cost, roll variance, push force), over the cells the map observed that
//!   are traversable in truth and that the model has a cost for;
//! * the **benchmark tour** (the scenario's first) driven with learned navigation: the Prágr22
//!   planner and gait selection on the per-gait models a passive Prágr22 learner learned from the
//!   data this strategy collected ([`strider_explore::shadow`]), one yardstick for strategies
//!   that learn different quantities.
//!
//! The simulator's world is the judge here, never seen by the strategies. Strategies come from
//! the registry or from outside it ([`Entrant::custom`]).

mod shard;
mod table;
mod truth;

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

use anyhow::{Context, Result, bail};
use rayon::prelude::*;
use serde::{Deserialize, Deserializer, Serialize};
use strider_core::snapshot::Quantity;
use strider_explore::TourExplorer;
use strider_explore::evaluate::NavigationMode;
use strider_explore::kernel::{BodyParams, Mission, Strategy};
use strider_explore::registry::{self, RobotSpec, StrategyInfo};
use strider_explore::shadow::Shadowed;
use strider_scenario::Scenario;

use crate::cancel::{Cancel, Completion};
use crate::io::{create_dir, write_json, write_text};
use crate::parallel::{MAX_JOBS, pool};
use crate::stats::Summary;
use crate::trial::{
    Learned, MAX_TRIALS, TrialRecord, checked_time_limit, configure, drive, robot_spec,
    run_tours_with, section,
};
pub use shard::{MAX_SHARDS, Shard, ShardInfo, merge};
pub use table::markdown;
use table::{pair_tests, summarise};
pub use truth::cost_errors;

/// Builds a strategy for a scenario's robot and a mission seed: the body it needs and the
/// strategy itself, or why it cannot run on that robot.
pub type Builder =
    dyn Fn(&Scenario, &RobotSpec, u64) -> Result<(BodyParams, Box<dyn Strategy + Send>)> + Sync;

/// A strategy taking part in a comparison.
pub struct Entrant {
    /// Its name in the tables.
    pub name: String,
    build: Box<Builder>,
}

impl Entrant {
    /// A strategy of the registry, configured from each scenario's `[strategy.<name>]`.
    pub fn registered(name: &str) -> Result<Self> {
        let info: &'static StrategyInfo = registry::find(name)?;
        Ok(Self {
            name: info.name.to_string(),
            build: Box::new(move |sc, robot, seed| {
                let (_, configured) = configure(sc, info.name, &[])?;
                Ok(configured.parts(robot, seed)?)
            }),
        })
    }

    /// A strategy from outside the registry.
    pub fn custom(
        name: &str,
        build: impl Fn(&Scenario, &RobotSpec, u64) -> Result<(BodyParams, Box<dyn Strategy + Send>)>
        + Sync
        + 'static,
    ) -> Self {
        Self {
            name: name.to_string(),
            build: Box::new(build),
        }
    }
}

/// What to compare.
#[derive(Clone, Debug)]
pub struct CompareOptions {
    /// Scenarios (built-in names or files).
    pub scenarios: Vec<String>,
    /// Trials per scenario and strategy.
    pub trials: usize,
    /// World seeds cycled through.
    pub world_seeds: u64,
    /// Trials run side by side.
    pub jobs: usize,
    /// Mission time limit override, simulated seconds.
    pub time_limit: Option<f64>,
    /// Stops the comparison early: running trials stop, the finished ones are compared.
    pub cancel: Cancel,
    /// Runs only this shard's trials (see [`Shard`]); `strider bench merge` joins the shards.
    pub shard: Option<Shard>,
}

/// One model's learned-cost error.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ModelError {
    /// The model (the gait's name for per-gait models).
    pub model: String,
    /// What it learns.
    pub quantity: Quantity,
    /// RMSE against the terrain table, in the quantity's unit (NaN without cells; JSON has
    /// no NaN, so it is written as null and read back as NaN).
    #[serde(deserialize_with = "nan_if_null")]
    pub rmse: f64,
    /// Cells compared.
    pub cells: usize,
}

/// A number JSON wrote as null because it was NaN.
fn nan_if_null<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::NAN))
}

/// One trial.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CompareTrial {
    /// Where it ran and how the exploration ended.
    #[serde(flatten)]
    pub trial: TrialRecord,
    /// Learned-cost error per model.
    pub cost_error: Vec<ModelError>,
    /// The benchmark tour's name.
    pub tour: Option<String>,
    /// Its time with learned navigation, simulated s.
    pub tour_time_s: Option<f64>,
    /// Every segment of the tour reached its waypoint.
    pub tour_completed: Option<bool>,
    /// Wall time of the trial, s.
    pub wall_s: f64,
}

/// A scenario × strategy cell of the table.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CompareCell {
    /// Scenario.
    pub scenario: String,
    /// Strategy.
    pub strategy: String,
    /// Why the strategy cannot run on this scenario's robot (no trials then).
    pub skipped: Option<String>,
    /// Exploration time, s.
    pub exploration_time_s: Option<Summary>,
    /// Observed cells.
    pub observed_cells: Option<Summary>,
    /// Learned-cost RMSE per model.
    pub cost_rmse: BTreeMap<String, Summary>,
    /// Benchmark-tour time over the trials whose tour completed, s (an incomplete tour's
    /// time leaves out the segments it could not plan, so it is not a time to compare).
    pub tour_time_s: Option<Summary>,
    /// Trials whose tour completed.
    pub tours_completed: usize,
}

/// Mann–Whitney U between two strategies on one scenario.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PairTest {
    /// Scenario.
    pub scenario: String,
    /// First strategy.
    pub a: String,
    /// Second strategy.
    pub b: String,
    /// What was compared (`exploration_time_s`, `tour_time_s`).
    pub measure: String,
    /// Two-sided p.
    pub p_two_sided: f64,
    /// p of "a is less than b".
    pub p_a_less: f64,
}

/// The comparison.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Comparison {
    /// Whether every trial finished, or the comparison was interrupted (then the cells and
    /// tests are of the trials finished so far).
    #[serde(flatten)]
    pub completion: Completion,
    /// Trials per cell.
    pub trials_per_cell: usize,
    /// World seeds cycled through.
    pub world_seeds: u64,
    /// The cells, scenario-major.
    pub cells: Vec<CompareCell>,
    /// Pairwise tests.
    pub tests: Vec<PairTest>,
    /// Every trial.
    pub trials: Vec<CompareTrial>,
    /// The shard this is, with what the merge needs (absent for a whole comparison).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub shard: Option<ShardInfo>,
}

struct Task<'a> {
    scenario: &'a str,
    entrant: &'a Entrant,
    world_seed: u64,
    seed: u64,
}

/// Runs the comparison (trials side by side on `jobs` threads; only the shard's with
/// `o.shard`) until it is done or `o.cancel` is requested; `on_trial` is called after every
/// finished trial.
pub fn run(
    o: &CompareOptions,
    entrants: &[Entrant],
    on_trial: impl Fn() + Sync,
) -> Result<Comparison> {
    check(o, entrants)?;
    let (tasks, skipped) = tasks(o, entrants)?;
    let mine: Vec<&Task> = tasks
        .iter()
        .enumerate()
        .filter(|(i, _)| o.shard.is_none_or(|s| s.owns(*i)))
        .map(|(_, t)| t)
        .collect();
    let finished: Vec<Option<CompareTrial>> = pool(o.jobs)?.install(|| {
        mine.par_iter()
            .with_max_len(1)
            .map(|t| -> Result<Option<CompareTrial>> {
                if o.cancel.requested() {
                    return Ok(None);
                }
                let r = run_task(t, o)?;
                if r.is_some() {
                    on_trial();
                }
                Ok(r)
            })
            .collect::<Result<Vec<_>>>()
    })?;
    let trials: Vec<CompareTrial> = finished.into_iter().flatten().collect();
    let completion = Completion::of(trials.len() < mine.len());
    let names: Vec<String> = entrants.iter().map(|e| e.name.clone()).collect();
    let mut c = assemble(o, &names, &skipped, trials, completion);
    c.shard = o.shard.map(|shard| ShardInfo {
        shard,
        scenarios: o.scenarios.clone(),
        strategies: names.clone(),
        time_limit: o.time_limit,
    });
    Ok(c)
}

/// One trial of a comparison, by name: what a task of a distributed sweep runs.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct TrialId {
    /// Scenario (built-in name or file).
    pub scenario: String,
    /// Strategy (entrant) name.
    pub strategy: String,
    /// World seed.
    pub world_seed: u64,
    /// Mission seed.
    pub seed: u64,
}

/// Every trial of the comparison in its order, and the (scenario, strategy) cells that cannot
/// run with why.
pub fn plan(o: &CompareOptions, entrants: &[Entrant]) -> Result<(Vec<TrialId>, Skipped)> {
    check(o, entrants)?;
    let (tasks, skipped) = tasks(o, entrants)?;
    let ids = tasks
        .iter()
        .map(|t| TrialId {
            scenario: t.scenario.to_string(),
            strategy: t.entrant.name.clone(),
            world_seed: t.world_seed,
            seed: t.seed,
        })
        .collect();
    Ok((ids, skipped))
}

/// Runs the trial `id` of a comparison with options `o` among `entrants`.
pub fn run_one(o: &CompareOptions, entrants: &[Entrant], id: &TrialId) -> Result<CompareTrial> {
    let Some(entrant) = entrants.iter().find(|e| e.name == id.strategy) else {
        bail!("strategy {} is not among the entrants", id.strategy);
    };
    let t = Task {
        scenario: &id.scenario,
        entrant,
        world_seed: id.world_seed,
        seed: id.seed,
    };
    run_task(&t, o)?.context("the trial was interrupted")
}

fn run_task(t: &Task, o: &CompareOptions) -> Result<Option<CompareTrial>> {
    run_trial(t, o).with_context(|| {
        format!(
            "{} on {} world seed {} seed {}",
            t.entrant.name, t.scenario, t.world_seed, t.seed
        )
    })
}

/// The comparison of `trials` (in any order; sorted here into the comparison's order) of the
/// strategies `names` under `o`: the cells, the pairwise tests and the trials.
pub fn assemble(
    o: &CompareOptions,
    names: &[String],
    skipped: &Skipped,
    mut trials: Vec<CompareTrial>,
    completion: Completion,
) -> Comparison {
    let rank = |v: &[String], x: &str| v.iter().position(|n| n == x).unwrap_or(usize::MAX);
    trials.sort_by_key(|t| {
        (
            rank(&o.scenarios, &t.trial.scenario),
            rank(names, &t.trial.strategy),
            t.trial.seed,
        )
    });
    let mut cells = Vec::new();
    for name in &o.scenarios {
        for e in names {
            let key = (name.clone(), e.clone());
            let mine: Vec<&CompareTrial> = trials
                .iter()
                .filter(|t| t.trial.scenario == *name && t.trial.strategy == *e)
                .collect();
            cells.push(summarise(name, e, skipped.get(&key).cloned(), &mine));
        }
    }
    Comparison {
        completion,
        trials_per_cell: o.trials,
        world_seeds: o.world_seeds,
        tests: pair_tests(&o.scenarios, names, &trials),
        cells,
        trials,
        shard: None,
    }
}

fn check(o: &CompareOptions, entrants: &[Entrant]) -> Result<()> {
    if let Some(t) = o.time_limit {
        checked_time_limit(t)?;
    }
    if o.trials == 0 || o.world_seeds == 0 || o.jobs == 0 {
        bail!("--trials, --world-seeds and --jobs must be at least 1");
    }
    if o.jobs > MAX_JOBS || o.trials > MAX_TRIALS {
        bail!("--jobs must be at most {MAX_JOBS} and --trials at most {MAX_TRIALS}");
    }
    if entrants.is_empty() || o.scenarios.is_empty() {
        bail!("give at least one scenario and one strategy");
    }
    let mut seen = BTreeSet::new();
    if let Some(n) = o.scenarios.iter().find(|n| !seen.insert(n.as_str())) {
        bail!("scenario {n} is listed twice");
    }
    let mut seen = BTreeSet::new();
    if let Some(e) = entrants.iter().find(|e| !seen.insert(e.name.as_str())) {
        bail!("strategy {} is listed twice", e.name);
    }
    Ok(())
}

/// Why an entrant cannot run on a scenario, by (scenario, strategy).
pub type Skipped = BTreeMap<(String, String), String>;

/// Every trial of the entrants that fit each scenario's robot, and why the others do not.
fn tasks<'a>(o: &'a CompareOptions, entrants: &'a [Entrant]) -> Result<(Vec<Task<'a>>, Skipped)> {
    let mut skipped = Skipped::new();
    let mut tasks = Vec::new();
    for name in &o.scenarios {
        let sc =
            Scenario::from_name_or_file(name, 1).with_context(|| format!("scenario {name}"))?;
        for e in entrants {
            if let Err(why) = fits(&sc, e) {
                skipped.insert((name.clone(), e.name.clone()), why);
                continue;
            }
            for i in 0..o.trials {
                tasks.push(Task {
                    scenario: name,
                    entrant: e,
                    world_seed: 1 + (i as u64 % o.world_seeds),
                    seed: 1 + i as u64,
                });
            }
        }
    }
    Ok((tasks, skipped))
}

/// `Ok` when the entrant can run on the scenario's robot, else why not.
fn fits(sc: &Scenario, e: &Entrant) -> std::result::Result<(), String> {
    let robot = robot_spec(sc);
    match (e.build)(sc, &robot, 1) {
        Ok(_) => Ok(()),
        Err(err) => Err(format!("{err:#}")),
    }
}

/// One trial; `None` when it was interrupted.
fn run_trial(t: &Task, o: &CompareOptions) -> Result<Option<CompareTrial>> {
    let cancel = &o.cancel;
    let wall = std::time::Instant::now();
    let sc = Scenario::from_name_or_file(t.scenario, t.world_seed)?;
    let mut robot = robot_spec(&sc);
    if let Some(limit) = o.time_limit {
        robot.time_limit_s = limit;
    }
    let (body, strategy) = (t.entrant.build)(&sc, &robot, t.seed)?;
    let yardstick = registry::find("gtsp")?.configure(section(&sc, "gtsp")?, &[])?;
    let learner_params = yardstick
        .tour_mission(&robot, t.seed)
        .context("gtsp has no Prágr22 learner")?;
    let learner = TourExplorer::new(learner_params)?;
    let mut mission = Mission::new(body, Shadowed::new(strategy, learner))?;
    drive(&sc, t.seed, &mut mission, (None, cancel), |_, _| {})?;
    if mission.interrupted() {
        return Ok(None);
    }
    let snap = mission.snapshot(true);
    let learner = mission.strategy().learner();
    let tours = run_tours_with(
        &sc,
        Learned {
            map: mission.body().map(),
            models: learner.models(),
            params: learner.params(),
        },
        t.seed,
        &[NavigationMode::Learned],
        |_, _| {},
    )?;
    let tour = tours.first();
    let result = tour.and_then(|(_, r)| r.first());
    Ok(Some(CompareTrial {
        trial: TrialRecord::of(
            t.scenario,
            &t.entrant.name,
            (t.world_seed, t.seed),
            &mission,
        ),
        cost_error: cost_errors(&sc, &snap),
        tour: tour.map(|(n, _)| n.clone()),
        tour_time_s: result.map(|r| r.total_s),
        tour_completed: result.map(|r| r.completed),
        wall_s: wall.elapsed().as_secs_f64(),
    }))
}

/// Writes `compare.json` (everything) and `compare.md` (the tables) into `out`.
pub fn write(out: &Path, c: &Comparison, command: &str) -> Result<()> {
    create_dir(out)?;
    write_json(&out.join("compare.json"), c)?;
    write_text(&out.join("compare.md"), &markdown(c, command))
}

/// The command that reproduces a comparison of the registry's strategies `names`.
pub fn command_line(o: &CompareOptions, names: &[String]) -> String {
    format!(
        "strider bench compare --scenarios {} --strategies {} --trials {} --world-seeds {}{}",
        o.scenarios.join(","),
        names.join(","),
        o.trials,
        o.world_seeds,
        o.time_limit
            .map_or_else(String::new, |t| format!(" --time-limit {t}"))
    )
}
