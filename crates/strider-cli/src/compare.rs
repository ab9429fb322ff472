//! `strider bench compare`: strategies from different papers on the same worlds.
//!
//! Per scenario × strategy × trial (world seed 1 + (i mod K), mission seed 1 + i) the strategy
//! explores the scenario's world; then
//! * the **learned cost's error**: per model of the strategy (per gait for the `001` explorers),
//!   the RMSE of its planning cost against the terrain table in the model's own quantity
//!   (inverse-velocity cost, roll variance, push force), over the cells the map observed that
//!   are traversable in truth and that the model has a cost for;
//! * the **benchmark tour** (the scenario's first) driven with learned navigation: the `001`
//!   planner and gait selection on the per-gait models a passive `001` learner learned from the
//!   data this strategy collected ([`strider_explore::shadow`]), one yardstick for strategies
//!   that learn different quantities.
//!
//! The simulator's world is the judge here, never seen by the strategies. Strategies come from
//! the registry or from outside it ([`Entrant::custom`]).

use anyhow::{Context, Result, bail};
use rayon::prelude::*;
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::Path;
use strider_core::snapshot::{Quantity, Snapshot};
use strider_core::{Cell, GaitId};
use strider_explore::evaluate::NavigationMode;
use strider_explore::kernel::{BodyParams, Mission, Strategy};
use strider_explore::registry::{self, RobotSpec};
use strider_explore::shadow::Shadowed;
use strider_explore::stats::{Summary, mann_whitney_u};
use strider_explore::{TourExplorer, registry::StrategyInfo};
use strider_learn::signals::tanh_bound;
use strider_scenario::Scenario;

use crate::trial::{Learned, configure, drive, robot_spec, run_tours_with, section};

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
}

/// One model's learned-cost error.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ModelError {
    /// The model (the gait's name for per-gait models).
    pub model: String,
    /// What it learns.
    pub quantity: Quantity,
    /// RMSE against the terrain table, in the quantity's unit (NaN without cells).
    pub rmse: f64,
    /// Cells compared.
    pub cells: usize,
}

/// One trial.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CompareTrial {
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
}

struct Task<'a> {
    scenario: &'a str,
    entrant: &'a Entrant,
    world_seed: u64,
    seed: u64,
}

/// Runs the comparison (trials side by side on `jobs` threads).
pub fn run(
    o: &CompareOptions,
    entrants: &[Entrant],
    on_trial: impl Fn() + Sync,
) -> Result<Comparison> {
    if o.trials == 0 || o.world_seeds == 0 || o.jobs == 0 {
        bail!("--trials, --world-seeds and --jobs must be at least 1");
    }
    if entrants.is_empty() || o.scenarios.is_empty() {
        bail!("give at least one scenario and one strategy");
    }
    let mut seen = std::collections::BTreeSet::new();
    if let Some(n) = o.scenarios.iter().find(|n| !seen.insert(n.as_str())) {
        bail!("scenario {n} is listed twice");
    }
    let mut seen = std::collections::BTreeSet::new();
    if let Some(e) = entrants.iter().find(|e| !seen.insert(e.name.as_str())) {
        bail!("strategy {} is listed twice", e.name);
    }
    let mut skipped: BTreeMap<(String, String), String> = BTreeMap::new();
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
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(o.jobs)
        .build()
        .context("cannot start the trial thread pool")?;
    let trials: Vec<CompareTrial> = pool.install(|| {
        tasks
            .par_iter()
            .with_max_len(1)
            .map(|t| {
                let r = run_trial(t, o.time_limit).with_context(|| {
                    format!(
                        "{} on {} world seed {} seed {}",
                        t.entrant.name, t.scenario, t.world_seed, t.seed
                    )
                });
                on_trial();
                r
            })
            .collect::<Result<Vec<_>>>()
    })?;
    let mut cells = Vec::new();
    for name in &o.scenarios {
        for e in entrants {
            let key = (name.clone(), e.name.clone());
            let mine: Vec<&CompareTrial> = trials
                .iter()
                .filter(|t| t.scenario == *name && t.strategy == e.name)
                .collect();
            cells.push(summarise(name, &e.name, skipped.get(&key).cloned(), &mine));
        }
    }
    Ok(Comparison {
        trials_per_cell: o.trials,
        world_seeds: o.world_seeds,
        tests: pair_tests(&o.scenarios, entrants, &trials),
        cells,
        trials,
    })
}

/// `Ok` when the entrant can run on the scenario's robot, else why not.
fn fits(sc: &Scenario, e: &Entrant) -> std::result::Result<(), String> {
    let robot = robot_spec(sc);
    match (e.build)(sc, &robot, 1) {
        Ok(_) => Ok(()),
        Err(err) => Err(format!("{err:#}")),
    }
}

fn run_trial(t: &Task, time_limit: Option<f64>) -> Result<CompareTrial> {
    let wall = std::time::Instant::now();
    let sc = Scenario::from_name_or_file(t.scenario, t.world_seed)?;
    let mut robot = robot_spec(&sc);
    if let Some(limit) = time_limit {
        robot.time_limit_s = limit;
    }
    let (body, strategy) = (t.entrant.build)(&sc, &robot, t.seed)?;
    let yardstick = registry::find("gtsp")?.configure(section(&sc, "gtsp")?, &[])?;
    let learner_params = yardstick
        .tour_mission(&robot, t.seed)
        .context("gtsp has no 001 learner")?;
    let learner = TourExplorer::new(learner_params)?;
    let mut mission = Mission::new(body, Shadowed::new(strategy, learner))?;
    drive(&sc, t.seed, &mut mission, None, |_, _| {})?;
    let snap = mission.snapshot(true);
    let record = mission.record();
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
    Ok(CompareTrial {
        scenario: t.scenario.to_string(),
        strategy: t.entrant.name.clone(),
        world_seed: t.world_seed,
        seed: t.seed,
        termination: format!("{:?}", record.termination),
        exploration_time_s: record.exploration_time_s,
        observed_cells: mission.body().map().observed_count(),
        cost_error: cost_errors(&sc, &snap),
        tour: tour.map(|(n, _)| n.clone()),
        tour_time_s: result.map(|r| r.total_s),
        tour_completed: result.map(|r| r.completed),
        wall_s: wall.elapsed().as_secs_f64(),
    })
}

/// The RMSE of each model layer of `snap` against the terrain table (module docs).
pub fn cost_errors(sc: &Scenario, snap: &Snapshot) -> Vec<ModelError> {
    let Some(layers) = &snap.layers else {
        return Vec::new();
    };
    let w = &sc.world;
    let admissible = w.gt_admissible(sc.map.rho_obstacle, sc.map.r_robot);
    let d = snap.cell_size;
    layers
        .models
        .iter()
        .map(|m| {
            let (mut sum, mut n) = (0.0, 0usize);
            for (k, c) in layers.rect.cells().enumerate() {
                let learned = m.cost[k] as f64;
                if !(layers.observed[k] && learned.is_finite()) {
                    continue;
                }
                let Some(truth) = truth_at(sc, &admissible, c, d, m.quantity, m.gait) else {
                    continue;
                };
                sum += (learned - truth).powi(2);
                n += 1;
            }
            ModelError {
                model: m.name.clone(),
                quantity: m.quantity,
                rmse: if n > 0 {
                    (sum / n as f64).sqrt()
                } else {
                    f64::NAN
                },
                cells: n,
            }
        })
        .collect()
}

/// The terrain table's value of `quantity` at map cell `c` for `gait`; `None` where the world
/// has no such cell, it is not traversable in truth (push force: not pushable), or the
/// quantity needs a gait the model does not name.
fn truth_at(
    sc: &Scenario,
    admissible: &[bool],
    c: Cell,
    cell_size: f64,
    quantity: Quantity,
    gait: Option<GaitId>,
) -> Option<f64> {
    let w = &sc.world;
    let k = w.index_at(c.center(cell_size))?;
    let terrain = w.terrain_type(w.terrain[k])?;
    let response = |g: GaitId| {
        let name = &sc.robot.gaits.get(g.0 as usize)?.name;
        Some((
            terrain.gaits.get(name).cloned().unwrap_or_default(),
            sc.robot.gaits[g.0 as usize].max_speed,
        ))
    };
    match quantity {
        Quantity::PushForce => terrain.push_force_n,
        Quantity::RollVariance => {
            let (r, _) = response(gait?)?;
            admissible[k].then_some(r.roll_variance)
        }
        Quantity::InverseVelocity { v_max, c_high } => {
            let (r, top) = response(gait?)?;
            // On stuck terrain the simulator's nominal speed is its stuck fraction of the gait's.
            let factor = if r.stuck {
                strider_sim::MotionParams::default().stuck_speed_fraction
            } else {
                r.speed_factor
            };
            let v = factor * top;
            admissible[k].then(|| tanh_bound(v_max / v, c_high))
        }
    }
}

fn summarise(
    scenario: &str,
    strategy: &str,
    skipped: Option<String>,
    trials: &[&CompareTrial],
) -> CompareCell {
    let of = |v: Vec<f64>| Summary::of(&v).ok();
    let mut rmse: BTreeMap<String, Vec<f64>> = BTreeMap::new();
    for t in trials {
        for e in &t.cost_error {
            if e.rmse.is_finite() {
                rmse.entry(e.model.clone()).or_default().push(e.rmse);
            }
        }
    }
    CompareCell {
        scenario: scenario.to_string(),
        strategy: strategy.to_string(),
        skipped,
        exploration_time_s: of(trials.iter().map(|t| t.exploration_time_s).collect()),
        observed_cells: of(trials.iter().map(|t| t.observed_cells as f64).collect()),
        cost_rmse: rmse
            .into_iter()
            .filter_map(|(m, v)| Some((m, Summary::of(&v).ok()?)))
            .collect(),
        tour_time_s: of(trials
            .iter()
            .filter_map(|t| completed_tour_time(t))
            .collect()),
        tours_completed: trials
            .iter()
            .filter(|t| t.tour_completed == Some(true))
            .count(),
    }
}

/// The tour time of a trial whose tour completed.
fn completed_tour_time(t: &CompareTrial) -> Option<f64> {
    t.tour_time_s.filter(|_| t.tour_completed == Some(true))
}

/// A per-trial figure the pairwise tests compare.
type Measure = fn(&CompareTrial) -> Option<f64>;

fn pair_tests(
    scenarios: &[String],
    entrants: &[Entrant],
    trials: &[CompareTrial],
) -> Vec<PairTest> {
    let series = |sc: &str, st: &str, f: Measure| -> Vec<f64> {
        trials
            .iter()
            .filter(|t| t.scenario == sc && t.strategy == st)
            .filter_map(f)
            .collect()
    };
    let measures: [(&str, Measure); 2] = [
        ("exploration_time_s", |t| Some(t.exploration_time_s)),
        ("tour_time_s", completed_tour_time),
    ];
    let mut out = Vec::new();
    for sc in scenarios {
        for (i, a) in entrants.iter().enumerate() {
            for b in &entrants[i + 1..] {
                for (measure, f) in measures {
                    let (x, y) = (series(sc, &a.name, f), series(sc, &b.name, f));
                    if let Ok(u) = mann_whitney_u(&x, &y) {
                        out.push(PairTest {
                            scenario: sc.clone(),
                            a: a.name.clone(),
                            b: b.name.clone(),
                            measure: measure.to_string(),
                            p_two_sided: u.p_two_sided,
                            p_a_less: u.p_less,
                        });
                    }
                }
            }
        }
    }
    out
}

/// Writes `compare.json` (everything) and `compare.md` (the tables) into `out`.
pub fn write(out: &Path, c: &Comparison, command: &str) -> Result<()> {
    std::fs::create_dir_all(out)
        .with_context(|| format!("{}: cannot create directory", out.display()))?;
    let json = out.join("compare.json");
    std::fs::write(&json, serde_json::to_string_pretty(c)? + "\n")
        .with_context(|| format!("{}: cannot write", json.display()))?;
    let md = out.join("compare.md");
    std::fs::write(&md, markdown(c, command))
        .with_context(|| format!("{}: cannot write", md.display()))?;
    Ok(())
}

/// median [min–max] of a summary, with `digits` decimals.
fn range(s: &Option<Summary>, digits: usize) -> String {
    s.as_ref().map_or_else(
        || "–".to_string(),
        |s| {
            format!(
                "{:.*} [{:.*}–{:.*}]",
                digits, s.median, digits, s.min, digits, s.max
            )
        },
    )
}

/// The unit of model `model`'s cost in the trials of `strategy` (empty for a dimensionless one).
fn unit_of(c: &Comparison, strategy: &str, model: &str) -> &'static str {
    let q = c
        .trials
        .iter()
        .filter(|t| t.strategy == strategy)
        .flat_map(|t| &t.cost_error)
        .find(|e| e.model == model)
        .map(|e| e.quantity);
    match q {
        Some(Quantity::RollVariance) => " rad²",
        Some(Quantity::PushForce) => " N",
        _ => "",
    }
}

/// The tables of `compare.md`.
pub fn markdown(c: &Comparison, command: &str) -> String {
    use std::fmt::Write;
    let mut m = String::new();
    let _ = writeln!(m, "# Strategies compared on the same worlds\n");
    let _ = writeln!(
        m,
        "Produced by `{command}`: {} trials per scenario and strategy over {} world seeds. Medians with [min–max] over trials. Cost RMSE: each model's planning cost (a model without data plans with its prior) against the terrain table in its own quantity (inverse-velocity cost, dimensionless; roll variance, rad²; push force, N), over the cells that strategy's map observed and that are traversable in truth. Tour: the scenario's first benchmark tour with learned navigation on the `001` models a passive learner fitted to the data the strategy collected; times over the trials whose tour completed.\n",
        c.trials_per_cell, c.world_seeds
    );
    let mut scenarios: Vec<&str> = c.cells.iter().map(|x| x.scenario.as_str()).collect();
    scenarios.dedup();
    for sc in scenarios {
        let _ = writeln!(m, "## {sc}\n");
        let _ = writeln!(
            m,
            "| strategy | exploration s | observed cells | learned cost RMSE | tour s (completed) | tours completed |"
        );
        let _ = writeln!(m, "|---|---|---|---|---|---|");
        for cell in c.cells.iter().filter(|x| x.scenario == sc) {
            if let Some(why) = &cell.skipped {
                let _ = writeln!(m, "| {} | cannot run: {why} | | | | |", cell.strategy);
                continue;
            }
            let rmse: Vec<String> = cell
                .cost_rmse
                .iter()
                .map(|(k, s)| format!("{k} {:.3}{}", s.median, unit_of(c, &cell.strategy, k)))
                .collect();
            let n = cell.exploration_time_s.as_ref().map_or(0, |s| s.n);
            let _ = writeln!(
                m,
                "| {} | {} | {} | {} | {} | {}/{} |",
                cell.strategy,
                range(&cell.exploration_time_s, 0),
                range(&cell.observed_cells, 0),
                if rmse.is_empty() {
                    "–".into()
                } else {
                    rmse.join(", ")
                },
                range(&cell.tour_time_s, 0),
                cell.tours_completed,
                n
            );
        }
        let tests: Vec<&PairTest> = c.tests.iter().filter(|t| t.scenario == sc).collect();
        if !tests.is_empty() {
            let _ = writeln!(
                m,
                "\nMann–Whitney U (two-sided p; p that the first is less):\n"
            );
            let _ = writeln!(m, "| pair | measure | p | p(first less) |");
            let _ = writeln!(m, "|---|---|---|---|");
            for t in tests {
                let _ = writeln!(
                    m,
                    "| {} vs {} | {} | {:.3} | {:.3} |",
                    t.a, t.b, t.measure, t.p_two_sided, t.p_a_less
                );
            }
        }
        let _ = writeln!(m);
    }
    m
}
