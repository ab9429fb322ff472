//! The pieces of `strider bench compare` a distributed sweep needs: the trial list, one trial,
//! and the comparison assembled from the trials, all as JSON text (what travels between the
//! tasks of a Ray cluster).

use pyo3::prelude::*;
use serde::Deserialize;
use strider_experiments::cancel::{Cancel, Completion};
use strider_experiments::compare::{self, CompareOptions, CompareTrial, Entrant, Skipped, TrialId};

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
