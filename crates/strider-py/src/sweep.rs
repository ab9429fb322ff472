//! The pieces of `strider bench compare` a distributed sweep needs: the trial list, one trial,
//! and the comparison assembled from the trials, all as JSON text (what travels between the
//! tasks of a Ray cluster); the same for `strider bench table5`.

use pyo3::prelude::*;
use serde::Deserialize;
use strider_experiments::cancel::{Cancel, Completion};
use strider_experiments::compare::{self, CompareOptions, CompareTrial, Entrant, Skipped, TrialId};
use strider_experiments::pragr22::{self, Table5Options, TrialResult};

use crate::errors::{msg, to_py};

/// A sweep's options, as `strider bench compare` takes them.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SweepOptions {
    scenarios: Vec<String>,
    strategies: Vec<String>,
    trials: usize,
    world_seeds: u64,
    time_limit: Option<f64>,
}

fn options(json: &str) -> PyResult<(CompareOptions, Vec<Entrant>, Vec<String>)> {
    let s: SweepOptions =
        serde_json::from_str(json).map_err(|e| msg(format!("sweep options: {e}")))?;
    let entrants = s
        .strategies
        .iter()
        .map(|n| Entrant::registered(n))
        .collect::<anyhow::Result<Vec<_>>>()
        .map_err(to_py)?;
    let o = CompareOptions {
        scenarios: s.scenarios,
        trials: s.trials,
        world_seeds: s.world_seeds,
        jobs: 1,
        time_limit: s.time_limit,
        cancel: Cancel::new(),
        shard: None,
    };
    Ok((o, entrants, s.strategies))
}

fn json<T: serde::Serialize>(v: &T) -> PyResult<String> {
    serde_json::to_string(v).map_err(|e| msg(format!("cannot serialise: {e}")))
}

/// The comparison's trials in order and its skipped cells: `{"trials": [...], "skipped":
/// [[scenario, strategy, why], ...]}`.
#[pyfunction]
pub fn compare_plan(py: Python<'_>, options_json: &str) -> PyResult<String> {
    let (o, entrants, _) = options(options_json)?;
    let (ids, skipped) = py.detach(|| compare::plan(&o, &entrants)).map_err(to_py)?;
    let skipped: Vec<(String, String, String)> = skipped
        .into_iter()
        .map(|((sc, st), why)| (sc, st, why))
        .collect();
    json(&serde_json::json!({"trials": ids, "skipped": skipped}))
}

/// One trial of the comparison, as JSON.
#[pyfunction]
pub fn compare_trial(py: Python<'_>, options_json: &str, trial_json: &str) -> PyResult<String> {
    let (o, entrants, _) = options(options_json)?;
    let id: TrialId = serde_json::from_str(trial_json).map_err(|e| msg(format!("trial: {e}")))?;
    let t = py
        .detach(|| compare::run_one(&o, &entrants, &id))
        .map_err(to_py)?;
    json(&t)
}

/// The comparison (`compare.json` of `strider bench compare`) of the trials' JSON texts.
#[pyfunction]
pub fn compare_assemble(
    options_json: &str,
    trials_json: Vec<String>,
    skipped: Vec<(String, String, String)>,
) -> PyResult<String> {
    let (o, _, names) = options(options_json)?;
    let trials = trials_json
        .iter()
        .map(|t| serde_json::from_str::<CompareTrial>(t))
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| msg(format!("trial: {e}")))?;
    let skipped: Skipped = skipped
        .into_iter()
        .map(|(sc, st, why)| ((sc, st), why))
        .collect();
    let c = compare::assemble(&o, &names, &skipped, trials, Completion::of(false));
    json(&c)
}

/// A Table 5 sweep's options, as `strider bench table5` takes them.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Table5SweepOptions {
    trials: usize,
    large_trials: usize,
    world_seeds: u64,
    time_limit: Option<f64>,
}

fn table5_options(json: &str) -> PyResult<Table5Options> {
    let s: Table5SweepOptions =
        serde_json::from_str(json).map_err(|e| msg(format!("sweep options: {e}")))?;
    Ok(Table5Options {
        trials: s.trials,
        large_trials: s.large_trials,
        world_seeds: s.world_seeds,
        jobs: 1,
        time_limit: s.time_limit,
        mcap_dir: None,
        resume: false,
        cancel: Cancel::new(),
        shard: None,
        sets: Vec::new(),
    })
}

/// The number of trials of `strider bench table5` for these options.
#[pyfunction]
pub fn table5_plan(options_json: &str) -> PyResult<usize> {
    pragr22::trial_count(&table5_options(options_json)?).map_err(to_py)
}

/// Trial `index` of the table, as JSON.
#[pyfunction]
pub fn table5_trial(py: Python<'_>, options_json: &str, index: usize) -> PyResult<String> {
    let o = table5_options(options_json)?;
    let t = py.detach(|| pragr22::run_trial(&o, index)).map_err(to_py)?;
    json(&t)
}

/// The table (`table5.json` of `strider bench table5`) of the trials' JSON texts; `wall_s` is
/// the sweep's wall time.
#[pyfunction]
pub fn table5_assemble(
    options_json: &str,
    trials_json: Vec<String>,
    wall_s: f64,
) -> PyResult<String> {
    let o = table5_options(options_json)?;
    let trials = trials_json
        .iter()
        .map(|t| serde_json::from_str::<TrialResult>(t))
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| msg(format!("trial: {e}")))?;
    json(&pragr22::assemble(&o, trials, wall_s))
}
