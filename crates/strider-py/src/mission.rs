//! Scenarios, missions and replays: the library functions `strider scenario list`,
//! `strider run` and `strider replay` call, with their results as JSON text (the report, which
//! the Python side reads into a report object) and numpy layers.

use std::path::PathBuf;

use numpy::{IntoPyArray, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use strider_experiments::cancel::Cancel;
use strider_experiments::live::Watch;
use strider_experiments::progress::Silent;
use strider_experiments::run::{RunOutcome, RunRequest};
use strider_experiments::trial::load;
use strider_scenario::builtin;

use crate::errors::{msg, to_py};
use crate::layers::{grid, to_dict};

/// The built-in scenarios as (name, description) pairs.
#[pyfunction]
pub fn scenarios() -> Vec<(&'static str, &'static str)> {
    builtin::names()
        .iter()
        .map(|n| (*n, builtin::describe(n).unwrap_or_default()))
        .collect()
}

/// The registered strategies as (name, paper key, summary) triples.
#[pyfunction]
pub fn strategies() -> Vec<(&'static str, &'static str, &'static str)> {
    strider_explore::registry::STRATEGIES
        .iter()
        .map(|s| (s.name, s.key, s.summary))
        .collect()
}

/// A scenario's world (built-in name with its world seed, or a scenario file) as numpy layers:
/// colour (rows, cols, 3) uint8, elevation float32 m, terrain index uint8, with `cell_size`,
/// `origin` and the terrain names.
#[pyfunction]
#[pyo3(signature = (scenario, world_seed = 1))]
pub fn scenario_layers<'py>(
    py: Python<'py>,
    scenario: &str,
    world_seed: u64,
) -> PyResult<Bound<'py, PyDict>> {
    let sc = py.detach(|| load(scenario, world_seed)).map_err(to_py)?;
    let w = sc.world;
    let (rows, cols) = (w.height(), w.width());
    let d = PyDict::new(py);
    d.set_item("name", sc.name)?;
    d.set_item("world_seed", world_seed)?;
    d.set_item("cell_size", w.resolution)?;
    let o = w.rect.min;
    d.set_item(
        "origin",
        (o.i as f64 * w.resolution, o.j as f64 * w.resolution),
    )?;
    d.set_item("elevation", grid(py, w.elevation, rows, cols)?)?;
    d.set_item("terrain", grid(py, w.terrain, rows, cols)?)?;
    let colour: Vec<u8> = w.color.iter().flat_map(|c| c.0).collect();
    d.set_item(
        "color",
        colour.into_pyarray(py).reshape([rows, cols, 3])?.into_any(),
    )?;
    let names: Vec<String> = w.terrains.iter().map(|t| t.name.clone()).collect();
    d.set_item("terrains", names)?;
    Ok(d)
}

/// A top-level report field whose JSON is longer than this travels as its own text, parsed by
/// the Python side only when it is read (a mission's tours are ~1 MB: 30 ms of `json.loads`
/// that a caller reading `exploration_time_s` should not pay).
const LAZY_FIELD_BYTES: usize = 64 * 1024;

/// The report as JSON text without its large fields, and those fields' (name, JSON text).
type SplitReport = (String, Vec<(String, String)>);

fn split_report<T: serde::Serialize>(report: &T) -> PyResult<SplitReport> {
    let bad = |e: serde_json::Error| msg(format!("cannot serialise the report: {e}"));
    let mut v = serde_json::to_value(report).map_err(bad)?;
    let mut lazy = Vec::new();
    if let Some(fields) = v.as_object_mut() {
        let mut large = Vec::new();
        for (k, f) in fields.iter() {
            let text = serde_json::to_string(f).map_err(bad)?;
            if text.len() > LAZY_FIELD_BYTES {
                large.push(k.clone());
                lazy.push((k.clone(), text));
            }
        }
        for k in large {
            fields.remove(&k);
        }
    }
    Ok((serde_json::to_string(&v).map_err(bad)?, lazy))
}

/// `strider run`: one mission written to `out`; returns the report as JSON text (large fields
/// apart, as (name, JSON text) pairs) and the final map and model layers.
#[pyfunction]
#[pyo3(signature = (scenario, strategy, seed, world_seed, time_limit, sets, out))]
#[allow(clippy::too_many_arguments)]
pub fn run<'py>(
    py: Python<'py>,
    scenario: &str,
    strategy: &str,
    seed: u64,
    world_seed: u64,
    time_limit: Option<f64>,
    sets: Vec<(String, String)>,
    out: PathBuf,
) -> PyResult<(SplitReport, Bound<'py, PyDict>)> {
    let cancel = Cancel::new();
    let req = RunRequest {
        scenario,
        world_seed,
        strategy,
        sets: &sets,
        seed,
        time_limit,
        out: &out,
        mcap: None,
        live: None,
        rate: None,
        cancel: &cancel,
    };
    let outcome = py
        .detach(|| strider_experiments::run::run(&req, &Silent))
        .map_err(to_py)?;
    let (json, last) = match outcome {
        RunOutcome::Tour(r) => (split_report(&r.report)?, r.last),
        RunOutcome::Rbcm(r) => (split_report(&r.report)?, r.last),
        RunOutcome::Escape(r) => (split_report(&r.report)?, r.last),
    };
    let Some(layers) = last.layers else {
        return Err(msg("the mission's final state has no layers"));
    };
    Ok((json, to_dict(py, layers, last.cell_size)?))
}

/// `strider replay`: a recorded MCAP log through the mission's mapping and learning, written
/// to `out`; returns the report as JSON text.
#[pyfunction]
pub fn replay(py: Python<'_>, log: PathBuf, config: PathBuf, out: PathBuf) -> PyResult<String> {
    let cancel = Cancel::new();
    let r = py
        .detach(|| {
            strider_experiments::replay::replay(
                (&log, &config),
                &out,
                Watch::from((None, &cancel)),
                &Silent,
            )
        })
        .map_err(to_py)?;
    serde_json::to_string(&r.report).map_err(|e| msg(format!("cannot serialise the report: {e}")))
}
